// MLAA, morphological antialiasing (Reshetov 2009) in the GPU form of Jimenez, Masia,
// Echevarria, Navarro and Gutierrez, "Practical Morphological Antialiasing" (GPU Pro 2),
// written for aa-lab. Three passes:
//
// 1. fs_edges: edges between each pixel and its left and top neighbours where the luma (or
//    largest channel) step of the sRGB-encoded image reaches the threshold. Pixels without
//    edges are discarded, so the stencil buffer (written on pass) marks the edge pixels and
//    the next pass runs only there.
// 2. fs_weights: for each edge, search both ends of its run with bilinear fetches that read
//    two pixels at once (a fetch halfway between two pixels returns 1 only when both carry
//    the edge), up to MAX_SEARCH_STEPS fetches each way; read the crossing edges at both ends
//    with one bilinear fetch each, a quarter pixel across the edge (0.75 this side + 0.25 the
//    other tells the four cases apart); look the covered areas up in the area table
//    (aa::mlaa::area, whose docs define the patterns). Orthogonal patterns only: no diagonal
//    or corner handling.
// 3. fs_blend: each pixel mixes with all four neighbours by the shares it takes from them,
//    in linear light, with bilinear fetches at the share's offset.
//
// Edges (Rg8Unorm): r = edge on the pixel's left side, g = on its top side.
// Weights (Rgba8Unorm): r = share this pixel takes from the pixel above, g = share the pixel
// above takes from this one, b = share taken from the left pixel, a = share the left pixel
// takes from this one.

struct Params {
    // Image size in pixels.
    size: vec2<f32>,
    threshold: f32,
    _pad: f32,
}

// Edge detection: 0 compares luma, 1 the largest colour channel step.
override EDGE_MODE: u32 = 0u;
// Bilinear search fetches (two pixels each) per direction.
override MAX_SEARCH_STEPS: i32 = 8;

@group(0) @binding(0) var<uniform> params: Params;
// Edge pass: the scene colour through an Rgba8Unorm view (sRGB-encoded values).
@group(0) @binding(1) var color_encoded: texture_2d<f32>;
// Weight pass: the edges (sampled bilinearly) and the area table (loaded).
@group(0) @binding(2) var edges_tex: texture_2d<f32>;
@group(0) @binding(3) var area_tex: texture_2d<f32>;
@group(0) @binding(4) var linear_sampler: sampler;
// Blend pass: the scene colour through its sRGB view (linear values) and the weights.
@group(0) @binding(5) var color_linear: texture_2d<f32>;
@group(0) @binding(6) var weights_tex: texture_2d<f32>;
// Debug views: the edges or the weights.
@group(0) @binding(7) var debug_source: texture_2d<f32>;

// Side of one area-table cell: distances 0..=32 (aa::mlaa::area::CELL).
const AREA_CELL: f32 = 33.0;

fn image_size() -> vec2<i32> {
    return vec2<i32>(params.size);
}

// ---------------------------------------------------------------------------------------
// 1. Edge detection

fn encoded(p: vec2<i32>) -> vec3<f32> {
    return textureLoad(color_encoded, clamp(p, vec2<i32>(0), image_size() - 1), 0).rgb;
}

fn difference(a: vec3<f32>, b: vec3<f32>) -> f32 {
    if EDGE_MODE == 1u {
        let d = abs(a - b);
        return max(max(d.r, d.g), d.b);
    }
    let luma = vec3<f32>(0.2126, 0.7152, 0.0722);
    return abs(dot(a, luma) - dot(b, luma));
}

@fragment
fn fs_edges(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(position.xy);
    let c = encoded(p);
    let delta = vec2<f32>(difference(c, encoded(p + vec2<i32>(-1, 0))), difference(c, encoded(p + vec2<i32>(0, -1))));
    let edges = step(vec2<f32>(params.threshold), delta);
    if edges.x + edges.y == 0.0 {
        discard;
    }
    return vec4<f32>(edges, 0.0, 1.0);
}

// ---------------------------------------------------------------------------------------
// 2. Blending weights

// Bilinear fetch of the edges at a point in pixel units.
fn edges_at(at: vec2<f32>) -> vec2<f32> {
    return textureSampleLevel(edges_tex, linear_sampler, at / params.size, 0.0).rg;
}

// Pixels from the pixel centred at `centre` to the last pixel of its edge run in direction
// `dir`, following the edge in `channel`, at most 2 * MAX_SEARCH_STEPS and never past the
// image's `room` pixels. Each fetch sits between the next two pixels: 1 when both carry the
// edge (keep going), 0.5 when only one does, 0 when neither.
fn search(centre: vec2<f32>, dir: vec2<f32>, channel: u32, room: i32) -> f32 {
    var at = centre + 1.5 * dir;
    var e = 0.0;
    var i = 0;
    for (; i < MAX_SEARCH_STEPS; i++) {
        let pair = edges_at(at);
        e = select(pair.x, pair.y, channel == 1u);
        // Below 0.9 rather than 1: bilinear weights are not exact.
        if e < 0.9 {
            break;
        }
        at += 2.0 * dir;
    }
    return min(min(2.0 * f32(i) + 2.0 * e, 2.0 * f32(MAX_SEARCH_STEPS)), f32(room));
}

// Crossing code at a run end: the crossing edges (in `channel`) of the pixel at `at`, read a
// quarter pixel towards the other side of the edge (`across`), times four: 3 for this side,
// 1 for the other, 4 both, 0 none. Nothing crosses past the image border.
fn crossing(at: vec2<f32>, across: vec2<f32>, channel: u32, inside: bool) -> f32 {
    let e = edges_at(at + 0.25 * across);
    return select(0.0, round(4.0 * select(e.x, e.y, channel == 1u)), inside);
}

fn area(distance: vec2<f32>, crossings: vec2<f32>) -> vec2<f32> {
    let texel = vec2<i32>(AREA_CELL * crossings + distance);
    return textureLoad(area_tex, texel, 0).rg;
}

// Areas for the edge on one side of pixel `p`: `along` the edge (towards its end), `across`
// towards the pixel on the other side; the followed edges are in `channel`, the crossing
// ones in the other. `before` and `after` are the pixels left in the image each way.
fn edge_weights(p: vec2<i32>, along: vec2<f32>, across: vec2<f32>, channel: u32, before: i32, after: i32) -> vec2<f32> {
    let centre = vec2<f32>(p) + 0.5;
    let d = vec2<f32>(search(centre, -along, channel, before), search(centre, along, channel, after));
    let other = 1u - channel;
    let crossings = vec2<f32>(
        crossing(centre - d.x * along, across, other, true),
        crossing(centre + (d.y + 1.0) * along, across, other, i32(d.y) < after),
    );
    return area(d, crossings);
}

@fragment
fn fs_weights(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(position.xy);
    let e = textureLoad(edges_tex, p, 0).rg;
    let last = image_size() - 1 - p;
    var w = vec4<f32>(0.0);
    if e.y > 0.5 {
        w = vec4<f32>(edge_weights(p, vec2<f32>(1.0, 0.0), vec2<f32>(0.0, -1.0), 1u, p.x, last.x), 0.0, 0.0);
    }
    if e.x > 0.5 {
        w = vec4<f32>(w.xy, edge_weights(p, vec2<f32>(0.0, 1.0), vec2<f32>(-1.0, 0.0), 0u, p.y, last.y));
    }
    return w;
}

// ---------------------------------------------------------------------------------------
// 3. Neighbourhood blending

fn weights_at(p: vec2<i32>) -> vec4<f32> {
    if any(p >= image_size()) {
        return vec4<f32>(0.0);
    }
    return textureLoad(weights_tex, p, 0);
}

@fragment
fn fs_blend(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(position.xy);
    let here = weights_at(p);
    // Shares taken from above, below, left and right.
    let share = vec4<f32>(here.r, weights_at(p + vec2<i32>(0, 1)).g, here.b, weights_at(p + vec2<i32>(1, 0)).a);
    let total = share.x + share.y + share.z + share.w;
    if total <= 0.0 {
        return vec4<f32>(textureLoad(color_linear, p, 0).rgb, 1.0);
    }
    // A bilinear fetch a fraction f of a pixel towards a neighbour mixes in f of it; the four
    // mixes are averaged by their shares.
    let centre = vec2<f32>(p) + 0.5;
    let up = textureSampleLevel(color_linear, linear_sampler, (centre - vec2<f32>(0.0, share.x)) / params.size, 0.0).rgb;
    let down = textureSampleLevel(color_linear, linear_sampler, (centre + vec2<f32>(0.0, share.y)) / params.size, 0.0).rgb;
    let left = textureSampleLevel(color_linear, linear_sampler, (centre - vec2<f32>(share.z, 0.0)) / params.size, 0.0).rgb;
    let right = textureSampleLevel(color_linear, linear_sampler, (centre + vec2<f32>(share.w, 0.0)) / params.size, 0.0).rgb;
    let mixed = share.x * up + share.y * down + share.z * left + share.w * right;
    return vec4<f32>(mixed / total, 1.0);
}

// ---------------------------------------------------------------------------------------
// Debug views

// Red: edge on the left side, green: on the top side (yellow: both), black: none.
@fragment
fn fs_debug_edges(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(textureLoad(debug_source, vec2<i32>(position.xy), 0).rg, 0.0, 1.0);
}

// Red: blending across the pixel's top edge (both ways), green: across its left edge, both
// doubled so that the common shares up to one half are visible.
@fragment
fn fs_debug_weights(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let w = textureLoad(debug_source, vec2<i32>(position.xy), 0);
    return vec4<f32>(saturate(2.0 * (w.r + w.g)), saturate(2.0 * (w.b + w.a)), 0.0, 1.0);
}
