// Supersampling passes, all in linear light (sRGB targets decode on load, encode on store).
//
// fs_downsample: ordered-grid SSAA. The scene was rendered k times larger (in tiles); each
//   output pixel of the current tile averages its k x k block (box filter).
// cs_accumulate: jittered SSAA. After each 1-sample render at one pattern position, every output
//   pixel adds the weighted colours of its 3x3 neighbourhood to a float accumulator; the weights
//   come from the CPU (filter evaluated at this sample's position, normalised over all samples).
// fs_resolve_accumulated: writes the accumulator, times a scale, to the output (the scale is 1
//   for a complete accumulation and 1 / accumulated weight for a progressive, partial one).

struct Downsample {
    // xy: top-left output pixel of the tile, z: factor k.
    origin_factor: vec4<u32>,
}

@group(0) @binding(0) var tile: texture_2d<f32>;
@group(0) @binding(1) var<uniform> downsample: Downsample;

@fragment
fn fs_downsample(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let k = downsample.origin_factor.z;
    let local = vec2<u32>(position.xy) - downsample.origin_factor.xy;
    var sum = vec3<f32>(0.0);
    for (var y = 0u; y < k; y++) {
        for (var x = 0u; x < k; x++) {
            sum += textureLoad(tile, local * k + vec2<u32>(x, y), 0).rgb;
        }
    }
    return vec4<f32>(sum / f32(k * k), 1.0);
}

struct AccumulateWeights {
    // Weight of neighbour (dx, dy) in -1..1 at index (dy + 1) * 3 + (dx + 1) (x of each vec4).
    w: array<vec4<f32>, 9>,
    // xy: image size.
    size: vec4<u32>,
}

@group(0) @binding(0) var jittered: texture_2d<f32>;
@group(0) @binding(1) var<uniform> accumulate_weights: AccumulateWeights;
@group(0) @binding(2) var<storage, read_write> accumulator: array<vec4<f32>>;

@compute @workgroup_size(8, 8)
fn cs_accumulate(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = accumulate_weights.size.xy;
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let pixel = vec2<i32>(id.xy);
    var sum = vec3<f32>(0.0);
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let w = accumulate_weights.w[(dy + 1) * 3 + (dx + 1)].x;
            if w != 0.0 {
                let neighbour = clamp(pixel + vec2<i32>(dx, dy), vec2<i32>(0), vec2<i32>(size) - 1);
                sum += w * textureLoad(jittered, neighbour, 0).rgb;
            }
        }
    }
    accumulator[id.y * size.x + id.x] += vec4<f32>(sum, 0.0);
}

@group(0) @binding(0) var<storage, read> accumulated: array<vec4<f32>>;
// xy: image size, z: bits of the f32 scale.
@group(0) @binding(1) var<uniform> resolve_params: vec4<u32>;

@fragment
fn fs_resolve_accumulated(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let pixel = vec2<u32>(position.xy);
    let value = accumulated[pixel.y * resolve_params.x + pixel.x].rgb * bitcast<f32>(resolve_params.z);
    return vec4<f32>(clamp(value, vec3<f32>(0.0), vec3<f32>(1.0)), 1.0);
}
