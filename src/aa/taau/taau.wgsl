// Temporal upscaler resolve: one fullscreen pass at the OUTPUT resolution that reconstructs
// each output pixel from jittered renders at the (lower or equal) render resolution,
// accumulating into an output-resolution history. The ideas follow AMD's FidelityFX Super
// Resolution 2 as its documentation describes them (written anew here):
//  1. The new samples: the 3x3 render pixels around the output pixel, each a point sample at
//     its pixel's centre minus this frame's jitter. On a still camera the samples inside the
//     output pixel count (1 each: the accumulation converges to the pixel's area average);
//     where resampling blurs the history, the samples are weighted by their distance from the
//     output pixel's centre (KERNEL: a Gaussian with the spread of one pixel, or radial
//     Lanczos-2; both scaled by the kernel width), by the same measure; at native scale in
//     full only across surfaces (where the 3x3's depths differ by more than the disocclusion
//     tolerance: on one surface the kernel blurs its texture, and it shares the estimate with
//     the pixel's own sample), and there in full wherever the pixel moves, as in TAA
//     (`spans_surfaces`, temporal.wgsl). The weighted sum is this frame's contribution and
//     the sum of weights its confidence. A wide Gaussian over the same samples (half a render
//     pixel) is the spatial estimate that fills in where the history holds too little (first
//     frame, disocclusion).
//  2. Motion: of the nearest surface (reverse-Z: largest depth) among the 3x3 render pixels, so
//     silhouettes move with the foreground.
//  3. Disocclusion: the history keeps the farthest depth of the render pixels it was written
//     from; where the nearest surface now lies behind everything the history saw at the
//     reprojected place (four texels; relative distance beyond the tolerance), that surface
//     was hidden before and the history is dropped. (The farthest against the nearest, so the
//     jitter moving the 3x3 window over a silhouette on a still camera drops nothing.)
//  4. Rectification: the history is clipped to the colour box of the 3x3 current samples
//     (clamp, YCoCg clip or variance clip), eased off where the pixel moves at the speed the
//     history was written with (thin features the current samples missed are kept, as in
//     this project's TAA).
//  5. Accumulation: the history's confidence (samples accumulated, in kernel weight) is capped
//     (fewer where reading the history between texels blurs it or the pixel moves, so the
//     history is read again next frame; fewer still on the reactive mask: surfaces moving on
//     their own) and falls off exponentially with the speed; at native scale its share
//     against one new sample falls off with the parallax (how differently the nearest and the
//     farthest surface of the 3x3 move; faster where most of the 3x3 lies on the farthest
//     surface: a silhouette over a broad background rather than strands over strands), as in
//     this project's TAA (below native the current frame's estimate reaches beyond the output
//     pixel's neighbours, and leaning on it there spread colours: docs/upscaling.md); the new
//     samples are added with their weights:
//     colour = (history * n + sum(w c)) / (n + sum(w)).
// Colour is linear (the sRGB input decodes on load, the sRGB output encodes on store). The
// output is the one render target; the history and its depth and speed are stored as storage
// textures (cheaper than render-target exports on GPUs whose output stage is narrow).

struct TaauParams {
    // xy: output size in pixels, zw: one output pixel in UV.
    output: vec4<f32>,
    // xy: render size in pixels, zw: one render pixel in UV.
    render: vec4<f32>,
    // xy: this frame's jitter in render pixels (the sample sits at the pixel centre minus it),
    // z: 1 when the history must be ignored, w: kernel width in output pixels.
    jitter: vec4<f32>,
    // x: most samples kept, y: most samples where the history read blurs most, z: variance
    // gamma, w: velocity tolerance (output pixels per frame; 0: always rectify in full).
    accumulate: vec4<f32>,
    // x: relative depth tolerance of the disocclusion test, y: reactive strength, z: the
    // confidence below which the spatial estimate fills in, w: the transparency reactive
    // mask's strength (with REACTIVE_MASK).
    guard: vec4<f32>,
    // x: 1 / the speed (output pixels per frame) over which the history's samples fall to 1/e
    // (0: no falloff), y: the same for the parallax (with PARALLAX), z: for the parallax where
    // the farthest surface is broad (0: y everywhere); w unused.
    falloff: vec4<f32>,
    // Current frame's NDC (x, y, depth) to the previous frame's clip space, camera only.
    reproject: mat4x4<f32>,
}

@group(0) @binding(0) var current: texture_2d<f32>;
@group(0) @binding(1) var depth: texture_depth_2d;
@group(0) @binding(2) var motion: texture_2d<f32>;
@group(0) @binding(3) var history: texture_2d<f32>;
@group(0) @binding(4) var history_aux: texture_2d<f32>;
@group(0) @binding(5) var bilinear: sampler;
@group(0) @binding(6) var<uniform> params: TaauParams;
// Coverage of alpha-blended surfaces at the render size (read only with REACTIVE_MASK).
@group(0) @binding(7) var transparency: texture_2d<f32>;
// The next history: colour and confidence; depth and speed (blue and alpha unused).
@group(0) @binding(8) var history_out: texture_storage_2d<rgba16float, write>;
@group(0) @binding(9) var history_aux_out: texture_storage_2d<rgba16float, write>;

// 0: bilinear history, 1: five-tap Catmull-Rom.
override HISTORY_FILTER: u32 = 1u;
// 0: none, 1: RGB clamp, 2: YCoCg clip towards the box centre, 3: YCoCg variance clip.
override RECTIFY: u32 = 3u;
// 0: Gaussian, 1: radial Lanczos-2.
override KERNEL: u32 = 0u;
// The renderer's mask of blended surfaces (after FSR 2's reactive mask) joins the derived one:
// the history keeps guard.w times their coverage fewer samples, and no velocity trust.
override REACTIVE_MASK: bool = false;
// The derived reactive mask (`reactive` above 0): the camera's own reprojection of the nearest
// surface, against its motion vector. Off, the pass skips that matrix product.
override OWN_MOTION: bool = false;
// The history also falls off with the parallax (native scale, `parallax_falloff` or
// `silhouette_falloff` above 0). A
// pipeline constant, not a test of the uniform: lavapipe recompiles a shader at every draw
// whose branches read uniforms only, and keeps every variant (tests/long_runs.rs).
override PARALLAX: bool = false;

// At native scale, the share of the kernel's estimate (against the pixel's own sample) where
// the 3x3 lies on one surface: without it a textured surface is sharper under the orbit but
// flickers more than TAA's in a slow pan (docs/upscaling.md, "The kernel on geometry only").
const SURFACE_KERNEL: f32 = 0.5;

// exp(-a d^2) with a = 6: the variance of a one-pixel box (1/12 per axis).
const BOX_SHARPNESS: f32 = 6.0;

fn to_ycocg(c: vec3<f32>) -> vec3<f32> {
    let co = 0.5 * (c.r - c.b);
    let t = c.b + co;
    let cg = 0.5 * (c.g - t);
    return vec3<f32>(t + cg, co, cg);
}

fn from_ycocg(c: vec3<f32>) -> vec3<f32> {
    let t = c.x - c.z;
    let g = c.x + c.z;
    let b = t - c.y;
    return vec3<f32>(b + 2.0 * c.y, g, b);
}

fn box_space(c: vec3<f32>) -> vec3<f32> {
    return select(c, to_ycocg(c), RECTIFY >= 2u);
}

fn from_box_space(c: vec3<f32>) -> vec3<f32> {
    return select(c, from_ycocg(c), RECTIFY >= 2u);
}

// The weight of a sample `offset` output pixels from the pixel centre.
fn kernel_weight(offset: vec2<f32>) -> f32 {
    let d = offset / params.jitter.w;
    let d2 = dot(d, d);
    if KERNEL == 1u {
        // Radial Lanczos-2 on the distance, scaled so its main lobe matches the Gaussian's
        // spread, zero beyond 2.
        let x = min(sqrt(d2) * 1.5, 2.0);
        let px = 3.14159265 * x;
        return select(sin(px) * sin(0.5 * px) / (0.5 * px * px), 1.0, x < 1e-4);
    }
    return exp(-BOX_SHARPNESS * d2);
}

// The history at `uv`: colour and confidence (the centre tap's).
fn history_at(uv: vec2<f32>) -> vec4<f32> {
    if HISTORY_FILTER == 0u {
        return textureSampleLevel(history, bilinear, uv, 0.0);
    }
    // Five bilinear taps of the 4x4 Catmull-Rom filter without its corners.
    let position = uv * params.output.xy - 0.5;
    let cell = floor(position);
    let t = position - cell;
    let t2 = t * t;
    let t3 = t2 * t;
    let w0 = -0.5 * t3 + t2 - 0.5 * t;
    let w1 = 1.5 * t3 - 2.5 * t2 + 1.0;
    let w2 = -1.5 * t3 + 2.0 * t2 + 0.5 * t;
    let w3 = 0.5 * t3 - 0.5 * t2;
    let w12 = w1 + w2;
    let one = params.output.zw;
    let at0 = (cell - 0.5) * one;
    let at12 = (cell + 0.5 + w2 / w12) * one;
    let at3 = (cell + 2.5) * one;
    let centre = textureSampleLevel(history, bilinear, at12, 0.0);
    let weighted = textureSampleLevel(history, bilinear, vec2<f32>(at12.x, at0.y), 0.0).rgb
        * (w12.x * w0.y)
        + textureSampleLevel(history, bilinear, vec2<f32>(at0.x, at12.y), 0.0).rgb
        * (w0.x * w12.y)
        + centre.rgb * (w12.x * w12.y)
        + textureSampleLevel(history, bilinear, vec2<f32>(at3.x, at12.y), 0.0).rgb
        * (w3.x * w12.y)
        + textureSampleLevel(history, bilinear, vec2<f32>(at12.x, at3.y), 0.0).rgb
        * (w12.x * w3.y);
    let total = w12.x * (w0.y + w12.y + w3.y) + w12.y * (w0.x + w3.x);
    return vec4<f32>(max(weighted / total, vec3<f32>(0.0)), centre.a);
}

// What the current frame's 3x3 render samples around an output pixel give.
struct Samples {
    // The samples inside the output pixel (box kernel): sum of colours and their count.
    box_sum: vec3<f32>,
    box_weight: f32,
    // Kernel-weighted sum of colours and the sum of weights.
    sum: vec3<f32>,
    weight: f32,
    // Wide-Gaussian sum and weight (the spatial estimate).
    wide_sum: vec3<f32>,
    wide_weight: f32,
    // Colour box in box space.
    low: vec3<f32>,
    high: vec3<f32>,
    moment1: vec3<f32>,
    moment2: vec3<f32>,
    count: f32,
    // Nearest surface: its render pixel and depth; the farthest depth.
    nearest: vec2<i32>,
    nearest_depth: f32,
    farthest_depth: f32,
    // The render pixel the 3x3 window is centred on.
    base: vec2<i32>,
    // The farthest surface's render pixel.
    farthest: vec2<i32>,
    // The share of the nine depths that lie on the farthest surface (`on_background`,
    // temporal.wgsl; with PARALLAX).
    background: f32,
}

// The factors of the sample weights along one axis, for the render pixels one before, at and
// one after the base pixel: every weight is a product of an x and a y factor (the Gaussians
// are separable, the box tests are per axis), so three evaluations per axis replace nine.
struct AxisFactors {
    // The samples' offsets from the output pixel's centre, in render pixels.
    offset: vec3<f32>,
    // Inside the output pixel (box kernel), 1 or 0.
    in_pixel: vec3<f32>,
    // The Gaussian kernel's factor (KERNEL 0).
    kernel: vec3<f32>,
    // The wide Gaussian's factor (the spatial estimate).
    wide: vec3<f32>,
    // Within the colour box's reach, 1 or 0.
    in_box: vec3<f32>,
}

fn axis_factors(base: f32, jitter: f32, centre: f32, ratio: f32, reach: f32) -> AxisFactors {
    let offset = vec3<f32>(base - 0.5, base + 0.5, base + 1.5) - jitter - centre;
    let d = offset * ratio / params.jitter.w;
    return AxisFactors(
        offset,
        select(vec3<f32>(0.0), vec3<f32>(1.0), abs(offset * ratio) < vec3<f32>(0.5)),
        exp(-BOX_SHARPNESS * d * d),
        exp(-2.0 * offset * offset),
        select(vec3<f32>(0.0), vec3<f32>(1.0), abs(offset) <= vec3<f32>(reach)),
    );
}

// Adds the render sample (`dx`, `dy`) from the base pixel (each -1, 0 or 1; `i` and `j` the
// same as indices 0..2 into the axis factors) with its depth `z`.
fn add_sample(s: ptr<function, Samples>, x: AxisFactors, y: AxisFactors, i: u32, j: u32, z: f32) {
    let pixel = (*s).base + vec2<i32>(i32(i) - 1, i32(j) - 1);
    let inside = clamp(pixel, vec2<i32>(0), vec2<i32>(params.render.xy) - 1);
    // Compressed before the tonemapper (radiance.wgsl, the prelude).
    let rgb = compressed(textureLoad(current, inside, 0).rgb);
    let inside_weight = x.in_pixel[i] * y.in_pixel[j];
    (*s).box_sum += inside_weight * rgb;
    (*s).box_weight += inside_weight;
    var w = x.kernel[i] * y.kernel[j];
    if KERNEL == 1u {
        w = kernel_weight(vec2<f32>(x.offset[i], y.offset[j]) * params.output.xy * params.render.zw);
    }
    (*s).sum += w * rgb;
    (*s).weight += w;
    let wide = x.wide[i] * y.wide[j];
    (*s).wide_sum += wide * rgb;
    (*s).wide_weight += wide;
    // The colour box: the samples within 1/2 + 1/ratio render pixels of the centre (all nine
    // at native; below it, those that can fall within about one output pixel's reach, so the
    // box stays as tight in output pixels as at native).
    // (Selects and products, not branches, so that a GPU issues the nine loads together.)
    let in_box = x.in_box[i] * y.in_box[j];
    let c = box_space(rgb);
    (*s).low = select((*s).low, min((*s).low, c), in_box > 0.0);
    (*s).high = select((*s).high, max((*s).high, c), in_box > 0.0);
    (*s).moment1 += in_box * c;
    (*s).moment2 += in_box * c * c;
    (*s).count += in_box;
    let nearer = z > (*s).nearest_depth;
    (*s).nearest_depth = select((*s).nearest_depth, z, nearer);
    (*s).nearest = select((*s).nearest, inside, nearer);
    let farther = z < (*s).farthest_depth;
    (*s).farthest = select((*s).farthest, inside, farther);
    (*s).farthest_depth = min((*s).farthest_depth, z);
}

// The 3x3 render samples around the output pixel. The depths come from four gathers, the
// 2x2 quarters of the 4x4 block whose upper-left 3x3 is the window (the sampler clamps at the
// border as the colour loads do), so nine depth loads cost four fetches; the samples are
// added in rows, left to right, so that ties pick the same nearest surface as a scan would.
fn gather_samples(centre: vec2<f32>) -> Samples {
    let jitter = params.jitter.xy;
    let ratio = params.output.xy * params.render.zw;
    let base = vec2<i32>(floor(centre + jitter));
    let zero = vec3<f32>(0.0);
    var s = Samples(
        zero, 0.0, zero, 0.0, zero, 0.0, vec3<f32>(1e9), vec3<f32>(-1e9), zero, zero, 0.0, base, -1.0, 2.0,
        base, base, 0.0,
    );
    let reach = 0.5 + 1.0 / max(ratio.x, ratio.y);
    let fb = vec2<f32>(base);
    let x = axis_factors(fb.x, jitter.x, centre.x, ratio.x, reach);
    let y = axis_factors(fb.y, jitter.y, centre.y, ratio.y, reach);
    // Gather order: (x) lower left, (y) lower right, (z) upper right, (w) upper left.
    let one = params.render.zw;
    let upper_left = textureGather(depth, bilinear, fb * one);
    let upper_right = textureGather(depth, bilinear, (fb + vec2<f32>(2.0, 0.0)) * one);
    let lower_left = textureGather(depth, bilinear, (fb + vec2<f32>(0.0, 2.0)) * one);
    let lower_right = textureGather(depth, bilinear, (fb + vec2<f32>(2.0, 2.0)) * one);
    add_sample(&s, x, y, 0u, 0u, upper_left.w);
    add_sample(&s, x, y, 1u, 0u, upper_left.z);
    add_sample(&s, x, y, 2u, 0u, upper_right.w);
    add_sample(&s, x, y, 0u, 1u, upper_left.x);
    add_sample(&s, x, y, 1u, 1u, upper_left.y);
    add_sample(&s, x, y, 2u, 1u, upper_right.x);
    add_sample(&s, x, y, 0u, 2u, lower_left.w);
    add_sample(&s, x, y, 1u, 2u, lower_left.z);
    add_sample(&s, x, y, 2u, 2u, lower_right.w);
    if PARALLAX {
        let far = s.farthest_depth;
        let on_far = on_background(upper_left.w, far) + on_background(upper_left.z, far)
            + on_background(upper_right.w, far) + on_background(upper_left.x, far)
            + on_background(upper_left.y, far) + on_background(upper_right.x, far)
            + on_background(lower_left.w, far) + on_background(lower_left.z, far)
            + on_background(lower_right.w, far);
        s.background = on_far / 9.0;
    }
    return s;
}

struct Resolved {
    colour: vec3<f32>,
    // Samples accumulated after this frame.
    confidence: f32,
    // Farthest depth around the pixel and speed (output pixels per frame), kept for the next
    // frame.
    depth: f32,
    speed: f32,
    // 0 history kept, 0.5 dropped (reset or off screen), 1 dropped (disocclusion).
    dropped: f32,
    // The new samples' weight and the reactive mask.
    weight: f32,
    reactive: f32,
}

fn resolve(position: vec2<f32>) -> Resolved {
    let uv = position * params.output.zw;
    let centre = uv * params.render.xy;
    let s = gather_samples(centre);

    // Motion of the nearest surface, in UV, and the speed in output pixels.
    let velocity = textureLoad(motion, s.nearest, 0).xy;
    let speed = length(velocity * params.output.xy);
    // The parallax: how differently the nearest and the farthest surface move, in output
    // pixels (read only where its falloff is on: at native scale).
    var parallax = 0.0;
    var parallax_rate = 0.0;
    if PARALLAX {
        let farthest_velocity = textureLoad(motion, s.farthest, 0).xy;
        parallax = length((velocity - farthest_velocity) * params.output.xy);
        // Faster where the farthest surface is broad, as in TAA (temporal.wgsl).
        parallax_rate = parallax_falloff_rate(params.falloff.y, params.falloff.z, s.background);
    }
    // The reactive mask: motion the camera does not explain (the surface moves on its own).
    var reactive = 0.0;
    if OWN_MOTION {
        let ndc = vec3<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, s.nearest_depth);
        let previous_clip = params.reproject * vec4<f32>(ndc, 1.0);
        let camera_uv =
            vec2<f32>(0.5, -0.5) * previous_clip.xy / max(previous_clip.w, 1e-12) + 0.5;
        let own_motion = length((uv - velocity - camera_uv) * params.output.xy);
        reactive = params.guard.y * saturate(own_motion);
    }
    if REACTIVE_MASK {
        let render_pixel = clamp(vec2<i32>(centre), vec2<i32>(0), vec2<i32>(params.render.xy) - 1);
        reactive = max(reactive, params.guard.w * textureLoad(transparency, render_pixel, 0).r);
    }

    let previous = uv - velocity;
    let off_screen = any(previous < vec2<f32>(0.0)) | any(previous > vec2<f32>(1.0));
    // How much reading the history between texels blurs it: 4 f (1 - f) of the fraction f
    // past a texel centre, 0 on a texel, 1 half-way (and 1 where there is no history).
    let f = fract(previous * params.output.xy - 0.5);
    let blur2 = 4.0 * f * (1.0 - f);
    let blur = select(max(blur2.x, blur2.y), 1.0, (params.jitter.z > 0.5) | off_screen);
    // This frame's estimate: on a still camera (a sharp history) the samples inside the
    // pixel, so the accumulation converges to the pixel's area average as the reference's
    // box filter does; where resampling blurs the history, the kernel's wider estimate, by the
    // same measure. The wide Gaussian is the spatial estimate.
    let spatial = s.wide_sum / s.wide_weight;
    let kernel_estimate = select(spatial, s.sum / s.weight, abs(s.weight) > 1e-4);
    let box_estimate = select(spatial, s.box_sum / s.box_weight, s.box_weight > 0.5);
    // At native scale the kernel's estimate is kept whole for geometry: where the 3x3 lies on
    // one surface (its depths within the disocclusion test's tolerance of each other) the
    // kernel only blurs the surface's texture, and the pixel's own sample takes half its place
    // (SURFACE_KERNEL); across an edge the kernel averages the geometry's aliasing. (Below
    // native the pixel often holds no sample of its own, and the spatial estimate that then
    // stands in is blurrier than the kernel's.)
    // Across surfaces a pixel that moves takes the kernel's estimate in full whatever this
    // frame's fraction, as TAA does (SETTLED_SPEED, temporal.wgsl).
    let ratio = params.output.xy * params.render.zw;
    let spans = spans_surfaces(s.nearest_depth, s.farthest_depth, params.guard.x);
    let native = all(abs(ratio - 1.0) < vec2<f32>(1e-3));
    let geometry = select(1.0, mix(SURFACE_KERNEL, 1.0, spans), native);
    let edge = select(0.0, moving_edge(spans, speed), native);
    var estimate = mix(box_estimate, kernel_estimate, max(blur * geometry, edge));
    let weight = mix(s.box_weight, max(s.weight, 0.0), blur);
    if KERNEL == 1u {
        // Lanczos' negative lobe may overshoot: keep the estimate inside the box.
        estimate = from_box_space(clamp(box_space(estimate), s.low, s.high));
    }
    var dropped = select(0.0, 0.5, (params.jitter.z > 0.5) | off_screen);
    var kept = vec3<f32>(0.0);
    var confidence = 0.0;
    if dropped == 0.0 {
        let sampled = history_at(previous);
        // Disocclusion: the four history texels around the reprojected place, gathered at
        // their shared corner (one fetch for the depths, one for the speeds).
        let texel = vec2<i32>(floor(previous * params.output.xy - 0.5));
        let corner = (vec2<f32>(texel) + 1.0) * params.output.zw;
        let depths = textureGather(0, history_aux, bilinear, corner);
        // The nearest surface now lies behind the farthest one the history saw there.
        let farthest_before = min(min(depths.x, depths.y), min(depths.z, depths.w));
        let revealed = behind(s.nearest_depth, farthest_before);
        // The speed of the texel the reprojected place lies in (one of the four: gather
        // order lower left, lower right, upper right, upper left).
        let speeds = textureGather(1, history_aux, bilinear, corner);
        let right = vec2<i32>(previous * params.output.xy) - texel == vec2<i32>(1);
        let here = select(select(speeds.w, speeds.z, right.x), select(speeds.x, speeds.y, right.x), right.y);
        if revealed > params.guard.x {
            dropped = 1.0;
        } else {
            // Rectification.
            let reprojected = sampled.rgb;
            var clipped = reprojected;
            if RECTIFY == 1u {
                clipped = clamp(reprojected, s.low, s.high);
            } else if RECTIFY >= 2u {
                var low = s.low;
                var high = s.high;
                if RECTIFY == 3u {
                    let mean = s.moment1 / s.count;
                    let sigma = sqrt(max(s.moment2 / s.count - mean * mean, vec3<f32>(0.0)));
                    low = max(mean - params.accumulate.z * sigma, s.low);
                    high = min(mean + params.accumulate.z * sigma, s.high);
                }
                let middle = 0.5 * (low + high);
                let extent = max(0.5 * (high - low), vec3<f32>(1e-6));
                let offset = to_ycocg(reprojected) - middle;
                let units = abs(offset / extent);
                let largest = max(units.x, max(units.y, units.z));
                clipped = from_ycocg(middle + offset / max(largest, 1.0));
            }
            // Thin features: where the content moves as it did, trust the history.
            let tolerance = params.accumulate.w;
            var trust = select(
                0.0,
                saturate(1.0 - abs(speed - here) / max(tolerance, 1e-6)),
                tolerance > 0.0,
            );
            if REACTIVE_MASK {
                trust *= 1.0 - reactive;
            }
            kept = mix(clipped, reprojected, trust);
            // Reading between texels blurs the history: keep fewer samples the more it does.
            // A moving pixel keeps the fewer samples whatever this frame's fraction: a read that
            // lands near a texel now leaves a long history that the next frames' reads blur
            // again, each generation a little more (at a render scale, where each frame adds
            // fewer samples, the history outlives more reads).
            let moving = max(blur, saturate(speed / SETTLED_SPEED));
            let cap = mix(params.accumulate.x, min(params.accumulate.y, params.accumulate.x), moving);
            // The faster the pixel moves, the fewer samples the history keeps. At native scale
            // the faster its surfaces part, the smaller the history's share against one new
            // sample, as TAA's: n / (n + 1) becomes F n / (n + 1), so six samples fall off as
            // fast as one (scaling n by F instead left a long history most of its share where
            // the surfaces part: docs/upscaling.md).
            let parting = exp(-parallax * parallax_rate);
            let held = min(sampled.a, cap) * (1.0 - reactive) * exp(-speed * params.falloff.x);
            confidence = held * parting / (1.0 + held * (1.0 - parting));
        }
    }
    // Where the history and the new samples together hold too little, the spatial estimate
    // fills in up to the floor.
    let fill = max(params.guard.z - confidence - weight, 0.0);
    let total = confidence + weight + fill;
    let colour = (kept * confidence + estimate * weight + spatial * fill) / total;
    return Resolved(colour, total, s.farthest_depth, speed, dropped, weight, reactive);
}

struct Varying {
    @builtin(position) position: vec4<f32>,
    @location(0) uv: vec2<f32>,
}

// Resolves the pixel at `position`, stores its history and returns its output colour.
fn resolve_and_store(position: vec2<f32>) -> Resolved {
    let r = resolve(position);
    let pixel = vec2<i32>(position);
    textureStore(history_out, pixel, vec4<f32>(r.colour, r.confidence));
    textureStore(history_aux_out, pixel, vec4<f32>(r.depth, r.speed, 0.0, 0.0));
    return r;
}

@fragment
fn fs_resolve(in: Varying) -> @location(0) vec4<f32> {
    let r = resolve_and_store(in.position.xy);
    return vec4<f32>(to_output(r.colour), 1.0);
}

struct ResolveDebugOutput {
    @location(0) colour: vec4<f32>,
    // x: dropped (0, 0.5 reset or off screen, 1 disocclusion), y: confidence, z: the new
    // samples' weight, w: reactive mask.
    @location(1) debug: vec4<f32>,
}

@fragment
fn fs_resolve_debug(in: Varying) -> ResolveDebugOutput {
    let r = resolve_and_store(in.position.xy);
    return ResolveDebugOutput(
        vec4<f32>(to_output(r.colour), 1.0),
        vec4<f32>(r.dropped, r.confidence, r.weight, r.reactive),
    );
}
