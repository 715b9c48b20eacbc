// MSAA debug views.
// fs_coverage: how many samples of each pixel geometry covers (reverse-Z: depth 0 is the
//   cleared background), as a ramp from black (none) through blue and orange to white (all).
// fs_complex: the resolved image dimmed, with "complex" pixels, whose samples do not all hold
//   the same colour (the pixels the resolve actually antialiases), painted magenta.

@group(0) @binding(0) var depth_samples: texture_depth_multisampled_2d;
@group(0) @binding(1) var color_samples: texture_multisampled_2d<f32>;

fn ramp(t: f32) -> vec3<f32> {
    let blue = vec3<f32>(0.1, 0.3, 1.0);
    let orange = vec3<f32>(1.0, 0.55, 0.1);
    if t <= 0.0 { return vec3<f32>(0.0); }
    if t >= 1.0 { return vec3<f32>(1.0); }
    if t < 0.5 { return mix(blue, orange, t * 2.0); }
    return mix(orange, vec3<f32>(1.0), (t - 0.5) * 2.0);
}

@fragment
fn fs_coverage(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(position.xy);
    let n = textureNumSamples(depth_samples);
    var covered = 0u;
    for (var s = 0u; s < n; s++) {
        if textureLoad(depth_samples, pixel, i32(s)) > 0.0 {
            covered += 1u;
        }
    }
    return vec4<f32>(ramp(f32(covered) / f32(n)), 1.0);
}

@fragment
fn fs_complex(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(position.xy);
    let n = i32(textureNumSamples(color_samples));
    let first = textureLoad(color_samples, pixel, 0);
    var sum = first.rgb;
    var complex = false;
    for (var s = 1; s < n; s++) {
        let c = textureLoad(color_samples, pixel, s);
        sum += c.rgb;
        if any(abs(c.rgb - first.rgb) > vec3<f32>(0.5 / 255.0)) {
            complex = true;
        }
    }
    if complex {
        return vec4<f32>(1.0, 0.0, 1.0, 1.0);
    }
    return vec4<f32>(sum / f32(n) * 0.35, 1.0);
}
