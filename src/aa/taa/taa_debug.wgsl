// TAA debug views, written through Rgba8Unorm views (the colours are display values).
//
// fs_velocity: the motion vectors TAA reprojects with, direction as hue (right red, down
//   yellow-green, left cyan, up blue-violet) and speed as brightness (black: static; half
//   brightness at `half_speed` pixels per frame).
// fs_jitter: one output pixel enlarged to the middle of the image, with the positions of the
//   jitter sequence's samples inside it: grey dots still to come in this cycle, white dots
//   already accumulated, the current frame's sample in red. The centre cross marks the pixel
//   centre.

struct DebugParams {
    // xy: image size in pixels, z: speed (pixels per frame) shown at half brightness,
    // w: number of samples in the sequence.
    size: vec4<f32>,
    // xy: sample position inside the pixel (0..1, y down); z: 0 to come, 1 done, 2 current.
    samples: array<vec4<f32>, 16>,
}

@group(0) @binding(0) var motion: texture_2d<f32>;
@group(0) @binding(1) var<uniform> debug: DebugParams;

struct Varying {
    @builtin(position) position: vec4<f32>,
    @location(0) uv: vec2<f32>,
}

fn hue(angle: f32) -> vec3<f32> {
    let t = angle / 6.2831853;
    let k = vec3<f32>(0.0, 2.0 / 3.0, 1.0 / 3.0);
    return saturate(abs(fract(vec3<f32>(t) + k) * 6.0 - 3.0) - 1.0);
}

@fragment
fn fs_velocity(in: Varying) -> @location(0) vec4<f32> {
    let velocity = textureLoad(motion, vec2<i32>(in.position.xy), 0).xy * debug.size.xy;
    let speed = length(velocity);
    if speed < 1e-4 {
        return vec4<f32>(0.0, 0.0, 0.0, 1.0);
    }
    let brightness = speed / (speed + debug.size.z);
    return vec4<f32>(hue(atan2(velocity.y, velocity.x)) * brightness, 1.0);
}

@fragment
fn fs_jitter(in: Varying) -> @location(0) vec4<f32> {
    let side = 0.8 * min(debug.size.x, debug.size.y);
    let origin = 0.5 * (debug.size.xy - vec2<f32>(side));
    let p = (in.position.xy - origin) / side;
    let line = 1.5 / side;
    var colour = vec3<f32>(0.08);
    if all(p >= vec2<f32>(0.0)) && all(p <= vec2<f32>(1.0)) {
        colour = vec3<f32>(0.16);
        let border = min(min(p.x, 1.0 - p.x), min(p.y, 1.0 - p.y));
        let cross = min(abs(p.x - 0.5), abs(p.y - 0.5));
        if border < line {
            colour = vec3<f32>(0.6);
        } else if cross < 0.5 * line && length(p - 0.5) < 0.05 {
            colour = vec3<f32>(0.45);
        }
    }
    let radius = 0.025;
    let count = u32(debug.size.w);
    // A constant trip count: a loop bounded by a uniform is specialised and recompiled at
    // every draw by lavapipe (see the note on uniforms in gpu/shader.rs).
    for (var i = 0u; i < 16u; i++) {
        let s = debug.samples[i];
        if i < count && length(p - s.xy) < radius {
            if s.z > 1.5 {
                colour = vec3<f32>(1.0, 0.15, 0.1);
            } else if s.z > 0.5 {
                colour = vec3<f32>(0.95);
            } else {
                colour = vec3<f32>(0.4);
            }
        }
    }
    return vec4<f32>(colour, 1.0);
}
