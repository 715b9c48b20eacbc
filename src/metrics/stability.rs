//! Temporal metrics of a clip: how much a technique's image changes from frame to frame
//! compared with the supersampled reference (`temporal_instability`), where it changes (a
//! per-pixel map), and how much error it leaves where the true image moves (`ghosting`).
//!
//! **Luma.** Every figure is computed on BT.601 luma of the 8-bit sRGB-*encoded* values,
//! `Y' = 0.299 R' + 0.587 G' + 0.114 B'`, in 0..255 (no linearisation), the same luma as SSIM
//! and the bench's flicker ratio in this crate ([`Plane::luma`]): encoded values are roughly
//! perceptually uniform, so a change of one level means about the same to the eye in shadows
//! and highlights.
//!
//! For a clip of frames `t = 0..N-1`, `P` pixels, a technique `T` and the reference `R`
//! (both rendered from the same cameras), with `Y_T(p, t)` the luma of pixel `p` at frame `t`:
//!
//! - **mean change**: `C_T = 1 / ((N-1) P) * sum over t = 1..N-1 and p of |Y_T(p,t) - Y_T(p,t-1)|`
//!   (luma levels per frame). Its per-pixel version, `c_T(p) = 1/(N-1) * sum over t of
//!   |Y_T(p,t) - Y_T(p,t-1)|`, is [`ChangeAccumulator::change_map`] (a heatmap of where a
//!   technique shimmers).
//! - **temporal_instability**: `C_T / C_R`. 1 means the technique changes as much as the true
//!   image does; 2 twice as much (crawling stair steps, shimmering sub-pixel geometry); below 1
//!   it is steadier than the truth, which a temporal technique reaches by blurring. Undefined
//!   (`None`) when `N < 2` or the reference does not change at all.
//! - **ghosting** (error at moving edges): the moving pixels of step `t` are
//!   `M_t = { p : |Y_R(p,t) - Y_R(p,t-1)| > GHOST_THRESHOLD }` (8 luma levels: where the true
//!   image changed, i.e. in front of and behind every moving silhouette and texture edge). Then
//!   `ghosting_T = sum over t = 1..N-1 and p in M_t of |Y_T(p,t) - Y_R(p,t)|  /  sum over t of |M_t|`:
//!   the mean absolute luma error against the reference on the pixels the motion uncovered or
//!   covered, in luma levels. A technique that lags behind the motion (TAA's history trails)
//!   shows last frame's values there and scores high; aliasing on moving edges adds to it
//!   too, so compare it with the technique's error on still frames. Undefined when no pixel
//!   moved.

use super::MetricsError;
use super::map::Plane;

/// Luma change of the reference, in levels of 0..255, above which a pixel counts as moving for
/// the ghosting measure (see the module docs).
pub const GHOST_THRESHOLD: f32 = 8.0;

/// Accumulates one image sequence's frame-to-frame luma change, per pixel and in all.
#[derive(Clone, Debug, Default)]
pub struct ChangeAccumulator {
    previous: Option<Plane>,
    /// Per pixel, the summed change. Single precision: a clip keeps one of these per technique
    /// at full frame size, and each addition rounds by about one part in ten million, far below
    /// the three decimals the figures are shown with.
    sum: Vec<f32>,
    steps: u32,
}

fn check_size(a: (u32, u32), b: (u32, u32)) -> Result<(), MetricsError> {
    if a == b {
        Ok(())
    } else {
        Err(MetricsError::SizeMismatch {
            reference: a,
            test: b,
        })
    }
}

impl ChangeAccumulator {
    /// An empty accumulator.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds the next frame's luma ([`Plane::luma`]); a frame of another size than the first
    /// is an error.
    pub fn push(&mut self, luma: Plane) -> Result<(), MetricsError> {
        if let Some(previous) = &self.previous {
            check_size(previous.size(), luma.size())?;
            if self.sum.is_empty() {
                self.sum = vec![0.0; luma.data.len()];
            }
            for ((sum, a), b) in self.sum.iter_mut().zip(&previous.data).zip(&luma.data) {
                *sum += (a - b).abs();
            }
            self.steps += 1;
        }
        self.previous = Some(luma);
        Ok(())
    }

    /// Frame pairs measured so far (frames - 1).
    pub fn steps(&self) -> u32 {
        self.steps
    }

    /// The last frame pushed.
    pub fn last(&self) -> Option<&Plane> {
        self.previous.as_ref()
    }

    /// Mean absolute luma change per pixel and frame pair, `C` of the module docs; `None`
    /// before two frames.
    pub fn mean_change(&self) -> Option<f64> {
        (self.steps > 0 && !self.sum.is_empty()).then(|| {
            let total: f64 = self.sum.iter().map(|&s| f64::from(s)).sum();
            total / (f64::from(self.steps) * self.sum.len() as f64)
        })
    }

    /// Per-pixel mean absolute luma change over the frame pairs, `c(p)` of the module docs;
    /// `None` before two frames.
    pub fn change_map(&self) -> Option<Plane> {
        let previous = self.previous.as_ref()?;
        if self.steps == 0 {
            return None;
        }
        let steps = self.steps as f32;
        Some(Plane {
            width: previous.width,
            height: previous.height,
            data: self.sum.iter().map(|s| s / steps).collect(),
        })
    }
}

/// `temporal_instability` of the module docs: a technique's mean change over the reference's,
/// `None` when either is undefined or the reference did not change.
pub fn temporal_instability(
    technique: &ChangeAccumulator,
    reference: &ChangeAccumulator,
) -> Option<f64> {
    let t = technique.mean_change()?;
    let r = reference.mean_change()?;
    (r > 0.0).then(|| t / r)
}

/// Accumulates the ghosting measure of the module docs for one technique.
#[derive(Clone, Debug, Default)]
pub struct MovingEdgeError {
    sum: f64,
    moving: u64,
    pixels: u64,
}

impl MovingEdgeError {
    /// An empty accumulator.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds step `t`: the technique's luma at `t`, the reference's at `t` and at `t - 1`.
    pub fn push(
        &mut self,
        technique: &Plane,
        reference: &Plane,
        reference_previous: &Plane,
    ) -> Result<(), MetricsError> {
        check_size(technique.size(), reference.size())?;
        check_size(reference.size(), reference_previous.size())?;
        for ((t, r), r0) in technique
            .data
            .iter()
            .zip(&reference.data)
            .zip(&reference_previous.data)
        {
            if (r - r0).abs() > GHOST_THRESHOLD {
                self.sum += f64::from((t - r).abs());
                self.moving += 1;
            }
        }
        self.pixels += technique.data.len() as u64;
        Ok(())
    }

    /// The ghosting measure in luma levels; `None` when no pixel moved.
    pub fn ghosting(&self) -> Option<f64> {
        (self.moving > 0).then(|| self.sum / self.moving as f64)
    }

    /// Share of pixels (over all steps) that counted as moving, 0..1.
    pub fn moving_fraction(&self) -> f64 {
        if self.pixels == 0 {
            0.0
        } else {
            self.moving as f64 / self.pixels as f64
        }
    }
}

/// The temporal figures of one technique over a clip.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TemporalScores {
    /// Mean absolute luma change per pixel and frame (levels of 0..255).
    pub mean_change: Option<f64>,
    /// Mean change over the reference's (1 = as steady as the reference).
    pub temporal_instability: Option<f64>,
    /// Mean absolute luma error against the reference on moving pixels (levels of 0..255).
    pub ghosting: Option<f64>,
}

/// Everything measured over a clip: the reference's change and, per technique, its change
/// and its error at moving edges. Push the frames in order.
#[derive(Clone, Debug, Default)]
pub struct ClipMetrics {
    reference: ChangeAccumulator,
    techniques: Vec<(ChangeAccumulator, MovingEdgeError)>,
}

impl ClipMetrics {
    /// Metrics of `techniques` sequences against a reference.
    pub fn new(techniques: usize) -> Self {
        Self {
            reference: ChangeAccumulator::new(),
            techniques: vec![Default::default(); techniques],
        }
    }

    /// Adds one frame: the reference's image and each technique's, in the order of
    /// [`ClipMetrics::new`] (sRGB-encoded RGBA8, all the same size).
    pub fn push(
        &mut self,
        reference: &image::RgbaImage,
        techniques: &[&image::RgbaImage],
    ) -> Result<(), MetricsError> {
        let reference_luma = Plane::luma(reference);
        if techniques.len() != self.techniques.len() {
            return Err(MetricsError::FrameCount {
                expected: self.techniques.len(),
                got: techniques.len(),
            });
        }
        for ((change, ghost), image) in self.techniques.iter_mut().zip(techniques) {
            let luma = Plane::luma(image);
            check_size(luma.size(), reference_luma.size())?;
            if let Some(previous) = self.reference.last() {
                ghost.push(&luma, &reference_luma, previous)?;
            }
            change.push(luma)?;
        }
        self.reference.push(reference_luma)
    }

    /// The reference's accumulated change.
    pub fn reference(&self) -> &ChangeAccumulator {
        &self.reference
    }

    /// Technique `index`'s accumulated change (its map is [`ChangeAccumulator::change_map`]).
    pub fn technique(&self, index: usize) -> Option<&ChangeAccumulator> {
        self.techniques.get(index).map(|(change, _)| change)
    }

    /// Share of pixels that counted as moving for the ghosting measure.
    pub fn moving_fraction(&self) -> f64 {
        self.techniques
            .first()
            .map_or(0.0, |(_, ghost)| ghost.moving_fraction())
    }

    /// The figures of every technique, in order.
    pub fn scores(&self) -> Vec<TemporalScores> {
        self.techniques
            .iter()
            .map(|(change, ghost)| TemporalScores {
                mean_change: change.mean_change(),
                temporal_instability: temporal_instability(change, &self.reference),
                ghosting: ghost.ghosting(),
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grey(width: u32, height: u32, f: impl Fn(u32, u32) -> u8) -> image::RgbaImage {
        image::RgbaImage::from_fn(width, height, |x, y| {
            let v = f(x, y);
            image::Rgba([v, v, v, 255])
        })
    }

    fn close(a: Option<f64>, b: f64) -> bool {
        a.is_some_and(|a| (a - b).abs() < 1e-6)
    }

    #[test]
    fn a_static_sequence_does_not_change() {
        let frame = grey(8, 6, |x, y| ((x * 31 + y * 17) % 256) as u8);
        let mut metrics = ClipMetrics::new(1);
        for _ in 0..5 {
            metrics.push(&frame, &[&frame]).unwrap();
        }
        let change = metrics.technique(0).unwrap();
        assert_eq!(change.steps(), 4);
        assert!(close(change.mean_change(), 0.0));
        assert!(change.change_map().unwrap().data.iter().all(|v| *v == 0.0));
        let scores = metrics.scores()[0];
        // The reference did not change either: no ratio, no moving pixels.
        assert_eq!(scores.temporal_instability, None);
        assert_eq!(scores.ghosting, None);
        assert_eq!(metrics.moving_fraction(), 0.0);
    }

    #[test]
    fn alternating_pixels_have_the_known_change() {
        // Every other pixel (a checkerboard) flips between black and white each frame; the
        // rest stay mid-grey. Half the pixels change by 255 levels per frame: mean 127.5.
        let frame = |t: u32| {
            grey(4, 4, move |x, y| {
                if (x + y) % 2 == 0 {
                    if t.is_multiple_of(2) { 0 } else { 255 }
                } else {
                    128
                }
            })
        };
        let mut change = ChangeAccumulator::new();
        assert_eq!(change.mean_change(), None);
        assert_eq!(change.change_map(), None);
        for t in 0..4 {
            change.push(Plane::luma(&frame(t))).unwrap();
        }
        assert_eq!(change.steps(), 3);
        assert!(
            close(change.mean_change(), 127.5),
            "{:?}",
            change.mean_change()
        );
        let map = change.change_map().unwrap();
        assert!((map.at(0, 0) - 255.0).abs() < 1e-3);
        assert!(map.at(1, 0).abs() < 1e-6);
    }

    #[test]
    fn a_static_technique_scores_zero_and_a_flickering_one_its_known_ratio() {
        // The reference brightens every pixel by 3 levels per frame (C_R = 3). A technique
        // that never changes scores 0; one whose every pixel alternates between 0 and 255
        // changes by 255 per frame: 85 times the reference.
        let mut metrics = ClipMetrics::new(2);
        for t in 0..5u8 {
            let reference = grey(4, 3, |_, _| 100 + 3 * t);
            let still = grey(4, 3, |_, _| 100);
            let flicker = grey(4, 3, |_, _| if t % 2 == 0 { 0 } else { 255 });
            metrics.push(&reference, &[&still, &flicker]).unwrap();
        }
        let scores = metrics.scores();
        assert!(close(scores[0].mean_change, 0.0));
        assert!(close(scores[0].temporal_instability, 0.0));
        assert!(close(scores[1].mean_change, 255.0));
        assert!(close(scores[1].temporal_instability, 85.0));
    }

    #[test]
    fn instability_divides_by_the_reference() {
        // Reference: every pixel up by 2 levels per frame (C_R = 2). Technique: up by 2 then
        // down by 6 (C_T = 4): twice as unsteady.
        let reference = [100u8, 102, 104];
        let technique = [100u8, 102, 96];
        let mut metrics = ClipMetrics::new(2);
        for (r, t) in reference.iter().zip(&technique) {
            let r = grey(3, 2, |_, _| *r);
            let t = grey(3, 2, |_, _| *t);
            metrics.push(&r, &[&t, &r]).unwrap();
        }
        assert!(close(metrics.reference().mean_change(), 2.0));
        let scores = metrics.scores();
        assert!(close(scores[0].mean_change, 4.0));
        assert!(close(scores[0].temporal_instability, 2.0));
        // The reference itself scores exactly 1 and no ghosting (2 levels is below the
        // threshold, so no pixel moved).
        assert!(close(scores[1].temporal_instability, 1.0));
        assert_eq!(scores[1].ghosting, None);
    }

    #[test]
    fn a_lagging_edge_shows_as_ghosting() {
        // A white bar on black moves one pixel right per frame in the reference; the lagging
        // technique shows the previous frame's image, the exact one the current frame.
        let bar = |t: u32| grey(8, 1, move |x, _| if x == t || x == t + 1 { 255 } else { 0 });
        let mut metrics = ClipMetrics::new(2);
        metrics.push(&bar(0), &[&bar(0), &bar(0)]).unwrap();
        for t in 1..4 {
            metrics.push(&bar(t), &[&bar(t - 1), &bar(t)]).unwrap();
        }
        let scores = metrics.scores();
        // Per step two pixels move (the one uncovered behind the bar and the one covered in
        // front), and the lagging image is wrong by 255 on both.
        assert!(close(scores[0].ghosting, 255.0), "{:?}", scores[0].ghosting);
        assert!(close(scores[1].ghosting, 0.0));
        assert!((metrics.moving_fraction() - 2.0 / 8.0).abs() < 1e-9);
        // The lagging image skipped one step of change (it repeated frame 0): 2 steps of the
        // reference's 3.
        assert!(close(scores[0].temporal_instability, 2.0 / 3.0));
    }

    #[test]
    fn frames_of_another_size_are_an_error() {
        let mut change = ChangeAccumulator::new();
        change.push(Plane::filled(4, 4, 0.0)).unwrap();
        assert!(change.push(Plane::filled(4, 5, 0.0)).is_err());
        let mut metrics = ClipMetrics::new(1);
        let a = grey(4, 4, |_, _| 0);
        let b = grey(5, 4, |_, _| 0);
        assert!(metrics.push(&a, &[&b]).is_err());
        assert!(metrics.push(&a, &[]).is_err());
    }
}
