// The viewer's solid fill (src/app/blit.rs): one colour over the viewport egui set, opaque or
// (premultiplied) blended by the pipeline, without a texture (egui's own rectangles sample a
// texture per pixel, which a software rasteriser pays for on every pixel of every panel).

@group(0) @binding(0) var<uniform> color: vec4<f32>;

@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    let corner = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    return vec4<f32>(corner * vec2<f32>(2.0, -2.0) + vec2<f32>(-1.0, 1.0), 0.0, 1.0);
}

@fragment
fn fs_main() -> @location(0) vec4<f32> {
    return color;
}
