// Upscaling a render to the output size, and sharpening (aa::scaled). Every entry point reads
// `source` through an Rgba8Unorm view, so it filters the sRGB-encoded (perceptual) values, as
// AMD recommends for FSR 1, and writes encoded values to an Rgba8Unorm view of its target.
//
// Upscalers (output pixel centre p maps to source position p * source_size / output_size, in
// source pixels, pixel centres at +0.5; reads past the border repeat the border pixel):
//   fs_nearest   the source pixel under p (debug views: render pixels shown as they are);
//   fs_bilinear  the hardware bilinear filter;
//   fs_bicubic   Catmull-Rom over 4x4 pixels (separable; reproduces linear ramps, overshoots);
//   fs_lanczos   Lanczos-2 over 4x4 pixels (separable, weights normalised; rings at edges);
//   fs_easu      edge-adaptive, after the ideas AMD documents for FSR 1 EASU (Lottes): over the
//                12 pixels of the 4x4 neighbourhood without its corners, the luma gradients of
//                the inner 2x2 pixels, weighted bilinearly, give a structure tensor whose main
//                eigenvector is the gradient direction and whose eigenvalue spread is the
//                anisotropy; how much the neighbourhood is one clean edge (anisotropic, of some
//                contrast, and a step rather than a thin line) shrinks each tap's along-edge
//                distance by up to half (the kernel stretches along the edge) and widens the
//                window of a polynomial kernel with a Lanczos-2-like zero at distance 1 from
//                sqrt(2) to 2 (a full negative lobe across clean edges only); the result is
//                clamped to the nearest 2x2 pixels' range, so it cannot ring. Written from the
//                description, not from AMD's source.
// Sharpening (source and target of the same size; `strength` 0 leaves the image unchanged):
//   fs_cas       contrast-adaptive (after AMD FidelityFX CAS): per channel, an amount from the
//                3x3 range (high where the range sits away from black and white, i.e. soft
//                detail; low in flat or clipped areas) scales a negative lobe on the four
//                direct neighbours, up to -1/5 at strength 1;
//   fs_rcas      robust (after FSR 1 RCAS): the negative lobe on the four direct neighbours is
//                the strongest, up to -3/16 at strength 1, that keeps every channel inside the
//                range of the pixel and its four neighbours (solved exactly per channel, the
//                most restrictive channel wins), so it never overshoots.

struct ResampleParams {
    // xy: source size in pixels; zw: output size in pixels.
    sizes: vec4<f32>,
    // x: sharpening strength in [0, 1]; yzw: unused.
    sharpen: vec4<f32>,
}

@group(0) @binding(0) var source: texture_2d<f32>;
@group(0) @binding(1) var bilinear: sampler;
@group(0) @binding(2) var<uniform> params: ResampleParams;

// The source pixel at integer coordinates, clamped to the image.
fn texel(at: vec2<i32>) -> vec4<f32> {
    let last = vec2<i32>(textureDimensions(source)) - vec2<i32>(1);
    return textureLoad(source, clamp(at, vec2<i32>(0), last), 0);
}

// The output pixel's centre in source pixel units.
fn source_position(position: vec4<f32>) -> vec2<f32> {
    return position.xy * params.sizes.xy / params.sizes.zw;
}

@fragment
fn fs_nearest(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    return texel(vec2<i32>(floor(source_position(position))));
}

@fragment
fn fs_bilinear(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let uv = source_position(position) / params.sizes.xy;
    return textureSampleLevel(source, bilinear, uv, 0.0);
}

fn catmull_rom(x: f32) -> f32 {
    let a = abs(x);
    if a < 1.0 {
        return (1.5 * a - 2.5) * a * a + 1.0;
    }
    if a < 2.0 {
        return ((-0.5 * a + 2.5) * a - 4.0) * a + 2.0;
    }
    return 0.0;
}

fn sinc(x: f32) -> f32 {
    if abs(x) < 1e-4 {
        return 1.0;
    }
    let px = 3.14159265 * x;
    return sin(px) / px;
}

fn lanczos2(x: f32) -> f32 {
    if abs(x) >= 2.0 {
        return 0.0;
    }
    return sinc(x) * sinc(0.5 * x);
}

// One row of a separable 4x4 filter: taps -1..2 around `base` weighted by `w`.
fn filtered_row(base: vec2<i32>, w: vec4<f32>) -> vec4<f32> {
    return w.x * texel(base + vec2<i32>(-1, 0)) + w.y * texel(base) + w.z * texel(base + vec2<i32>(1, 0))
        + w.w * texel(base + vec2<i32>(2, 0));
}

// A separable 4x4 filter: `weights_x` holds the x weights of taps -1..2 around the source
// pixel `base`, `weights_y` the y weights; both normalised here. Rows and taps are written out
// rather than looped over with indexed weights, which a GPU compiler may keep in memory.
fn separable_4x4(base: vec2<i32>, weights_x: vec4<f32>, weights_y: vec4<f32>) -> vec4<f32> {
    let wx = weights_x / dot(weights_x, vec4<f32>(1.0));
    let wy = weights_y / dot(weights_y, vec4<f32>(1.0));
    return wy.x * filtered_row(base + vec2<i32>(0, -1), wx) + wy.y * filtered_row(base, wx)
        + wy.z * filtered_row(base + vec2<i32>(0, 1), wx) + wy.w * filtered_row(base + vec2<i32>(0, 2), wx);
}

// Distances from the source position to taps -1..2 of each axis, and the pixel of tap 0.
struct Taps {
    base: vec2<i32>,
    fraction: vec2<f32>,
}

fn taps(position: vec4<f32>) -> Taps {
    let at = source_position(position) - vec2<f32>(0.5);
    let base = floor(at);
    return Taps(vec2<i32>(base), at - base);
}

@fragment
fn fs_bicubic(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let t = taps(position);
    let f = t.fraction;
    let wx = vec4<f32>(
        catmull_rom(f.x + 1.0), catmull_rom(f.x), catmull_rom(f.x - 1.0), catmull_rom(f.x - 2.0)
    );
    let wy = vec4<f32>(
        catmull_rom(f.y + 1.0), catmull_rom(f.y), catmull_rom(f.y - 1.0), catmull_rom(f.y - 2.0)
    );
    return saturate(separable_4x4(t.base, wx, wy));
}

@fragment
fn fs_lanczos(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let t = taps(position);
    let f = t.fraction;
    let wx = vec4<f32>(lanczos2(f.x + 1.0), lanczos2(f.x), lanczos2(f.x - 1.0), lanczos2(f.x - 2.0));
    let wy = vec4<f32>(lanczos2(f.y + 1.0), lanczos2(f.y), lanczos2(f.y - 1.0), lanczos2(f.y - 2.0));
    return saturate(separable_4x4(t.base, wx, wy));
}

fn luma(c: vec4<f32>) -> f32 {
    return dot(c.rgb, vec3<f32>(0.299, 0.587, 0.114));
}

// The squared gradient terms of one inner pixel of the edge-adaptive upscaler, from its luma
// `c` and its four direct neighbours: (gx^2, gx gy, gy^2) and how much the pixel sits on a
// step rather than a peak or a dip (a thin line): the central difference over the larger
// one-sided difference, per axis (1 on a step or ramp, 0 on a line's centre).
struct Gradient {
    tensor: vec3<f32>,
    step: f32,
}

fn gradient(c: f32, left: f32, right: f32, up: f32, down: f32) -> Gradient {
    let g = vec2<f32>(right - left, down - up);
    let one_sided = max(max(abs(right - c), abs(c - left)), max(abs(down - c), abs(c - up)));
    let ratio = saturate(length(g) / max(one_sided, 1e-5) * 0.5);
    return Gradient(vec3<f32>(g.x * g.x, g.x * g.y, g.y * g.y), ratio);
}

// The windowed kernel over the squared (stretched) distance d2: the window
// (1 - d2 / reach2)^2, which ends at distance sqrt(reach2), times (1 - d2), which has
// a zero at distance 1 as Lanczos-2's central lobe; the part beyond it, up to the window's
// end, is the negative lobe (reach2 4: close to Lanczos-2's, for clean edges; reach2 2: a
// short one elsewhere).
fn easu_weight(d2: f32, reach2: f32) -> f32 {
    let window = max(0.0, 1.0 - d2 / reach2);
    return window * window * (1.0 - d2);
}

// The kernel's frame at one output pixel: the fraction past tap 0, the unit vectors across
// and along the edge, how much along-edge distances shrink, and the window's reach.
struct EasuKernel {
    fraction: vec2<f32>,
    across: vec2<f32>,
    along: vec2<f32>,
    shrink_along: f32,
    reach2: f32,
}

// The running weighted sum of the taps' colours and the sum of their weights.
struct Accumulated {
    sum: vec4<f32>,
    weight: f32,
}

// `acc` with the tap at `offset` from tap 0, of colour `colour`, added.
fn easu_tap(acc: Accumulated, k: EasuKernel, offset: vec2<f32>, colour: vec4<f32>) -> Accumulated {
    let d = offset - k.fraction;
    let u = dot(d, k.across);
    let s = dot(d, k.along) * k.shrink_along;
    let w = easu_weight(u * u + s * s, k.reach2);
    return Accumulated(acc.sum + w * colour, acc.weight + w);
}

// The 12 taps are the 4x4 block -1..2 around tap 0 without its corners, named by row (a: -1,
// b: 0, c: 1, d: 2) and column (-1, 0, 1, 2 as m, 0, 1, 2). They are held in named values,
// not arrays: a GPU compiler may keep a function's arrays in memory rather than registers
// (TAA's resolve cost twice as much that way).
@fragment
fn fs_easu(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let t = taps(position);
    let f = t.fraction;
    let a0 = texel(t.base + vec2<i32>(0, -1));
    let a1 = texel(t.base + vec2<i32>(1, -1));
    let bm = texel(t.base + vec2<i32>(-1, 0));
    let b0 = texel(t.base);
    let b1 = texel(t.base + vec2<i32>(1, 0));
    let b2 = texel(t.base + vec2<i32>(2, 0));
    let cm = texel(t.base + vec2<i32>(-1, 1));
    let c0 = texel(t.base + vec2<i32>(0, 1));
    let c1 = texel(t.base + vec2<i32>(1, 1));
    let c2 = texel(t.base + vec2<i32>(2, 1));
    let d0 = texel(t.base + vec2<i32>(0, 2));
    let d1 = texel(t.base + vec2<i32>(1, 2));
    // Central-difference gradients of the inner 2x2 pixels (b0, b1, c0, c1), each from its
    // four direct neighbours among the 12 taps, accumulated as a structure tensor with
    // bilinear weights; the step measure (see `gradient`) is accumulated squared.
    let bilinear_weights = vec4<f32>((1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), (1.0 - f.x) * f.y, f.x * f.y);
    let gb0 = gradient(luma(b0), luma(bm), luma(b1), luma(a0), luma(c0));
    let gb1 = gradient(luma(b1), luma(b0), luma(b2), luma(a1), luma(c1));
    let gc0 = gradient(luma(c0), luma(cm), luma(c1), luma(b0), luma(d0));
    let gc1 = gradient(luma(c1), luma(c0), luma(c2), luma(b1), luma(d1));
    let tensor = bilinear_weights.x * gb0.tensor + bilinear_weights.y * gb1.tensor
        + bilinear_weights.z * gc0.tensor + bilinear_weights.w * gc1.tensor;
    let step = bilinear_weights.x * gb0.step * gb0.step + bilinear_weights.y * gb1.step * gb1.step
        + bilinear_weights.z * gc0.step * gc0.step + bilinear_weights.w * gc1.step * gc1.step;
    // Eigen-decomposition of the 2x2 tensor [[a, b], [b, c]].
    let trace = tensor.x + tensor.z;
    let spread = sqrt(max(0.0, 0.25 * (tensor.x - tensor.z) * (tensor.x - tensor.z) + tensor.y * tensor.y));
    var across = vec2<f32>(1.0, 0.0);
    var anisotropy = 0.0;
    if trace > 1e-8 {
        let largest = 0.5 * trace + spread;
        let v = vec2<f32>(tensor.y, largest - tensor.x);
        let w = vec2<f32>(largest - tensor.z, tensor.y);
        let pick = select(w, v, dot(v, v) > dot(w, w));
        if dot(pick, pick) > 1e-12 {
            across = normalize(pick);
        }
        anisotropy = 2.0 * spread / trace;
    }
    // How much the neighbourhood is one edge: anisotropic and of some contrast.
    let edge = anisotropy * step * saturate(sqrt(trace) * 8.0);
    let k = EasuKernel(f, across, vec2<f32>(-across.y, across.x), 1.0 - 0.5 * edge, mix(2.0, 4.0, edge));
    var acc = Accumulated(vec4<f32>(0.0), 0.0);
    acc = easu_tap(acc, k, vec2<f32>(0.0, -1.0), a0);
    acc = easu_tap(acc, k, vec2<f32>(1.0, -1.0), a1);
    acc = easu_tap(acc, k, vec2<f32>(-1.0, 0.0), bm);
    acc = easu_tap(acc, k, vec2<f32>(0.0, 0.0), b0);
    acc = easu_tap(acc, k, vec2<f32>(1.0, 0.0), b1);
    acc = easu_tap(acc, k, vec2<f32>(2.0, 0.0), b2);
    acc = easu_tap(acc, k, vec2<f32>(-1.0, 1.0), cm);
    acc = easu_tap(acc, k, vec2<f32>(0.0, 1.0), c0);
    acc = easu_tap(acc, k, vec2<f32>(1.0, 1.0), c1);
    acc = easu_tap(acc, k, vec2<f32>(2.0, 1.0), c2);
    acc = easu_tap(acc, k, vec2<f32>(0.0, 2.0), d0);
    acc = easu_tap(acc, k, vec2<f32>(1.0, 2.0), d1);
    let result = acc.sum / acc.weight;
    let low = min(min(b0, b1), min(c0, c1));
    let high = max(max(b0, b1), max(c0, c1));
    return clamp(result, low, high);
}

// The centre pixel and its four direct neighbours of a sharpening pass.
struct Cross {
    center: vec4<f32>,
    up: vec4<f32>,
    left: vec4<f32>,
    right: vec4<f32>,
    down: vec4<f32>,
}

fn cross_at(position: vec4<f32>) -> Cross {
    let p = vec2<i32>(floor(position.xy));
    return Cross(
        texel(p),
        texel(p + vec2<i32>(0, -1)),
        texel(p + vec2<i32>(-1, 0)),
        texel(p + vec2<i32>(1, 0)),
        texel(p + vec2<i32>(0, 1)),
    );
}

// The centre with a negative lobe `lobe` (per channel, <= 0, > -1/4) on the four neighbours.
fn with_lobe(c: Cross, lobe: vec3<f32>) -> vec4<f32> {
    let neighbours = c.up.rgb + c.left.rgb + c.right.rgb + c.down.rgb;
    let rgb = (c.center.rgb + lobe * neighbours) / (vec3<f32>(1.0) + 4.0 * lobe);
    return vec4<f32>(saturate(rgb), c.center.a);
}

@fragment
fn fs_cas(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let c = cross_at(position);
    let p = vec2<i32>(floor(position.xy));
    var low = min(min(c.center.rgb, min(c.up.rgb, c.down.rgb)), min(c.left.rgb, c.right.rgb));
    var high = max(max(c.center.rgb, max(c.up.rgb, c.down.rgb)), max(c.left.rgb, c.right.rgb));
    for (var n = 0; n < 4; n++) {
        let corner = texel(p + vec2<i32>((n & 1) * 2 - 1, (n >> 1u) * 2 - 1)).rgb;
        low = min(low, corner);
        high = max(high, corner);
    }
    // Room to the nearer end of the range, relative to the brightest value.
    let room = min(low, vec3<f32>(1.0) - high) / max(high, vec3<f32>(1e-5));
    let amount = sqrt(saturate(room));
    return with_lobe(c, -0.2 * params.sharpen.x * amount);
}

// The least negative lobe below which the sharpened value leaves [low, high], per channel:
// out = (e + lobe S) / (1 + 4 lobe) stays >= low while lobe >= -(e - low) / (S - 4 low), and
// <= high while lobe >= -(high - e) / (4 high - S).
fn rcas_limit(e: f32, neighbours: f32, low: f32, high: f32) -> f32 {
    let below = -(e - low) / max(neighbours - 4.0 * low, 1e-6);
    let above = -(high - e) / max(4.0 * high - neighbours, 1e-6);
    return max(below, above);
}

@fragment
fn fs_rcas(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let c = cross_at(position);
    let neighbours = c.up.rgb + c.left.rgb + c.right.rgb + c.down.rgb;
    let low = min(min(c.center.rgb, min(c.up.rgb, c.down.rgb)), min(c.left.rgb, c.right.rgb));
    let high = max(max(c.center.rgb, max(c.up.rgb, c.down.rgb)), max(c.left.rgb, c.right.rgb));
    var lobe = -0.1875 * params.sharpen.x;
    for (var k = 0; k < 3; k++) {
        lobe = max(lobe, rcas_limit(c.center[k], neighbours[k], low[k], high[k]));
    }
    lobe = min(lobe, 0.0);
    return with_lobe(c, vec3<f32>(lobe));
}
