// The smallest aa-lab user technique: every pixel keeps the scene's colour, so aa-lab
// shows exactly what No AA shows, bit for bit. Copy it to start your own.
//
//   aa-lab render --technique none,user:assets/user_techniques/passthrough.wgsl

fn aa_main(pixel: vec2<u32>, uv: vec2<f32>) -> vec4<f32> {
    return aa_load(vec2<i32>(pixel));
}
