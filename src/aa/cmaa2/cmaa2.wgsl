// CMAA 2 (Conservative Morphological Anti-Aliasing 2.0, Filip Strugar and Adam T. Lake, Intel,
// 2018), aa-lab's own port of its ideas and parameters. Entry points, in frame order:
// - cs_edges: one thread per pixel finds the pixel's four edges (local contrast adaptation
//   drops an edge that a stronger edge touching its ends dominates), stores them packed and
//   appends the pixel to the shape candidates when two of its edges meet in a corner;
// - cs_candidate_args: the indirect dispatch size of the next pass from the candidate count;
// - cs_process: one thread per candidate: the simple-shape (corner) blend of the pixel itself,
//   then Z-shape detection, tracing of the two edge runs and a blend ramp along them; every
//   blended colour is added to its pixel's sums (fixed point, atomic, so the result does not
//   depend on thread order);
// - fs_debug_edges / fs_debug_blends: the debug views (before the apply clears the sums);
// - fs_apply: a fullscreen pass: a pixel with blends gets their weighted average and its sums
//   cleared for the next frame, every other pixel passes through unchanged.
// Edges are found on the sRGB-encoded values (binding 0), colours are blended in linear light
// (binding 1, the sRGB view) and encoded again by the apply pass.
// With RADIANCE (CMAA 2 before the tonemapper of an HDR frame, aa::common::perceptual) binding
// 0 is the perceptual copy of the radiance (Karis-compressed, encoded: the thresholds keep
// their meaning), binding 1 the radiance, which the blends mix; a pixel's blends are summed
// Karis-weighted, compressed to c / (1 + max channel) (below 1, as the fixed-point sums need),
// and their average is expanded back to radiance, which the apply pass writes unencoded.

override RADIANCE: bool = false;

struct Params {
    // width, height, pixel count (the capacity of the candidate list), unused
    size: vec4<u32>,
    // edge threshold, local contrast adaptation amount, colour edges (0 luma, 1 colour), unused
    edges: vec4<f32>,
    // simple-shape blur amount, neighbour-edge damping base and divisor, round shape quality
    shapes: vec4<f32>,
    // run length ratio that stops the trace, Z blend damping per pixel of run, unused, unused
    lines: vec4<f32>,
}

@group(0) @binding(0) var color_encoded: texture_2d<f32>;
@group(0) @binding(1) var color_linear: texture_2d<f32>;
@group(0) @binding(2) var<uniform> params: Params;
// Per pixel: bit 0 right, 1 bottom, 2 left, 3 top edge.
@group(0) @binding(3) var<storage, read_write> edges: array<u32>;
// Candidate pixels, x << 16 | y.
@group(0) @binding(4) var<storage, read_write> candidates: array<u32>;
// 0 candidates found (cleared once counted), 1 candidates to process.
@group(0) @binding(5) var<storage, read_write> control: array<atomic<u32>>;
// Per pixel: red, green, blue sums (linear, times COLOR_SCALE, times the weight) and the
// weight sum in the low bits with the number of Z-shape blends from bit Z_SHIFT.
@group(0) @binding(6) var<storage, read_write> sums: array<atomic<u32>>;
// Indirect dispatch arguments (x, y, z) of cs_process.
@group(0) @binding(7) var<storage, read_write> indirect: array<u32>;

const LUMA_WEIGHTS = vec3<f32>(0.299, 0.587, 0.114);
// Longest edge run the Z-shape trace follows per side (Intel's value).
const MAX_LINE_LENGTH: i32 = 86;
// Most pixels one Z-shape blends: half of each traced side plus the ends.
const MAX_Z_PIXELS: i32 = 90;
// Offset that shortens a run of odd length in the blend ramp (Intel's symmetry correction).
const SYMMETRY_CORRECTION = 0.22;
const PROCESS_GROUP: u32 = 64u;
const COLOR_SCALE = 65535.0;
// Weights of the blends in a pixel's average: a Z-shape ramp counts three times a corner blend.
const SIMPLE_WEIGHT: u32 = 1u;
const Z_WEIGHT: u32 = 3u;
const Z_SHIFT: u32 = 20u;
const WEIGHT_MASK: u32 = 0xFFFFFu;

fn image_size() -> vec2<i32> {
    return vec2<i32>(params.size.xy);
}

fn inside(p: vec2<i32>) -> bool {
    return all(p >= vec2<i32>(0)) & all(p < image_size());
}

fn clamped(p: vec2<i32>) -> vec2<i32> {
    return clamp(p, vec2<i32>(0), image_size() - vec2<i32>(1));
}

fn pixel_index(p: vec2<i32>) -> u32 {
    let c = clamped(p);
    return u32(c.y) * params.size.x + u32(c.x);
}

fn pack_pixel(p: vec2<i32>) -> u32 {
    return (u32(p.x) << 16u) | u32(p.y);
}

fn unpack_pixel(packed: u32) -> vec2<i32> {
    return vec2<i32>(i32(packed >> 16u), i32(packed & 0xFFFFu));
}

fn encoded(p: vec2<i32>) -> vec3<f32> {
    return textureLoad(color_encoded, clamped(p), 0).rgb;
}

fn linear(p: vec2<i32>) -> vec3<f32> {
    return textureLoad(color_linear, clamped(p), 0).rgb;
}

// ---------------------------------------------------------------------------------------------
// Edge detection

// How different two neighbours look: the difference of their luma, or the luma-weighted sum of
// their channel differences (colour edges), on sRGB-encoded values.
fn contrast(a: vec3<f32>, b: vec3<f32>) -> f32 {
    let luma = abs(dot(a - b, LUMA_WEIGHTS));
    let color = dot(abs(a - b), LUMA_WEIGHTS);
    return select(luma, color, params.edges.z > 0.5);
}

// The 3x3 neighbourhood of a pixel, row by row (the image border repeats).
struct Neighbourhood {
    c: array<vec3<f32>, 9>,
}

fn at(n: ptr<function, Neighbourhood>, x: i32, y: i32) -> vec3<f32> {
    return (*n).c[(x + 1) + (y + 1) * 3];
}

fn across_x(n: ptr<function, Neighbourhood>, x: i32, y: i32) -> f32 {
    return contrast(at(n, x, y), at(n, x + 1, y));
}

fn across_y(n: ptr<function, Neighbourhood>, x: i32, y: i32) -> f32 {
    return contrast(at(n, x, y), at(n, x, y + 1));
}

fn is_edge(difference: f32, strongest_neighbour: f32) -> f32 {
    let adapted = difference - strongest_neighbour * params.edges.y;
    return select(0.0, 1.0, adapted > params.edges.x);
}

// The edge between (x, y) and (x + 1, y), against the four edges that touch its ends.
fn vertical_edge(n: ptr<function, Neighbourhood>, x: i32, y: i32) -> f32 {
    let touching = max(
        max(across_y(n, x, y - 1), across_y(n, x, y)),
        max(across_y(n, x + 1, y - 1), across_y(n, x + 1, y)),
    );
    return is_edge(across_x(n, x, y), touching);
}

// The edge between (x, y) and (x, y + 1), against the four edges that touch its ends.
fn horizontal_edge(n: ptr<function, Neighbourhood>, x: i32, y: i32) -> f32 {
    let touching = max(
        max(across_x(n, x - 1, y), across_x(n, x, y)),
        max(across_x(n, x - 1, y + 1), across_x(n, x, y + 1)),
    );
    return is_edge(across_y(n, x, y), touching);
}

@compute @workgroup_size(8, 8)
fn cs_edges(@builtin(global_invocation_id) id: vec3<u32>) {
    let p = vec2<i32>(id.xy);
    if !inside(p) {
        return;
    }
    var n: Neighbourhood;
    for (var i = 0; i < 9; i++) {
        n.c[i] = encoded(p + vec2<i32>(i % 3 - 1, i / 3 - 1));
    }
    // Each edge is computed with the same expression by both pixels it separates.
    let e = vec4<f32>(
        vertical_edge(&n, 0, 0),
        horizontal_edge(&n, 0, 0),
        vertical_edge(&n, -1, 0),
        horizontal_edge(&n, 0, -1),
    );
    let bits = vec4<u32>(e) << vec4<u32>(0u, 1u, 2u, 3u);
    edges[pixel_index(p)] = bits.x | bits.y | bits.z | bits.w;
    let corners = e.x * e.y + e.y * e.z + e.z * e.w + e.w * e.x;
    if corners > 0.0 {
        let slot = atomicAdd(&control[0], 1u);
        if slot < params.size.z {
            candidates[slot] = pack_pixel(p);
        }
    }
}

@compute @workgroup_size(1)
fn cs_candidate_args() {
    let count = min(atomicLoad(&control[0]), params.size.z);
    atomicStore(&control[1], count);
    // The edge pass of the next frame counts from zero.
    atomicStore(&control[0], 0u);
    indirect[0] = (count + PROCESS_GROUP - 1u) / PROCESS_GROUP;
    indirect[1] = 1u;
    indirect[2] = 1u;
}

// ---------------------------------------------------------------------------------------------
// Shape processing

fn edge_bits(p: vec2<i32>) -> u32 {
    return select(0u, edges[pixel_index(p)], inside(p));
}

// (right, bottom, left, top) as 0 or 1; nothing outside the image.
fn edges_at(p: vec2<i32>) -> vec4<f32> {
    let bits = vec4<u32>(edge_bits(p)) >> vec4<u32>(0u, 1u, 2u, 3u);
    return vec4<f32>(bits & vec4<u32>(1u));
}

fn max_channel(c: vec3<f32>) -> f32 {
    return max(c.x, max(c.y, c.z));
}

// A blended colour as the sums hold it: display values clamped to [0, 1], or radiance
// compressed (Karis' weighting in its max-channel form).
fn to_sum(color: vec3<f32>) -> vec3<f32> {
    let c = max(color, vec3<f32>(0.0));
    return select(saturate(color), c / (1.0 + max_channel(c)), RADIANCE);
}

// The average of a pixel's sums as a colour: `to_sum` reversed.
fn from_sum(average: vec3<f32>) -> vec3<f32> {
    return select(average, average / max(1.0 - max_channel(average), 1e-3), RADIANCE);
}

// Adds one blended colour to a pixel's sums.
fn add_blend(p: vec2<i32>, color: vec3<f32>, weight: u32) {
    if !inside(p) {
        return;
    }
    let base = 4u * pixel_index(p);
    let fixed = vec3<u32>(to_sum(color) * COLOR_SCALE + 0.5) * (weight & WEIGHT_MASK);
    atomicAdd(&sums[base], fixed.x);
    atomicAdd(&sums[base + 1u], fixed.y);
    atomicAdd(&sums[base + 2u], fixed.z);
    atomicAdd(&sums[base + 3u], weight);
}

// The corner blend of a candidate: weights towards (left, top, right, bottom). A pixel blends
// towards the sides it has edges on; an L corner also leans along an edge that continues past
// the corner in a neighbour; many edges around (text, texture) damp it.
fn simple_shape_weights(e: vec4<f32>, l: vec4<f32>, r: vec4<f32>, t: vec4<f32>, b: vec4<f32>) -> vec4<f32> {
    let edge_count = dot(e, vec4<f32>(1.0));
    let around = dot(l.yzw, vec3<f32>(1.0)) + dot(r.xyw, vec3<f32>(1.0))
        + dot(t.xzw, vec3<f32>(1.0)) + dot(b.xyz, vec3<f32>(1.0));
    let corner = select(0.0, 1.0, edge_count == 2.0);
    let lean = 0.85 * corner;
    let from_right = e.x + lean * (e.y * t.x * (1.0 - l.y) + e.w * b.x * (1.0 - l.w));
    let from_below = e.y + lean * (e.z * r.y * (1.0 - t.z) + e.x * l.y * (1.0 - t.x));
    let from_left = e.z + lean * (e.w * b.z * (1.0 - r.w) + e.y * t.z * (1.0 - r.y));
    let from_above = e.w + lean * (e.x * l.w * (1.0 - b.x) + e.z * r.w * (1.0 - b.z));
    let damping = saturate(params.shapes.y - around / params.shapes.z);
    let blur = params.shapes.x * mix(1.0, 0.7, corner) * damping;
    return vec4<f32>(from_left, from_above, from_right, from_below) * blur;
}

// Scores of the two Z shapes along a horizontal edge through the pixel, from its edges and
// those of its left neighbour (m1) and the two pixels to its right (p1, p2): the inverted Z
// (bottom edge on the left, top edge on the right of the step) and the normal Z.
fn z_scores(e: vec4<f32>, m1: vec4<f32>, p1: vec4<f32>, p2: vec4<f32>) -> vec2<f32> {
    let inverted = e.x * e.y * p1.w
        * (2.0 + (m1.y + p2.w) - (e.w + p1.y) - 0.7 * (p2.y + m1.w + e.z + p1.x));
    let normal = e.x * e.w * p1.y
        * (2.0 + (m1.w + p2.y) - (e.y + p1.w) - 0.7 * (p2.w + m1.y + e.z + p1.x));
    return vec2<f32>(inverted, normal);
}

// Lengths of the two edge runs of a Z shape at `p`: backwards along -step the pixels that have
// `mask_back`, forwards from the next pixel those with `mask_ahead`. The longer run is cut
// when it grows well past the shorter one, so a step is blended symmetrically.
fn run_lengths(p: vec2<i32>, step: vec2<i32>, mask_back: u32, mask_ahead: u32) -> vec2<f32> {
    var back = 1.0;
    var ahead = 1.0;
    var going_back = true;
    var going_ahead = true;
    let ratio = params.lines.x;
    let longest_allowed = f32(MAX_LINE_LENGTH);
    for (var i = 0; i < MAX_LINE_LENGTH; i++) {
        let behind = edge_bits(p - step * i32(back));
        let before = edge_bits(p + step * (i32(ahead) + 1));
        going_back = going_back & ((behind & mask_back) != 0u);
        going_ahead = going_ahead & ((before & mask_ahead) != 0u);
        back += select(0.0, 1.0, going_back);
        ahead += select(0.0, 1.0, going_ahead);
        let stopped = !going_back & !going_ahead;
        let longest = select(max(back, ahead), longest_allowed, stopped);
        if longest >= min(longest_allowed, ratio * min(back, ahead) - (ratio - 1.0)) {
            break;
        }
    }
    return vec2<f32>(back, ahead);
}

// The blend ramp of a Z shape: pixels from the middle of the back run to the middle of the
// ahead run mix with their neighbour across the edge, most at the step, least at the ends.
fn blend_z(p: vec2<i32>, step: vec2<i32>, across: vec2<i32>, lengths: vec2<f32>, shape_quality: f32) {
    let back_odd = SYMMETRY_CORRECTION * (lengths.x % 2.0);
    let ahead_odd = SYMMETRY_CORRECTION * (lengths.y % 2.0);
    let damping = saturate((lengths.x + lengths.y - shape_quality) * params.lines.y);
    let first = 1.0 - floor((lengths.x + 1.0) / 2.0);
    let last = floor((lengths.y + 1.0) / 2.0);
    let k_step = 1.0 / (last - first + 1.0 - back_odd - ahead_odd);
    let k_first = (0.5 - back_odd - first) * k_step;
    for (var n = 0; n < MAX_Z_PIXELS; n++) {
        let i = first + f32(n);
        if i > last {
            break;
        }
        let ahead_part = select(0.0, 1.0, i > 0.0);
        let side = 1.0 - 2.0 * ahead_part;
        let k = ((k_step * i + k_first) * side + ahead_part) * damping;
        let pixel = p + step * i32(i);
        let mixed = mix(linear(pixel), linear(pixel + across * i32(side)), saturate(k));
        add_blend(pixel, mixed, Z_WEIGHT | (1u << Z_SHIFT));
    }
}

@compute @workgroup_size(64)
fn cs_process(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= atomicLoad(&control[1]) {
        return;
    }
    let p = unpack_pixel(candidates[id.x]);
    let e = edges_at(p);
    let l = edges_at(p + vec2<i32>(-1, 0));
    let r = edges_at(p + vec2<i32>(1, 0));
    let t = edges_at(p + vec2<i32>(0, -1));
    let b = edges_at(p + vec2<i32>(0, 1));

    // Simple shape: the corner blend of the candidate itself.
    let w = simple_shape_weights(e, l, r, t, b);
    let own = linear(p) * (1.0 - dot(w, vec4<f32>(1.0)));
    let blended_color = own + w.x * linear(p + vec2<i32>(-1, 0)) + w.y * linear(p + vec2<i32>(0, -1))
        + w.z * linear(p + vec2<i32>(1, 0)) + w.w * linear(p + vec2<i32>(0, 1));
    add_blend(p, blended_color, SIMPLE_WEIGHT);

    // Z shapes: along a horizontal edge, and along a vertical one (the same test on the edges
    // turned a quarter, with the pixels below and above as the neighbours).
    let horizontal = z_scores(e, l, r, edges_at(p + vec2<i32>(2, 0)));
    let vertical = z_scores(e.wxyz, b.wxyz, t.wxyz, edges_at(p + vec2<i32>(0, -2)).wxyz);
    let best_horizontal = max(horizontal.x, horizontal.y);
    let best_vertical = max(vertical.x, vertical.y);
    let is_vertical = best_vertical > best_horizontal;
    let scores = select(horizontal, vertical, is_vertical);
    let best = max(best_horizontal, best_vertical);
    if best <= 0.0 {
        return;
    }
    let inverted = scores.x > scores.y;
    // 0: every expected edge present, up to 3: dubious; shortens the runs.
    let quality_raw = clamp(4.0 - best, 0.0, 3.0);
    let shape_quality = select(floor(quality_raw), round(quality_raw), params.shapes.w > 0.5);
    let step = select(vec2<i32>(1, 0), vec2<i32>(0, -1), is_vertical);
    // Horizontal: the back run has top edges, the ahead run bottom edges; vertical: left and
    // right edges. An inverted Z swaps them, and blends from the other side.
    let masks = select(vec2<u32>(8u, 2u), vec2<u32>(4u, 1u), is_vertical);
    let traced = select(masks, masks.yx, inverted);
    let across_normal = select(vec2<i32>(0, -1), vec2<i32>(-1, 0), is_vertical);
    let across = select(across_normal, -across_normal, inverted);
    let lengths = run_lengths(p, step, traced.x, traced.y) - vec2<f32>(shape_quality);
    if lengths.x + lengths.y >= 5.0 {
        blend_z(p, step, across, lengths, shape_quality);
    }
}

// ---------------------------------------------------------------------------------------------
// Deferred apply and debug views

struct Sums {
    color: vec3<f32>,
    weight: u32,
    z_blends: u32,
}

fn decode_sums(raw: vec4<u32>) -> Sums {
    var s: Sums;
    s.weight = raw.w & WEIGHT_MASK;
    s.z_blends = raw.w >> Z_SHIFT;
    s.color = from_sum(vec3<f32>(raw.xyz) / (COLOR_SCALE * f32(max(s.weight, 1u))));
    return s;
}

fn encode_srgb(linear: vec3<f32>) -> vec3<f32> {
    let c = saturate(linear);
    let low = c * 12.92;
    let high = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(high, low, c <= vec3<f32>(0.0031308));
}

// Written through the output's encoded view (or, on radiance, into the half-float output):
// untouched pixels keep their exact bytes.
@fragment
fn fs_apply(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(position.xy);
    let source = select(textureLoad(color_encoded, clamped(p), 0), textureLoad(color_linear, clamped(p), 0), RADIANCE);
    let base = 4u * pixel_index(p);
    if atomicLoad(&sums[base + 3u]) == 0u {
        return source;
    }
    let raw = vec4<u32>(
        atomicExchange(&sums[base], 0u),
        atomicExchange(&sums[base + 1u], 0u),
        atomicExchange(&sums[base + 2u], 0u),
        atomicExchange(&sums[base + 3u], 0u),
    );
    let color = decode_sums(raw).color;
    return vec4<f32>(select(encode_srgb(color), color, RADIANCE), source.a);
}

fn dimmed(p: vec2<i32>) -> vec3<f32> {
    return vec3<f32>(0.1 + 0.4 * dot(encoded(p), LUMA_WEIGHTS));
}

@fragment
fn fs_debug_edges(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(position.xy);
    let e = edges_at(p);
    let across_x = max(e.x, e.z);
    let across_y = max(e.y, e.w);
    var color = dimmed(p);
    color = mix(color, vec3<f32>(1.0, 0.25, 0.1), across_x * (1.0 - across_y));
    color = mix(color, vec3<f32>(0.2, 0.9, 0.25), across_y * (1.0 - across_x));
    color = mix(color, vec3<f32>(1.0, 0.9, 0.1), across_x * across_y);
    return vec4<f32>(color, 1.0);
}

@fragment
fn fs_debug_blends(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(position.xy);
    let base = 4u * pixel_index(p);
    let s = decode_sums(vec4<u32>(
        atomicLoad(&sums[base]),
        atomicLoad(&sums[base + 1u]),
        atomicLoad(&sums[base + 2u]),
        atomicLoad(&sums[base + 3u]),
    ));
    let change = abs(s.color - linear(p));
    let amount = saturate(max(change.x, max(change.y, change.z)) * 4.0);
    let hue = select(vec3<f32>(1.0, 0.55, 0.1), vec3<f32>(0.25, 0.55, 1.0), s.z_blends > 0u);
    let touched = select(0.0, 0.35 + 0.65 * amount, s.weight > 0u);
    return vec4<f32>(mix(dimmed(p), hue, touched), 1.0);
}
