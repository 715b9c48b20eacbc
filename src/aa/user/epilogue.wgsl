// aa-lab's entry points for a user technique, placed after the user's file: the fullscreen
// pass's fragment stage calls the user's aa_main for every pixel. aa_fragment writes its
// linear colour through the output's sRGB view (after the tonemapper, and in LDR frames);
// aa_fragment_radiance (before the tonemapper of an HDR frame, where aa_main read the
// exposed radiance compressed to c / (1 + luma)) expands it back to radiance with
// c / (1 - luma) and takes the exposure off again, into the half-float output that the graph
// then tonemaps (with the exposure). The expansion is `to_output` of aa/common/radiance.wgsl,
// written out here because that file's names would enter the user's namespace.
@fragment
fn aa_fragment(@builtin(position) position: vec4<f32>, @location(0) uv: vec2<f32>) -> @location(0) vec4<f32> {
    return aa_main(vec2<u32>(position.xy), uv);
}

@fragment
fn aa_fragment_radiance(@builtin(position) position: vec4<f32>, @location(0) uv: vec2<f32>) -> @location(0) vec4<f32> {
    let c = aa_main(vec2<u32>(position.xy), uv);
    let luma = dot(c.rgb, vec3<f32>(0.2126, 0.7152, 0.0722));
    return vec4<f32>(c.rgb / (max(1.0 - luma, 1e-3) * aa_frame_info.exposure.x), c.a);
}
