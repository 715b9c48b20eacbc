//! Rolling statistics for the metrics panel: UI frame times (FPS and the plot) and GPU
//! milliseconds per pass, per technique and per shared scene render, each the median of the
//! last frames in which that pass ran (so techniques that skip frames keep their figures).

use std::collections::{BTreeMap, VecDeque};
use std::time::{Duration, Instant};

use crate::graph::{FrameTimings, median_of_sorted, split_pass_label};

/// Frames kept per pass for the GPU medians.
const GPU_WINDOW: usize = 30;
/// Seconds of frame times kept for the plot.
const PLOT_SECONDS: f64 = 20.0;

/// Median of an unsorted window.
fn median(values: &VecDeque<f64>) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    let mut sorted: Vec<f64> = values.iter().copied().collect();
    sorted.sort_by(f64::total_cmp);
    Some(median_of_sorted(&sorted))
}

/// Rendered frames over time (UI frames that only redraw the interface do not count).
#[derive(Debug)]
pub struct FrameClock {
    start: Instant,
    /// Seconds of the previous rendered frame, unless the app idled since.
    last_rendered: Option<f64>,
    /// (seconds, ms since the previous rendered frame) of recent rendered frames.
    rendered: VecDeque<(f64, f64)>,
}

impl Default for FrameClock {
    fn default() -> Self {
        Self {
            start: Instant::now(),
            last_rendered: None,
            rendered: VecDeque::new(),
        }
    }
}

impl FrameClock {
    /// Records a UI frame; `rendered` says whether it published newly rendered techniques.
    pub fn tick(&mut self, rendered: bool) {
        let t = self.start.elapsed().as_secs_f64();
        if rendered {
            if let Some(previous) = self.last_rendered {
                self.rendered.push_back((t, (t - previous) * 1000.0));
            }
            self.last_rendered = Some(t);
        }
        while self
            .rendered
            .front()
            .is_some_and(|(s, _)| t - s > PLOT_SECONDS)
        {
            self.rendered.pop_front();
        }
    }

    /// The app went idle: the next rendered frame starts a new interval.
    pub fn idle(&mut self) {
        self.last_rendered = None;
    }

    /// Rendered frames per second over the last `window`, and the median interval in ms.
    pub fn fps(&self, window: Duration) -> Option<(f64, f64)> {
        let end = self.rendered.back()?.0;
        let recent: VecDeque<f64> = self
            .rendered
            .iter()
            .filter(|(t, _)| end - t <= window.as_secs_f64())
            .map(|(_, ms)| *ms)
            .collect();
        let total: f64 = recent.iter().sum();
        (total > 0.0).then(|| {
            (
                recent.len() as f64 * 1000.0 / total,
                median(&recent).unwrap_or(0.0),
            )
        })
    }

    /// (seconds, ms) points of the rendered frames, for the plot.
    pub fn points(&self) -> Vec<[f64; 2]> {
        self.rendered.iter().map(|(t, ms)| [*t, *ms]).collect()
    }
}

/// GPU milliseconds per pass label.
#[derive(Debug, Default)]
pub struct GpuStats {
    passes: BTreeMap<String, VecDeque<f64>>,
    /// Label order as last reported (recording order of the frame graph).
    order: Vec<String>,
    /// (seconds, total ms) of each reported frame, for the plot.
    totals: VecDeque<(f64, f64)>,
    start: Option<Instant>,
}

impl GpuStats {
    /// Adds one frame's timings.
    pub fn add(&mut self, timings: &FrameTimings) {
        let start = *self.start.get_or_insert_with(Instant::now);
        for pass in &timings.passes {
            let window = self.passes.entry(pass.label.clone()).or_default();
            window.push_back(pass.ms);
            if window.len() > GPU_WINDOW {
                window.pop_front();
            }
            if !self.order.contains(&pass.label) {
                self.order.push(pass.label.clone());
            }
        }
        let t = start.elapsed().as_secs_f64();
        self.totals.push_back((t, timings.total_ms()));
        while self
            .totals
            .front()
            .is_some_and(|(s, _)| t - s > PLOT_SECONDS)
        {
            self.totals.pop_front();
        }
    }

    /// Drops everything (new scene or size: old figures no longer apply).
    pub fn clear(&mut self) {
        self.passes.clear();
        self.order.clear();
        self.totals.clear();
    }

    /// Median ms of one pass label.
    pub fn pass_ms(&self, label: &str) -> Option<f64> {
        self.passes.get(label).and_then(median)
    }

    /// The pass labels of a technique (`id/...`) in recording order, with their medians.
    pub fn technique_passes(&self, id: &str) -> Vec<(String, f64)> {
        self.order
            .iter()
            .filter_map(|label| {
                let (_, pass) =
                    split_pass_label(label).filter(|(technique, _)| *technique == id)?;
                self.pass_ms(label).map(|ms| (pass.to_owned(), ms))
            })
            .collect()
    }

    /// Sum of a technique's pass medians.
    pub fn technique_ms(&self, id: &str) -> Option<f64> {
        let passes = self.technique_passes(id);
        (!passes.is_empty()).then(|| passes.iter().map(|(_, ms)| ms).sum())
    }

    /// The shared scene renders (labels without a `/`) with their medians.
    pub fn scene_renders(&self) -> Vec<(String, f64)> {
        self.order
            .iter()
            .filter(|label| split_pass_label(label).is_none())
            .filter_map(|label| self.pass_ms(label).map(|ms| (label.clone(), ms)))
            .collect()
    }

    /// (seconds, total GPU ms) of recent frames.
    pub fn total_points(&self) -> Vec<[f64; 2]> {
        self.totals.iter().map(|(t, ms)| [*t, *ms]).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::graph::PassTiming;

    fn frame(passes: &[(&str, f64)]) -> FrameTimings {
        FrameTimings {
            passes: passes
                .iter()
                .map(|(l, ms)| PassTiming {
                    label: (*l).to_owned(),
                    ms: *ms,
                })
                .collect(),
        }
    }

    #[test]
    fn medians_per_pass_survive_frames_without_the_pass() {
        let mut stats = GpuStats::default();
        stats.add(&frame(&[
            ("scene 1x", 10.0),
            ("fxaa/fxaa", 1.0),
            ("none/copy", 0.1),
        ]));
        stats.add(&frame(&[("scene 1x", 12.0), ("fxaa/fxaa", 3.0)]));
        stats.add(&frame(&[("scene 1x", 11.0), ("fxaa/fxaa", 2.0)]));
        stats.add(&frame(&[("reference/scene sample", 9.0)]));
        assert_eq!(stats.pass_ms("scene 1x"), Some(11.0));
        assert_eq!(stats.technique_ms("fxaa"), Some(2.0));
        assert_eq!(stats.technique_ms("none"), Some(0.1));
        assert_eq!(stats.technique_ms("smaa"), None);
        assert_eq!(
            stats.technique_passes("fxaa"),
            vec![("fxaa".to_owned(), 2.0)]
        );
        assert_eq!(stats.scene_renders(), vec![("scene 1x".to_owned(), 11.0)]);
        assert_eq!(stats.total_points().len(), 4);
    }

    #[test]
    fn user_technique_ids_with_slashes_get_their_passes() {
        let mut stats = GpuStats::default();
        let id = "user:/home/me/aa/edge.wgsl";
        stats.add(&frame(&[
            ("scene 1x", 10.0),
            (&format!("{id}/user pass"), 1.5),
        ]));
        assert_eq!(stats.technique_ms(id), Some(1.5));
        assert_eq!(
            stats.technique_passes(id),
            vec![("user pass".to_owned(), 1.5)]
        );
        assert_eq!(stats.technique_ms("user:"), None);
        assert_eq!(stats.scene_renders(), vec![("scene 1x".to_owned(), 10.0)]);
    }

    #[test]
    fn fps_counts_rendered_frames_and_ui_frames_apart() {
        let mut clock = FrameClock::default();
        assert!(clock.fps(Duration::from_secs(1)).is_none());
        clock.tick(true);
        std::thread::sleep(Duration::from_millis(5));
        clock.tick(false);
        std::thread::sleep(Duration::from_millis(5));
        clock.tick(true);
        let (fps, ms) = clock.fps(Duration::from_secs(5)).expect("one interval");
        assert!(fps > 1.0 && fps < 100.0, "{fps}");
        assert!(ms >= 9.0, "{ms}");
        assert_eq!(clock.points().len(), 1);
        clock.idle();
        clock.tick(true);
        assert_eq!(clock.points().len(), 1);
    }
}
