// The tonemapping operators, compiled in front of the scene shader and of the tonemap pass
// (graph/hdr.rs, gpu/shader.rs `TONEMAP_OPERATORS`): linear scene radiance after exposure to
// linear display values in [0, 1], one operator chosen by the override constant `OPERATOR`.

// 0: Reinhard per channel, 1: ACES (Narkowicz's fit), 2: AgX, 3: Khronos PBR Neutral.
override OPERATOR: u32 = 0u;

fn reinhard(x: vec3<f32>) -> vec3<f32> {
    return x / (1.0 + x);
}

// Krzysztof Narkowicz's 2015 rational fit of the ACES reference rendering and sRGB output
// transforms.
fn aces_fit(x: vec3<f32>) -> vec3<f32> {
    let y = (x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14);
    return clamp(y, vec3<f32>(0.0), vec3<f32>(1.0));
}

// AgX (Troy Sobotka's Blender 4 view transform) in the compact form of Benjamin Wrensch: an
// inset into a wider working space, a log2 encoding over 16.5 stops, a sigmoid fitted by a
// sixth-order polynomial, the inverse inset, and the display's 2.2 power back to linear.
fn agx_curve(x: vec3<f32>) -> vec3<f32> {
    let x2 = x * x;
    let x4 = x2 * x2;
    return 15.5 * x4 * x2 - 40.14 * x4 * x + 31.96 * x4 - 6.868 * x2 * x + 0.4298 * x2
        + 0.1191 * x - 0.00232;
}

fn agx(x: vec3<f32>) -> vec3<f32> {
    let inset = mat3x3<f32>(
        vec3<f32>(0.842479062253094, 0.0423282422610123, 0.0423756549057051),
        vec3<f32>(0.0784335999999992, 0.878468636469772, 0.0784336),
        vec3<f32>(0.0792237451477643, 0.0791661274605434, 0.879142973793104),
    );
    let outset = mat3x3<f32>(
        vec3<f32>(1.19687900512017, -0.0528968517574562, -0.0529716355144438),
        vec3<f32>(-0.0980208811401368, 1.15190312990417, -0.0980434501171241),
        vec3<f32>(-0.0990297440797205, -0.0989611768448433, 1.15107367264116),
    );
    let min_ev = -12.47393;
    let max_ev = 4.026069;
    let encoded = clamp(log2(max(inset * x, vec3<f32>(1e-10))), vec3<f32>(min_ev), vec3<f32>(max_ev));
    let curved = agx_curve((encoded - min_ev) / (max_ev - min_ev));
    return pow(clamp(outset * curved, vec3<f32>(0.0), vec3<f32>(1.0)), vec3<f32>(2.2));
}

// Khronos PBR Neutral (2024): identity below 0.76 apart from a small toe offset, a highlight
// compression above it towards 1, and a desaturation that grows with the compression.
fn pbr_neutral(color_in: vec3<f32>) -> vec3<f32> {
    let start_compression = 0.8 - 0.04;
    let desaturation = 0.15;
    let lowest = min(color_in.r, min(color_in.g, color_in.b));
    let offset = select(0.04, lowest - 6.25 * lowest * lowest, lowest < 0.08);
    var color = color_in - offset;
    let peak = max(color.r, max(color.g, color.b));
    if peak < start_compression {
        return color;
    }
    let d = 1.0 - start_compression;
    let new_peak = 1.0 - d * d / (peak + d - start_compression);
    color = color * (new_peak / peak);
    let g = 1.0 - 1.0 / (desaturation * (peak - new_peak) + 1.0);
    return mix(color, vec3<f32>(new_peak), g);
}

// Radiance through an exposure `scale` (2^EV) and the operator, to linear display values.
fn tonemap_radiance(radiance: vec3<f32>, scale: f32) -> vec3<f32> {
    return tonemap_operator(max(radiance * scale, vec3<f32>(0.0)));
}

// The operator of `OPERATOR` on exposed radiance `x` (non-negative), to linear display values.
fn tonemap_operator(x: vec3<f32>) -> vec3<f32> {
    switch OPERATOR {
        case 1u: {
            return aces_fit(x);
        }
        case 2u: {
            return agx(x);
        }
        case 3u: {
            return clamp(pbr_neutral(x), vec3<f32>(0.0), vec3<f32>(1.0));
        }
        default: {
            return reinhard(x);
        }
    }
}

