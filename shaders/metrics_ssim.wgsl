// SSIM, mean absolute error and squared error of two RGBA8 images on the GPU, in three compute
// passes that mirror the CPU reference in src/metrics/ssim.rs and src/metrics/pixel.rs:
//
// 1. cs_horizontal: BT.601 luma of both images (sRGB-encoded values, 0..255, read through
//    Rgba8Unorm views), shifted by -127.5; Gaussian-weighted horizontal sums of x, y, x^2, y^2
//    and x*y over 11 taps with mirrored edges (SciPy's "reflect"). The shift leaves variances
//    and covariance unchanged but keeps x^2 small, so E[x^2] - E[x]^2 loses less to f32
//    cancellation.
// 2. cs_vertical: the same weights vertically, then the SSIM formula per pixel (written to the
//    SSIM map), the absolute and squared error of R'G'B' per pixel, and a workgroup reduction
//    of (SSIM over interior pixels, absolute error, squared error, interior pixel count).
// 3. cs_reduce: one workgroup sums the per-workgroup partials into four totals.

const RADIUS: i32 = 5;
const SHIFT: f32 = 127.5;

struct Params {
    size: vec2<u32>,
    partial_count: u32,
    groups_x: u32,
    c1: f32,
    c2: f32,
    _pad: vec2<f32>,
    // The 11 normalised Gaussian weights, four to a vec4.
    weights: array<vec4<f32>, 3>,
}

@group(0) @binding(0) var<uniform> params: Params;

// Pass 1.
@group(0) @binding(1) var reference_image: texture_2d<f32>;
@group(0) @binding(2) var test_image: texture_2d<f32>;
@group(0) @binding(3) var moments_out: texture_storage_2d<rgba32float, write>;
@group(0) @binding(4) var cross_out: texture_storage_2d<r32float, write>;

// Pass 2 (also reads the two images through bindings 1 and 2).
@group(0) @binding(5) var moments_in: texture_2d<f32>;
@group(0) @binding(6) var cross_in: texture_2d<f32>;
@group(0) @binding(7) var ssim_map: texture_storage_2d<r32float, write>;
@group(0) @binding(8) var<storage, read_write> partials: array<vec4<f32>>;

// Pass 3.
@group(0) @binding(9) var<storage, read> partials_in: array<vec4<f32>>;
@group(0) @binding(10) var<storage, read_write> totals: vec4<f32>;

var<workgroup> scratch: array<vec4<f32>, 256>;

fn weight(k: i32) -> f32 {
    return params.weights[k / 4][k % 4];
}

fn reflect_index(i: i32, n: i32) -> i32 {
    if i < 0 {
        return -i - 1;
    }
    if i >= n {
        return 2 * n - i - 1;
    }
    return i;
}

fn luma(c: vec4<f32>) -> f32 {
    return dot(c.rgb, vec3<f32>(0.299, 0.587, 0.114)) * 255.0;
}

@compute @workgroup_size(16, 16)
fn cs_horizontal(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.size.x || id.y >= params.size.y {
        return;
    }
    let w = i32(params.size.x);
    let y = i32(id.y);
    var m = vec4<f32>(0.0);
    var c = 0.0;
    for (var k = 0; k < 2 * RADIUS + 1; k++) {
        let x = reflect_index(i32(id.x) + k - RADIUS, w);
        let a = luma(textureLoad(reference_image, vec2<i32>(x, y), 0)) - SHIFT;
        let b = luma(textureLoad(test_image, vec2<i32>(x, y), 0)) - SHIFT;
        let wk = weight(k);
        m += wk * vec4<f32>(a, b, a * a, b * b);
        c += wk * a * b;
    }
    textureStore(moments_out, vec2<i32>(id.xy), m);
    textureStore(cross_out, vec2<i32>(id.xy), vec4<f32>(c, 0.0, 0.0, 0.0));
}

// Sums scratch[0..256) into scratch[0]; every invocation of the workgroup must call it.
fn reduce_scratch(index: u32) {
    for (var stride = 128u; stride > 0u; stride >>= 1u) {
        workgroupBarrier();
        if index < stride {
            scratch[index] += scratch[index + stride];
        }
    }
    workgroupBarrier();
}

@compute @workgroup_size(16, 16)
fn cs_vertical(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
    @builtin(workgroup_id) group: vec3<u32>,
) {
    let size = vec2<i32>(params.size);
    let p = vec2<i32>(id.xy);
    var value = vec4<f32>(0.0);
    if p.x < size.x && p.y < size.y {
        var m = vec4<f32>(0.0);
        var c = 0.0;
        for (var k = 0; k < 2 * RADIUS + 1; k++) {
            let q = vec2<i32>(p.x, reflect_index(p.y + k - RADIUS, size.y));
            let wk = weight(k);
            m += wk * textureLoad(moments_in, q, 0);
            c += wk * textureLoad(cross_in, q, 0).x;
        }
        let ux = m.x + SHIFT;
        let uy = m.y + SHIFT;
        let vx = m.z - m.x * m.x;
        let vy = m.w - m.y * m.y;
        let cov = c - m.x * m.y;
        let s = ((2.0 * ux * uy + params.c1) * (2.0 * cov + params.c2))
            / ((ux * ux + uy * uy + params.c1) * (vx + vy + params.c2));
        textureStore(ssim_map, p, vec4<f32>(s, 0.0, 0.0, 0.0));
        let d = (textureLoad(reference_image, p, 0).rgb - textureLoad(test_image, p, 0).rgb) * 255.0;
        let interior = all(p >= vec2<i32>(RADIUS)) && all(p + RADIUS < size);
        let inside = select(0.0, 1.0, interior);
        let ad = abs(d);
        value = vec4<f32>(s * inside, (ad.x + ad.y + ad.z) / 3.0, dot(d, d) / 3.0, inside);
    }
    scratch[local] = value;
    reduce_scratch(local);
    if local == 0u {
        partials[group.y * params.groups_x + group.x] = scratch[0];
    }
}

@compute @workgroup_size(256)
fn cs_reduce(@builtin(local_invocation_index) local: u32) {
    var sum = vec4<f32>(0.0);
    for (var i = local; i < params.partial_count; i += 256u) {
        sum += partials_in[i];
    }
    scratch[local] = sum;
    reduce_scratch(local);
    if local == 0u {
        totals = scratch[0];
    }
}
