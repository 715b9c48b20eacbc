//! The bench report: the data model `aa-lab bench` fills in (serialised as `report.json`, its
//! schema documented in `docs/bench-report.md`), the Markdown rendering (`report.md`, tables in
//! the shape of the thesis' figures) and the charts (PNG, through [`super::charts`]).
//!
//! Every number carries its meaning in the field name and docs: `*_ms` are GPU milliseconds
//! from timestamp queries, summarised over the timed frames as median and 95th percentile;
//! a technique's `total_ms` is its own passes plus the scene render it reads (the cost of
//! running it alone), while `inputs` lists each shared scene render once (what the frame graph
//! actually spends when techniques run together). In a sweep over render scales
//! ([`SCALE_SWEEP`]) every technique runs at each scale in the same run, at the same output
//! size, so native and upscaled techniques meet on one Pareto front of quality against cost
//! ([`QualityFronts`], charted per metric with each technique's scales in one colour).

use std::path::{Path, PathBuf};

use super::ExportError;
use super::charts::{
    BarChart, BarLayout, BarSeries, ChartError, Line, LineChart, draw_bars, draw_lines,
};
use super::tradeoff::{TradeoffChart, TradeoffPoint, draw_tradeoff, quality_front};
use crate::aa::combo::Combo;
use crate::aa::{self, ParamMap};
use crate::files::{self, Overwrite};
use crate::gpu::Capabilities;
use crate::metrics::{Comparison, Metric, Summary};
use crate::spec::RenderSpec;

/// Schema identifier written into every report.
pub const SCHEMA: &str = "aa-lab-bench/1";

/// A whole bench run.
#[derive(Clone, Debug, serde::Serialize)]
pub struct BenchReport {
    /// [`SCHEMA`].
    pub schema: &'static str,
    /// aa-lab version and commit.
    pub build: String,
    /// The adapter's capability report.
    pub adapter: Capabilities,
    /// The command line that produced the report.
    pub command: String,
    /// Seconds since the Unix epoch when the bench started.
    pub started_unix: u64,
    /// Wall-clock seconds the whole bench took (scene generation, warm-up, references and
    /// metrics included).
    pub wall_seconds: f64,
    /// What was measured and how.
    pub settings: BenchSettings,
    /// One entry per scene x size (x density).
    pub runs: Vec<RunReport>,
}

/// Settings of a bench.
#[derive(Clone, Debug, serde::Serialize)]
pub struct BenchSettings {
    /// Technique ids, in report order.
    pub techniques: Vec<String>,
    /// Timed frames per run.
    pub frames: u32,
    /// Untimed frames before them.
    pub warmup: u32,
    /// Frames read back for the flicker ratio (the last timed ones).
    pub flicker_frames: u32,
    /// Camera motion per frame of the timing and flicker sequence, in pixels at the orbit
    /// target's distance.
    pub track_step_px: f32,
    /// Frame of the scene's own camera path whose images are scored (temporal techniques run
    /// frames 0..=N of it).
    pub quality_frame: u64,
    /// Whether image quality and flicker were measured.
    pub quality: bool,
    /// The reference technique and its settings (SSAA, ordered grid, factor 8: 64 samples).
    pub reference: crate::spec::TechniqueSpec,
    /// `resolution` or `density` for a scaling sweep, [`SCALE_SWEEP`] for a sweep over render
    /// scales.
    pub sweep: Option<String>,
    /// The render scales of a [`SCALE_SWEEP`] (per axis, 1 = native), in the order given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scales: Option<Vec<f32>>,
    /// The display model, version and rate of the techniques' `jod`, with `--jod`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jod: Option<crate::metrics::jod::JodSetting>,
    /// Whether the techniques' scene renders had geometric specular antialiasing (never the
    /// reference's); left out when off.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub specular_aa: bool,
    /// How the scenes' radiance was displayed (`--tonemap`); left out when `auto`.
    #[serde(skip_serializing_if = "crate::graph::hdr::TonemapChoice::is_auto")]
    pub tonemap: crate::graph::hdr::TonemapChoice,
    /// Exposure of HDR renders in stops.
    pub exposure: f32,
}

/// [`BenchSettings::sweep`] of a sweep over render scales: every technique at every scale, at
/// the same output size, against the native reference.
pub const SCALE_SWEEP: &str = "scale";

/// GPU time of one scene render the frame graph shares between techniques.
#[derive(Clone, Debug, serde::Serialize)]
pub struct InputReport {
    /// Its label (`scene 1x`, `scene msaa4`, `scene 1x jittered`).
    pub label: String,
    /// Technique ids that read it.
    pub users: Vec<String>,
    /// GPU milliseconds per frame.
    pub ms: Summary,
    /// Fragment-shader invocations of the render.
    pub fragment_invocations: Option<u64>,
}

/// GPU time of a technique's passes that share a label (SSAA's tiles, for instance).
#[derive(Clone, Debug, serde::Serialize)]
pub struct PassReport {
    /// `technique/pass`.
    pub label: String,
    /// Passes with this label per frame.
    pub count: usize,
    /// Their summed GPU milliseconds per frame.
    pub ms: Summary,
    /// Their summed fragment-shader invocations.
    pub fragment_invocations: Option<u64>,
}

/// Fragment-shader invocations of a technique.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct Invocations {
    /// In its own passes.
    pub own: u64,
    /// In the scene render it reads.
    pub input: u64,
    /// Both.
    pub total: u64,
    /// `total` per output pixel.
    pub per_pixel: f64,
}

/// Memory of a technique, bytes.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct MemorySummary {
    /// Everything it needs to run alone: input targets, private resources, output.
    pub standalone_bytes: u64,
    /// Private resources and output.
    pub own_bytes: u64,
    /// The scene input's targets.
    pub input_bytes: u64,
}

/// Everything measured for one technique in one run.
#[derive(Clone, Debug, serde::Serialize)]
pub struct TechniqueReport {
    /// Registry id, with its render scale, upscaler and sharpening (`smaa@performance:easu`).
    pub id: String,
    /// Display name.
    pub name: String,
    /// Render scale per axis: 1 at the output resolution, below 1 when rendered smaller and
    /// upscaled to it.
    pub render_scale: f32,
    /// The scene input it reads (label), `None` when it renders the scene itself.
    pub input: Option<String>,
    /// Post-process technique: reads a one-sample render (shared or jittered) and filters it.
    pub post_process: bool,
    /// Its settings.
    pub settings: ParamMap,
    /// Its own passes.
    pub passes: Vec<PassReport>,
    /// Its own passes per frame.
    pub own_ms: Summary,
    /// The scene render it reads, per frame.
    pub input_ms: Summary,
    /// Own passes plus input, per frame: its cost when run alone.
    pub total_ms: Summary,
    /// `total_ms.median` over No AA's.
    pub relative_to_none: Option<f64>,
    /// Own passes' median over the full-screen copy floor's median (post-process only).
    pub floor_multiple: Option<f64>,
    /// Memory.
    pub memory: Option<MemorySummary>,
    /// Fragment-shader invocations.
    pub fragment_invocations: Option<Invocations>,
    /// Scores against the 64-sample SSAA reference on the quality frame.
    pub quality: Option<Comparison>,
    /// Scores against the analytic ground truth (`chart` only), over the test elements.
    pub truth: Option<Comparison>,
    /// HDR-FLIP of its radiance against the reference's, when it ran before the tonemapper of
    /// an HDR frame (`metrics::hdr_flip`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hdr_flip: Option<f64>,
    /// Mean absolute luma change per frame over the flicker frames.
    pub mean_change: Option<f64>,
    /// `mean_change` over the reference's: the `temporal_instability` of `aa-lab clip`
    /// (see [`crate::metrics::stability`]), over the flicker frames.
    pub flicker_ratio: Option<f64>,
    /// Mean absolute luma error against the reference on the pixels where the reference moved
    /// between consecutive flicker frames (the ghosting measure of
    /// [`crate::metrics::stability`]), levels of 0..255.
    pub ghosting: Option<f64>,
    /// ColorVideoVDP's JOD of the flicker frames against the reference's, with `--jod`
    /// ([`BenchSettings::jod`] says how).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jod: Option<f64>,
}

/// One scene at one size (and density).
#[derive(Clone, Debug, serde::Serialize)]
pub struct RunReport {
    /// Scene name.
    pub scene: String,
    /// Scene density (hairball triangle scale).
    pub density: f32,
    /// Triangles per scene render.
    pub triangles: usize,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// The quality frame's render spec: `aa-lab render --from` on it reproduces the images
    /// that were scored.
    pub spec: RenderSpec,
    /// The reference's render spec.
    pub reference_spec: RenderSpec,
    /// Scene renders the graph records per frame (shared inputs plus techniques' own).
    pub scene_renders_per_frame: usize,
    /// Every pass of the techniques together per frame (shared inputs counted once; the copy
    /// floor excluded).
    pub frame_ms: Summary,
    /// The full-screen copy pass.
    pub floor_ms: Summary,
    /// Shared scene renders.
    pub inputs: Vec<InputReport>,
    /// Per technique.
    pub techniques: Vec<TechniqueReport>,
    /// The reference's mean absolute luma change per frame over the flicker frames.
    pub reference_change: Option<f64>,
    /// The graph's memory, shared inputs once, scene included, bytes.
    pub memory_total_bytes: u64,
    /// The techniques on the Pareto fronts of quality against cost, when quality was scored.
    pub quality_fronts: Option<QualityFronts>,
}

/// The Pareto fronts of a run: the techniques that no technique matches or beats in quality at
/// the same or lower cost (`total_ms` median, the technique alone).
#[derive(Clone, Debug, serde::Serialize)]
pub struct QualityFronts {
    /// Ids on the SSIM front (higher is better), cheapest first.
    pub ssim: Vec<String>,
    /// Ids on the FLIP front (lower is better), cheapest first.
    pub flip: Vec<String>,
}

impl QualityFronts {
    /// The fronts of `techniques`; `None` when none was scored.
    pub fn of(techniques: &[TechniqueReport]) -> Option<Self> {
        let scored: Vec<&TechniqueReport> =
            techniques.iter().filter(|t| t.quality.is_some()).collect();
        if scored.is_empty() {
            return None;
        }
        let front = |metric| {
            let points = metric_points(&scored, metric);
            quality_front(&points, metric == Metric::Flip)
                .into_iter()
                .map(|i| scored[i].id.clone())
                .collect()
        };
        Some(Self {
            ssim: front(Metric::Ssim),
            flip: front(Metric::Flip),
        })
    }
}

/// `metric`'s value in `quality`.
pub fn metric_value(quality: &Comparison, metric: Metric) -> f64 {
    match metric {
        Metric::Ssim => quality.ssim,
        Metric::Flip => quality.flip,
        Metric::Mae => quality.mae,
    }
}

/// The scored `techniques` as ungrouped trade-off points (name, total ms median, `metric`).
fn metric_points(techniques: &[&TechniqueReport], metric: Metric) -> Vec<TradeoffPoint> {
    techniques
        .iter()
        .filter_map(|t| {
            t.quality.map(|q| TradeoffPoint {
                name: t.name.clone(),
                cost: t.total_ms.median,
                quality: metric_value(&q, metric),
                group: 0,
                upscaled: t.render_scale < 1.0,
            })
        })
        .collect()
}

impl RunReport {
    /// `scene-WxH` (plus `-dN` for non-default densities), used in file names.
    pub fn key(&self) -> String {
        let mut key = format!("{}-{}x{}", self.scene, self.width, self.height);
        if (self.density - 1.0).abs() > 1e-6 {
            key += &format!("-d{}", self.density);
        }
        key
    }

    /// The technique with an id.
    pub fn technique(&self, id: &str) -> Option<&TechniqueReport> {
        self.techniques.iter().find(|t| t.id == id)
    }

    /// Writes the run's two records into `dir` (`<key>.spec.json`, `<key>.reference.spec.json`),
    /// which `aa-lab render --from` reproduces.
    pub fn write_sidecars(&self, dir: &Path, policy: &Overwrite) -> Result<(), ExportError> {
        for (suffix, spec) in [
            ("spec", &self.spec),
            ("reference.spec", &self.reference_spec),
        ] {
            let path = dir.join(format!("{}.{suffix}.json", self.key()));
            let json = serde_json::to_vec_pretty(spec).map_err(|source| ExportError::Record {
                path: path.clone(),
                source,
            })?;
            files::write_bytes(&path, policy, &json)?;
        }
        Ok(())
    }
}

/// Milliseconds with a precision that suits their size.
pub fn fmt_ms(ms: f64) -> String {
    if !ms.is_finite() {
        "-".to_owned()
    } else if ms >= 100.0 {
        format!("{ms:.0}")
    } else if ms >= 10.0 {
        format!("{ms:.1}")
    } else if ms >= 0.1 {
        format!("{ms:.2}")
    } else {
        format!("{ms:.3}")
    }
}

/// Ids of every technique that appears in any run, in first-seen order, with names.
pub(super) fn technique_columns(report: &BenchReport) -> Vec<(String, String)> {
    let mut columns: Vec<(String, String)> = Vec::new();
    for t in report.runs.iter().flat_map(|r| &r.techniques) {
        if !columns.iter().any(|(id, _)| *id == t.id) {
            columns.push((t.id.clone(), t.name.clone()));
        }
    }
    columns
}

/// The scene column of a run: its name, and its density and triangle count when a density
/// sweep (or `--density`) changed them.
pub(super) fn scene_label(run: &RunReport) -> String {
    if (run.density - 1.0).abs() > 1e-6 {
        format!(
            "{} (density {}, {} k tris)",
            run.scene,
            run.density,
            run.triangles / 1000
        )
    } else {
        run.scene.clone()
    }
}

/// The techniques of a run that scored quality as points of `metric` against their total GPU
/// ms (median), with the groups' names. In a scale sweep (`by_scale`) a technique's points at
/// every scale form one group, each labelled with its scale and upscaler; otherwise each point
/// is labelled with its technique's name, in one group.
fn tradeoff_points(
    run: &RunReport,
    metric: Metric,
    by_scale: bool,
) -> (Vec<TradeoffPoint>, Vec<String>) {
    let scored: Vec<&TechniqueReport> = run.techniques.iter().collect();
    let mut points = metric_points(&scored, metric);
    if !by_scale {
        return (points, Vec::new());
    }
    let mut groups: Vec<(String, String)> = Vec::new();
    let scored = run.techniques.iter().filter(|t| t.quality.is_some());
    for (point, technique) in points.iter_mut().zip(scored) {
        let Ok(combo) = Combo::parse(&technique.id) else {
            continue;
        };
        let key = Combo {
            scale: 1.0,
            ..combo.clone()
        }
        .id();
        point.group = groups
            .iter()
            .position(|(k, _)| *k == key)
            .unwrap_or_else(|| {
                groups.push((key, unscaled_name(&combo)));
                groups.len() - 1
            });
        point.name = scale_label(&combo);
    }
    (points, groups.into_iter().map(|(_, name)| name).collect())
}

/// The display name of a combination's technique without its render scale (with its
/// sharpening): `SMAA 1x + RCAS 0.2`.
pub(super) fn unscaled_name(combo: &Combo) -> String {
    let native = Combo {
        scale: 1.0,
        ..combo.clone()
    };
    aa::registry::display_name(&native.base) + &native.label_suffix()
}

/// `native`, or the render scale in percent per axis with the upscaler (`50% EASU`).
pub(super) fn scale_label(combo: &Combo) -> String {
    let unsharpened = Combo {
        sharpen: None,
        ..combo.clone()
    };
    let suffix = unsharpened.label_suffix();
    match suffix.trim_start().strip_prefix('@') {
        Some(scale) => scale.trim().to_owned(),
        None => "native".to_owned(),
    }
}

/// The quantity a load sweep varies (`resolution`, `density`): not a [`SCALE_SWEEP`], which
/// varies the techniques within each run.
pub(super) fn scaling_sweep(report: &BenchReport) -> Option<&str> {
    report
        .settings
        .sweep
        .as_deref()
        .filter(|by| *by != SCALE_SWEEP)
}

/// Whether the report is a sweep over render scales.
pub(super) fn is_scale_sweep(report: &BenchReport) -> bool {
    report.settings.sweep.as_deref() == Some(SCALE_SWEEP)
}

/// File name of a run's chart of `metric` against cost.
pub(super) fn tradeoff_chart_name(run: &RunReport, metric: Metric) -> String {
    match metric {
        Metric::Ssim => format!("quality-cost-{}.png", run.key()),
        other => format!("{}-cost-{}.png", other.name(), run.key()),
    }
}

/// One point of a scaling curve.
#[derive(Clone, Debug, PartialEq)]
pub struct ScalingPoint {
    /// Megapixels or millions of triangles.
    pub x: f64,
    /// Median total ms.
    pub total_ms: f64,
    /// Median total minus No AA's median total: what antialiasing adds.
    pub overhead_ms: f64,
}

/// Scaling curves of one scene: per technique (id, name), its points in x order. `by` picks
/// the x axis: `resolution` (megapixels) or `density` (millions of triangles).
pub fn scaling_curves(
    report: &BenchReport,
    scene: &str,
    by: &str,
) -> Vec<(String, String, Vec<ScalingPoint>)> {
    let mut runs: Vec<&RunReport> = report.runs.iter().filter(|r| r.scene == scene).collect();
    let x_of = |r: &RunReport| match by {
        "density" => r.triangles as f64 / 1e6,
        _ => f64::from(r.width) * f64::from(r.height) / 1e6,
    };
    runs.sort_by(|a, b| x_of(a).total_cmp(&x_of(b)));
    technique_columns(report)
        .into_iter()
        .map(|(id, name)| {
            let points = runs
                .iter()
                .filter_map(|r| {
                    let t = r.technique(&id)?;
                    let none = r.technique(aa::none::ID).map_or(0.0, |n| n.total_ms.median);
                    Some(ScalingPoint {
                        x: x_of(r),
                        total_ms: t.total_ms.median,
                        overhead_ms: t.total_ms.median - none,
                    })
                })
                .collect();
            (id, name, points)
        })
        .collect()
}

pub(super) fn scenes(report: &BenchReport) -> Vec<String> {
    let mut scenes: Vec<String> = Vec::new();
    for r in &report.runs {
        if !scenes.contains(&r.scene) {
            scenes.push(r.scene.clone());
        }
    }
    scenes
}

/// Writes the report's charts into `dir` and returns their paths: per run, GPU time per
/// technique (scene input and own passes stacked) and, with quality, SSIM against GPU ms with
/// the Pareto front (FLIP too in a scale sweep); per scene, SSIM per technique (one series
/// per size); per scene of a resolution or density sweep, the scaling curves (total and
/// overhead over No AA).
pub fn write_charts(
    report: &BenchReport,
    dir: &Path,
    policy: &Overwrite,
) -> Result<Vec<PathBuf>, ChartError> {
    let mut written = time_charts(report, dir, policy)?;
    if report.settings.quality {
        written.extend(tradeoff_charts(report, dir, policy)?);
        written.extend(ssim_charts(report, dir, policy)?);
    }
    if let Some(by) = scaling_sweep(report) {
        written.extend(scaling_charts(report, by, dir, policy)?);
    }
    Ok(written)
}

/// Per run: each technique's GPU time, its scene render and its own passes stacked.
fn time_charts(
    report: &BenchReport,
    dir: &Path,
    policy: &Overwrite,
) -> Result<Vec<PathBuf>, ChartError> {
    let mut written = Vec::new();
    for run in &report.runs {
        let names: Vec<String> = run.techniques.iter().map(|t| t.name.clone()).collect();
        let series = vec![
            BarSeries {
                name: "scene render it reads".to_owned(),
                values: run.techniques.iter().map(|t| t.input_ms.median).collect(),
            },
            BarSeries {
                name: "its own passes".to_owned(),
                values: run.techniques.iter().map(|t| t.own_ms.median).collect(),
            },
        ];
        let path = dir.join(format!("time-{}.png", run.key()));
        let title = format!(
            "GPU time per frame, {} {}x{} ({})",
            run.scene, run.width, run.height, report.adapter.adapter_name
        );
        draw_bars(
            &path,
            &BarChart {
                title: &title,
                value_label: "GPU milliseconds per frame (median), technique alone",
                categories: &names,
                series: &series,
                layout: BarLayout::Stacked,
                range: None,
                decimals: if run.techniques.iter().any(|t| t.total_ms.median >= 100.0) {
                    0
                } else {
                    2
                },
            },
            policy,
        )?;
        written.push(path);
    }
    Ok(written)
}

/// Per run: SSIM against GPU time, one point per technique and the Pareto front; in a scale
/// sweep also FLIP, each technique's points at every scale in its colour.
fn tradeoff_charts(
    report: &BenchReport,
    dir: &Path,
    policy: &Overwrite,
) -> Result<Vec<PathBuf>, ChartError> {
    let by_scale = is_scale_sweep(report);
    let metrics: &[Metric] = if by_scale {
        &[Metric::Ssim, Metric::Flip]
    } else {
        &[Metric::Ssim]
    };
    let mut written = Vec::new();
    for run in &report.runs {
        for &metric in metrics {
            let (points, groups) = tradeoff_points(run, metric, by_scale);
            if points.is_empty() {
                continue;
            }
            let path = dir.join(tradeoff_chart_name(run, metric));
            let title = format!(
                "{} against cost{}, {} {}x{} ({})",
                metric.name().to_uppercase(),
                if by_scale {
                    " at every render scale"
                } else {
                    ""
                },
                run.scene,
                run.width,
                run.height,
                report.adapter.adapter_name
            );
            let y_label = match metric {
                Metric::Flip => "FLIP against the 64-sample reference (lower is better)",
                _ => "SSIM against the 64-sample reference",
            };
            draw_tradeoff(
                &path,
                &TradeoffChart {
                    title: &title,
                    x_label: "GPU milliseconds per frame (median), technique alone",
                    y_label,
                    points: &points,
                    lower_is_better: metric == Metric::Flip,
                    groups: &groups,
                },
                policy,
            )?;
            written.push(path);
        }
    }
    Ok(written)
}

/// Per scene: each technique's SSIM, one bar per size.
fn ssim_charts(
    report: &BenchReport,
    dir: &Path,
    policy: &Overwrite,
) -> Result<Vec<PathBuf>, ChartError> {
    let mut written = Vec::new();
    for scene in scenes(report) {
        let runs: Vec<&RunReport> = report.runs.iter().filter(|r| r.scene == scene).collect();
        let columns = technique_columns(report);
        let names: Vec<String> = columns.iter().map(|(_, n)| n.clone()).collect();
        let series: Vec<BarSeries> = runs
            .iter()
            .map(|r| BarSeries {
                name: format!("{}x{}", r.width, r.height),
                values: columns
                    .iter()
                    .map(|(id, _)| {
                        r.technique(id)
                            .and_then(|t| t.quality)
                            .map_or(f64::NAN, |q| q.ssim)
                    })
                    .collect(),
            })
            .collect();
        let lowest = series
            .iter()
            .flat_map(|s| s.values.iter().copied())
            .filter(|v| v.is_finite())
            .fold(1.0, f64::min);
        let floor = ((lowest - 0.05) * 10.0).floor() / 10.0;
        let path = dir.join(format!("ssim-{scene}.png"));
        let title = format!("SSIM against 64-sample SSAA, {scene}");
        draw_bars(
            &path,
            &BarChart {
                title: &title,
                value_label: "mean SSIM (luma), 1 = identical to the reference",
                categories: &names,
                series: &series,
                layout: BarLayout::Grouped,
                range: Some((floor.clamp(0.0, 0.9), 1.0)),
                decimals: 3,
            },
            policy,
        )?;
        written.push(path);
    }
    Ok(written)
}

/// Per scene of a sweep (`by` density or resolution): GPU time and the time added over No AA
/// against the swept quantity.
fn scaling_charts(
    report: &BenchReport,
    by: &str,
    dir: &Path,
    policy: &Overwrite,
) -> Result<Vec<PathBuf>, ChartError> {
    let mut written = Vec::new();
    let x_label = if by == "density" {
        "millions of triangles"
    } else {
        "megapixels"
    };
    for scene in scenes(report) {
        let curves = scaling_curves(report, &scene, by);
        for (kind, title, log_y) in [
            ("total", "GPU ms per frame, technique alone", true),
            ("overhead", "GPU ms added over No AA", false),
        ] {
            let lines: Vec<Line> = curves
                .iter()
                .filter(|(id, _, _)| kind == "total" || id != aa::none::ID)
                .map(|(_, name, points)| Line {
                    name: name.clone(),
                    points: points
                        .iter()
                        .map(|p| {
                            (
                                p.x,
                                if kind == "total" {
                                    p.total_ms
                                } else {
                                    p.overhead_ms
                                },
                            )
                        })
                        .collect(),
                })
                .collect();
            let path = dir.join(format!("scaling-{by}-{scene}-{kind}.png"));
            let title = format!("{title}: {scene}, {by} sweep");
            draw_lines(
                &path,
                &LineChart {
                    title: &title,
                    x_label,
                    y_label: "GPU ms (median)",
                    lines: &lines,
                    log_y,
                },
                policy,
            )?;
            written.push(path);
        }
    }
    Ok(written)
}
