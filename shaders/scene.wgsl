// Forward Blinn-Phong scene shader: one directional light, ambient + diffuse + specular,
// base-colour texture with mip bias and a bounded anisotropic filter, alpha-mask materials (alpha test, or sharpened
// alpha-to-coverage), procedural normal detail (ripples and flakes in world space), optional
// geometric specular antialiasing, and screen-space motion vectors in a second target;
// alpha-blended materials output premultiplied colour and their alpha as a reactive mask
// (a third target, present only when asked for).
//
// Three vertex/fragment entry-point pairs differ only in how varyings are interpolated:
//   *_center   : at the pixel centre (ordinary MSAA: one shade per pixel)
//   *_centroid : texture coordinates at the centroid of the covered samples
//   *_sample   : every varying per sample, which makes the fragment shader run once per sample
//                (sample-rate shading: MSAA turned into SSAA at the same count)
// WebGPU requires the interpolation of a vertex output to match the fragment input, hence the
// pairs; all of them share `shade_vertex` and `shade_fragment`.

struct View {
    // Rasterisation matrix: projection with the sub-pixel jitter (and SSAA tile) applied.
    view_proj: mat4x4<f32>,
    // Un-jittered matrices of this and the previous frame, for motion vectors.
    unjittered_view_proj: mat4x4<f32>,
    prev_view_proj: mat4x4<f32>,
    eye: vec4<f32>,
    light_direction: vec4<f32>,   // xyz: direction the light travels
    light_color: vec4<f32>,
    ambient: vec4<f32>,
    // x: texture mip bias, y: 1 when motion vectors are written, z: exposure scale 2^EV
    // (HDR renders only)
    params: vec4<f32>,
}

struct Material {
    base_color: vec4<f32>,
    specular: vec4<f32>,    // rgb: specular colour, a: shininess
    // x: alpha cutoff, y: 1 when unlit, z: 1 when the material is alpha-masked, w: unused
    params: vec4<f32>,
    // Normal detail: x periods per world unit, y ripple slope, z flake slope (0 without)
    detail: vec4<f32>,
    // rgb: emitted radiance, added to the shading (above 1 in HDR scenes)
    emissive: vec4<f32>,
}

struct Object {
    model: mat4x4<f32>,
    prev_model: mat4x4<f32>,
    normal_matrix: mat4x4<f32>,
}

@group(0) @binding(0) var<uniform> view: View;
@group(1) @binding(0) var<uniform> material: Material;
@group(1) @binding(1) var base_texture: texture_2d<f32>;
@group(1) @binding(2) var base_sampler: sampler;
@group(2) @binding(0) var<uniform> object: Object;

// True when the pipeline uses alpha-to-coverage instead of the alpha test.
override ALPHA_TO_COVERAGE: bool = false;
// True when the specular lobe is widened by the normal's change across the pixel.
override SPECULAR_AA: bool = false;
// What the colour target receives (graph/hdr.rs): 0 display values clamped to [0, 1] (the LDR
// path), 1 linear radiance (a floating-point HDR target), 2 radiance after exposure and the
// tonemapping operator `OPERATOR` (an HDR scene rendered for a technique after tonemapping).
override OUTPUT: u32 = 0u;
// True in the pipelines of materials whose texture is filtered anisotropically (linear
// filters and mipmaps): the shader's own filter, `sample_base_color`. Other materials, and
// every material of an untextured scene, take one plain lookup and pay nothing for it.
override ANISOTROPIC: bool = false;
// True in the pipelines of materials with normal detail (ripples or flakes): the others skip
// the detail's arithmetic rather than compute it and select it away.
override DETAIL: bool = false;
// True in the pipelines of alpha-blended materials: colour is premultiplied by alpha (the
// blend composites it over the target), and the alpha is the reactive mask's coverage.
override BLENDED: bool = false;

struct VertexInput {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
}

struct Shaded {
    clip: vec4<f32>,
    world_position: vec3<f32>,
    normal: vec3<f32>,
    uv: vec2<f32>,
    current_clip: vec4<f32>,
    previous_clip: vec4<f32>,
}

fn shade_vertex(v: VertexInput) -> Shaded {
    var out: Shaded;
    let world = object.model * vec4<f32>(v.position, 1.0);
    out.clip = view.view_proj * world;
    out.world_position = world.xyz;
    out.normal = (object.normal_matrix * vec4<f32>(v.normal, 0.0)).xyz;
    out.uv = v.uv;
    out.current_clip = view.unjittered_view_proj * world;
    out.previous_clip = view.prev_view_proj * (object.prev_model * vec4<f32>(v.position, 1.0));
    return out;
}

struct FragmentOutput {
    @location(0) color: vec4<f32>,
    @location(1) motion: vec2<f32>,
    // How much a blended surface covers the pixel (ignored without a reactive-mask target).
    @location(2) reactive: f32,
}

fn clip_to_uv(clip: vec4<f32>) -> vec2<f32> {
    let ndc = clip.xy / clip.w;
    return vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
}

// Directions of the four plane waves of the ripples (unit vectors, none in a coordinate plane,
// so no axis-aligned surface sees a wave run along it).
const RIPPLE_DIRECTIONS = array<vec3<f32>, 4>(
    vec3<f32>(0.5773503, 0.5773503, 0.5773503),
    vec3<f32>(-0.7071068, 0.4082483, 0.5773503),
    vec3<f32>(0.2672612, -0.8017837, 0.5345225),
    vec3<f32>(0.8164966, 0.4082483, -0.4082483),
);
const TAU: f32 = 6.2831853;

// PCG3D integer hash (Jarzynski and Olano, "Hash Functions for GPU Rendering", JCGT 2020).
fn pcg3d(cell: vec3<u32>) -> vec3<u32> {
    var v = cell * 1664525u + 1013904223u;
    v.x += v.y * v.z;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    v ^= v >> vec3<u32>(16u);
    v.x += v.y * v.z;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    return v;
}

// The normal with the material's detail: a tilt made of smooth ripples (the gradient of four
// plane waves, each a quarter of the ripple slope) and flakes (one random tilt in -1..1 per
// axis, times the flake slope, per cubic cell of the world-space grid), times `strength`, of
// which only the part tangent to the surface bends the normal. Without detail the tilt is zero.
fn detail_normal(n: vec3<f32>, world_position: vec3<f32>, strength: f32) -> vec3<f32> {
    let x = world_position * material.detail.x;
    var ripple = vec3<f32>(0.0);
    for (var i = 0u; i < 4u; i++) {
        let d = RIPPLE_DIRECTIONS[i];
        ripple += d * cos(TAU * dot(d, x) + f32(i));
    }
    let hash = pcg3d(bitcast<vec3<u32>>(vec3<i32>(floor(x))));
    let flake = vec3<f32>(hash >> vec3<u32>(8u)) * (2.0 / 16777216.0) - 1.0;
    let tilt = (ripple * (0.25 * material.detail.y) + flake * material.detail.z) * strength;
    return normalize(n + tilt - n * dot(n, tilt));
}

// Specular antialiasing, two parts.
//
// The normal detail is filtered the way Toksvig ("Mipmapping normal maps", JGT 2005) filters
// a normal map's mips, analytically since the detail is procedural: of a pattern with
// `cells` periods across the pixel, the fraction u = cells^2 / (1 + cells^2) of its slope
// variance is averaged away inside the pixel (flakes and ripples average to no tilt; the
// mean of about cells^2 independent flakes keeps 1 / cells^2 of their variance), so the tilt
// is scaled by sqrt(1 - u) and the variance u sigma^2 becomes roughness instead (flakes
// uniform in -f..f: sigma^2 = f^2 / 3 per axis; four ripples of amplitude r / 4: r^2 / 24;
// Beckmann alpha^2 = 2 sigma^2): the lobe's spread over the pixel stays what it was.
fn unresolved_detail(world_position: vec3<f32>) -> f32 {
    let dx = dpdx(world_position);
    let dy = dpdy(world_position);
    let cells = sqrt(max(dot(dx, dx), dot(dy, dy))) * material.detail.x;
    return cells * cells / (1.0 + cells * cells);
}

fn detail_roughness2(unresolved: f32) -> f32 {
    let ripple = material.detail.y;
    let flakes = material.detail.z;
    return 2.0 * unresolved * (flakes * flakes / 3.0 + ripple * ripple / 24.0);
}

// Then geometric specular antialiasing after Kaplanyan, Hill, Patney and Lefohn ("Filtering
// distributions of normals for shading antialiasing", HPG 2016) and Tokuyoshi and Kaplanyan
// ("Improved geometric specular antialiasing", I3D 2019; "Stable geometric specular
// antialiasing with projected-space NDF filtering", JCGT 2021): the surface normal's change
// across the pixel, from its screen-space derivatives, is a variance of the normal
// distribution that is added to the lobe's squared roughness, clamped. The derivatives are
// the base normal's: the detail's variance is counted above, not twice (counting it here
// too blurred the sparkle scene's glitter further from the reference, docs/hard-cases.md). The Blinn-Phong
// exponent s maps to Beckmann roughness by alpha^2 = 2 / (s + 2) (Walter et al. 2007). The
// widened lobe (x: its exponent) is scaled (y) by the ratio of the two lobes' normalisation
// factors, (s' + 2) / (s + 2), so that it reflects the energy the narrow one did.
const PIXEL_FILTER_VARIANCE: f32 = 0.25;
const KERNEL_ROUGHNESS_CLAMP: f32 = 0.18;

fn filtered_lobe(n_dx: vec3<f32>, n_dy: vec3<f32>, exponent: f32, extra_roughness2: f32) -> vec2<f32> {
    let variance = PIXEL_FILTER_VARIANCE * (dot(n_dx, n_dx) + dot(n_dy, n_dy));
    let kernel_roughness2 = min(2.0 * variance, KERNEL_ROUGHNESS_CLAMP);
    let roughness2 = min(2.0 / (exponent + 2.0) + extra_roughness2 + kernel_roughness2, 1.0);
    let filtered = max(2.0 / roughness2 - 2.0, 1.0);
    return vec2<f32>(filtered, (filtered + 2.0) / (exponent + 2.0));
}

// Anisotropic filtering by trilinear probes along the footprint's major axis, the same on
// every adapter (the samplers' hardware anisotropy is off everywhere; scene/renderer/mod.rs
// says why). The pixel's footprint in texel space is the parallelogram spanned by the texture
// coordinates' screen derivatives; the singular values of that 2x2 Jacobian are the axes of
// its ellipse (Heckbert's EWA footprint), the eigenvector of the larger one its major
// direction. Up to MAX_ANISOTROPY probes are spread evenly over the major axis, each a
// trilinear lookup whose level is the minor axis' (widened to major / MAX_ANISOTROPY where
// the footprint is more elongated than that, as hardware clamps do), and averaged: the
// classic multi-probe approximation of an elliptical filter (the "Texram" and
// Feline-style probe schemes; Mavridis and Papaioannou, "High quality elliptical texture
// filtering on GPU", I3D 2011, who place probes the same way). The mip bias scales the
// derivatives by 2^bias. Derivatives are clamped to a finite range so that the helper lanes
// of sliver triangles, whose extrapolated coordinates can be huge, still get a finite
// footprint: the probe count, not the footprint, bounds the work.
const MAX_ANISOTROPY: f32 = 8.0;
const MAX_FOOTPRINT_TEXELS: f32 = 1e6;

struct Footprint {
    // Offset in texture coordinates from the first probe to the last
    major: vec2<f32>,
    // Gradients (both axis-aligned, in texture coordinates) that give each probe its level
    grad_x: vec2<f32>,
    grad_y: vec2<f32>,
    probes: u32,
}

fn anisotropic_footprint(duv_dx: vec2<f32>, duv_dy: vec2<f32>, texels: vec2<f32>) -> Footprint {
    let jx = clamp(duv_dx * texels, vec2<f32>(-MAX_FOOTPRINT_TEXELS), vec2<f32>(MAX_FOOTPRINT_TEXELS));
    let jy = clamp(duv_dy * texels, vec2<f32>(-MAX_FOOTPRINT_TEXELS), vec2<f32>(MAX_FOOTPRINT_TEXELS));
    // J J^T = [[a, b], [b, c]]: its eigenvalues are the squared axes of the ellipse.
    let a = jx.x * jx.x + jy.x * jy.x;
    let b = jx.x * jx.y + jy.x * jy.y;
    let c = jx.y * jx.y + jy.y * jy.y;
    let mean = 0.5 * (a + c);
    let spread = sqrt(0.25 * (a - c) * (a - c) + b * b);
    let major_length = sqrt(mean + spread);
    let minor_length = sqrt(max(mean - spread, 0.0));
    // Eigenvector of the larger eigenvalue, from whichever row of (J J^T - lambda I) is better
    // conditioned; any direction where the footprint is round (one probe then).
    let from_row_a = vec2<f32>(b, mean + spread - a);
    let from_row_c = vec2<f32>(mean + spread - c, b);
    let direction = select(from_row_c, from_row_a, dot(from_row_a, from_row_a) > dot(from_row_c, from_row_c));
    let direction_length = length(direction);
    let unit = select(vec2<f32>(1.0, 0.0), direction / direction_length, direction_length > 0.0);
    let probe_width = max(minor_length, major_length / MAX_ANISOTROPY);
    let probes = clamp(ceil(major_length / max(probe_width, 1e-20)), 1.0, MAX_ANISOTROPY);
    var out: Footprint;
    out.probes = u32(probes);
    // Each probe covers 1 / probes of the major axis; the first and last sit half a probe in.
    out.major = unit * (major_length * (probes - 1.0) / probes) / texels;
    out.grad_x = vec2<f32>(probe_width / texels.x, 0.0);
    out.grad_y = vec2<f32>(0.0, probe_width / texels.y);
    return out;
}

// The material's base-colour texel at `uv`: anisotropically filtered in the pipelines of
// materials whose sampler is linear and mipmapped (ANISOTROPIC), else one lookup with the mip
// bias.
fn sample_base_color(uv: vec2<f32>) -> vec4<f32> {
    if !ANISOTROPIC {
        return textureSampleBias(base_texture, base_sampler, uv, view.params.x);
    }
    let bias_scale = exp2(view.params.x);
    let footprint = anisotropic_footprint(
        dpdx(uv) * bias_scale,
        dpdy(uv) * bias_scale,
        vec2<f32>(textureDimensions(base_texture)),
    );
    let step = footprint.major / max(f32(footprint.probes) - 1.0, 1.0);
    let first = uv - 0.5 * footprint.major;
    var sum = vec4<f32>(0.0);
    for (var i = 0u; i < footprint.probes; i++) {
        sum += textureSampleGrad(base_texture, base_sampler, first + step * f32(i), footprint.grad_x, footprint.grad_y);
    }
    return sum / f32(footprint.probes);
}

fn shade_fragment(
    world_position: vec3<f32>,
    normal_in: vec3<f32>,
    uv: vec2<f32>,
    current_clip: vec4<f32>,
    previous_clip: vec4<f32>,
    front_facing: bool,
) -> FragmentOutput {
    var n = normalize(normal_in);
    if !front_facing {
        n = -n;
    }
    // Normal detail bends the normal of the specular term only, like flakes and ripples
    // under a clear coat over a smooth base: the sparkle it makes is specular aliasing alone.
    var specular_n = n;
    if DETAIL {
        specular_n = detail_normal(n, world_position, 1.0);
    }
    // The lobe: the material's, or widened by specular antialiasing (derivatives are taken
    // here, before the alpha test's discard, where control flow is still uniform).
    var lobe = vec2<f32>(material.specular.a, 1.0);
    if SPECULAR_AA {
        var unresolved = 0.0;
        if DETAIL {
            unresolved = unresolved_detail(world_position);
            specular_n = detail_normal(n, world_position, sqrt(1.0 - unresolved));
        }
        let extra = detail_roughness2(unresolved);
        lobe = filtered_lobe(dpdx(n), dpdy(n), material.specular.a, extra);
    }

    let texel = sample_base_color(uv);
    let albedo = material.base_color.rgb * texel.rgb;
    var alpha = texel.a * material.base_color.a;
    // Material switches choose results with select, never code paths: lavapipe recompiles a
    // shader at every draw whose branch conditions read uniforms only (gpu/shader.rs).
    let masked = material.params.z > 0.5;
    if ALPHA_TO_COVERAGE {
        // Sharpened alpha-to-coverage: the cutoff maps to 50% coverage and the transition
        // spans about one pixel, so masked edges keep their shape in every mip level.
        let coverage = clamp((alpha - material.params.x) / max(fwidth(alpha), 1e-4) + 0.5, 0.0, 1.0);
        alpha = select(alpha, coverage, masked);
    } else if masked & (alpha < material.params.x) {
        discard;
    }

    let l = -normalize(view.light_direction.xyz);
    let v = normalize(view.eye.xyz - world_position);
    let h = normalize(l + v);
    let n_dot_l = max(dot(n, l), 0.0);
    let diffuse = albedo * n_dot_l;
    var specular = vec3<f32>(0.0);
    if n_dot_l > 0.0 {
        specular = material.specular.rgb * lobe.y * pow(max(dot(specular_n, h), 0.0), lobe.x);
    }
    let lit = view.ambient.rgb * albedo + view.light_color.rgb * (diffuse + specular);
    let unlit = material.params.y > 0.5;
    let rgb = select(lit, albedo, unlit) + material.emissive.rgb;

    var out: FragmentOutput;
    var shown = clamp(rgb, vec3<f32>(0.0), vec3<f32>(1.0));
    if OUTPUT == 1u {
        shown = max(rgb, vec3<f32>(0.0));
    } else if OUTPUT == 2u {
        shown = tonemap_radiance(rgb, view.params.z);
    }
    out.color = vec4<f32>(shown, alpha);
    if BLENDED {
        let coverage = saturate(alpha);
        out.color = vec4<f32>(out.color.rgb * coverage, coverage);
        out.reactive = coverage;
    }
    // Motion in UV units from the previous frame's position to this one's, without jitter.
    out.motion = (clip_to_uv(current_clip) - clip_to_uv(previous_clip)) * view.params.y;
    return out;
}

// ---- centre interpolation -------------------------------------------------------------------

struct VaryingsCenter {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) current_clip: vec4<f32>,
    @location(4) previous_clip: vec4<f32>,
}

@vertex
fn vs_center(v: VertexInput) -> VaryingsCenter {
    let s = shade_vertex(v);
    return VaryingsCenter(s.clip, s.world_position, s.normal, s.uv, s.current_clip, s.previous_clip);
}

@fragment
fn fs_center(in: VaryingsCenter, @builtin(front_facing) front_facing: bool) -> FragmentOutput {
    return shade_fragment(in.world_position, in.normal, in.uv, in.current_clip, in.previous_clip, front_facing);
}

// ---- centroid texture coordinates -----------------------------------------------------------

struct VaryingsCentroid {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) @interpolate(perspective, centroid) uv: vec2<f32>,
    @location(3) current_clip: vec4<f32>,
    @location(4) previous_clip: vec4<f32>,
}

@vertex
fn vs_centroid(v: VertexInput) -> VaryingsCentroid {
    let s = shade_vertex(v);
    return VaryingsCentroid(s.clip, s.world_position, s.normal, s.uv, s.current_clip, s.previous_clip);
}

@fragment
fn fs_centroid(in: VaryingsCentroid, @builtin(front_facing) front_facing: bool) -> FragmentOutput {
    return shade_fragment(in.world_position, in.normal, in.uv, in.current_clip, in.previous_clip, front_facing);
}

// ---- per-sample shading ---------------------------------------------------------------------

struct VaryingsSample {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(perspective, sample) world_position: vec3<f32>,
    @location(1) @interpolate(perspective, sample) normal: vec3<f32>,
    @location(2) @interpolate(perspective, sample) uv: vec2<f32>,
    @location(3) @interpolate(perspective, sample) current_clip: vec4<f32>,
    @location(4) @interpolate(perspective, sample) previous_clip: vec4<f32>,
}

@vertex
fn vs_sample(v: VertexInput) -> VaryingsSample {
    let s = shade_vertex(v);
    return VaryingsSample(s.clip, s.world_position, s.normal, s.uv, s.current_clip, s.previous_clip);
}

@fragment
fn fs_sample(in: VaryingsSample, @builtin(front_facing) front_facing: bool) -> FragmentOutput {
    return shade_fragment(in.world_position, in.normal, in.uv, in.current_clip, in.previous_clip, front_facing);
}
