//! Per-pass GPU times of a frame, from the timestamp queries wgpu-profiler brackets every pass
//! with. Pass labels are `technique/pass` for a technique's own passes and `scene ...` for the
//! shared scene renders, so times can be summed per technique or per shared input.

/// GPU time of one pass.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PassTiming {
    /// `technique/pass` or the scene input's label (see [`split_pass_label`]).
    pub label: String,
    /// Milliseconds between the pass's begin and end timestamps.
    pub ms: f64,
}

impl PassTiming {
    /// The technique id of a technique pass, `None` for a shared scene render.
    pub fn technique(&self) -> Option<&str> {
        split_pass_label(&self.label).map(|(t, _)| t)
    }
}

/// A technique pass's label `technique/pass` split into the technique id and the pass name;
/// `None` for a shared scene render's label. The split is at the last `/`: pass names have
/// none, but ids may (a user technique's id holds its file's path, `user:/home/me/aa.wgsl`).
pub fn split_pass_label(label: &str) -> Option<(&str, &str)> {
    label.rsplit_once('/')
}

/// All pass times of one frame, in recording order.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct FrameTimings {
    /// Every timed pass.
    pub passes: Vec<PassTiming>,
}

impl FrameTimings {
    pub(super) fn from_profiler(results: &[wgpu_profiler::GpuTimerQueryResult]) -> Self {
        fn walk(results: &[wgpu_profiler::GpuTimerQueryResult], out: &mut Vec<PassTiming>) {
            for r in results {
                if let Some(time) = &r.time {
                    out.push(PassTiming {
                        label: r.label.clone(),
                        ms: (time.end - time.start) * 1000.0,
                    });
                }
                walk(&r.nested_queries, out);
            }
        }
        let mut passes = Vec::new();
        walk(results, &mut passes);
        Self { passes }
    }

    /// Milliseconds of a technique's own passes.
    pub fn technique_ms(&self, id: &str) -> f64 {
        self.passes
            .iter()
            .filter(|p| p.technique() == Some(id))
            .map(|p| p.ms)
            .sum()
    }

    /// Milliseconds of the pass with exactly this label (a scene input's render).
    pub fn pass_ms(&self, label: &str) -> Option<f64> {
        self.passes.iter().find(|p| p.label == label).map(|p| p.ms)
    }

    /// The passes of one technique.
    pub fn technique_passes<'a>(
        &'a self,
        id: &'a str,
    ) -> impl Iterator<Item = &'a PassTiming> + 'a {
        self.passes
            .iter()
            .filter(move |p| p.technique() == Some(id))
    }

    /// Sum of every pass.
    pub fn total_ms(&self) -> f64 {
        self.passes.iter().map(|p| p.ms).sum()
    }
}

impl FrameTimings {
    /// Per-pass median over several frames that recorded the same passes in the same order;
    /// `None` when there are no frames or their passes differ.
    pub fn median(frames: &[FrameTimings]) -> Option<FrameTimings> {
        let first = frames.first()?;
        let same_shape = frames.iter().all(|f| {
            f.passes.len() == first.passes.len()
                && f.passes
                    .iter()
                    .zip(&first.passes)
                    .all(|(a, b)| a.label == b.label)
        });
        if !same_shape {
            return None;
        }
        let passes = first
            .passes
            .iter()
            .enumerate()
            .map(|(i, pass)| {
                let mut values: Vec<f64> = frames.iter().map(|f| f.passes[i].ms).collect();
                values.sort_by(f64::total_cmp);
                PassTiming {
                    label: pass.label.clone(),
                    ms: median_of_sorted(&values),
                }
            })
            .collect();
        Some(FrameTimings { passes })
    }
}

/// Median of an ascending slice (mean of the two middle values for even lengths).
pub fn median_of_sorted(values: &[f64]) -> f64 {
    match values.len() {
        0 => 0.0,
        n if n % 2 == 1 => values[n / 2],
        n => 0.5 * (values[n / 2 - 1] + values[n / 2]),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(ms: &[f64]) -> FrameTimings {
        FrameTimings {
            passes: ms
                .iter()
                .enumerate()
                .map(|(i, &ms)| PassTiming {
                    label: format!("t/p{i}"),
                    ms,
                })
                .collect(),
        }
    }

    #[test]
    fn median_is_per_pass() {
        let m = FrameTimings::median(&[
            frame(&[1.0, 10.0]),
            frame(&[3.0, 30.0]),
            frame(&[2.0, 20.0]),
        ])
        .unwrap();
        assert_eq!(m.passes[0].ms, 2.0);
        assert_eq!(m.passes[1].ms, 20.0);
        assert_eq!(m.technique_ms("t"), 22.0);
        assert!(FrameTimings::median(&[frame(&[1.0]), frame(&[1.0, 2.0])]).is_none());
    }
}
