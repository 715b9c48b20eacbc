// Custom MSAA resolve in linear light (Rgba8UnormSrgb samples are decoded on load): each output
// pixel is a weighted sum of the samples of its 3x3 pixel neighbourhood. The weights are
// computed on the CPU (aa::sampling::gather_weights and quincunx_weights) from the standard
// sample positions and the chosen filter, already normalised, so this shader only gathers.

struct Weights {
    // Weight of sample s of neighbour (dx, dy) in -1..1 at flat index
    // ((dy + 1) * 3 + (dx + 1)) * 16 + s, packed four to a vec4.
    w: array<vec4<f32>, 36>,
}

// Karis' weighting: every sample's weight is divided by 1 + its luminance and the sum is
// normalised, so one very bright sample of an HDR render cannot take over the average (the
// tonemap-aware resolve); without it the weights are used as given.
override LUMA_WEIGHT: bool = false;

@group(0) @binding(0) var samples: texture_multisampled_2d<f32>;
@group(0) @binding(1) var<uniform> weights: Weights;

fn weight(index: u32) -> f32 {
    return weights.w[index / 4u][index % 4u];
}

@fragment
fn fs_resolve(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(position.xy);
    let size = vec2<i32>(textureDimensions(samples));
    let n = textureNumSamples(samples);
    var sum = vec3<f32>(0.0);
    var total = 0.0;
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let neighbour = clamp(pixel + vec2<i32>(dx, dy), vec2<i32>(0), size - 1);
            let base = u32((dy + 1) * 3 + (dx + 1)) * 16u;
            for (var s = 0u; s < n; s++) {
                let w = weight(base + s);
                if w != 0.0 {
                    let c = textureLoad(samples, neighbour, i32(s)).rgb;
                    var weighted = w;
                    if LUMA_WEIGHT {
                        weighted = w / (1.0 + dot(c, vec3<f32>(0.2126, 0.7152, 0.0722)));
                    }
                    sum += weighted * c;
                    total += weighted;
                }
            }
        }
    }
    // Normalised weights sum to 1 already; only the luminance weighting needs the division.
    return vec4<f32>(select(sum, sum / max(total, 1e-8), LUMA_WEIGHT), 1.0);
}
