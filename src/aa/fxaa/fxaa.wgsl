// FXAA 3.11, quality path (after Timothy Lottes, NVIDIA 2011).
//
// Per pixel:
//  1. Local contrast: luma of the pixel and its four direct neighbours. When their range is
//     zero or below max(edge_threshold_min, edge_threshold * brightest luma), the pixel is
//     returned unchanged (flat regions cost one early exit and stay exact).
//  2. Edge orientation from second differences of the 3x3 lumas (horizontal edges have a
//     strong vertical second difference), and which side of the pixel the edge lies on (the
//     neighbour across the steeper gradient).
//  3. From the point half a pixel towards that neighbour, walk both ways along the edge with
//     bilinear luma reads (each read averages the two rows across the edge) until the average
//     departs from the local average by a quarter of the gradient. The step lengths come from
//     the quality preset (override constants STEP_0..STEP_11, STEP_COUNT of them); the last step
//     is taken without a read, as a guess that the edge runs on.
//  4. The nearer end decides the blend: pixels near the end of a staircase step move up to half
//     a pixel across the edge, provided the luma at that end falls on the other side of the
//     local average. A sub-pixel term from the 3x3 low-pass (weighted by `subpix`) handles
//     isolated features that have no edge span; it moves the read at most `subpix_limit` of a
//     pixel (see there).
//  5. One bilinear read at the pixel centre moved across the edge by that offset.
//
// Colour spaces, as FXAA 3.11 prescribes for sRGB targets: every luma test (steps 1-4) reads
// the sRGB-encoded values through an Rgba8Unorm view (`image`), because the thresholds are
// tuned for perceptual luma, and unchanged pixels are written back as they were read; the
// blend of step 5 reads through the sRGB view (`image_linear`), so the bilinear read mixes
// linear light, and is encoded again for the Rgba8Unorm view of the output. Mixing the
// encoded values instead darkens every blended edge pixel (a half-covered black/white pixel
// comes out at half the encoded scale, 21% of the light, instead of half the light).
// fs_fxaa writes the antialiased image; fs_mask writes the debug mask of the same analysis
// (through an Rgba8Unorm view: the mask colours are display values).
//
// With RADIANCE (an HDR frame with FXAA before the tonemapper, graph/hdr.rs) `image` is the
// encoded view of the radiance's perceptual copy (aa/common/perceptual.rs: compressed with
// Karis' c / (1 + luma), then sRGB-encoded), so the luma tests and thresholds see the same
// kind of values as on a displayed image; `image_linear` is the half-float radiance itself,
// and the blend writes radiance, unencoded, as an engine's FXAA before its tonemapper does.

override RADIANCE: bool = false;

struct FxaaParams {
    // xy: size of one pixel in UV, z: subpix (0 off .. 1 softest), w: subpix_limit (the
    // longest sub-pixel move, in pixels).
    rcp_frame_subpix: vec4<f32>,
    // x: edge_threshold, y: edge_threshold_min.
    thresholds: vec4<f32>,
    // x: subpix_strands, y: subpix_clean_edges (factors on the sub-pixel amount).
    subpix_factors: vec4<f32>,
}

@group(0) @binding(0) var image: texture_2d<f32>;
@group(0) @binding(1) var bilinear: sampler;
@group(0) @binding(2) var<uniform> params: FxaaParams;
@group(0) @binding(3) var image_linear: texture_2d<f32>;

// Luma from the green channel instead of BT.601 weights.
override GREEN_AS_LUMA: bool = false;
// Number of search steps of the preset (at most 12) and their lengths in pixels; the defaults
// are quality preset 12.
override STEP_COUNT: u32 = 5u;
override STEP_0: f32 = 1.0;
override STEP_1: f32 = 1.5;
override STEP_2: f32 = 2.0;
override STEP_3: f32 = 4.0;
override STEP_4: f32 = 12.0;
override STEP_5: f32 = 0.0;
override STEP_6: f32 = 0.0;
override STEP_7: f32 = 0.0;
override STEP_8: f32 = 0.0;
override STEP_9: f32 = 0.0;
override STEP_10: f32 = 0.0;
override STEP_11: f32 = 0.0;

fn step_length(i: u32) -> f32 {
    switch i {
        case 0u: { return STEP_0; }
        case 1u: { return STEP_1; }
        case 2u: { return STEP_2; }
        case 3u: { return STEP_3; }
        case 4u: { return STEP_4; }
        case 5u: { return STEP_5; }
        case 6u: { return STEP_6; }
        case 7u: { return STEP_7; }
        case 8u: { return STEP_8; }
        case 9u: { return STEP_9; }
        case 10u: { return STEP_10; }
        default: { return STEP_11; }
    }
}

fn luma_of(encoded: vec3<f32>) -> f32 {
    if GREEN_AS_LUMA {
        return encoded.g;
    }
    return dot(encoded, vec3<f32>(0.299, 0.587, 0.114));
}

// Linear light to the sRGB transfer function (IEC 61966-2-1).
fn encode_srgb(linear: vec3<f32>) -> vec3<f32> {
    let c = saturate(linear);
    let low = c * 12.92;
    let high = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(high, low, c <= vec3<f32>(0.0031308));
}

// The sRGB transfer function's inverse for one value, as a cubic (within 0.002 of it over
// 0..1; three multiply-adds where the exact curve costs a pow).
fn decode_srgb(encoded: f32) -> f32 {
    let c = saturate(encoded);
    return c * (c * (c * 0.305306011 + 0.682171111) + 0.012522878);
}

// The sub-pixel move on radiance (before the tonemapper), where the read mixes radiance: a
// fraction of radiance is no fraction of the light as displayed, since a bright tube runs to 40
// times white and 5% of it lights the pixel beside it past white. So the read moves by the
// fraction of the compressed light (the perceptual copy, decoded) that moves its encoded luma
// `amount` of the way up from the darker of the pixel and its neighbour across, the same for
// both pixels of a pair (moving the compressed light itself by `amount` scored worse against
// the display-referred reference: `docs/techniques/fxaa.md`).
fn subpix_on_radiance(amount: f32, luma: f32, luma_across: f32) -> f32 {
    let darker = min(luma, luma_across);
    let brighter = max(luma, luma_across);
    let decoded_darker = decode_srgb(darker);
    let decoded_step = decode_srgb(brighter) - decoded_darker;
    if decoded_step <= 1e-4 {
        return amount;
    }
    return (decode_srgb(darker + amount * (brighter - darker)) - decoded_darker) / decoded_step;
}

fn luma_at(pixel: vec2<i32>) -> f32 {
    let last = vec2<i32>(textureDimensions(image)) - 1;
    return luma_of(textureLoad(image, clamp(pixel, vec2<i32>(0), last), 0).rgb);
}

fn luma_between(uv: vec2<f32>) -> f32 {
    return luma_of(textureSampleLevel(image, bilinear, uv, 0.0).rgb);
}

struct Analysis {
    // The antialiased colour (sRGB-encoded).
    colour: vec4<f32>,
    // Luma of the pixel.
    luma: f32,
    // The contrast test found an edge (false: early exit, colour unchanged).
    edge: bool,
    // The edge runs horizontally (blend vertically).
    horizontal: bool,
    // Distance the read moved across the edge, in pixels (0 .. 0.5, up to 1 for sub-pixel).
    offset: f32,
}

fn analyse(position: vec2<f32>) -> Analysis {
    let pixel = vec2<i32>(position);
    let texel = params.rcp_frame_subpix.xy;
    let uv = (floor(position) + 0.5) * texel;
    let centre = textureLoad(image, pixel, 0);

    var result: Analysis;
    // An unchanged pixel is written back as it was read: encoded, or as radiance (`image`
    // then holds its perceptual copy).
    result.colour = vec4<f32>(centre.rgb, 1.0);
    if RADIANCE {
        result.colour = vec4<f32>(textureLoad(image_linear, pixel, 0).rgb, 1.0);
    }
    result.luma = luma_of(centre.rgb);
    result.edge = false;
    result.horizontal = false;
    result.offset = 0.0;

    // 1. Local contrast of the cross.
    let luma_m = result.luma;
    var luma_n = luma_at(pixel + vec2<i32>(0, -1));
    var luma_s = luma_at(pixel + vec2<i32>(0, 1));
    let luma_w = luma_at(pixel + vec2<i32>(-1, 0));
    let luma_e = luma_at(pixel + vec2<i32>(1, 0));
    let brightest = max(max(max(luma_n, luma_s), max(luma_w, luma_e)), luma_m);
    let darkest = min(min(min(luma_n, luma_s), min(luma_w, luma_e)), luma_m);
    let range = brightest - darkest;
    // A flat cross is never an edge, even with both thresholds at 0 (the tests below divide
    // by the range).
    if range <= 0.0 || range < max(params.thresholds.y, brightest * params.thresholds.x) {
        return result;
    }
    result.edge = true;

    // 2. Orientation from second differences over the 3x3 block.
    let luma_nw = luma_at(pixel + vec2<i32>(-1, -1));
    let luma_ne = luma_at(pixel + vec2<i32>(1, -1));
    let luma_sw = luma_at(pixel + vec2<i32>(-1, 1));
    let luma_se = luma_at(pixel + vec2<i32>(1, 1));
    let across_vertical = abs(luma_nw + luma_sw - 2.0 * luma_w)
        + 2.0 * abs(luma_n + luma_s - 2.0 * luma_m)
        + abs(luma_ne + luma_se - 2.0 * luma_e);
    let across_horizontal = abs(luma_nw + luma_ne - 2.0 * luma_n)
        + 2.0 * abs(luma_w + luma_e - 2.0 * luma_m)
        + abs(luma_sw + luma_se - 2.0 * luma_s);
    let horizontal = across_vertical >= across_horizontal;
    result.horizontal = horizontal;

    // Sub-pixel amount: how far the pixel stands out of the 3x3 low-pass, relative to the range.
    let low_pass = (2.0 * (luma_n + luma_s + luma_w + luma_e)
        + (luma_nw + luma_ne + luma_sw + luma_se)) / 12.0;
    let contrast = saturate(abs(low_pass - luma_m) / range);
    let eased = (3.0 - 2.0 * contrast) * contrast * contrast;
    var subpix = eased * eased * params.rcp_frame_subpix.z;

    // The two neighbours along the edge, and across it: north/south for a horizontal edge, else
    // west/east.
    let luma_along = select(vec2<f32>(luma_n, luma_s), vec2<f32>(luma_w, luma_e), horizontal);
    if !horizontal {
        luma_n = luma_w;
        luma_s = luma_e;
    }
    let gradient_n = luma_n - luma_m;
    let gradient_s = luma_s - luma_m;
    let towards_n = abs(gradient_n) >= abs(gradient_s);
    let gradient = max(abs(gradient_n), abs(gradient_s));

    // Where the pixel lies decides how far the sub-pixel term moves it. Brighter or darker
    // than both neighbours across the edge, it is a strand or dot thinner than a pixel, which
    // the edge search cannot place: `subpix_strands`. Between them, with neighbours along the
    // edge that match it, it lies wholly on one side of a clean edge that the search places,
    // where the term would only blur it: `subpix_clean_edges`, easing back to the full amount
    // as its neighbours along the edge differ from it by up to a tenth of the range. The move
    // is never longer than `subpix_limit`: the pixels that stand out most are the one-pixel
    // strands of sub-pixel geometry, which a long move would nearly erase.
    if gradient_n * gradient_s > 0.0 {
        subpix *= params.subpix_factors.x;
    } else {
        let along_contrast = max(abs(luma_along.x - luma_m), abs(luma_along.y - luma_m)) / range;
        subpix *= mix(params.subpix_factors.y, 1.0, saturate(along_contrast * 10.0));
    }
    subpix = min(subpix, params.rcp_frame_subpix.w);
    var across = select(texel.x, texel.y, horizontal);
    var local_average = 0.5 * (luma_s + luma_m);
    if towards_n {
        across = -across;
        local_average = 0.5 * (luma_n + luma_m);
    }

    if RADIANCE {
        subpix = min(subpix, subpix_on_radiance(subpix, luma_m, select(luma_s, luma_n, towards_n)));
    }

    // 3. Walk along the edge from the point half a pixel across it.
    var on_edge = uv;
    if horizontal {
        on_edge.y += 0.5 * across;
    } else {
        on_edge.x += 0.5 * across;
    }
    let along = select(vec2<f32>(0.0, texel.y), vec2<f32>(texel.x, 0.0), horizontal);
    let end_threshold = 0.25 * gradient;
    var pos_n = on_edge - along * STEP_0;
    var pos_p = on_edge + along * STEP_0;
    var end_n = luma_between(pos_n) - local_average;
    var end_p = luma_between(pos_p) - local_average;
    var done_n = abs(end_n) >= end_threshold;
    var done_p = abs(end_p) >= end_threshold;
    for (var i = 1u; i < STEP_COUNT; i++) {
        if !done_n {
            pos_n -= along * step_length(i);
        }
        if !done_p {
            pos_p += along * step_length(i);
        }
        if (done_n && done_p) || i + 1u == STEP_COUNT {
            break;
        }
        if !done_n {
            end_n = luma_between(pos_n) - local_average;
            done_n = abs(end_n) >= end_threshold;
        }
        if !done_p {
            end_p = luma_between(pos_p) - local_average;
            done_p = abs(end_p) >= end_threshold;
        }
    }

    // 4. The nearer end decides; it must have crossed to the other side of the local average.
    var distance_n = uv.y - pos_n.y;
    var distance_p = pos_p.y - uv.y;
    if horizontal {
        distance_n = uv.x - pos_n.x;
        distance_p = pos_p.x - uv.x;
    }
    let nearer_n = distance_n < distance_p;
    let nearest = min(distance_n, distance_p);
    let span_offset = 0.5 - nearest / (distance_n + distance_p);
    let centre_below = luma_m - local_average < 0.0;
    let good_n = (end_n < 0.0) != centre_below;
    let good_p = (end_p < 0.0) != centre_below;
    let good = select(good_p, good_n, nearer_n);
    let offset = max(select(0.0, span_offset, good), subpix);
    result.offset = offset;

    // 5. Read across the edge.
    var read_at = uv;
    if horizontal {
        read_at.y += offset * across;
    } else {
        read_at.x += offset * across;
    }
    let mixed = textureSampleLevel(image_linear, bilinear, read_at, 0.0).rgb;
    result.colour = vec4<f32>(select(encode_srgb(mixed), mixed, RADIANCE), 1.0);
    return result;
}

struct Varying {
    @builtin(position) position: vec4<f32>,
    @location(0) uv: vec2<f32>,
}

@fragment
fn fs_fxaa(in: Varying) -> @location(0) vec4<f32> {
    return analyse(in.position.xy).colour;
}

// Debug mask: the image's luma dimmed; pixels that pass the contrast test painted orange
// (horizontal edge, blended vertically) or blue (vertical edge, blended horizontally), the
// more saturated the further FXAA moved the read.
@fragment
fn fs_mask(in: Varying) -> @location(0) vec4<f32> {
    let a = analyse(in.position.xy);
    let base = vec3<f32>(a.luma * 0.35);
    if !a.edge {
        return vec4<f32>(base, 1.0);
    }
    let hue = select(vec3<f32>(0.15, 0.55, 1.0), vec3<f32>(1.0, 0.55, 0.1), a.horizontal);
    let strength = 0.35 + 0.65 * saturate(a.offset * 2.0);
    return vec4<f32>(mix(base, hue, strength), 1.0);
}
