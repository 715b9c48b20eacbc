//! The bench as a library the command line and the viewer both drive: [`BenchRunner`] measures
//! a run (a scene at a size) and summarises it into its report; [`TimingSamples`] gathers,
//! frame by frame, each technique's GPU time (its own passes, pass by pass, and the scene
//! input it reads), each shared scene input's time and readers, the whole frame and the copy
//! floor every post-process pass is compared with, and the fragment invocations of a
//! statistics frame; [`reference_spec`] is the 64-sample reference both `bench` and `clip`
//! score against; [`scales`] turns techniques into the techniques at every render scale of a
//! sweep over scales. `cli::bench` plans the runs (sizes, sweeps), loads the scenes and writes
//! the reports.

use crate::aa::floor::COPY_FLOOR_ID;
use crate::aa::{self, Named, ParamValue, SceneInput, TechniqueError};
use crate::export::ExportError;
use crate::export::charts::ChartError;
use crate::export::report::{BenchReport, write_charts};
use crate::export::report_markdown::markdown;
use crate::files::{self, Overwrite};
use crate::gpu::Gpu;
use crate::graph::{FrameStatistics, FrameTimings};
use crate::metrics::Comparison;
use crate::spec::TechniqueSpec;
use std::path::{Path, PathBuf};

mod runner;
pub mod scales;

pub use runner::{
    BenchError, BenchOptions, BenchProgress, BenchRunner, DEFAULT_FLICKER_FRAMES,
    DEFAULT_QUALITY_FRAME, DEFAULT_WARMUP, ImageOutput, JOD_FPS, RunPlan,
};

/// Camera motion per frame of the timing and flicker track, pixels.
pub const TRACK_STEP_PX: f32 = 0.25;
/// Ordered-grid factor of the reference: 8 x 8 = 64 samples per pixel.
pub const REFERENCE_FACTOR: u32 = 8;

/// The reference: SSAA, ordered grid, 8 x 8 (`bench` and `clip`).
pub fn reference_spec(gpu: &Gpu) -> Result<TechniqueSpec, TechniqueError> {
    let mut ssaa = aa::create(gpu, aa::ssaa::ID)?;
    aa::set_param(
        ssaa.as_mut(),
        "mode",
        ParamValue::Choice(aa::ssaa::Mode::Ordered.name().into()),
    )?;
    aa::set_param(
        ssaa.as_mut(),
        "factor",
        ParamValue::Int(i64::from(REFERENCE_FACTOR)),
    )?;
    Ok(TechniqueSpec::of(ssaa.as_ref()))
}

/// HDR-FLIP per technique id (see [`hdr_flips`]).
pub type HdrFlipScores = Vec<(String, f64)>;

/// The HDR-FLIP of every technique of `output` that has radiance against the radiance of
/// `reference` (the reference's run), by technique id; none when the reference has none.
pub fn hdr_flips(
    reference: &crate::spec::RenderOutput,
    output: &crate::spec::RenderOutput,
) -> Result<HdrFlipScores, crate::metrics::MetricsError> {
    let Some((_, reference)) = reference.radiance.first() else {
        return Ok(Vec::new());
    };
    (output.radiance.iter())
        .map(|(id, radiance)| {
            let score = crate::metrics::hdr_flip::hdr_flip(reference, radiance)?;
            Ok((id.clone(), score.mean))
        })
        .collect()
}

/// A technique's quality against the reference and, on `chart`, against the exact coverage.
pub type QualityScores = (String, Comparison, Option<Comparison>);

/// Per-frame sums of two sample series (a technique's own passes and its input); `a` when
/// `b` is empty.
pub fn sum_samples(a: &[f64], b: &[f64]) -> Vec<f64> {
    if b.is_empty() {
        return a.to_vec();
    }
    a.iter().zip(b).map(|(x, y)| x + y).collect()
}

/// Per-frame samples of one technique.
#[derive(Default)]
pub struct TechniqueSamples {
    /// Label of the scene input it reads, once a frame has shown it.
    pub input_label: Option<String>,
    /// Whether that input is a one-sample render (the technique is a post-process pass).
    pub post_process: bool,
    /// Milliseconds of its own passes, per frame.
    pub own: Vec<f64>,
    /// Milliseconds of the scene input it reads, per frame.
    pub input: Vec<f64>,
    /// Per pass label, in first-seen order: passes per frame and ms per frame.
    pub passes: Vec<(String, usize, Vec<f64>)>,
}

/// Per-frame samples of one shared input, keyed by label and users.
pub struct InputSamples {
    /// The input's label.
    pub label: String,
    /// The techniques that read it.
    pub users: Vec<String>,
    /// Milliseconds of its render, per frame.
    pub ms: Vec<f64>,
    /// Fragment-shader invocations of its render (from the statistics frame).
    pub invocations: Option<u64>,
}

/// Everything the timing loop collects.
pub struct TimingSamples {
    /// Per technique id, in the order asked for.
    pub techniques: Vec<(String, TechniqueSamples)>,
    /// Per distinct (input, readers), in first-seen order.
    pub inputs: Vec<InputSamples>,
    /// Milliseconds of the whole frame (the copy floor left out), per frame.
    pub frame: Vec<f64>,
    /// Milliseconds of the copy floor, per frame.
    pub floor: Vec<f64>,
}

impl TimingSamples {
    /// No samples yet, for the techniques `ids`.
    pub fn new(ids: &[&'static str]) -> Self {
        Self {
            techniques: ids
                .iter()
                .map(|id| ((*id).to_owned(), TechniqueSamples::default()))
                .collect(),
            inputs: Vec::new(),
            frame: Vec::new(),
            floor: Vec::new(),
        }
    }

    /// Adds one frame: `inputs` are the graph's scene inputs in render order.
    pub fn add(&mut self, timings: &FrameTimings, inputs: &[(SceneInput, Vec<&'static str>)]) {
        let input_ms: Vec<f64> = timings
            .passes
            .iter()
            .filter(|p| p.technique().is_none())
            .map(|p| p.ms)
            .collect();
        self.frame.push(
            timings
                .passes
                .iter()
                .filter(|p| p.technique() != Some(COPY_FLOOR_ID))
                .map(|p| p.ms)
                .sum(),
        );
        self.floor.push(timings.technique_ms(COPY_FLOOR_ID));
        for (n, (input, readers)) in inputs.iter().enumerate() {
            let ms = input_ms.get(n).copied().unwrap_or(f64::NAN);
            let users: Vec<String> = readers
                .iter()
                .filter(|u| **u != COPY_FLOOR_ID)
                .map(|u| (*u).to_owned())
                .collect();
            let label = input.label();
            match self
                .inputs
                .iter_mut()
                .find(|i| i.label == label && i.users == users)
            {
                Some(existing) => existing.ms.push(ms),
                None => self.inputs.push(InputSamples {
                    label,
                    users,
                    ms: vec![ms],
                    invocations: None,
                }),
            }
            for user in readers {
                if let Some((_, t)) = self.techniques.iter_mut().find(|(id, _)| id == user) {
                    t.input.push(ms);
                    t.input_label = Some(input.label());
                    t.post_process = input.sample_count() == 1;
                }
            }
        }
        for (id, samples) in &mut self.techniques {
            samples.own.push(timings.technique_ms(id));
            let mut frame_passes: Vec<(String, usize, f64)> = Vec::new();
            for pass in timings.technique_passes(id) {
                match frame_passes.iter_mut().find(|(l, _, _)| *l == pass.label) {
                    Some(entry) => {
                        entry.1 += 1;
                        entry.2 += pass.ms;
                    }
                    None => frame_passes.push((pass.label.clone(), 1, pass.ms)),
                }
            }
            for (label, count, ms) in frame_passes {
                match samples.passes.iter_mut().find(|(l, _, _)| *l == label) {
                    Some(entry) => entry.2.push(ms),
                    None => samples.passes.push((label, count, vec![ms])),
                }
            }
        }
    }

    /// Records the statistics frame's invocations on the shared inputs.
    pub fn add_statistics(
        &mut self,
        statistics: &FrameStatistics,
        inputs: &[(SceneInput, Vec<&'static str>)],
    ) {
        let counts: Vec<u64> = statistics
            .passes
            .iter()
            .filter(|p| p.technique().is_none())
            .map(|p| p.fragment_invocations)
            .collect();
        for ((input, users), count) in inputs.iter().zip(counts) {
            let users: Vec<String> = users
                .iter()
                .filter(|u| **u != COPY_FLOOR_ID)
                .map(|u| (*u).to_owned())
                .collect();
            if let Some(i) = self
                .inputs
                .iter_mut()
                .find(|i| i.label == input.label() && i.users == users)
            {
                i.invocations = Some(count);
            }
        }
    }
}

/// The bench's report files in `dir`: `report.json` and `report.md` (the charts are named
/// after the runs).
pub fn report_paths(dir: &Path) -> [PathBuf; 2] {
    [dir.join("report.json"), dir.join("report.md")]
}

/// Writes `report` into `dir`: `report.json`, `report.md` and the charts. Returns a line per
/// file written (`wrote PATH`, `replaced PATH`).
pub fn write_report(
    report: &BenchReport,
    dir: &Path,
    policy: &Overwrite,
) -> Result<Vec<String>, ChartError> {
    let [json, md] = report_paths(dir);
    let text = serde_json::to_string_pretty(report).map_err(|source| ExportError::Record {
        path: json.clone(),
        source,
    })?;
    let mut lines = Vec::new();
    let replaced = files::write_bytes(&json, policy, text.as_bytes()).map_err(ExportError::from)?;
    lines.push(files::wrote_line(&json, replaced));
    let text = markdown(report);
    let replaced = files::write_bytes(&md, policy, text.as_bytes()).map_err(ExportError::from)?;
    lines.push(files::wrote_line(&md, replaced));
    for chart in write_charts(report, dir, policy)? {
        lines.push(format!("wrote {}", chart.display()));
    }
    Ok(lines)
}
