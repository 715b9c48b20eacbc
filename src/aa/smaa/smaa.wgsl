// SMAA 1x, the three passes of Jimenez, Echevarria, Sousa and Gutierrez, "SMAA: Enhanced
// Subpixel Morphological Antialiasing" (Eurographics 2012), written for aa-lab:
//
// 1. fs_edges / fs_edges_depth: edges between each pixel and its left and top neighbours
//    (luma or colour of the sRGB-encoded image, or depth), with local contrast adaptation and
//    optional depth predication. Pixels without edges are discarded, so the stencil buffer
//    (written on pass) marks exactly the edge pixels; the next pass runs only there.
// 2. fs_weights: for each edge, search the ends of the edge run (bilinear fetches decoded by
//    the search table), classify the crossing edges at the ends and read the covered areas
//    from the area table; 45-degree staircases are handled first by the diagonal search;
//    sharp corners are blended less. Both tables are generated on the CPU (aa::smaa::lut),
//    whose module docs define the frames used here.
// 3. fs_blend: each pixel mixes with its neighbours across the edges in linear light, using
//    bilinear fetches at the blend offset.
//
// Edges (Rg8Unorm): r = edge on the pixel's left side, g = on its top side.
// Weights (Rgba8Unorm): r = share this pixel takes from the pixel above, g = share the pixel
// above takes from this one, b = share taken from the left pixel, a = share the left pixel
// takes from this one.

struct Params {
    // Image size in pixels.
    size: vec2<f32>,
    threshold: f32,
    depth_threshold: f32,
    local_contrast: f32,
    predication_threshold: f32,
    predication_scale: f32,
    predication_strength: f32,
    // Area sub-tables: horizontal edges, vertical edges, "/" and "\" diagonals.
    subsample: vec4<u32>,
    // Fraction of blending kept at detected corners.
    corner_rounding: f32,
    _pad0: f32,
    _pad1: f32,
    _pad2: f32,
}

// Edge detection: 0 compares luma, 1 the largest colour channel step.
override EDGE_MODE: u32 = 0u;
// Predicated thresholds from depth edges.
override PREDICATION: bool = false;
// Orthogonal search steps (two pixels each) per direction.
override MAX_SEARCH_STEPS: i32 = 16;
// Diagonal search steps (one pixel each) per direction; 0 disables diagonal handling.
override MAX_SEARCH_STEPS_DIAG: i32 = 8;
// Corner detection.
override CORNER_DETECTION: bool = true;

@group(0) @binding(0) var<uniform> params: Params;
// Edge pass: the scene colour through an Rgba8Unorm view (sRGB-encoded values) and depth.
@group(0) @binding(1) var color_encoded: texture_2d<f32>;
@group(0) @binding(2) var scene_depth: texture_depth_2d;
// Weight pass: edges and the two lookup tables.
@group(0) @binding(3) var edges_tex: texture_2d<f32>;
@group(0) @binding(4) var area_tex: texture_2d<f32>;
@group(0) @binding(5) var search_tex: texture_2d<f32>;
@group(0) @binding(6) var linear_sampler: sampler;
// Blend pass: the scene colour through its sRGB view (linear values), weights, motion.
@group(0) @binding(7) var color_linear: texture_2d<f32>;
@group(0) @binding(8) var weights_tex: texture_2d<f32>;
@group(0) @binding(9) var motion_tex: texture_2d<f32>;

// Area table layout (see aa::smaa::lut).
const AREA_SIZE: vec2<f32> = vec2<f32>(160.0, 560.0);
const SUBTABLE_HEIGHT: f32 = 80.0;
const ORTHO_CELL: f32 = 16.0;
const DIAG_X: i32 = 80;
const DIAG_CELL: i32 = 20;
// Search table layout: forward entries start at column 33; a stored 127 is one pixel.
const SEARCH_SIZE: vec2<i32> = vec2<i32>(64, 16);
const SEARCH_FORWARD_X: i32 = 33;
const SEARCH_UNIT: f32 = 127.0;

fn image_size() -> vec2<i32> {
    return vec2<i32>(params.size);
}

// Whether `p` lies in the image: one unsigned comparison per axis (a negative coordinate
// becomes a large unsigned one).
fn inside(p: vec2<i32>) -> bool {
    return all(vec2<u32>(p) < vec2<u32>(params.size));
}

fn clamp_pixel(p: vec2<i32>) -> vec2<i32> {
    return clamp(p, vec2<i32>(0), image_size() - 1);
}

// ---------------------------------------------------------------------------------------
// 1. Edge detection

fn encoded(p: vec2<i32>) -> vec3<f32> {
    return textureLoad(color_encoded, clamp_pixel(p), 0).rgb;
}

fn depth_at(p: vec2<i32>) -> f32 {
    return textureLoad(scene_depth, clamp_pixel(p), 0);
}

// Contrast between two sRGB-encoded colours.
fn difference(a: vec3<f32>, b: vec3<f32>) -> f32 {
    if EDGE_MODE == 1u {
        let d = abs(a - b);
        return max(max(d.r, d.g), d.b);
    }
    let luma = vec3<f32>(0.2126, 0.7152, 0.0722);
    return abs(dot(a, luma) - dot(b, luma));
}

// Thresholds for the left and top edges: with predication, raised away from depth edges and
// lowered again across them.
fn thresholds(p: vec2<i32>) -> vec2<f32> {
    if !PREDICATION {
        return vec2<f32>(params.threshold);
    }
    let d = depth_at(p);
    let delta = abs(d - vec2<f32>(depth_at(p + vec2<i32>(-1, 0)), depth_at(p + vec2<i32>(0, -1))));
    let geometric = step(vec2<f32>(params.predication_threshold), delta);
    return params.predication_scale * params.threshold * (1.0 - params.predication_strength * geometric);
}

@fragment
fn fs_edges(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(position.xy);
    let c = encoded(p);
    let left = encoded(p + vec2<i32>(-1, 0));
    let top = encoded(p + vec2<i32>(0, -1));
    let delta = vec2<f32>(difference(c, left), difference(c, top));
    var edges = step(thresholds(p), delta);
    if edges.x + edges.y == 0.0 {
        discard;
    }
    // Local contrast adaptation: drop an edge when a neighbouring edge (the other side of
    // this pixel, or the far side of the left or top neighbour) is much stronger.
    let right = difference(c, encoded(p + vec2<i32>(1, 0)));
    let bottom = difference(c, encoded(p + vec2<i32>(0, 1)));
    let left2 = difference(left, encoded(p + vec2<i32>(-2, 0)));
    let top2 = difference(top, encoded(p + vec2<i32>(0, -2)));
    let strongest = max(max(max(delta.x, delta.y), max(right, bottom)), max(left2, top2));
    edges *= step(vec2<f32>(strongest), params.local_contrast * delta);
    if edges.x + edges.y == 0.0 {
        discard;
    }
    return vec4<f32>(edges, 0.0, 1.0);
}

@fragment
fn fs_edges_depth(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(position.xy);
    let d = depth_at(p);
    let delta = abs(d - vec2<f32>(depth_at(p + vec2<i32>(-1, 0)), depth_at(p + vec2<i32>(0, -1))));
    let edges = step(vec2<f32>(params.depth_threshold), delta);
    if edges.x + edges.y == 0.0 {
        discard;
    }
    return vec4<f32>(edges, 0.0, 1.0);
}

// ---------------------------------------------------------------------------------------
// 2. Blending weights

// Edges of a pixel; none outside the image (a select, not a branch, so that a GPU issues the
// loads of a function together; an out-of-bounds load returns some texel or zero in WGSL, and
// the select discards it, so the coordinate needs no clamp).
fn edge_at(p: vec2<i32>) -> vec2<f32> {
    return select(vec2<f32>(0.0), textureLoad(edges_tex, p, 0).rg, inside(p));
}

fn has(e: f32) -> i32 {
    return select(0, 1, e > 0.5);
}

// The frame of an orthogonal edge run: `along` the edge, `across` towards the pixel on the
// other side of it, and which channel holds the followed edges (the other holds crossings).
struct Axis {
    along: vec2<i32>,
    across: vec2<i32>,
    edge: u32,
}

fn channel(e: vec2<f32>, c: u32) -> f32 {
    return select(e.x, e.y, c == 1u);
}

// How many pixels of the last fetch still belong to the run (search table).
fn search_length(e: vec2<f32>, forward: bool) -> i32 {
    let edge = i32(round(e.x * 32.0));
    let crossing = i32(round(e.y * 32.0));
    let texel = vec2<i32>(crossing + select(0, SEARCH_FORWARD_X, forward), 32 - edge);
    if any(texel < vec2<i32>(0)) | any(texel >= SEARCH_SIZE) {
        return 0;
    }
    return i32(round(textureLoad(search_tex, texel, 0).r * 255.0 / SEARCH_UNIT));
}

// The last pixel of the run through `p` in direction `dir`. Each step is one bilinear fetch
// covering the near pixel and the far one (two pixels per step) in this row and the row
// across: (followed edges, crossing edges), weights 21/7/3/1 out of 32. The step count is
// bounded by the image border up front and the fetch position advances by a fixed stride, so
// the loop does the fetch and one test per step.
fn search(p: vec2<i32>, dir: vec2<i32>, axis: Axis, forward: bool) -> vec2<i32> {
    let q = select(p, p + dir, forward);
    if !inside(q) {
        return p;
    }
    let room = max(dir, vec2<i32>(0)) * (image_size() - 1 - q) + max(-dir, vec2<i32>(0)) * q;
    let steps = min(MAX_SEARCH_STEPS, (room.x + room.y) / 2 + 1);
    let texel = 1.0 / params.size;
    let first = (vec2<f32>(q) + 0.5 + 0.25 * vec2<f32>(dir) + 0.125 * vec2<f32>(axis.across)) * texel;
    let stride = 2.0 * vec2<f32>(dir) * texel;
    var e = vec2<f32>(1.0, 0.0);
    var i = 0;
    loop {
        let pair = textureSampleLevel(edges_tex, linear_sampler, first + f32(i) * stride, 0.0).rg;
        e = vec2<f32>(channel(pair, axis.edge), channel(pair, 1u - axis.edge));
        i++;
        // Stop unless both pixels carry the edge (21 + 7 out of 32) and nothing crosses it.
        if (i >= steps) | (e.x < 0.8281) | (e.y > 0.0) {
            break;
        }
    }
    return clamp_pixel(q + (2 * (i - 1) + search_length(e, forward) - 1) * dir);
}

// Cell of the crossing edges at the boundary before pixel `b` (along the run): 3 * crossing
// in this row + crossing in the row across, read by one bilinear fetch a quarter pixel
// towards the row across (3/4 of this row's edge + 1/4 of the other's: 4 x the cell). Outside
// the image nothing crosses; where the row across is outside, the clamped fetch read this
// row twice.
fn crossing_cell(b: vec2<i32>, axis: Axis) -> i32 {
    let at = vec2<f32>(b) + 0.5 + 0.25 * vec2<f32>(axis.across);
    let e = textureSampleLevel(edges_tex, linear_sampler, at / params.size, 0.0).rg;
    let code = i32(round(4.0 * channel(e, 1u - axis.edge)));
    let across_outside = select(code - code / 4, code, inside(b + axis.across));
    return select(0, across_outside, inside(b));
}

fn area_ortho(distance: vec2<f32>, cells: vec2<i32>, subtable: u32) -> vec2<f32> {
    let texel = ORTHO_CELL * vec2<f32>(cells) + sqrt(distance) + 0.5;
    let at = vec2<f32>(texel.x, texel.y + SUBTABLE_HEIGHT * f32(subtable)) / AREA_SIZE;
    return textureSampleLevel(area_tex, linear_sampler, at, 0.0).rg;
}

// Sharp corners: where a crossing edge continues for a second pixel the outline really turns
// there, so the nearer end's blending is reduced to the rounding fraction.
fn corners(w: vec2<f32>, start: vec2<i32>, end: vec2<i32>, distance: vec2<f32>, axis: Axis) -> vec2<f32> {
    if !CORNER_DETECTION {
        return w;
    }
    let nearer = step(distance, distance.yx);
    let rounding = (1.0 - params.corner_rounding) * nearer / (nearer.x + nearer.y);
    let c = 1u - axis.edge;
    let after = end + axis.along;
    let start_sides = vec2<f32>(
        channel(edge_at(start - axis.across), c),
        channel(edge_at(start + 2 * axis.across), c),
    );
    let end_sides = vec2<f32>(
        channel(edge_at(after - axis.across), c),
        channel(edge_at(after + 2 * axis.across), c),
    );
    return w * saturate(vec2<f32>(1.0) - rounding.x * start_sides - rounding.y * end_sides);
}

fn ortho_weights(p: vec2<i32>, axis: Axis, subtable: u32) -> vec2<f32> {
    let start = search(p, -axis.along, axis, false);
    let end = search(p, axis.along, axis, true);
    let distance = vec2<f32>(f32(dot(p - start, axis.along)), f32(dot(end - p, axis.along)));
    let cells = vec2<i32>(crossing_cell(start, axis), crossing_cell(end + axis.along, axis));
    let w = area_ortho(distance, cells, subtable);
    return corners(w, start, end, distance, axis);
}

// Diagonals. Offsets are given in the frame of the "/" staircase (pixels with left and top
// edges); `mirrored` reads the "\" staircase (pixels with a top edge and a right edge) by
// mirroring x, where a left edge of the mirrored pixel is the left edge of its right neighbour.
fn diag_left(p: vec2<i32>, o: vec2<i32>, mirrored: bool) -> i32 {
    let q = select(p + o, p + vec2<i32>(1 - o.x, o.y), mirrored);
    return has(edge_at(q).x);
}

fn diag_top(p: vec2<i32>, o: vec2<i32>, mirrored: bool) -> i32 {
    let q = select(p + o, p + vec2<i32>(-o.x, o.y), mirrored);
    return has(edge_at(q).y);
}

// Whether the pixel at offset `o` is on the staircase: one fetch. Unmirrored, both edges of
// one pixel; mirrored, the top edge of pixel t and the left edge of t + (1, 0), read by one
// bilinear fetch a quarter pixel right of t's centre (3/4 of t + 1/4 of its neighbour per
// channel: the neighbour's left edge is there when 4 x red is 1 or 4, t's top edge when 4 x
// green is 3 or more).
fn on_staircase(p: vec2<i32>, o: vec2<i32>, mirrored: bool) -> bool {
    if !mirrored {
        let e = edge_at(p + o);
        return (e.x > 0.5) & (e.y > 0.5);
    }
    let t = p + vec2<i32>(-o.x, o.y);
    let at = (vec2<f32>(t) + vec2<f32>(0.75, 0.5)) / params.size;
    let e = round(4.0 * textureSampleLevel(edges_tex, linear_sampler, at, 0.0).rg);
    let right_left = (e.x == 1.0) | (e.x == 4.0);
    let both_inside = all(vec2<u32>(t) < vec2<u32>(params.size) - vec2<u32>(1u, 0u));
    return right_left & (e.y >= 3.0) & both_inside;
}

// Staircase pixels beyond `p` in direction `dir`: (count, 1 when the end was found).
fn diag_search(p: vec2<i32>, dir: vec2<i32>, mirrored: bool) -> vec2<i32> {
    for (var k = 1; k <= MAX_SEARCH_STEPS_DIAG; k++) {
        if !on_staircase(p, k * dir, mirrored) {
            return vec2<i32>(k - 1, 1);
        }
    }
    return vec2<i32>(MAX_SEARCH_STEPS_DIAG, 0);
}

fn diag_weights(p: vec2<i32>, mirrored: bool, subtable: u32) -> vec2<f32> {
    if !on_staircase(p, vec2<i32>(0), mirrored) {
        return vec2<f32>(0.0);
    }
    let near = diag_search(p, vec2<i32>(-1, 1), mirrored);
    let far = diag_search(p, vec2<i32>(1, -1), mirrored);
    let l = near.x;
    let r = far.x;
    if l + r < 2 {
        return vec2<f32>(0.0);
    }
    // How the outline continues past each end: vertical step + 2 * horizontal step.
    var near_cell = 0;
    if near.y == 1 {
        near_cell = diag_left(p, vec2<i32>(-l, l + 1), mirrored) + 2 * diag_top(p, vec2<i32>(-l - 1, l + 1), mirrored);
    }
    var far_cell = 0;
    if far.y == 1 {
        far_cell = diag_left(p, vec2<i32>(r + 1, -r - 1), mirrored) + 2 * diag_top(p, vec2<i32>(r + 1, -r), mirrored);
    }
    let texel = vec2<i32>(
        DIAG_X + DIAG_CELL * near_cell + l,
        i32(SUBTABLE_HEIGHT) * i32(subtable) + DIAG_CELL * far_cell + r,
    );
    return textureLoad(area_tex, texel, 0).rg;
}

// Whether `q` blends along a "\\" staircase, i.e. whether diag_weights(q, true, ..) is not
// zero: q is on the staircase and the run through it is two or more pixels long, since every
// such run has an area (lut.rs tests it). The length test needs two steps each way, not the
// full searches: five fetches, issued together.
fn on_blended_staircase(q: vec2<i32>) -> bool {
    let deep = MAX_SEARCH_STEPS_DIAG >= 2;
    let near1 = on_staircase(q, vec2<i32>(-1, 1), true);
    let near2 = on_staircase(q, vec2<i32>(-2, 2), true) & deep;
    let far1 = on_staircase(q, vec2<i32>(1, -1), true);
    let far2 = on_staircase(q, vec2<i32>(2, -2), true) & deep;
    let long_run = (near1 & near2) | (far1 & far2) | (near1 & far1);
    return on_staircase(q, vec2<i32>(0), true) & long_run;
}

@fragment
fn fs_weights(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(position.xy);
    let e = edge_at(p);
    var w = vec4<f32>(0.0);
    if e.y > 0.5 {
        // Staircases have top edges, so they are looked for here; when one is found the
        // pixel is blended along it only.
        if MAX_SEARCH_STEPS_DIAG > 0 {
            let diagonal = diag_weights(p, false, params.subsample.z) + diag_weights(p, true, params.subsample.w);
            if diagonal.x + diagonal.y > 0.0 {
                return vec4<f32>(diagonal, 0.0, 0.0);
            }
        }
        w = vec4<f32>(ortho_weights(p, Axis(vec2<i32>(1, 0), vec2<i32>(0, -1), 1u), params.subsample.x), 0.0, 0.0);
    }
    if e.x > 0.5 {
        // On a "\\" staircase the left edge belongs to the step of the left neighbour, which
        // blends along the diagonal; this pixel gets its share from the staircase pixel below.
        let on_diagonal = MAX_SEARCH_STEPS_DIAG > 0 && on_blended_staircase(p - vec2<i32>(1, 0));
        if !on_diagonal {
            w = vec4<f32>(w.xy, ortho_weights(p, Axis(vec2<i32>(0, 1), vec2<i32>(-1, 0), 0u), params.subsample.y));
        }
    }
    return w;
}

// ---------------------------------------------------------------------------------------
// 3. Neighbourhood blending

fn weights_at(p: vec2<i32>) -> vec4<f32> {
    if !inside(p) {
        return vec4<f32>(0.0);
    }
    return textureLoad(weights_tex, p, 0);
}

fn blended(p: vec2<i32>) -> vec3<f32> {
    let here = weights_at(p);
    // Shares taken from above, below, left and right.
    let up = here.r;
    let down = weights_at(p + vec2<i32>(0, 1)).g;
    let left = here.b;
    let right = weights_at(p + vec2<i32>(1, 0)).a;
    if up + down + left + right < 1e-5 {
        return textureLoad(color_linear, p, 0).rgb;
    }
    // One axis only: the one with the larger share.
    var towards = vec4<f32>(0.0, down, 0.0, -up);
    var share = vec2<f32>(down, up);
    if max(left, right) > max(up, down) {
        towards = vec4<f32>(right, 0.0, -left, 0.0);
        share = vec2<f32>(right, left);
    }
    share /= share.x + share.y;
    // A bilinear fetch a fraction f of a pixel towards a neighbour mixes in f of it.
    let centre = vec2<f32>(p) + 0.5;
    let a = textureSampleLevel(color_linear, linear_sampler, (centre + towards.xy) / params.size, 0.0).rgb;
    let b = textureSampleLevel(color_linear, linear_sampler, (centre + towards.zw) / params.size, 0.0).rgb;
    return share.x * a + share.y * b;
}

@fragment
fn fs_blend(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(blended(vec2<i32>(position.xy)), 1.0);
}

// T2x: alpha keeps the pixel's speed (sqrt(5 |motion|), motion in UV units) for the temporal
// resolve's velocity weighting.
@fragment
fn fs_blend_velocity(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(position.xy);
    let motion = textureLoad(motion_tex, p, 0).xy;
    return vec4<f32>(blended(p), sqrt(5.0 * length(motion)));
}
