// The cost floor of a post-process pass: one fullscreen triangle whose fragment stage reads the
// input pixel under it and writes it out unchanged. Both sides are bound through Rgba8Unorm
// views of sRGB textures, so the stored bytes pass through without decoding or encoding.
// Every real post-process pass reads at least this much and writes at least this much.

@group(0) @binding(0) var source: texture_2d<f32>;

@fragment
fn fs_copy(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    return textureLoad(source, vec2<i32>(position.xy), 0);
}
