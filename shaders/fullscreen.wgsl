// The vertex stage of every post-process pass: one triangle that covers the viewport,
// generated from the vertex index (no vertex buffer). `uv` is (0,0) at the top-left corner
// and (1,1) at the bottom-right; fragment stages may also use @builtin(position) for the
// pixel they shade.

struct FullscreenVarying {
    @builtin(position) position: vec4<f32>,
    @location(0) uv: vec2<f32>,
}

@vertex
fn vs_fullscreen(@builtin(vertex_index) index: u32) -> FullscreenVarying {
    let uv = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    var out: FullscreenVarying;
    out.position = vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, 0.0, 1.0);
    out.uv = uv;
    return out;
}
