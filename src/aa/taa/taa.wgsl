// Temporal antialiasing resolve, after Brian Karis ("High Quality Temporal Supersampling",
// SIGGRAPH 2014) and Marco Salvi ("An Excursion in Temporal Supersampling", GDC 2016).
//
// Every frame the scene is rendered with a different sub-pixel jitter (Halton 2,3), and this
// pass blends that one-sample image into an accumulated history:
//  1. Neighbourhood: the current colours around the pixel (3x3, or the 5-pixel cross) give the
//     colour box (min/max, mean and variance; a fragment loads its own colour and its
//     neighbours outside its 2x2 quad, and takes those inside from its quad partners' loads
//     through the fine derivatives), and the nearest surface among the pixel and its
//     neighbours (reverse-Z: largest depth; the two 2x2 quads that share the pixel, read by two
//     gathers, the 4 diagonal ones or all 8) gives the motion vector, so silhouettes carry the
//     foreground's motion; the farthest surface among them gives the parallax (step 4), and
//     the share of the depths searched that lie on it tells a silhouette over a broad
//     background from strands over other strands.
//     The current frame's contribution is either the pixel's own sample or (Gaussian
//     filter) the neighbourhood's samples weighed by exp(-a d^2) of their distance d from the
//     pixel centre (a sample sits at its pixel's centre minus the jitter; a = 6 gives the
//     variance of the pixel's box): an estimate of the pixel's area average from the reads the
//     box already makes (Karis filters the current frame the same way). The filtered estimate
//     is mixed in as far as resampling blurs the history (step 4), and in full wherever the
//     pixel moves (half a pixel per frame or more) and its depths span surfaces (an edge,
//     whose aliasing the filter averages; `spans_surfaces`, temporal.wgsl).
//  2. Reprojection: the history is read at uv - motion (the motion vectors hold no jitter) with
//     one bilinear tap or a five-tap bilinear-optimised Catmull-Rom filter (sharper; fewer taps
//     than the 4x4 cubic by dropping its corners; its overshoot is removed by the
//     rectification). History that falls off screen, or a reset (camera cut, resize, new
//     settings), leaves the current frame alone.
//  3. Rectification: the history is forced into the current neighbourhood's colour box, which
//     removes ghosts of content that has moved away: per-channel RGB clamp, clipping towards
//     the box centre in YCoCg, or clipping to the variance box mean +/- gamma * sigma in YCoCg
//     (intersected with min/max). Where the pixel's own surface moves at the speed the history
//     was written with (kept in the history's alpha), the history shows the same surface and
//     the rectification is eased off, so thin lines that this frame's jitter missed stay.
//  4. Blend: the current frame gets `current_weight`, more under motion (the resampling softens
//     the history a little every frame: the weight follows the speed, or the blur of the read
//     between texels), and more again as the history's share falls off exponentially with the
//     parallax (how differently the nearest and the farthest surface move: one motion vector
//     cannot carry both; faster where the farthest surface is broad) and with the speed;
//     optionally weighed by 1 / (1 + luminance)
//     against the history's so a lone bright sample does not flicker.
// Colour is linear (the sRGB input decodes on load, the sRGB output encodes on store); the
// history is Rgba16Float. fs_resolve writes the output and stores the history (a storage
// texture); fs_resolve_debug also writes the history-rejection mask (through an Rgba8Unorm
// view: the mask colours are display values).

struct TaaParams {
    // xy: image size in pixels, zw: one pixel in UV.
    size: vec4<f32>,
    // x: current frame weight, y: variance-clip gamma, z: 1 when the history must be ignored,
    // w: current frame weight at one pixel per frame of motion and faster.
    blend: vec4<f32>,
    // x: change of speed (pixels per frame) between the history and the current pixel at which
    // rectification applies in full (0: always in full); y: 1 to raise the current weight with
    // the blur of resampling the history (else with the speed); z: 1 to ease the trust off as
    // that blur grows; w: the reactive mask's strength (with REACTIVE_MASK). (Whose speed the
    // trust compares is TRUST_OWN_SPEED.)
    trust: vec4<f32>,
    // x: 1 / the parallax (pixels per frame) over which the history's share falls to 1/e, y: the
    // same for the speed, z: for the parallax where the farthest surface is broad (0: no
    // falloff; z 0: x everywhere).
    falloff: vec4<f32>,
    // Weights of the current frame's filter for the 3x3 taps, row by row (index 3 (dy + 1) +
    // dx + 1), normalised over the taps of the colour neighbourhood: exp(-a d^2) of each
    // sample's distance d from the pixel centre (they depend only on this frame's jitter, so
    // they are computed once per frame), or 1 for the centre tap alone (no filter).
    current_filter: array<vec4<f32>, 3>,
}

@group(0) @binding(0) var current: texture_2d<f32>;
@group(0) @binding(1) var depth: texture_depth_2d;
@group(0) @binding(2) var motion: texture_2d<f32>;
@group(0) @binding(3) var history: texture_2d<f32>;
@group(0) @binding(4) var bilinear: sampler;
@group(0) @binding(5) var<uniform> params: TaaParams;
// Coverage of alpha-blended surfaces (read only with REACTIVE_MASK).
@group(0) @binding(6) var reactive: texture_2d<f32>;
// The next history (colour and speed), stored rather than exported (see PingPong in
// aa/common/temporal.rs).
@group(0) @binding(7) var history_out: texture_storage_2d<rgba16float, write>;

// 0: bilinear history, 1: five-tap Catmull-Rom.
override HISTORY_FILTER: u32 = 1u;
// 0: none (ghosts), 1: RGB min/max clamp, 2: YCoCg clip towards the box centre,
// 3: YCoCg variance clip.
override RECTIFY: u32 = 3u;
// Karis' 1 / (1 + luminance) weighting of the blend.
override LUMA_WEIGHT: bool = true;
// Motion of the nearest surface among: 0 the pixel alone, 1 the pixel and its 4 diagonal
// neighbours, 2 the 3x3 neighbourhood, 3 the two 2x2 quads that share the pixel along its main
// diagonal (two gathers).
override VELOCITY_TAPS: u32 = 3u;
// Colour box from 0: the 3x3 neighbourhood, 1: the pixel and its 4 direct neighbours.
override NEIGHBOURHOOD: u32 = 0u;
// The velocity trust compares the speed of the pixel's own surface (one more motion read)
// instead of the nearest surface's. A constant, not a uniform, so that the read is skipped
// when it is off.
override TRUST_OWN_SPEED: bool = false;
// Reactive mask (after FSR 2's): where blended surfaces cover the pixel, the current frame's
// share rises to at least trust.w times their coverage and the velocity trust falls by it.
override REACTIVE_MASK: bool = false;

fn luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}

fn rgb_to_ycocg(c: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(
        0.25 * c.r + 0.5 * c.g + 0.25 * c.b,
        0.5 * c.r - 0.5 * c.b,
        -0.25 * c.r + 0.5 * c.g - 0.25 * c.b,
    );
}

fn ycocg_to_rgb(c: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(c.x + c.y - c.z, c.x + c.z, c.x - c.y - c.z);
}

// The space the neighbourhood box is built in.
fn to_box_space(c: vec3<f32>) -> vec3<f32> {
    if RECTIFY >= 2u {
        return rgb_to_ycocg(c);
    }
    return c;
}

fn clip_towards_center(colour: vec3<f32>, center: vec3<f32>, extent: vec3<f32>) -> vec3<f32> {
    let offset = colour - center;
    let units = abs(offset / max(extent, vec3<f32>(1e-6)));
    let largest = max(units.x, max(units.y, units.z));
    if largest > 1.0 {
        return center + offset / largest;
    }
    return colour;
}

fn catmull_rom_weights(t: vec2<f32>) -> array<vec2<f32>, 4> {
    let t2 = t * t;
    let t3 = t2 * t;
    return array<vec2<f32>, 4>(
        -0.5 * t3 + t2 - 0.5 * t,
        1.5 * t3 - 2.5 * t2 + 1.0,
        -1.5 * t3 + 2.0 * t2 + 0.5 * t,
        0.5 * t3 - 0.5 * t2,
    );
}

// The history's colour at `uv` (alpha: the speed it was written with).
fn history_at(uv: vec2<f32>) -> vec4<f32> {
    if HISTORY_FILTER == 0u {
        return textureSampleLevel(history, bilinear, uv, 0.0);
    }
    // Texel whose centre is at or left/above the sample point, and the fraction past it.
    let position = uv * params.size.xy - 0.5;
    let base = floor(position);
    let w = catmull_rom_weights(position - base);
    let middle = w[1] + w[2];
    let texel = params.size.zw;
    let before = (base - 0.5) * texel;
    let inner = (base + 0.5 + w[2] / middle) * texel;
    let after = (base + 2.5) * texel;
    // Five taps in straight-line code (no arrays: GPU compilers would put them in memory).
    let up = textureSampleLevel(history, bilinear, vec2<f32>(inner.x, before.y), 0.0).rgb;
    let left = textureSampleLevel(history, bilinear, vec2<f32>(before.x, inner.y), 0.0).rgb;
    let centre = textureSampleLevel(history, bilinear, inner, 0.0);
    let right = textureSampleLevel(history, bilinear, vec2<f32>(after.x, inner.y), 0.0).rgb;
    let down = textureSampleLevel(history, bilinear, vec2<f32>(inner.x, after.y), 0.0).rgb;
    let w_up = middle.x * w[0].y;
    let w_left = w[0].x * middle.y;
    let w_centre = middle.x * middle.y;
    let w_right = w[3].x * middle.y;
    let w_down = middle.x * w[3].y;
    let sum = w_up * up + w_left * left + w_centre * centre.rgb + w_right * right + w_down * down;
    let total = w_up + w_left + w_centre + w_right + w_down;
    // The speed is the centre tap's.
    return vec4<f32>(max(sum / total, vec3<f32>(0.0)), centre.a);
}

// The current frame's colour at a pixel, clamped to the image.
fn current_at(pixel: vec2<i32>, last: vec2<i32>) -> vec3<f32> {
    // Compressed before the tonemapper (radiance.wgsl, the prelude).
    return compressed(textureLoad(current, clamp(pixel, vec2<i32>(0), last), 0).rgb);
}

// A value of the fragment's partner across its 2x2 quad in x: the fine derivative is the odd
// column's value minus the even one's in both fragments of a row, so each gets the other's.
fn across_x(value: vec3<f32>, odd: bool) -> vec3<f32> {
    let difference = dpdxFine(value);
    return select(value + difference, value - difference, odd);
}

// The same across the quad in y.
fn across_y(value: vec3<f32>, odd: bool) -> vec3<f32> {
    let difference = dpdyFine(value);
    return select(value + difference, value - difference, odd);
}

// The current colours of the pixel's 3x3 neighbourhood, clamped at the image's border.
struct Neighbours {
    centre: vec3<f32>,
    left: vec3<f32>,
    right: vec3<f32>,
    up: vec3<f32>,
    down: vec3<f32>,
    up_left: vec3<f32>,
    up_right: vec3<f32>,
    down_left: vec3<f32>,
    down_right: vec3<f32>,
}

// Each fragment loads its own colour and its neighbours outside its 2x2 quad; the neighbours
// inside the quad are its partners' loads, exchanged through the fine derivatives: 3 texture
// loads for the 5-pixel cross instead of 5, 4 for the 3x3 block instead of 9 (the diagonals
// are only loaded for the 3x3 box). Called in uniform control flow (derivatives); a partner
// beyond the image's last row or column is a helper fragment, which loads the clamped pixel,
// as a clamped load would. Plain values, no arrays: GPU compilers keep them in registers.
fn neighbours(pixel: vec2<i32>, last: vec2<i32>) -> Neighbours {
    let odd = (pixel & vec2<i32>(1)) == vec2<i32>(1);
    // One step from the pixel away from its quad partner (an even pixel's partner is at +1).
    let outward = select(vec2<i32>(-1), vec2<i32>(1), odd);
    let own = current_at(pixel, last);
    let outside_x = current_at(pixel + vec2<i32>(outward.x, 0), last);
    let outside_y = current_at(pixel + vec2<i32>(0, outward.y), last);
    var outside_xy = vec3<f32>(0.0);
    if NEIGHBOURHOOD == 0u {
        outside_xy = current_at(pixel + outward, last);
    }
    let inside_x = across_x(own, odd.x);
    let inside_y = across_y(own, odd.y);
    // The corners: inside or outside the quad in x, then in y.
    let inside_inside = across_y(inside_x, odd.y);
    let outside_inside = across_y(outside_x, odd.y);
    let inside_outside = across_x(outside_y, odd.x);
    // The left neighbour is inside the quad for an odd column, the upper one for an odd row.
    let left_in = odd.x;
    let up_in = odd.y;
    return Neighbours(
        own,
        select(outside_x, inside_x, left_in),
        select(inside_x, outside_x, left_in),
        select(outside_y, inside_y, up_in),
        select(inside_y, outside_y, up_in),
        corner(left_in, up_in, inside_inside, outside_inside, inside_outside, outside_xy),
        corner(!left_in, up_in, inside_inside, outside_inside, inside_outside, outside_xy),
        corner(left_in, !up_in, inside_inside, outside_inside, inside_outside, outside_xy),
        corner(!left_in, !up_in, inside_inside, outside_inside, inside_outside, outside_xy),
    );
}

// One of the four corners, by whether it lies inside the quad in x and in y.
fn corner(
    x_inside: bool,
    y_inside: bool,
    inside_inside: vec3<f32>,
    outside_inside: vec3<f32>,
    inside_outside: vec3<f32>,
    outside_outside: vec3<f32>,
) -> vec3<f32> {
    return select(
        select(outside_outside, inside_outside, x_inside),
        select(outside_inside, inside_inside, x_inside),
        y_inside,
    );
}

// The colour box the history is rectified against, and the current frame's filtered estimate.
struct ColourBox {
    low: vec3<f32>,
    high: vec3<f32>,
    sum: vec3<f32>,
    sum_squares: vec3<f32>,
    count: f32,
    filtered: vec3<f32>,
}

// Adds the neighbour at 3x3 index `tap` (3 (dy + 1) + dx + 1) to the box.
fn add_tap(colour_box: ptr<function, ColourBox>, rgb: vec3<f32>, tap: u32) {
    (*colour_box).filtered += params.current_filter[tap / 4u][tap % 4u] * rgb;
    let c = to_box_space(rgb);
    (*colour_box).low = min((*colour_box).low, c);
    (*colour_box).high = max((*colour_box).high, c);
    (*colour_box).sum += c;
    (*colour_box).sum_squares += c * c;
    (*colour_box).count += 1.0;
}

// The nearest and the farthest surface (reverse-Z: largest and smallest depth) among the
// pixels searched: the nearest's motion reprojects the pixel; the two motions' difference is
// the parallax inside the neighbourhood.
struct Surfaces {
    nearest: vec2<i32>,
    near_depth: f32,
    farthest: vec2<i32>,
    far_depth: f32,
    // The share of the depths searched that lie on the farthest surface (`on_background`,
    // temporal.wgsl): high where an edge stands before a broad background, low among strands
    // over other strands.
    background: f32,
}

// The surfaces of the 2x2 quad above-left of the pixel and the one below-right, each read
// with one gather at the quad's centre (a corner of the pixel) instead of four loads; the
// clamp-to-edge sampler repeats the border pixels, as the loads' clamped coordinates do.
fn surfaces_in_quads(pixel: vec2<i32>, last: vec2<i32>) -> Surfaces {
    let corner = vec2<f32>(pixel) * params.size.zw;
    // A gather's components: (x0, y1), (x1, y1), (x1, y0), (x0, y0).
    let above = textureGather(depth, bilinear, corner);
    let below = textureGather(depth, bilinear, corner + params.size.zw);
    var s = Surfaces(pixel, above.y, pixel, above.y, 0.0);
    s = widen(s, above.x, pixel + vec2<i32>(-1, 0));
    s = widen(s, above.z, pixel + vec2<i32>(0, -1));
    s = widen(s, above.w, pixel + vec2<i32>(-1, -1));
    s = widen(s, below.x, pixel + vec2<i32>(0, 1));
    s = widen(s, below.y, pixel + vec2<i32>(1, 1));
    s = widen(s, below.z, pixel + vec2<i32>(1, 0));
    // Seven depths (the pixel's is in both quads).
    let far = s.far_depth;
    let on_far = on_background(above.x, far) + on_background(above.y, far)
        + on_background(above.z, far) + on_background(above.w, far)
        + on_background(below.x, far) + on_background(below.y, far)
        + on_background(below.z, far);
    return Surfaces(
        clamp(s.nearest, vec2<i32>(0), last),
        s.near_depth,
        clamp(s.farthest, vec2<i32>(0), last),
        s.far_depth,
        on_far / 7.0,
    );
}

// Whether the loads search the neighbour (`dx`, `dy`) for surfaces (VELOCITY_TAPS 1: the four
// diagonal ones, 2: all eight).
fn searched(dx: i32, dy: i32) -> bool {
    let diagonal = dx != 0 && dy != 0;
    return (dx != 0 || dy != 0) && (VELOCITY_TAPS == 2u || diagonal);
}

// The surfaces with the candidate at `pixel` taken in where it is nearer or farther.
fn widen(s: Surfaces, depth: f32, pixel: vec2<i32>) -> Surfaces {
    let nearer = depth > s.near_depth;
    let farther = depth < s.far_depth;
    return Surfaces(
        select(s.nearest, pixel, nearer),
        select(s.near_depth, depth, nearer),
        select(s.farthest, pixel, farther),
        select(s.far_depth, depth, farther),
        s.background,
    );
}

struct Resolved {
    colour: vec3<f32>,
    // Speed of the pixel's content in pixels per frame (kept in the history's alpha).
    speed: f32,
    // How far rectification moved the history (0 kept .. 1 replaced).
    rectified: f32,
    // The history was not used at all (reset, or reprojected off screen).
    rejected: bool,
}

fn resolve(position: vec2<f32>) -> Resolved {
    let pixel = vec2<i32>(position);
    let last = vec2<i32>(params.size.xy) - 1;

    // 1. Neighbourhood colour box and nearest surface.
    let n = neighbours(pixel, last);
    var centre = n.centre;
    let zero = vec3<f32>(0.0);
    var colour_box = ColourBox(vec3<f32>(1e9), vec3<f32>(-1e9), zero, zero, 0.0, zero);
    add_tap(&colour_box, n.up, 1u);
    add_tap(&colour_box, n.left, 3u);
    add_tap(&colour_box, n.centre, 4u);
    add_tap(&colour_box, n.right, 5u);
    add_tap(&colour_box, n.down, 7u);
    if NEIGHBOURHOOD == 0u {
        add_tap(&colour_box, n.up_left, 0u);
        add_tap(&colour_box, n.up_right, 2u);
        add_tap(&colour_box, n.down_left, 6u);
        add_tap(&colour_box, n.down_right, 8u);
    }
    let low = colour_box.low;
    let high = colour_box.high;
    var surfaces = Surfaces(pixel, 0.0, pixel, 0.0, 0.0);
    if VELOCITY_TAPS == 1u || VELOCITY_TAPS == 2u {
        let own_depth = textureLoad(depth, pixel, 0);
        surfaces = Surfaces(pixel, own_depth, pixel, own_depth, 0.0);
        for (var dy = -1; dy <= 1; dy++) {
            for (var dx = -1; dx <= 1; dx++) {
                if searched(dx, dy) {
                    let p = clamp(pixel + vec2<i32>(dx, dy), vec2<i32>(0), last);
                    surfaces = widen(surfaces, textureLoad(depth, p, 0), p);
                }
            }
        }
        // The same depths again (cached), now that the farthest is known.
        var on_far = on_background(own_depth, surfaces.far_depth);
        var count = 1.0;
        for (var dy = -1; dy <= 1; dy++) {
            for (var dx = -1; dx <= 1; dx++) {
                if searched(dx, dy) {
                    let p = clamp(pixel + vec2<i32>(dx, dy), vec2<i32>(0), last);
                    on_far += on_background(textureLoad(depth, p, 0), surfaces.far_depth);
                    count += 1.0;
                }
            }
        }
        surfaces.background = on_far / count;
    } else if VELOCITY_TAPS == 3u {
        surfaces = surfaces_in_quads(pixel, last);
    }

    // 2. Reprojection.
    let uv = (floor(position) + 0.5) * params.size.zw;
    let velocity = textureLoad(motion, surfaces.nearest, 0).xy;
    // Parallax: how differently the farthest surface around the pixel moves, in pixels per
    // frame (none with the pixel's own motion, which searches no neighbours).
    var parallax = 0.0;
    if VELOCITY_TAPS > 0u {
        let farthest_velocity = textureLoad(motion, surfaces.farthest, 0).xy;
        parallax = length((velocity - farthest_velocity) * params.size.xy);
    }
    let speed = length(velocity * params.size.xy);
    // The speed the trust test compares (and the history keeps): the pixel's own surface's.
    var own_speed = speed;
    if VELOCITY_TAPS > 0u && TRUST_OWN_SPEED {
        own_speed = length(textureLoad(motion, pixel, 0).xy * params.size.xy);
    }
    let previous = uv - velocity;
    let off_screen = any(previous < vec2<f32>(0.0)) || any(previous > vec2<f32>(1.0));
    if (params.blend.z > 0.5) | off_screen {
        return Resolved(centre, own_speed, 1.0, true);
    }
    let sampled = history_at(previous);
    let reprojected = sampled.rgb;
    // How much reading between texels blurs the history: 4 f (1 - f) of the fraction f past a
    // texel centre, 0 on a texel, 1 half-way.
    let f = fract(previous * params.size.xy - 0.5);
    let blur2 = 4.0 * f * (1.0 - f);
    let blur = max(blur2.x, blur2.y);

    // 3. Rectification.
    var kept = reprojected;
    if RECTIFY == 1u {
        kept = clamp(reprojected, low, high);
    } else if RECTIFY >= 2u {
        var box_low = low;
        var box_high = high;
        if RECTIFY == 3u {
            let mean = colour_box.sum / colour_box.count;
            let variance = colour_box.sum_squares / colour_box.count - mean * mean;
            let sigma = sqrt(max(variance, vec3<f32>(0.0)));
            box_low = max(mean - params.blend.y * sigma, low);
            box_high = min(mean + params.blend.y * sigma, high);
        }
        let clipped = clip_towards_center(
            rgb_to_ycocg(reprojected),
            0.5 * (box_low + box_high),
            0.5 * (box_high - box_low),
        );
        kept = ycocg_to_rgb(clipped);
    }
    // Velocity-weighted trust: where the content moves as it did when the history was written,
    // the history shows the same surface and rectification, which cannot tell a thin feature
    // missed by this frame's jitter from a ghost, is eased off; a change of speed (an occluder
    // moving over its background) brings it back in full.
    // Selects, not branches on the uniforms: see "Uniforms never steer control flow" in
    // gpu/shader.rs.
    let tolerance = params.trust.x;
    var trust = select(
        0.0,
        saturate(1.0 - abs(own_speed - sampled.a) / max(tolerance, 1e-6)),
        tolerance > 0.0,
    );
    // A blurred history spreads a little into its neighbours every frame; trusted, that
    // spread is never rectified away.
    trust *= select(1.0, 1.0 - blur, params.trust.z > 0.5);
    var reactive_share = 0.0;
    if REACTIVE_MASK {
        reactive_share = params.trust.w * textureLoad(reactive, pixel, 0).r;
        trust *= 1.0 - reactive_share;
    }
    kept = mix(kept, reprojected, trust);

    // 4. Blend. Motion-adaptive feedback: the current frame's share rises from blend.x towards
    // blend.w with the speed, or with how much the read between texels blurs the history (a
    // still camera and whole-pixel motion keep the history sharp; half-pixel motion softens it
    // most).
    let adapt = select(saturate(speed), blur, params.trust.y > 0.5);
    // The history's share then falls off with the parallax and with the speed.
    // The parallax falls off faster where the farthest surface is broad (temporal.wgsl).
    let parallax_rate =
        parallax_falloff_rate(params.falloff.x, params.falloff.z, surfaces.background);
    let stale = parallax * parallax_rate + speed * params.falloff.y;
    let blended = mix(params.blend.x, max(params.blend.x, params.blend.w), adapt);
    let alpha = max(1.0 - (1.0 - blended) * exp(-stale), reactive_share);
    // The current frame's estimate of the pixel: where the history stays sharp (still camera,
    // whole-pixel motion) the accumulated point samples converge to the pixel's box average and
    // the pixel's own sample is exact; where resampling blurs the history every frame it never
    // gets there, the current frame's weight rises and its point-sample noise dominates, so the
    // filtered estimate takes over by the same measure (a mix, not a branch on the uniform).
    // Across surfaces a pixel that moves takes the filtered estimate in full whatever the
    // fraction (SETTLED_SPEED, spans_surfaces: temporal.wgsl): at a moving edge the point
    // sample's aliasing is what the filter removes.
    let spans = spans_surfaces(surfaces.near_depth, surfaces.far_depth, BACKGROUND_TOLERANCE);
    centre = mix(centre, colour_box.filtered, max(adapt, moving_edge(spans, speed)));
    var colour: vec3<f32>;
    if LUMA_WEIGHT {
        let w_current = alpha / (1.0 + luminance(centre));
        let w_history = (1.0 - alpha) / (1.0 + luminance(kept));
        colour = (centre * w_current + kept * w_history) / (w_current + w_history);
    } else {
        colour = mix(kept, centre, alpha);
    }
    let moved = length(kept - reprojected);
    return Resolved(colour, own_speed, saturate(moved * 4.0), false);
}

struct Varying {
    @builtin(position) position: vec4<f32>,
    @location(0) uv: vec2<f32>,
}

// Resolves the pixel at `position` and stores its history.
fn resolve_and_store(position: vec2<f32>) -> Resolved {
    let r = resolve(position);
    textureStore(history_out, vec2<i32>(position), vec4<f32>(r.colour, r.speed));
    return r;
}

@fragment
fn fs_resolve(in: Varying) -> @location(0) vec4<f32> {
    return vec4<f32>(to_output(resolve_and_store(in.position.xy).colour), 1.0);
}

struct ResolveDebugOutput {
    @location(0) colour: vec4<f32>,
    @location(1) rejection: vec4<f32>,
}

// History-rejection mask: the result's luminance dimmed, red where the history was dropped
// (reset or off screen), yellow where rectification moved it, brighter the further.
@fragment
fn fs_resolve_debug(in: Varying) -> ResolveDebugOutput {
    let r = resolve_and_store(in.position.xy);
    let base = vec3<f32>(0.3 * sqrt(luminance(r.colour)));
    var mask = mix(base, vec3<f32>(1.0, 0.85, 0.1), r.rectified);
    if r.rejected {
        mask = vec3<f32>(0.9, 0.1, 0.1);
    }
    return ResolveDebugOutput(vec4<f32>(to_output(r.colour), 1.0), vec4<f32>(mask, 1.0));
}
