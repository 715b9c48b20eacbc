// The temporal upscaler's debug views at the output size, written through Rgba8Unorm views
// (the colours are display values). The resolve's debug variant writes one Rgba16Float image
// per frame (x: history dropped, 0 kept, 0.5 reset or off screen, 1 disocclusion; y: samples
// accumulated; z: the new samples' weight; w: reactive mask); each view draws one of its
// channels, and the motion view reads the render-size motion vectors.

struct ViewParams {
    // xy: output size, z: speed (output pixels per frame) drawn at half saturation,
    // w: the most samples the history keeps (full scale of the confidence view).
    size: vec4<f32>,
}

@group(0) @binding(0) var state: texture_2d<f32>;
@group(0) @binding(1) var motion: texture_2d<f32>;
@group(0) @binding(2) var<uniform> view: ViewParams;

struct Varying {
    @builtin(position) position: vec4<f32>,
    @location(0) uv: vec2<f32>,
}

fn state_at(in: Varying) -> vec4<f32> {
    return textureLoad(state, vec2<i32>(in.position.xy), 0);
}

// Motion in output pixels per frame: red grows to the right, green downwards, both 0.5 when
// still; the further from grey, the faster (half way at `size.z`).
@fragment
fn fs_motion(in: Varying) -> @location(0) vec4<f32> {
    let dims = vec2<f32>(textureDimensions(motion));
    let texel = min(vec2<i32>(in.uv * dims), vec2<i32>(dims) - 1);
    let pixels = textureLoad(motion, texel, 0).xy * view.size.xy;
    let squashed = pixels / (length(pixels) + view.size.z);
    return vec4<f32>(0.5 + 0.5 * squashed, 0.5, 1.0);
}

// Red where a disocclusion dropped the history, blue where a reset or the screen edge did.
@fragment
fn fs_disocclusion(in: Varying) -> @location(0) vec4<f32> {
    let dropped = state_at(in).x;
    if dropped > 0.75 {
        return vec4<f32>(0.95, 0.1, 0.1, 1.0);
    }
    if dropped > 0.25 {
        return vec4<f32>(0.1, 0.3, 0.95, 1.0);
    }
    return vec4<f32>(0.08, 0.08, 0.08, 1.0);
}

// Samples accumulated: black none, white the most the history keeps.
@fragment
fn fs_confidence(in: Varying) -> @location(0) vec4<f32> {
    let level = saturate(state_at(in).y / view.size.w);
    return vec4<f32>(vec3<f32>(level), 1.0);
}

// The new samples' kernel weight this frame: black none, yellow one sample at the centre.
@fragment
fn fs_weight(in: Varying) -> @location(0) vec4<f32> {
    let w = saturate(state_at(in).z);
    return vec4<f32>(w, 0.85 * w, 0.1 * w, 1.0);
}

// The reactive mask: magenta where surfaces moving on their own lean on the current frame.
@fragment
fn fs_reactive(in: Varying) -> @location(0) vec4<f32> {
    let r = saturate(state_at(in).w);
    return vec4<f32>(0.9 * r, 0.1 * r, 0.9 * r, 1.0);
}
