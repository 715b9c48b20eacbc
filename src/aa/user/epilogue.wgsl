
// aa-lab's entry point for a user technique, placed after the user's file: the fullscreen
// pass's fragment stage calls the user's aa_main for every pixel and writes its linear colour
// through the output's sRGB view.
@fragment
fn aa_fragment(@builtin(position) position: vec4<f32>, @location(0) uv: vec2<f32>) -> @location(0) vec4<f32> {
    return aa_main(vec2<u32>(position.xy), uv);
}
