// Karis' reversible tonemap for the techniques before the tonemapper of an HDR frame
// (graph/hdr.rs), compiled in front of taa.wgsl and taau.wgsl (and of SMAA's resolves and the
// morphological techniques' perceptual copy, aa/common/perceptual.rs): with RADIANCE every sample read
// is compressed to c / (1 + luma), so the neighbourhood, the rectification and the blend work
// on values below 1 that no bright sample dominates; the history keeps them, and the output is
// expanded back to radiance with c / (1 - luma). Without RADIANCE both are the identity.

override RADIANCE: bool = false;

fn radiance_luma(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}

// A sample as the resolve works on it.
fn compressed(c: vec3<f32>) -> vec3<f32> {
    return select(c, c / (1.0 + radiance_luma(c)), RADIANCE);
}

// A resolved colour as the output holds it.
fn to_output(c: vec3<f32>) -> vec3<f32> {
    return select(c, c / max(1.0 - radiance_luma(c), 1e-3), RADIANCE);
}
