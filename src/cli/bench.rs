//! `aa-lab bench`: for every scene x size (or every point of a sweep), runs all chosen
//! techniques together in one frame graph and measures each one: GPU time per pass and in total
//! (median and 95th percentile over the timed frames), cost relative to No AA and to a
//! full-screen copy pass, memory, fragment-shader invocations, image quality against a 64-sample
//! SSAA reference (SSIM, PSNR, MAE, FLIP; against the exact coverage too on `chart`) and the
//! flicker ratio. Writes `report.json`, `report.md`, charts and reproducibility sidecars.
//!
//! Per run, in order:
//! 1. timing: `--warmup` + `--frames` frames along a slow camera track ([`SlowTrack`]), every
//!    technique each frame, the GPU drained after each so every frame's timings are collected;
//!    the last `--flicker-frames` outputs of each technique go into a [`ChangeMeter`] (and
//!    their luma is kept for the ghosting measure);
//! 2. one more frame with pipeline-statistics queries on (fragment invocations; untimed);
//! 3. the reference (SSAA 8x8) on those same flicker frames, for the flicker ratio (the
//!    `temporal_instability` of `aa-lab clip`) and the ghosting measure
//!    ([`crate::metrics::stability`]);
//! 4. quality: `spec::run` of frame `--quality-frame` of the scene's own camera path (exactly
//!    what `aa-lab render --from <run>.spec.json` reproduces) and of the reference, scored
//!    with every metric.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, bail};
use indicatif::{ProgressBar, ProgressStyle};

use super::render::{configured_specs, parse_size, set_flags, technique_ids};
use crate::aa::floor::{COPY_FLOOR_ID, CopyFloor};
use crate::aa::{self, FrameInfo, SceneInput};
use crate::bench::{
    Flicker, QualityScores, TRACK_STEP_PX, Timed, TimingSamples, reference_spec, sum_samples,
};
use crate::export::heatmap::{HeatmapStyle, write_heatmap};
use crate::export::report::{
    self, BenchReport, BenchSettings, InputReport, Invocations, MemorySummary, PassReport,
    RunReport, TechniqueReport,
};
use crate::export::write_png;
use crate::files::{self, Overwrite};
use crate::gpu::{Gpu, read_texture_rgba8};
use crate::graph::{FrameGraph, FrameScope};
use crate::metrics::coverage::chart_truth;
use crate::metrics::stability::MovingEdgeError;
use crate::metrics::temporal::{ChangeMeter, SlowTrack, flicker_ratio};
use crate::metrics::{Comparison, Metric, Plane, Summary, compare_with_maps};
use crate::scene::Scene;
use crate::scene::procedural::{SceneOptions, chart_layout};
use crate::scene::source;
use crate::spec::{self, RenderSpec, RunOptions, TechniqueSpec};

/// Image sizes of `--sweep resolution`: 720p to 4K.
pub const RESOLUTION_SWEEP: [(u32, u32); 4] =
    [(1280, 720), (1920, 1080), (2560, 1440), (3840, 2160)];
/// Hairball densities of `--sweep density`: about 100k to 2.1M triangles.
pub const DENSITY_SWEEP: [f32; 5] = [0.34, 1.0, 2.0, 4.0, 7.0];

/// What a sweep varies.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Sweep {
    /// Image size from 1280x720 to 3840x2160.
    Resolution,
    /// Hairball triangle count from about 100k to 2.1M.
    Density,
}

/// Arguments of `aa-lab bench`.
#[derive(Debug, clap::Args)]
pub struct BenchArgs {
    /// Comma-separated scenes (hairball, atrium, chart or .obj/.gltf/.glb paths).
    #[arg(long, default_value = "hairball,atrium")]
    pub scene: String,
    /// Comma-separated technique ids, or `all` (every technique this adapter can run).
    #[arg(long, short, default_value = "all")]
    pub technique: String,
    /// Apply a preset: TECHNIQUE=PRESET (repeatable), e.g. taa=fast.
    #[arg(long, value_name = "TECHNIQUE=PRESET")]
    pub preset: Vec<String>,
    /// Set any parameter: TECHNIQUE.KEY=VALUE (repeatable), e.g. taa.velocity=own.
    #[arg(long = "set", value_name = "TECHNIQUE.KEY=VALUE")]
    pub set: Vec<String>,
    /// Comma-separated image sizes, WIDTHxHEIGHT.
    #[arg(long, default_value = "1280x720")]
    pub size: String,
    /// Timed frames per run (1 to 100000).
    #[arg(long, default_value_t = 60, value_parser = clap::value_parser!(u32).range(1..=MAX_FRAMES))]
    pub frames: u32,
    /// Untimed frames before the timed ones (shader compilation, caches, temporal history;
    /// 0 to 100000).
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(0..=MAX_FRAMES))]
    pub warmup: u32,
    /// Timed frames (the last ones) read back for the flicker ratio; 0 skips flicker.
    #[arg(long, default_value_t = 4)]
    pub flicker_frames: u32,
    /// Frame of each scene's camera path whose images are scored against the reference.
    #[arg(long, default_value_t = 16, value_parser = clap::value_parser!(u64).range(0..=spec::MAX_FRAME))]
    pub quality_frame: u64,
    /// Measure cost only: no reference renders, no image metrics, no flicker.
    #[arg(long)]
    pub no_quality: bool,
    /// Scaling sweep (cost only): `resolution` (720p to 4K) or `density` (hairball, about
    /// 100k to 2.1M triangles).
    #[arg(long, value_enum)]
    pub sweep: Option<Sweep>,
    /// Built-in scene density (hairball triangle scale).
    #[arg(long, default_value_t = 1.0)]
    pub density: f32,
    /// Built-in scene seed.
    #[arg(long, default_value_t = SceneOptions::default().seed)]
    pub seed: u64,
    /// Output directory for report.json, report.md, charts and sidecars.
    #[arg(long, short, default_value = "report")]
    pub out: PathBuf,
    /// Also write the scored images, the reference and FLIP heatmaps (PNG, with records).
    #[arg(long)]
    pub images: bool,
    /// Replace files of an earlier bench in --out (without it, aa-lab never replaces a file).
    #[arg(long)]
    pub force: bool,
    /// The camera of every scene, when not its default view (the timed frames then follow
    /// this camera's slow track).
    #[command(flatten)]
    pub camera: super::render::CameraArgs,
}

/// Most timed or warm-up frames per run.
const MAX_FRAMES: i64 = 100_000;

/// One run to measure.
#[derive(Clone, Debug)]
struct RunPlan {
    scene: String,
    density: f32,
    size: (u32, u32),
}

fn plan(args: &BenchArgs) -> anyhow::Result<Vec<RunPlan>> {
    let scenes: Vec<String> = args
        .scene
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(str::to_owned)
        .collect();
    if scenes.is_empty() {
        bail!("no scene given; use --scene with hairball, atrium, chart or an .obj path");
    }
    let sizes: Vec<(u32, u32)> = match args.sweep {
        Some(Sweep::Resolution) => RESOLUTION_SWEEP.to_vec(),
        _ => args
            .size
            .split(',')
            .map(|s| parse_size(s.trim()).map_err(anyhow::Error::msg))
            .collect::<anyhow::Result<_>>()?,
    };
    if let Some(&(w, h)) = sizes.iter().find(|(w, h)| *w == 0 || *h == 0) {
        bail!("--size {w}x{h}: width and height must be at least 1");
    }
    let mut runs = Vec::new();
    match args.sweep {
        Some(Sweep::Density) => {
            if scenes.iter().any(|s| s != "hairball") {
                eprintln!("--sweep density varies the hairball only; other scenes are skipped");
            }
            for &density in &DENSITY_SWEEP {
                for &size in &sizes {
                    runs.push(RunPlan {
                        scene: "hairball".to_owned(),
                        density,
                        size,
                    });
                }
            }
        }
        _ => {
            for scene in &scenes {
                for &size in &sizes {
                    runs.push(RunPlan {
                        scene: scene.clone(),
                        density: args.density,
                        size,
                    });
                }
            }
        }
    }
    Ok(runs)
}

/// The progress bar of the whole bench.
fn progress_bar(total: u64) -> ProgressBar {
    let bar = ProgressBar::new(total);
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] [{bar:32}] {pos}/{len} steps, eta {eta}  {msg}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> "),
    );
    bar.enable_steady_tick(std::time::Duration::from_millis(200));
    bar
}

struct Bench<'a> {
    gpu: &'a Gpu,
    args: &'a BenchArgs,
    policy: Overwrite,
    techniques: Vec<TechniqueSpec>,
    reference: TechniqueSpec,
    quality: bool,
    bar: ProgressBar,
}

/// Steps one run advances the progress bar by.
fn run_steps(args: &BenchArgs, quality: bool) -> u64 {
    let timing = u64::from(args.warmup) + u64::from(args.frames) + 1;
    if quality {
        timing + u64::from(args.flicker_frames.min(args.frames)) + args.quality_frame + 2
    } else {
        timing
    }
}

impl Bench<'_> {
    fn spec(&self, run: &RunPlan, techniques: Vec<TechniqueSpec>) -> RenderSpec {
        RenderSpec {
            scene: run.scene.clone(),
            density: run.density,
            seed: self.args.seed,
            width: run.size.0,
            height: run.size.1,
            frame: self.args.quality_frame,
            camera: None,
            rig: None,
            image: None,
            techniques,
            adapter: Some(format!(
                "{} ({})",
                self.gpu.caps.adapter_name, self.gpu.caps.backend
            )),
            build: Some(spec::build_id()),
        }
    }

    fn message(&self, run: &RunPlan, phase: &str) {
        self.bar.set_message(format!(
            "{} {}x{}{}: {phase}",
            run.scene,
            run.size.0,
            run.size.1,
            if (run.density - 1.0).abs() > 1e-6 {
                format!(" density {}", run.density)
            } else {
                String::new()
            }
        ));
    }

    /// Reads every technique's current output into its change meter, and keeps its luma
    /// for the ghosting measure against the reference frames rendered later.
    fn read_outputs(
        &self,
        graph: &FrameGraph,
        meters: &mut [(String, ChangeMeter, Vec<Plane>)],
    ) -> anyhow::Result<()> {
        for slot in graph.slots() {
            let id = slot.technique.id();
            let (Some(output), Some((_, meter, lumas))) =
                (slot.output(), meters.iter_mut().find(|(m, _, _)| m == id))
            else {
                continue;
            };
            let image = read_texture_rgba8(self.gpu, output)?;
            meter.push(&image);
            lumas.push(Plane::luma(&image));
        }
        Ok(())
    }

    fn run(&self, run: &RunPlan) -> anyhow::Result<RunReport> {
        let args = self.args;
        self.message(run, "building the scene");
        let options = SceneOptions {
            density: run.density,
            seed: args.seed,
        };
        let mut scene = source::load(&run.scene, &options)?;
        for note in &scene.notes {
            self.bar.println(format!("note: {note}"));
        }
        for warning in &scene.warnings {
            self.bar.println(format!("warning: {warning}"));
        }
        let mut spec = self.spec(run, self.techniques.clone());
        let mut reference_spec = self.spec(run, vec![self.reference.clone()]);
        args.camera.apply(&mut spec, &mut scene)?;
        reference_spec.rig = spec.rig;
        let track = SlowTrack::new(&scene.camera, run.size, TRACK_STEP_PX);
        let flicker_frames = if self.quality {
            args.flicker_frames.min(args.frames)
        } else {
            0
        };
        let timed = self.time(run, &scene, &spec, &track, flicker_frames)?;
        let flicker = self.reference_flicker(
            run,
            &scene,
            &reference_spec,
            &track,
            flicker_frames,
            &timed.meters,
        )?;
        // 4. Quality on the scene's own camera path.
        let scores = if self.quality {
            self.quality(run, &scene, &spec, &reference_spec)?
        } else {
            Vec::new()
        };
        let floor_ms = Summary::of(&timed.samples.floor);
        let techniques = self.technique_reports(run, &timed, &scores, &flicker, floor_ms.median);
        let floor_bytes = timed
            .memory
            .techniques
            .iter()
            .find(|m| m.technique == COPY_FLOOR_ID)
            .map_or(0, |m| m.own_bytes());
        Ok(RunReport {
            // Model files get a hash of their path, so two `sponza.obj` never share files.
            scene: super::render::output_stem(&scene.name, &run.scene),
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
        flicker_frames: u32,
    ) -> anyhow::Result<Timed> {
        let args = self.args;
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
        let total_frames = u64::from(args.warmup) + u64::from(args.frames);
        let flicker_from = total_frames - u64::from(flicker_frames);
        for frame in 0..total_frames {
            self.message(
                run,
                if frame < u64::from(args.warmup) {
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
            if frame >= u64::from(args.warmup) {
                let timings = graph.timings().with_context(|| {
                    format!(
                        "{} returned no GPU timings (timestamp queries unsupported?)",
                        self.gpu.caps.adapter_name
                    )
                })?;
                samples.add(timings, &graph.scene_inputs_last_frame());
            }
            if frame >= flicker_from {
                self.read_outputs(&graph, &mut meters)?;
            }
            self.bar.inc(1);
        }
        // 2. Fragment invocations on one more (untimed) frame; a frame with more passes than
        // the query set held is rendered again.
        self.message(run, "pipeline statistics");
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
        self.bar.inc(1);
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
        flicker_frames: u32,
        meters: &[(String, ChangeMeter, Vec<Plane>)],
    ) -> anyhow::Result<Flicker> {
        let total_frames = u64::from(self.args.warmup) + u64::from(self.args.frames);
        let flicker_from = total_frames - u64::from(flicker_frames);
        let mut reference_meter = ChangeMeter::new();
        let mut ghosts: Vec<MovingEdgeError> =
            meters.iter().map(|_| MovingEdgeError::new()).collect();
        let mut reference_previous: Option<Plane> = None;
        if flicker_frames > 0 {
            self.message(run, "reference for flicker");
            let mut reference = spec::build_graph(self.gpu, scene, reference_spec)?;
            for frame in flicker_from..total_frames {
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
                }
                self.bar.inc(1);
            }
        }

        Ok(Flicker {
            reference: reference_meter,
            ghosts,
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
                    mean_change: meter.and_then(ChangeMeter::mean_change),
                    flicker_ratio: meter.and_then(|m| flicker_ratio(m, &flicker.reference)),
                    ghosting,
                }
            })
            .collect()
    }

    /// Renders the quality frame of every technique and the reference and scores them; on the
    /// chart also against the exact coverage. Returns (id, vs reference, vs truth).
    fn quality(
        &self,
        run: &RunPlan,
        scene: &Scene,
        spec: &RenderSpec,
        reference_spec: &RenderSpec,
    ) -> anyhow::Result<Vec<QualityScores>> {
        self.message(run, "quality frame");
        let base = self.bar.position();
        let progress = |done: u64, _total: u64| self.bar.set_position(base + done);
        let options = RunOptions {
            debug_views: false,
            timing_repeats: 0,
            progress: Some(&progress),
            image: None,
        };
        let output = spec::run(self.gpu, scene, spec, &options)?;
        self.bar.set_position(base + spec.frame + 1);
        self.message(run, "reference frame");
        let reference = spec::run(self.gpu, scene, reference_spec, &RunOptions::default())?;
        self.bar.inc(1);
        let reference_image = reference
            .images
            .into_iter()
            .next()
            .context("the reference produced no image")?
            .image;
        let truth = (scene.name == "chart").then(|| chart_truth(&chart_layout(), run.size));
        let key = format!("{}-{}x{}", run.scene, run.size.0, run.size.1);
        if self.args.images {
            let record = serde_json::to_string_pretty(reference_spec)?;
            write_png(
                &self.args.out.join(format!("{key}-reference.png")),
                &reference_image,
                Some(&record),
                &self.policy,
            )?;
        }
        let mut scores = Vec::new();
        for image in output.images.iter().filter(|i| i.view.is_none()) {
            self.message(run, &format!("metrics of {}", image.id));
            let (quality, maps) = compare_with_maps(&reference_image, &image.image)?;
            let truth_score = truth
                .as_ref()
                .map(|t| -> anyhow::Result<Comparison> {
                    let (_, maps) = compare_with_maps(&t.image, &image.image)?;
                    Ok(maps.pool(Some(&t.mask)))
                })
                .transpose()?;
            if self.args.images {
                let record = serde_json::to_string_pretty(spec)?;
                write_png(
                    &self
                        .args
                        .out
                        .join(format!("{key}-{}.png", aa::user::file_name_part(&image.id))),
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
                    &self.args.out.join(format!(
                        "{key}-{}-flip.png",
                        aa::user::file_name_part(&image.id)
                    )),
                    &maps.error_map(Metric::Flip),
                    &HeatmapStyle {
                        legend: Metric::Flip.legend(),
                        range: (0.0, 1.0),
                    },
                    Some(&serde_json::to_string_pretty(&sidecar)?),
                    &self.policy,
                )?;
            }
            scores.push((image.id.clone(), quality, truth_score));
        }
        Ok(scores)
    }
}

/// Runs `aa-lab bench`.
pub fn run(args: &BenchArgs) -> anyhow::Result<()> {
    let started = Instant::now();
    let started_unix = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let runs = plan(args)?;
    let policy = Overwrite::new(args.force);
    let json = args.out.join("report.json");
    let md = args.out.join("report.md");
    // Refuse before hours of measuring, not after.
    policy.check_all([json.as_path(), md.as_path()])?;
    let gpu = Gpu::headless()?;
    if !gpu.caps.timestamps {
        bail!(
            "{} has no timestamp queries, so GPU time per pass cannot be measured",
            gpu.caps.adapter_name
        );
    }
    let ids = technique_ids(&gpu, &args.technique)?;
    let quality = !args.no_quality && args.sweep.is_none();
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create output directory {}", args.out.display()))?;
    let bench = Bench {
        gpu: &gpu,
        args,
        policy: policy.clone(),
        techniques: configured_specs(&gpu, &ids, &args.preset, &set_flags(&args.set, &ids)?)?,
        reference: reference_spec(&gpu)?,
        quality,
        bar: progress_bar(runs.len() as u64 * run_steps(args, quality)),
    };
    let mut reports = Vec::new();
    for run in &runs {
        let report = bench.run(run)?;
        report.write_sidecars(&args.out, &policy)?;
        reports.push(report);
    }
    bench.bar.finish_and_clear();
    let report = BenchReport {
        schema: report::SCHEMA,
        build: spec::build_id(),
        adapter: gpu.caps.clone(),
        command: std::env::args().collect::<Vec<_>>().join(" "),
        started_unix,
        wall_seconds: started.elapsed().as_secs_f64(),
        settings: BenchSettings {
            techniques: ids,
            frames: args.frames,
            warmup: args.warmup,
            flicker_frames: if quality {
                args.flicker_frames.min(args.frames)
            } else {
                0
            },
            track_step_px: TRACK_STEP_PX,
            quality_frame: args.quality_frame,
            quality,
            reference: bench.reference.clone(),
            sweep: args.sweep.map(|s| match s {
                Sweep::Resolution => "resolution".to_owned(),
                Sweep::Density => "density".to_owned(),
            }),
        },
        runs: reports,
    };
    let replaced = files::write_bytes(
        &json,
        &policy,
        serde_json::to_string_pretty(&report)?.as_bytes(),
    )?;
    println!("{}", files::wrote_line(&json, replaced));
    let replaced = files::write_bytes(
        &md,
        &policy,
        crate::export::report_markdown::markdown(&report).as_bytes(),
    )?;
    println!("{}", files::wrote_line(&md, replaced));
    let charts = report::write_charts(&report, &args.out, &policy)?;
    for chart in charts {
        println!("wrote {}", chart.display());
    }
    println!(
        "bench finished in {:.1} s ({} run(s), {} technique(s), {} timed frames each)",
        report.wall_seconds,
        report.runs.len(),
        report.settings.techniques.len(),
        args.frames
    );
    Ok(())
}
