// The edge input of SMAA, MLAA and CMAA 2 before the tonemapper of an HDR frame
// (aa::common::perceptual), compiled after radiance.wgsl with RADIANCE set: every pixel of the
// radiance is compressed with Karis' reversible tonemap c / (1 + luma) and written through an
// sRGB view, so the edge passes read the same kind of perceptual, encoded values as on the
// displayed image and their thresholds keep their meaning. The frame's exposure (x: the factor
// 2^EV) scales the radiance first, as the tonemapper does, so the edges are those of the image
// the viewer sees.

@group(0) @binding(0) var radiance_image: texture_2d<f32>;
@group(0) @binding(1) var<uniform> exposure: vec4<f32>;

@fragment
fn fs_perceptual(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let c = textureLoad(radiance_image, vec2<i32>(position.xy), 0);
    return vec4<f32>(compressed(max(c.rgb * exposure.x, vec3<f32>(0.0))), c.a);
}
