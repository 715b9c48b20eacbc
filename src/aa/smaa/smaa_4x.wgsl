// SMAA 4x's one pass of its own (aa::smaa::x4): on adapters with 2x MSAA the technique renders
// its jittered two-sample frame itself, and fs_extract_motion copies the motion vectors of the
// first sample into a single-sample target for the SMAA blend (speed in alpha) and the
// temporal resolve. Both samples of a pixel belong to the same surface almost everywhere, and
// the motion vectors exclude the jitter, so one sample's motion serves the pixel.

@group(0) @binding(0) var samples_motion: texture_multisampled_2d<f32>;

@fragment
fn fs_extract_motion(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(textureLoad(samples_motion, vec2<i32>(position.xy), 0).xy, 0.0, 0.0);
}
