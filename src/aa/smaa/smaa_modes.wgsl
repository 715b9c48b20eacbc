// The passes around SMAA 1x that make its other modes and its debug views (aa::smaa):
// - fs_resolve: SMAA T2x's temporal resolve. The current frame's SMAA result is mixed with the
//   previous frame's, fetched where the motion vector says the pixel was; the previous frame
//   counts half, less where the pixel's speed changed (alpha of both holds sqrt(5 |motion|)).
// - fs_extract_sample: SMAA S2x on a 2x MSAA render copies one sample of colour and depth into
//   single-sample targets, so the SMAA 1x passes can run on it unchanged.
// - fs_average: the average of S2x's two per-sample results, in linear light; alpha is
//   averaged too (1 for S2x; SMAA 4x keeps the pixel's speed there for its resolve).
// - fs_debug_edges / fs_debug_weights: the edges and blending weights as viewable images.
// Compiled after radiance.wgsl (aa/common): with RADIANCE (SMAA before the tonemapper of an HDR
// frame) the resolve and the average mix Karis-compressed colours and expand the result back
// to radiance, so one very bright sample does not dominate them; without it `compressed` and
// `to_output` are the identity.

struct ResolveParams {
    // 1 when the history is valid, 0 after a reset.
    history: f32,
    // Velocity weighting scale (0 ignores velocity).
    weight_scale: f32,
    _pad: vec2<f32>,
}

// Which sample fs_extract_sample copies.
override SAMPLE_INDEX: u32 = 0u;

@group(0) @binding(0) var<uniform> resolve_params: ResolveParams;
@group(0) @binding(1) var current_tex: texture_2d<f32>;
@group(0) @binding(2) var previous_tex: texture_2d<f32>;
@group(0) @binding(3) var motion_tex: texture_2d<f32>;
@group(0) @binding(4) var linear_sampler: sampler;
@group(0) @binding(5) var samples_color: texture_multisampled_2d<f32>;
@group(0) @binding(6) var samples_depth: texture_depth_multisampled_2d;
@group(0) @binding(7) var first_tex: texture_2d<f32>;
@group(0) @binding(8) var second_tex: texture_2d<f32>;
@group(0) @binding(9) var debug_source: texture_2d<f32>;

@fragment
fn fs_resolve(@builtin(position) position: vec4<f32>, @location(0) uv: vec2<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(position.xy);
    let current = textureLoad(current_tex, p, 0);
    // Motion is uv_current - uv_previous.
    let previous_uv = uv - textureLoad(motion_tex, p, 0).xy;
    let on_screen = all(previous_uv >= vec2<f32>(0.0)) && all(previous_uv <= vec2<f32>(1.0));
    if resolve_params.history == 0.0 || !on_screen {
        return vec4<f32>(current.rgb, 1.0);
    }
    let previous = textureSampleLevel(previous_tex, linear_sampler, previous_uv, 0.0);
    // Both alphas hold sqrt(5 |v|): the difference of the squares is 5 times the change of speed.
    let speed_change = abs(current.a * current.a - previous.a * previous.a) / 5.0;
    let weight = 0.5 * saturate(1.0 - sqrt(speed_change) * resolve_params.weight_scale);
    return vec4<f32>(to_output(mix(compressed(current.rgb), compressed(previous.rgb), weight)), 1.0);
}

struct Extracted {
    @location(0) color: vec4<f32>,
    @builtin(frag_depth) depth: f32,
}

@fragment
fn fs_extract_sample(@builtin(position) position: vec4<f32>) -> Extracted {
    let p = vec2<i32>(position.xy);
    return Extracted(textureLoad(samples_color, p, SAMPLE_INDEX), textureLoad(samples_depth, p, SAMPLE_INDEX));
}

@fragment
fn fs_average(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(position.xy);
    let first = textureLoad(first_tex, p, 0);
    let second = textureLoad(second_tex, p, 0);
    return vec4<f32>(to_output(0.5 * (compressed(first.rgb) + compressed(second.rgb))), 0.5 * (first.a + second.a));
}

// Red: edge on the left side, green: on the top side (yellow: both), black: none.
@fragment
fn fs_debug_edges(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let e = textureLoad(debug_source, vec2<i32>(position.xy), 0).rg;
    return vec4<f32>(e, 0.0, 1.0);
}

// Red: blending across the pixel's top edge (both directions), green: across its left edge,
// both doubled so that the common 1/8..1/2 shares are visible.
@fragment
fn fs_debug_weights(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let w = textureLoad(debug_source, vec2<i32>(position.xy), 0);
    return vec4<f32>(saturate(2.0 * (w.r + w.g)), saturate(2.0 * (w.b + w.a)), 0.0, 1.0);
}
