// The viewer's image blit (src/app/blit.rs): one texel load per framebuffer pixel, nearest
// neighbour, mapped from the image's placement on screen.

struct Placement {
    // Screen rectangle of the whole image, in framebuffer pixels.
    rect_min: vec2<f32>,
    rect_size: vec2<f32>,
    // The part of the image shown there, in UV.
    uv_min: vec2<f32>,
    uv_size: vec2<f32>,
    // Darkening of the pixel grid's lines, 0 for none.
    grid: f32,
};

@group(0) @binding(0) var image: texture_2d<f32>;
@group(0) @binding(1) var<uniform> placement: Placement;

// One triangle covering the viewport egui set (the visible part of the image).
@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    let corner = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    return vec4<f32>(corner * vec2<f32>(2.0, -2.0) + vec2<f32>(-1.0, 1.0), 0.0, 1.0);
}

@fragment
fn fs_main(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let size = vec2<i32>(textureDimensions(image));
    let uv = placement.uv_min
        + (position.xy - placement.rect_min) / placement.rect_size * placement.uv_size;
    let texel = clamp(vec2<i32>(floor(uv * vec2<f32>(size))), vec2<i32>(0), size - vec2<i32>(1));
    let color = textureLoad(image, texel, 0);
    // The grid: the first screen pixel row and column of every texel but the first. Written
    // as arithmetic, not a branch on the uniform (see gpu/shader.rs).
    let cell = placement.rect_size / (placement.uv_size * vec2<f32>(size));
    let inside = position.xy - placement.rect_min;
    let along = inside - floor(inside / cell) * cell;
    let edge = (along < vec2<f32>(1.0)) & (inside > vec2<f32>(1.0));
    let line = f32(edge.x | edge.y);
    return vec4<f32>(color.rgb * (1.0 - placement.grid * line), color.a);
}
