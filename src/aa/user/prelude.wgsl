// aa-lab's prelude to a user technique (src/aa/user): the bindings and the functions the
// user's file may call. It is placed before the user's file, and `epilogue.wgsl` after it,
// so that errors in the user's code keep their own line numbers once this file's lines are
// subtracted. Every name aa-lab defines starts with `aa_`.

struct AaFrameInfo {
    // x: frame number of the deterministic camera; yzw: unused.
    frame: vec4<u32>,
    // x: the factor 2^EV of the frame's exposure (1 on the LDR path); yzw: unused.
    exposure: vec4<f32>,
}

// The 1x scene render through its sRGB view: reads decode to linear light.
@group(0) @binding(0) var aa_scene_color: texture_2d<f32>;
@group(0) @binding(1) var aa_scene_depth: texture_depth_2d;
// Motion vectors in UV units (current minus previous position); a 1x1 zero texture when the
// user's code never calls aa_motion (then the shared 1x render is read, which has none).
@group(0) @binding(2) var aa_scene_motion: texture_2d<f32>;
@group(0) @binding(3) var aa_bilinear: sampler;
@group(0) @binding(4) var<uniform> aa_frame_info: AaFrameInfo;

// Output size in pixels (the scene render's size).
fn aa_size() -> vec2<u32> {
    return textureDimensions(aa_scene_color);
}

fn aa_clamp_pixel(pixel: vec2<i32>) -> vec2<i32> {
    return clamp(pixel, vec2<i32>(0), vec2<i32>(aa_size()) - vec2<i32>(1));
}

// The scene's colour at a pixel, linear light, coordinates clamped to the image.
fn aa_load(pixel: vec2<i32>) -> vec4<f32> {
    return textureLoad(aa_scene_color, aa_clamp_pixel(pixel), 0);
}

// Bilinear read of the scene's colour in linear light at `uv` ((0,0) top-left corner,
// (1,1) bottom-right), clamped to the edges.
fn aa_sample(uv: vec2<f32>) -> vec4<f32> {
    return textureSampleLevel(aa_scene_color, aa_bilinear, uv, 0.0);
}

// The depth buffer at a pixel: reverse-Z, 1 at the near plane and 0 at infinity.
fn aa_depth(pixel: vec2<i32>) -> f32 {
    return textureLoad(aa_scene_depth, aa_clamp_pixel(pixel), 0);
}

// How far the surface seen at a pixel moved on screen since the previous frame, in pixels
// (current minus previous position: it was at `pixel - aa_motion(pixel)`).
fn aa_motion(pixel: vec2<i32>) -> vec2<f32> {
    let dims = textureDimensions(aa_scene_motion);
    let at = clamp(pixel, vec2<i32>(0), vec2<i32>(dims) - vec2<i32>(1));
    return textureLoad(aa_scene_motion, at, 0).xy * vec2<f32>(aa_size());
}

// The frame number (of the deterministic camera path in the CLI, of the viewer's clock).
fn aa_frame() -> u32 {
    return aa_frame_info.frame.x;
}
