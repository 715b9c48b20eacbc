// Edge-aware blur, an example aa-lab user technique: a pixel whose luma differs enough from
// its four direct neighbours is blended towards their average; flat areas and contrast
// below the threshold stay sharp. Contrast is judged on perceptual luma, the blend mixes
// linear light. Settings (override constants; a `[MIN, MAX]` comment gives the range):
//
//   aa-lab render --technique none,fxaa,user:assets/user_techniques/edge_blur.wgsl \
//       --set user.strength=0.8

override strength: f32 = 0.6;   // [0, 1] How far an edge pixel moves towards its neighbours' average
override threshold: f32 = 0.08; // [0.01, 0.5] Perceptual luma contrast at which the blend starts
override ramp: f32 = 2.0;       // [1.25, 8] Contrast (in thresholds) at which the blend is full

// Luma of a linear colour, square-rooted to a roughly perceptual scale.
fn perceptual_luma(color: vec4<f32>) -> f32 {
    return sqrt(dot(color.rgb, vec3<f32>(0.2126, 0.7152, 0.0722)));
}

fn aa_main(pixel: vec2<u32>, uv: vec2<f32>) -> vec4<f32> {
    let p = vec2<i32>(pixel);
    let centre = aa_load(p);
    let north = aa_load(p + vec2<i32>(0, -1));
    let south = aa_load(p + vec2<i32>(0, 1));
    let east = aa_load(p + vec2<i32>(1, 0));
    let west = aa_load(p + vec2<i32>(-1, 0));
    let lumas = vec4<f32>(
        perceptual_luma(north),
        perceptual_luma(south),
        perceptual_luma(east),
        perceptual_luma(west),
    );
    let own = perceptual_luma(centre);
    let highest = max(own, max(max(lumas.x, lumas.y), max(lumas.z, lumas.w)));
    let lowest = min(own, min(min(lumas.x, lumas.y), min(lumas.z, lumas.w)));
    let edge = smoothstep(threshold, threshold * ramp, highest - lowest);
    let average = (north + south + east + west) * 0.25;
    return mix(centre, average, edge * strength);
}
