//! The bench engine: measures every chosen technique together in one frame graph, run after
//! run (a scene at a size), for `aa-lab bench` and the viewer alike. Per run, in order:
//! 1. timing: `warmup` + `frames` frames along a slow camera track ([`SlowTrack`]), every
//!    technique each frame, the GPU drained after each so every frame's timings are collected,
//!    with a full-screen copy pass alongside (the floor post-process passes are compared
//!    with); the last `flicker_frames` outputs of each technique go into a [`ChangeMeter`]
//!    (and their luma is kept for the ghosting measure);
//! 2. one more frame with pipeline-statistics queries on (fragment invocations; untimed);
//! 3. the reference (SSAA 8x8) on those same flicker frames, for the flicker ratio (the
//!    `temporal_instability` of `aa-lab clip`) and the ghosting measure
//!    ([`crate::metrics::stability`]);
//! 4. quality: `spec::run` of frame `quality_frame` of the scene's own camera path (exactly
//!    what `aa-lab render --from <run>.spec.json` reproduces) and of the reference, scored
//!    with every metric (against the exact coverage too on `chart`);
//! 5. with a [`JodScorer`] ([`BenchRunner::run_scored`]), each technique's ColorVideoVDP JOD
//!    over the flicker frames against the reference's, played at [`JOD_FPS`]: the flicker
//!    frames are then kept whole (every technique's and the reference's) until it is scored.
//!
//! The front end loads each run's scene, may set its camera, says how it shows progress
//! ([`BenchProgress`]) and writes the reports ([`RunReport::write_sidecars`], the run's
//! [`crate::export::report::BenchReport`]).

use crate::graph::hdr::TonemapChoice;
use std::path::PathBuf;

use super::{QualityScores, TRACK_STEP_PX, TimingSamples, sum_samples};
use crate::aa::floor::{COPY_FLOOR_ID, CopyFloor};
use crate::aa::{self, FrameInfo, SceneInput};
use crate::export::charts::ChartError;
use crate::export::heatmap::{HeatmapStyle, write_heatmap};
use crate::export::report::{
    BenchSettings, InputReport, Invocations, MemorySummary, PassReport, QualityFronts, RunReport,
    TechniqueReport,
};
use crate::export::{ExportError, write_png};
use crate::files::Overwrite;
use crate::gpu::readback::ReadbackError;
use crate::gpu::{Gpu, read_texture_rgba8};
use crate::graph::overlay::OverlayOrder;
use crate::graph::{FrameGraph, FrameScope, FrameStatistics, GraphError, MemoryReport};
use crate::metrics::coverage::chart_truth;
use crate::metrics::jod::JodScorer;
use crate::metrics::stability::MovingEdgeError;
use crate::metrics::temporal::{ChangeMeter, SlowTrack, flicker_ratio};
use crate::metrics::{
    Comparison, ComparisonMaps, Metric, MetricsError, Plane, Summary, compare_with_maps,
};
use crate::scene::Scene;
use crate::scene::procedural::chart_layout;
use crate::spec::{self, RenderSpec, RunOptions, TechniqueImage, TechniqueSpec};

/// Errors of a bench run.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// A technique, a frame or a readback of a spec failed.
    #[error(transparent)]
    Render(#[from] spec::RenderError),
    /// A frame of the timing or flicker loop failed.
    #[error(transparent)]
    Graph(#[from] GraphError),
    /// Reading an output back failed.
    #[error(transparent)]
    Readback(#[from] ReadbackError),
    /// Two images could not be compared.
    #[error(transparent)]
    Metrics(#[from] MetricsError),
    /// An image could not be written.
    #[error(transparent)]
    Export(#[from] ExportError),
    /// A heatmap could not be drawn or written.
    #[error(transparent)]
    Chart(#[from] ChartError),
    /// A record could not be serialised.
    #[error("cannot serialise a record: {0}")]
    Record(#[from] serde_json::Error),
    /// The adapter gave no timings.
    #[error("{0} returned no GPU timings (timestamp queries unsupported?)")]
    NoTimings(String),
    /// The reference rendered nothing.
    #[error("the reference produced no image")]
    NoReferenceImage,
    /// The front end stopped the bench ([`BenchProgress::cancelled`]).
    #[error("the bench was cancelled")]
    Cancelled,
}

/// One run to measure: a scene (built-in name or model path) at a density and a size.
#[derive(Clone, Debug)]
pub struct RunPlan {
    /// The scene as loaded (`hairball`, a path).
    pub scene: String,
    /// Hairball density.
    pub density: f32,
    /// Image size.
    pub size: (u32, u32),
}

/// How a front end hears of a bench's progress.
pub trait BenchProgress {
    /// The run is in a new phase (`warm-up`, `timed frames`, `quality frame`...).
    fn phase(&self, run: &RunPlan, phase: &str);
    /// `steps` more of the run's [`BenchOptions::steps_per_run`] are done.
    fn advance(&self, steps: u64);

    /// Whether the bench should stop: the runner looks before every frame and phase, and
    /// ends the run with [`BenchError::Cancelled`].
    fn cancelled(&self) -> bool {
        false
    }
}

/// Where the quality frame's images and FLIP heatmaps go, when they are kept.
#[derive(Clone, Debug)]
pub struct ImageOutput {
    /// The folder.
    pub folder: PathBuf,
    /// The overwrite policy of the bench's outputs.
    pub policy: Overwrite,
}

impl ImageOutput {
    /// Writes technique `image`'s quality frame (with its record) and its FLIP heatmap
    /// (with the scores and both records), under the run's `key`.
    fn write(
        &self,
        key: &str,
        (spec, reference_spec): (&RenderSpec, &RenderSpec),
        image: &TechniqueImage,
        quality: &Comparison,
        maps: &ComparisonMaps,
    ) -> Result<(), BenchError> {
        let name = aa::user::file_name_part(&image.id);
        let record = serde_json::to_string_pretty(spec)?;
        write_png(
            &self.folder.join(format!("{key}-{name}.png")),
            &image.image,
            Some(&record),
            &self.policy,
        )?;
        let sidecar = serde_json::json!({
            "heatmap": { "metric": Metric::Flip, "technique": image.id, "scores": quality },
            "spec": spec,
            "reference": reference_spec,
        });
        write_heatmap(
            &self.folder.join(format!("{key}-{name}-flip.png")),
            &maps.error_map(Metric::Flip),
            &HeatmapStyle {
                legend: Metric::Flip.legend(),
                range: (0.0, 1.0),
            },
            Some(&serde_json::to_string_pretty(&sidecar)?),
            &self.policy,
        )?;
        Ok(())
    }
}

/// Untimed frames before the timed ones, unless a front end says otherwise.
pub const DEFAULT_WARMUP: u32 = 3;
/// The last timed frames read back for the flicker ratio, by default.
pub const DEFAULT_FLICKER_FRAMES: u32 = 4;
/// The frame of the scene's camera path scored for quality, by default.
pub const DEFAULT_QUALITY_FRAME: u64 = 16;
/// The rate the flicker frames are played at for JOD, frames per second.
pub const JOD_FPS: f32 = 30.0;

/// What a bench measures in each run.
#[derive(Clone, Debug)]
pub struct BenchOptions {
    /// Frames rendered before the timed ones.
    pub warmup: u32,
    /// Timed frames.
    pub frames: u32,
    /// The last timed frames whose outputs are measured for flicker (at most `frames`).
    pub flicker_frames: u32,
    /// The frame of the scene's camera path scored for quality.
    pub quality_frame: u64,
    /// Whether flicker and quality are measured (not in a sweep, not with `--no-quality`).
    pub quality: bool,
    /// Seed of the procedural scenes.
    pub seed: u64,
    /// Geometric specular antialiasing in the techniques' scene renders (never the
    /// reference's).
    pub specular_aa: bool,
    /// How the scenes' radiance is displayed (`auto`: HDR scenes through the default
    /// tonemapper), and the exposure of HDR renders.
    pub tonemap: TonemapChoice,
    /// Exposure of HDR renders in stops.
    pub exposure: f32,
    /// Where the quality images go, when kept.
    pub images: Option<ImageOutput>,
    /// The UI overlay over every frame, and where it is drawn.
    pub overlay: Option<OverlayOrder>,
}

impl BenchOptions {
    /// Frames of the timing loop, warm-up included.
    fn total_frames(&self) -> u64 {
        u64::from(self.warmup) + u64::from(self.frames)
    }

    /// Flicker frames actually measured.
    pub fn flicker_frames(&self) -> u32 {
        if self.quality {
            self.flicker_frames.min(self.frames)
        } else {
            0
        }
    }

    /// Progress steps of one run: its frames, the statistics frame and, with quality, the
    /// reference's flicker frames and the two quality renders.
    pub fn steps_per_run(&self) -> u64 {
        let timing = self.total_frames() + 1;
        if self.quality {
            timing + u64::from(self.flicker_frames()) + self.quality_frame + 2
        } else {
            timing
        }
    }
}

/// What the timing phase of a run leaves for its report.
struct Timed {
    /// The timed frames' GPU times.
    samples: TimingSamples,
    /// Per technique: its change meter over the flicker frames and their luma.
    meters: Vec<(String, ChangeMeter, Vec<Plane>)>,
    /// Per technique, in the order of `meters`: its flicker frames, whole, when they are kept
    /// for JOD (empty otherwise).
    frames: Vec<Vec<image::RgbaImage>>,
    /// Fragment invocations of the statistics frame, when the adapter counts them.
    statistics: Option<FrameStatistics>,
    /// The graph's memory after the timed frames.
    memory: MemoryReport,
    /// Scene renders per frame.
    scene_renders: usize,
    /// Each technique's scene input, for techniques whose timings never showed it.
    slot_info: Vec<(String, Option<SceneInput>)>,
}

/// The reference's change over the flicker frames, and each technique's ghosting meter.
struct Flicker {
    /// The reference's change meter.
    reference: ChangeMeter,
    /// Each technique's error at moving edges, in the order of [`Timed::meters`].
    ghosts: Vec<MovingEdgeError>,
    /// The reference's flicker frames, whole, when they are kept for JOD.
    frames: Vec<image::RgbaImage>,
}

/// Measures runs of `techniques` against `reference` on `gpu` (see the module docs).
pub struct BenchRunner<'a> {
    /// The device everything renders on.
    pub gpu: &'a Gpu,
    /// What each run measures.
    pub options: BenchOptions,
    /// The techniques, with their settings.
    pub techniques: Vec<TechniqueSpec>,
    /// The reference (SSAA with [`super::REFERENCE_FACTOR`]^2 samples,
    /// [`super::reference_spec`]).
    pub reference: TechniqueSpec,
    /// Where progress goes.
    pub progress: &'a dyn BenchProgress,
}

impl BenchRunner<'_> {
    /// The render record of `run` with `techniques`, at the quality frame.
    fn spec(&self, run: &RunPlan, techniques: Vec<TechniqueSpec>) -> RenderSpec {
        RenderSpec {
            scene: run.scene.clone(),
            density: run.density,
            seed: self.options.seed,
            specular_aa: self.options.specular_aa,
            tonemap: self.options.tonemap,
            exposure: self.options.exposure,
            width: run.size.0,
            height: run.size.1,
            frame: self.options.quality_frame,
            camera: None,
            rig: None,
            image: None,
            techniques,
            overlay: self.options.overlay,
            adapter: Some(format!(
                "{} ({})",
                self.gpu.caps.adapter_name, self.gpu.caps.backend
            )),
            build: Some(spec::build_id()),
        }
    }

    /// Reads every technique's current output into its change meter, and keeps its luma
    /// for the ghosting measure against the reference frames rendered later (and, when
    /// `frames` has a list per meter, the whole image, for JOD).
    fn read_outputs(
        &self,
        graph: &FrameGraph,
        meters: &mut [(String, ChangeMeter, Vec<Plane>)],
        frames: &mut [Vec<image::RgbaImage>],
    ) -> Result<(), BenchError> {
        for slot in graph.slots() {
            let id = slot.technique.id();
            let Some(index) = meters.iter().position(|(m, _, _)| m == id) else {
                continue;
            };
            let Some(output) = slot.output() else {
                continue;
            };
            let image = read_texture_rgba8(self.gpu, output)?;
            let (_, meter, lumas) = &mut meters[index];
            meter.push(&image);
            lumas.push(Plane::luma(&image));
            if let Some(kept) = frames.get_mut(index) {
                kept.push(image);
            }
        }
        Ok(())
    }

    /// The bench's settings for its report: `techniques` (the ids asked for), what each run
    /// measured and the `sweep`, if any.
    pub fn settings(&self, techniques: Vec<String>, sweep: Option<String>) -> BenchSettings {
        let options = &self.options;
        BenchSettings {
            techniques,
            frames: options.frames,
            warmup: options.warmup,
            flicker_frames: options.flicker_frames(),
            track_step_px: TRACK_STEP_PX,
            quality_frame: options.quality_frame,
            quality: options.quality,
            reference: self.reference.clone(),
            sweep,
            scales: None,
            jod: None,
            specular_aa: options.specular_aa,
            tonemap: options.tonemap,
            exposure: options.exposure,
        }
    }

    /// [`BenchError::Cancelled`] once the front end asks the bench to stop.
    fn stop_if_cancelled(&self) -> Result<(), BenchError> {
        if self.progress.cancelled() {
            return Err(BenchError::Cancelled);
        }
        Ok(())
    }

    /// The render records of `run`: the techniques' and the reference's, at the quality
    /// frame of the scene's own camera path. A front end may set their camera (`rig`,
    /// `camera`) before [`BenchRunner::run`].
    pub fn specs(&self, run: &RunPlan) -> (RenderSpec, RenderSpec) {
        (
            self.spec(run, self.techniques.clone()),
            RenderSpec {
                specular_aa: false,
                ..self.spec(run, vec![self.reference.clone()])
            },
        )
    }

    /// Measures `run` on `scene` (loaded as `run` says) with the records of
    /// [`BenchRunner::specs`]: the phases of the module docs but JOD, then the run's report.
    pub fn run(
        &self,
        run: &RunPlan,
        scene: &Scene,
        spec: RenderSpec,
        reference_spec: RenderSpec,
    ) -> Result<RunReport, BenchError> {
        self.run_scored(run, scene, spec, reference_spec, None)
    }

    /// [`BenchRunner::run`], and with `jod` each technique's JOD over the flicker frames
    /// (phase 5 of the module docs) in its report.
    pub fn run_scored(
        &self,
        run: &RunPlan,
        scene: &Scene,
        spec: RenderSpec,
        reference_spec: RenderSpec,
        jod: Option<&JodScorer>,
    ) -> Result<RunReport, BenchError> {
        let options = &self.options;
        let track = SlowTrack::new(&scene.camera, run.size, TRACK_STEP_PX);
        let flicker_frames = options.flicker_frames();
        let keep = jod.is_some() && flicker_frames > 0;
        let timed = self.time(run, scene, &spec, &track, (flicker_frames, keep))?;
        let flicker = self.reference_flicker(
            run,
            scene,
            &reference_spec,
            &track,
            (flicker_frames, keep),
            &timed.meters,
        )?;
        // 4. Quality on the scene's own camera path.
        let (scores, hdr_flips) = if options.quality {
            self.quality(run, scene, &spec, &reference_spec)?
        } else {
            (Vec::new(), Vec::new())
        };
        let floor_ms = Summary::of(&timed.samples.floor);
        let mut techniques =
            self.technique_reports(run, &timed, &scores, &flicker, floor_ms.median);
        for (id, score) in hdr_flips {
            if let Some(report) = techniques.iter_mut().find(|t| t.id == id) {
                report.hdr_flip = Some(score);
            }
        }
        if let (Some(scorer), true) = (jod, keep) {
            self.stop_if_cancelled()?;
            self.progress.phase(run, "ColorVideoVDP");
            let jods = scorer.score_each(&timed.frames, &flicker.frames, JOD_FPS, |_| ())?;
            for (report, jod) in techniques.iter_mut().zip(jods) {
                report.jod = Some(jod);
            }
        }
        let quality_fronts = QualityFronts::of(&techniques);
        let floor_bytes = timed
            .memory
            .techniques
            .iter()
            .find(|m| m.technique == COPY_FLOOR_ID)
            .map_or(0, |m| m.own_bytes());
        Ok(RunReport {
            // Model files get a hash of their path, so two `sponza.obj` never share files.
            scene: crate::export::output_stem(&scene.name, &run.scene),
            density: run.density,
            triangles: scene.triangle_count(),
            width: run.size.0,
            height: run.size.1,
            spec,
            reference_spec,
            scene_renders_per_frame: timed.scene_renders,
            frame_ms: Summary::of(&timed.samples.frame),
            floor_ms,
            inputs: timed
                .samples
                .inputs
                .iter()
                .map(|i| InputReport {
                    label: i.label.clone(),
                    users: i.users.clone(),
                    ms: Summary::of(&i.ms),
                    fragment_invocations: i.invocations,
                })
                .collect(),
            techniques,
            reference_change: flicker.reference.mean_change(),
            memory_total_bytes: timed.memory.total_bytes - floor_bytes,
            quality_fronts,
        })
    }

    /// Steps 1 and 2 (module docs): the timed frames along the slow track with the copy
    /// floor alongside, the last ones read into the change meters, then one statistics frame.
    fn time(
        &self,
        run: &RunPlan,
        scene: &Scene,
        spec: &RenderSpec,
        track: &SlowTrack,
        (flicker_frames, keep): (u32, bool),
    ) -> Result<Timed, BenchError> {
        let options = &self.options;
        let mut graph = spec::build_graph(self.gpu, scene, spec)?;
        graph.add(Box::new(CopyFloor::new(self.gpu)));
        let ids: Vec<&'static str> = graph
            .slots()
            .iter()
            .map(|s| s.technique.id())
            .filter(|id| *id != COPY_FLOOR_ID)
            .collect();
        let mut samples = TimingSamples::new(&ids);
        let mut meters: Vec<(String, ChangeMeter, Vec<Plane>)> = ids
            .iter()
            .map(|id| ((*id).to_owned(), ChangeMeter::new(), Vec::new()))
            .collect();
        let mut frames = vec![Vec::new(); if keep { ids.len() } else { 0 }];
        let total_frames = options.total_frames();
        let flicker_from = total_frames - u64::from(flicker_frames);
        for frame in 0..total_frames {
            self.stop_if_cancelled()?;
            self.progress.phase(
                run,
                if frame < u64::from(options.warmup) {
                    "warm-up"
                } else {
                    "timed frames"
                },
            );
            let info = FrameInfo {
                camera: track.camera(frame),
                reset_history: frame == 0,
            };
            graph.render(&info, FrameScope::All)?;
            graph.finish();
            if frame >= u64::from(options.warmup) {
                let timings = graph
                    .timings()
                    .ok_or_else(|| BenchError::NoTimings(self.gpu.caps.adapter_name.clone()))?;
                samples.add(timings, &graph.scene_inputs_last_frame());
            }
            if frame >= flicker_from {
                self.read_outputs(&graph, &mut meters, &mut frames)?;
            }
            self.progress.advance(1);
        }
        // 2. Fragment invocations on one more (untimed) frame; a frame with more passes than
        // the query set held is rendered again.
        self.progress.phase(run, "pipeline statistics");
        let mut statistics = None;
        if graph.set_pipeline_statistics(true) {
            for _ in 0..2 {
                let info = FrameInfo {
                    camera: track.camera(total_frames),
                    reset_history: false,
                };
                graph.render(&info, FrameScope::All)?;
                if let Some(s) = graph.pipeline_statistics() {
                    statistics = Some(s.clone());
                    break;
                }
            }
            graph.set_pipeline_statistics(false);
        }
        if let Some(s) = &statistics {
            samples.add_statistics(s, &graph.scene_inputs_last_frame());
        }
        self.progress.advance(1);
        let memory = graph.memory_report();
        let scene_renders = graph.scene_renders_last_frame();
        let slot_info: Vec<(String, Option<SceneInput>)> = graph
            .slots()
            .iter()
            .map(|s| {
                let info = FrameInfo {
                    camera: track.camera(total_frames),
                    reset_history: false,
                };
                (s.technique.id().to_owned(), s.technique.scene_input(&info))
            })
            .collect();
        Ok(Timed {
            samples,
            meters,
            frames,
            statistics,
            memory,
            scene_renders,
            slot_info,
        })
    }

    /// Step 3 (module docs): the reference over the flicker frames, and each technique's error
    /// where the reference moved.
    fn reference_flicker(
        &self,
        run: &RunPlan,
        scene: &Scene,
        reference_spec: &RenderSpec,
        track: &SlowTrack,
        (flicker_frames, keep): (u32, bool),
        meters: &[(String, ChangeMeter, Vec<Plane>)],
    ) -> Result<Flicker, BenchError> {
        let total_frames = self.options.total_frames();
        let flicker_from = total_frames - u64::from(flicker_frames);
        let mut reference_meter = ChangeMeter::new();
        let mut ghosts: Vec<MovingEdgeError> =
            meters.iter().map(|_| MovingEdgeError::new()).collect();
        let mut reference_previous: Option<Plane> = None;
        let mut frames = Vec::new();
        if flicker_frames > 0 {
            self.progress.phase(run, "reference for flicker");
            let mut reference = spec::build_graph(self.gpu, scene, reference_spec)?;
            for frame in flicker_from..total_frames {
                self.stop_if_cancelled()?;
                let info = FrameInfo {
                    camera: track.camera(frame),
                    reset_history: frame == flicker_from,
                };
                reference.render(&info, FrameScope::All)?;
                reference.finish();
                if let Some(output) = reference.slots().first().and_then(|s| s.output()) {
                    let image = read_texture_rgba8(self.gpu, output)?;
                    reference_meter.push(&image);
                    let luma = Plane::luma(&image);
                    if let Some(previous) = &reference_previous {
                        let step = (frame - flicker_from) as usize;
                        for ((_, _, lumas), ghost) in meters.iter().zip(&mut ghosts) {
                            if let Some(technique) = lumas.get(step) {
                                ghost.push(technique, &luma, previous)?;
                            }
                        }
                    }
                    reference_previous = Some(luma);
                    if keep {
                        frames.push(image);
                    }
                }
                self.progress.advance(1);
            }
        }

        Ok(Flicker {
            reference: reference_meter,
            ghosts,
            frames,
        })
    }

    /// Each technique's report from the run's measurements.
    fn technique_reports(
        &self,
        run: &RunPlan,
        timed: &Timed,
        scores: &[QualityScores],
        flicker: &Flicker,
        floor_median_ms: f64,
    ) -> Vec<TechniqueReport> {
        let Timed {
            samples,
            meters,
            statistics,
            memory,
            slot_info,
            ..
        } = timed;
        let none_total = samples
            .techniques
            .iter()
            .find(|(id, _)| id == aa::none::ID)
            .map(|(_, s)| Summary::of(&sum_samples(&s.own, &s.input)).median);
        let pixels = f64::from(run.size.0) * f64::from(run.size.1);
        samples
            .techniques
            .iter()
            .zip(&self.techniques)
            .map(|((id, s), technique_spec)| {
                let total = Summary::of(&sum_samples(&s.own, &s.input));
                let own = Summary::of(&s.own);
                let input_label = s.input_label.clone().or_else(|| {
                    slot_info
                        .iter()
                        .find(|(i, _)| i == id)
                        .and_then(|(_, input)| input.map(|x| x.label()))
                });
                let post_process = s.input_label.is_some() && s.post_process && id != aa::none::ID;
                let invocations = statistics.as_ref().map(|st| {
                    let own = st.technique_invocations(id);
                    let input = samples
                        .inputs
                        .iter()
                        .find(|i| i.users.iter().any(|u| u == id))
                        .and_then(|i| i.invocations)
                        .unwrap_or(0);
                    Invocations {
                        own,
                        input,
                        total: own + input,
                        per_pixel: (own + input) as f64 / pixels,
                    }
                });
                let memory = memory
                    .techniques
                    .iter()
                    .find(|m| m.technique == *id)
                    .map(|m| MemorySummary {
                        standalone_bytes: m.standalone_bytes(),
                        own_bytes: m.own_bytes(),
                        input_bytes: m.input_bytes(),
                    });
                let (quality, truth) = scores
                    .iter()
                    .find(|(i, _, _)| i == id)
                    .map_or((None, None), |(_, q, t)| (Some(*q), *t));
                let index = meters.iter().position(|(m, _, _)| m == id);
                let meter = index.map(|i| &meters[i].1);
                let ghosting = index.and_then(|i| flicker.ghosts[i].ghosting());
                TechniqueReport {
                    id: id.clone(),
                    name: aa::registry::display_name(id),
                    render_scale: aa::combo::Combo::parse(id).map_or(1.0, |c| c.scale),
                    input: input_label,
                    post_process,
                    settings: technique_spec.settings.clone(),
                    passes: s
                        .passes
                        .iter()
                        .map(|(label, count, ms)| PassReport {
                            label: label.clone(),
                            count: *count,
                            ms: Summary::of(ms),
                            fragment_invocations: statistics.as_ref().and_then(|st| {
                                st.passes
                                    .iter()
                                    .filter(|p| p.label == *label)
                                    .map(|p| p.fragment_invocations)
                                    .reduce(|a, b| a + b)
                            }),
                        })
                        .collect(),
                    own_ms: own,
                    input_ms: Summary::of(&s.input),
                    relative_to_none: none_total.filter(|n| *n > 0.0).map(|n| total.median / n),
                    floor_multiple: (post_process && floor_median_ms > 0.0)
                        .then(|| own.median / floor_median_ms),
                    total_ms: total,
                    memory,
                    fragment_invocations: invocations,
                    quality,
                    truth,
                    hdr_flip: None,
                    mean_change: meter.and_then(ChangeMeter::mean_change),
                    flicker_ratio: meter.and_then(|m| flicker_ratio(m, &flicker.reference)),
                    ghosting,
                    jod: None,
                }
            })
            .collect()
    }

    /// Renders the quality frame of every technique and the reference and scores them; on the
    /// chart also against the exact coverage. Returns (id, vs reference, vs truth), and the
    /// HDR-FLIP of every technique whose radiance can be scored against the reference's (both
    /// ran before the tonemapper of an HDR frame).
    fn quality(
        &self,
        run: &RunPlan,
        scene: &Scene,
        spec: &RenderSpec,
        reference_spec: &RenderSpec,
    ) -> Result<(Vec<QualityScores>, super::HdrFlipScores), BenchError> {
        self.stop_if_cancelled()?;
        self.progress.phase(run, "quality frame");
        let reported = std::cell::Cell::new(0);
        let progress = |done: u64, _total: u64| {
            self.progress
                .advance(done.saturating_sub(reported.replace(done)));
        };
        let options = RunOptions {
            debug_views: false,
            timing_repeats: 0,
            progress: Some(&progress),
            image: None,
            radiance: true,
        };
        let output = spec::run(self.gpu, scene, spec, &options)?;
        self.progress
            .advance((spec.frame + 1).saturating_sub(reported.get()));
        self.stop_if_cancelled()?;
        self.progress.phase(run, "reference frame");
        let reference_options = RunOptions {
            radiance: true,
            ..RunOptions::default()
        };
        let reference = spec::run(self.gpu, scene, reference_spec, &reference_options)?;
        let hdr_flips = super::hdr_flips(&reference, &output)?;
        self.progress.advance(1);
        let reference_image = reference
            .images
            .into_iter()
            .next()
            .ok_or(BenchError::NoReferenceImage)?
            .image;
        let truth = (scene.name == "chart").then(|| chart_truth(&chart_layout(), run.size));
        let key = format!("{}-{}x{}", run.scene, run.size.0, run.size.1);
        if let Some(images) = &self.options.images {
            let record = serde_json::to_string_pretty(reference_spec)?;
            write_png(
                &images.folder.join(format!("{key}-reference.png")),
                &reference_image,
                Some(&record),
                &images.policy,
            )?;
        }
        let mut scores = Vec::new();
        for image in output.images.iter().filter(|i| i.view.is_none()) {
            self.progress
                .phase(run, &format!("metrics of {}", image.id));
            let (quality, maps) = compare_with_maps(&reference_image, &image.image)?;
            let truth_score = truth
                .as_ref()
                .map(|t| -> Result<Comparison, BenchError> {
                    let (_, maps) = compare_with_maps(&t.image, &image.image)?;
                    Ok(maps.pool(Some(&t.mask)))
                })
                .transpose()?;
            if let Some(images) = &self.options.images {
                images.write(&key, (spec, reference_spec), image, &quality, &maps)?;
            }
            scores.push((image.id.clone(), quality, truth_score));
        }
        Ok((scores, hdr_flips))
    }
}
