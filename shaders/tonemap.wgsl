// The tonemap pass (graph/hdr.rs), after the operators of tonemap_operators.wgsl: exposure,
// the operator, written to an sRGB target (the hardware encodes): the displayed image of a
// technique that ran on radiance.

struct Exposure {
    // x: the linear scale 2^EV
    scale: vec4<f32>,
}

@group(0) @binding(1) var<uniform> exposure: Exposure;

@group(0) @binding(0) var source: texture_2d<f32>;

@fragment
fn fs_tonemap(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let texel = textureLoad(source, vec2<i32>(position.xy), 0);
    return vec4<f32>(tonemap_radiance(texel.rgb, exposure.scale.x), texel.a);
}
