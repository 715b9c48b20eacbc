// What the temporal resolves (TAA, and TAAU at native scale) share in WGSL: the prelude of
// `taa.wgsl` and `taau.wgsl`, itself after `radiance.wgsl` (its prelude). Both let the history
// fall off with the parallax around the pixel, faster where most of the depths the resolve
// searched lie on the farthest surface: an edge over a broad background (a column before a
// wall) rather than strands over other strands, whose farthest surface is as thin as the
// nearest (`silhouette_falloff` and `parallax_falloff`, `aa/common/temporal.rs`; measured in
// docs/techniques/taa.md).

// How much nearer than the farthest depth a depth may be and still lie on the farthest
// surface: relative distance (reverse-Z depth is 1 / distance).
const BACKGROUND_TOLERANCE: f32 = 0.05;

// 1 where reverse-Z `depth` lies on the farthest surface, whose depth is `far`.
fn on_background(depth: f32, far: f32) -> f32 {
    return select(0.0, 1.0, depth <= far * (1.0 + BACKGROUND_TOLERANCE));
}

// The rate (1 / length, per pixel per frame of parallax) at which the history falls off, from
// the farthest surface's share `background` of the depths searched: from 2 of 7 on it to 6 of
// 7 it moves from `parallax_rate` to `silhouette_rate` (0: `parallax_rate` everywhere).
fn parallax_falloff_rate(parallax_rate: f32, silhouette_rate: f32, background: f32) -> f32 {
    let broad = saturate((background - 2.0 / 7.0) * 7.0 / 4.0);
    return select(parallax_rate, mix(parallax_rate, silhouette_rate, broad), silhouette_rate > 0.0);
}
