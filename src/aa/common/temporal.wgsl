// What the temporal resolves (TAA, and TAAU at native scale) share in WGSL: the prelude of
// `taa.wgsl` and `taau.wgsl`, itself after `radiance.wgsl` (its prelude). Both let the history
// fall off with the parallax around the pixel, faster where most of the depths the resolve
// searched lie on the farthest surface: an edge over a broad background (a column before a
// wall) rather than strands over other strands, whose farthest surface is as thin as the
// nearest (`silhouette_falloff` and `parallax_falloff`, `aa/common/temporal.rs`; measured in
// docs/techniques/taa.md). Both also filter this frame's samples wherever the pixel moves
// across surfaces (`spans_surfaces`, `SETTLED_SPEED`).

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

// Speed (pixels per frame) from which a pixel counts as moving whatever fraction past a texel
// its history read lands at: TAAU's history keeps only its motion samples from there, and both
// resolves take this frame's filtered estimate in full where the pixel also spans surfaces.
// Slower, both follow the fraction, so a slow steady pan (whose read lands at the same
// fraction every frame) keeps its calm.
const SETTLED_SPEED: f32 = 0.5;

// How far the depths a resolve searched span more than one surface: 0 where the nearest
// (reverse-Z `near`) and the farthest (`far`) coincide, rising linearly to 1 where they lie
// `tolerance` (relative distance) apart or more. On one surface this frame's filter only
// blurs a texture; across surfaces it averages an edge's aliasing, which a moving edge's
// history cannot hold.
fn spans_surfaces(near: f32, far: f32, tolerance: f32) -> f32 {
    return saturate(behind(far, near) / tolerance);
}

// How far a pixel that spans surfaces by `spans` (`spans_surfaces`) and moves at `speed`
// (pixels per frame) is a moving edge, whose filtered estimate both resolves take in full: 1
// from SETTLED_SPEED on, less below it.
fn moving_edge(spans: f32, speed: f32) -> f32 {
    return spans * saturate(speed / SETTLED_SPEED);
}

// How far (relative distance) the surface at reverse-Z depth `now` lies behind the one at
// `before` (0 where it is not behind): reverse-Z depth is 1/distance, so the ratio of depths
// is that of distances. (TAAU's disocclusion test compares the same way.)
fn behind(now: f32, before: f32) -> f32 {
    return max(before - now, 0.0) / max(before, 1e-12);
}
