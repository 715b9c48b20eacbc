// Composites the user-interface overlay (straight alpha, sRGB texture read as linear) over a
// target: the pipeline blends it in linear light, so the target keeps its colour where the
// overlay is transparent. The overlay is sampled at the target's UV, so a target rendered
// below the output size (a render scale) gets the overlay filtered down to its pixels.

@group(0) @binding(0) var overlay: texture_2d<f32>;
@group(0) @binding(1) var overlay_sampler: sampler;

@fragment
fn fs_overlay(@location(0) uv: vec2<f32>) -> @location(0) vec4<f32> {
    return textureSampleLevel(overlay, overlay_sampler, uv, 0.0);
}
