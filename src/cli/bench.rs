//! `aa-lab bench`: for every scene x size (or every point of a sweep), runs all chosen
//! techniques together in one frame graph and measures each one: GPU time per pass and in total
//! (median and 95th percentile over the timed frames), cost relative to No AA and to a
//! full-screen copy pass, memory, fragment-shader invocations, image quality against a 64-sample
//! SSAA reference (SSIM, PSNR, MAE, FLIP; against the exact coverage too on `chart`) and the
//! flicker ratio. Writes `report.json`, `report.md`, charts and reproducibility sidecars.
//!
//! Sweeps: `resolution` and `density` vary the load run by run (cost only); `scale` runs every
//! technique at every render scale of `--scales` in each run ([`crate::bench::scales`]), at
//! the same output size, quality included, for the Pareto front of native and upscaled
//! techniques.
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
//!    with every metric;
//! 5. with `--jod`, each technique's ColorVideoVDP JOD over the flicker frames against the
//!    reference's ([`crate::metrics::jod`], the scorer `clip` and `compare` use).

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, bail};
use indicatif::ProgressBar;

use super::clip_record::JodDisplayArgs;
use super::render::{
    configured_specs, parse_size, progress_bar_with_eta, set_flags, technique_ids,
};
use crate::bench::scales::{default_scales, parse_scales, sweep_techniques};
use crate::bench::{
    BenchOptions, BenchProgress, BenchRunner, DEFAULT_FLICKER_FRAMES, DEFAULT_QUALITY_FRAME,
    DEFAULT_WARMUP, ImageOutput, JOD_FPS, RunPlan, reference_spec, report_paths, write_report,
};
use crate::export::report::{self, BenchReport, BenchSettings, RunReport};
use crate::files::Overwrite;
use crate::gpu::Gpu;
use crate::metrics::jod::JodScorer;
use crate::scene::procedural::SceneOptions;
use crate::scene::source;
use crate::spec::{self, TechniqueSpec};

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
    /// Every technique at every render scale of `--scales`, upscaled to the same output size.
    Scale,
}

impl Sweep {
    /// The name the report records.
    fn name(self) -> &'static str {
        match self {
            Self::Resolution => "resolution",
            Self::Density => "density",
            Self::Scale => report::SCALE_SWEEP,
        }
    }
}

/// Arguments of `aa-lab bench`.
#[derive(Debug, clap::Args)]
pub struct BenchArgs {
    /// Comma-separated scenes (hairball, atrium, chart, sparkle, glass or .obj/.gltf/.glb paths).
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
    #[arg(long, default_value_t = DEFAULT_WARMUP, value_parser = clap::value_parser!(u32).range(0..=MAX_FRAMES))]
    pub warmup: u32,
    /// Timed frames (the last ones) read back for the flicker ratio; 0 skips flicker.
    #[arg(long, default_value_t = DEFAULT_FLICKER_FRAMES)]
    pub flicker_frames: u32,
    /// Frame of each scene's camera path whose images are scored against the reference.
    #[arg(long, default_value_t = DEFAULT_QUALITY_FRAME, value_parser = clap::value_parser!(u64).range(0..=spec::MAX_FRAME))]
    pub quality_frame: u64,
    /// Measure cost only: no reference renders, no image metrics, no flicker.
    #[arg(long)]
    pub no_quality: bool,
    /// Sweep: `resolution` (720p to 4K, cost only), `density` (hairball, about 100k to 2.1M
    /// triangles, cost only) or `scale` (every technique at every render scale of --scales,
    /// upscaled to the output size and scored against the native reference).
    #[arg(long, value_enum)]
    pub sweep: Option<Sweep>,
    /// Render scales of --sweep scale, comma-separated: numbers from 0.25 to 1 or presets
    /// (native, quality, balanced, performance, ultra-performance); all five presets by
    /// default. A technique whose id names a scale runs at that scale only.
    #[arg(long, value_name = "SCALES")]
    pub scales: Option<String>,
    /// Built-in scene density (hairball triangle scale).
    #[arg(long, default_value_t = 1.0)]
    pub density: f32,
    /// Built-in scene seed.
    #[arg(long, default_value_t = SceneOptions::default().seed)]
    pub seed: u64,
    /// Draw a game-like UI overlay over the frames, `before` or `after` the antialiasing
    /// (see `render --help`).
    #[arg(long, value_name = "ORDER", value_parser = super::render::parse_overlay)]
    pub ui_overlay: Option<crate::graph::overlay::OverlayOrder>,
    /// Specular antialiasing in every technique's scene render (each highlight's lobe widened
    /// by the normal's variation inside the pixel); the reference stays unfiltered.
    #[arg(long)]
    pub specular_aa: bool,
    /// How radiance is displayed: auto, none, reinhard, aces, agx or neutral (see
    /// `render --help`).
    #[arg(long, value_name = "NAME", default_value = "auto", value_parser = super::render::parse_tonemap)]
    pub tonemap: crate::graph::hdr::TonemapChoice,
    /// Exposure of HDR renders in stops (EV).
    #[arg(long, value_name = "EV", default_value_t = 0.0, allow_hyphen_values = true, value_parser = super::render::parse_exposure)]
    pub exposure: f32,
    /// Output directory for report.json, report.md, charts and sidecars.
    #[arg(long, short, default_value = "report")]
    pub out: PathBuf,
    /// Also write the scored images, the reference and FLIP heatmaps (PNG, with records).
    #[arg(long)]
    pub images: bool,
    /// Also score every technique's flicker frames with ColorVideoVDP against the
    /// reference's: how visible the difference is to a person watching them, in JOD (10:
    /// none). Keeps the flicker frames whole until scored.
    #[arg(long)]
    pub jod: bool,
    /// The display model and viewing distance of --jod.
    #[command(flatten)]
    pub jod_view: JodDisplayArgs,
    /// Replace files of an earlier bench in --out (without it, aa-lab never replaces a file).
    #[arg(long)]
    pub force: bool,
    /// The camera of every scene, when not its default view (the timed frames then follow
    /// this camera's slow track).
    #[command(flatten)]
    pub camera: super::camera::CameraArgs,
}

/// Most timed or warm-up frames per run.
const MAX_FRAMES: i64 = 100_000;

fn plan(args: &BenchArgs) -> anyhow::Result<Vec<RunPlan>> {
    let scenes: Vec<String> = args
        .scene
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(str::to_owned)
        .collect();
    if scenes.is_empty() {
        bail!(
            "no scene given; use --scene with hairball, atrium, chart, sparkle, glass or an .obj path"
        );
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

/// The command line's progress: one bar over every run's steps, the run and its phase as the
/// message.
struct BarProgress(ProgressBar);

impl BenchProgress for BarProgress {
    fn phase(&self, run: &RunPlan, phase: &str) {
        self.0.set_message(format!(
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

    fn advance(&self, steps: u64) {
        self.0.inc(steps);
    }
}

/// Loads `run`'s scene (its notes and warnings above the bar), points the camera as the
/// command line says and measures the run.
fn measure(
    runner: &BenchRunner,
    bar: &ProgressBar,
    (args, jod): (&BenchArgs, Option<&JodScorer>),
    run: &RunPlan,
) -> anyhow::Result<RunReport> {
    runner.progress.phase(run, "building the scene");
    let options = SceneOptions {
        density: run.density,
        seed: args.seed,
    };
    let mut scene = source::load(&run.scene, &options)?;
    for note in &scene.notes {
        bar.println(format!("note: {note}"));
    }
    for warning in &scene.warnings {
        bar.println(format!("warning: {warning}"));
    }
    let (mut spec, mut reference_spec) = runner.specs(run);
    args.camera.apply(&mut spec, &mut scene)?;
    reference_spec.rig = spec.rig;
    Ok(runner.run_scored(run, &scene, spec, reference_spec, jod)?)
}

/// The scorer of `--jod`; refused where the bench reads no flicker frames to score.
fn jod_scorer(args: &BenchArgs) -> anyhow::Result<Option<JodScorer>> {
    if !args.jod {
        return Ok(None);
    }
    if args.no_quality || args.flicker_frames == 0 {
        bail!(
            "--jod scores the flicker frames against the reference's: leave out --no-quality and give --flicker-frames of 1 or more"
        );
    }
    if matches!(args.sweep, Some(Sweep::Resolution | Sweep::Density)) {
        bail!("--jod scores quality, which a --sweep over resolution or density does not measure");
    }
    Ok(Some(args.jod_view.scorer(false)?))
}

/// The render scales of a sweep over scales: `--scales`, or every preset.
fn sweep_scales(args: &BenchArgs) -> anyhow::Result<Option<Vec<f32>>> {
    match (args.sweep, &args.scales) {
        (Some(Sweep::Scale), Some(list)) => Ok(Some(
            parse_scales(list).map_err(|e| anyhow::anyhow!("--scales {list}: {e}"))?,
        )),
        (Some(Sweep::Scale), None) => Ok(Some(default_scales())),
        (_, Some(_)) => bail!("--scales sets the scales of --sweep scale; add --sweep scale"),
        (_, None) => Ok(None),
    }
}

/// The techniques `ids` with the command line's presets and settings, each at every scale of
/// `scales` in a sweep over scales.
fn techniques(
    gpu: &Gpu,
    args: &BenchArgs,
    ids: &[String],
    scales: Option<&[f32]>,
) -> anyhow::Result<Vec<TechniqueSpec>> {
    let configured = configured_specs(gpu, ids, &args.preset, &set_flags(&args.set, ids)?)?;
    let Some(scales) = scales else {
        return Ok(configured);
    };
    let written: Vec<(&str, &TechniqueSpec)> =
        ids.iter().map(String::as_str).zip(&configured).collect();
    // Each created once, before anything is measured: a combination this adapter or the
    // technique refuses fails here, and each id is recorded in its canonical form.
    sweep_techniques(&written, scales)?
        .iter()
        .map(|spec| Ok(TechniqueSpec::of(spec.create(gpu)?.as_ref())))
        .collect()
}

/// Runs `aa-lab bench`.
pub fn run(args: &BenchArgs) -> anyhow::Result<()> {
    let started = Instant::now();
    let started_unix = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let runs = plan(args)?;
    let scales = sweep_scales(args)?;
    let scorer = jod_scorer(args)?;
    let policy = Overwrite::new(args.force);
    // Refuse before hours of measuring, not after.
    policy.check_all(report_paths(&args.out).iter().map(PathBuf::as_path))?;
    let gpu = Gpu::headless()?;
    if !gpu.caps.timestamps {
        bail!(
            "{} has no timestamp queries, so GPU time per pass cannot be measured",
            gpu.caps.adapter_name
        );
    }
    let ids = technique_ids(&gpu, &args.technique)?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create output directory {}", args.out.display()))?;
    let options = BenchOptions {
        warmup: args.warmup,
        frames: args.frames,
        flicker_frames: args.flicker_frames,
        quality_frame: args.quality_frame,
        quality: !args.no_quality && args.sweep.is_none_or(|s| s == Sweep::Scale),
        seed: args.seed,
        specular_aa: args.specular_aa,
        tonemap: args.tonemap,
        exposure: args.exposure,
        images: args.images.then(|| ImageOutput {
            folder: args.out.clone(),
            policy: policy.clone(),
        }),
        overlay: args.ui_overlay,
    };
    let progress = BarProgress(progress_bar_with_eta(
        runs.len() as u64 * options.steps_per_run(),
        "steps",
    ));
    let techniques = techniques(&gpu, args, &ids, scales.as_deref())?;
    let runner = BenchRunner {
        gpu: &gpu,
        options,
        techniques,
        reference: reference_spec(&gpu)?,
        progress: &progress,
    };
    let mut reports = Vec::new();
    for run in &runs {
        let report = measure(&runner, &progress.0, (args, scorer.as_ref()), run)?;
        report.write_sidecars(&args.out, &policy)?;
        reports.push(report);
    }
    progress.0.finish_and_clear();
    let report = BenchReport {
        schema: report::SCHEMA,
        build: spec::build_id(),
        adapter: gpu.caps.clone(),
        command: std::env::args().collect::<Vec<_>>().join(" "),
        started_unix,
        wall_seconds: started.elapsed().as_secs_f64(),
        settings: BenchSettings {
            scales,
            jod: scorer.as_ref().map(|s| s.setting(JOD_FPS)),
            ..runner.settings(
                runner.techniques.iter().map(|t| t.id.clone()).collect(),
                args.sweep.map(|s| s.name().to_owned()),
            )
        },
        runs: reports,
    };
    for path in write_report(&report, &args.out, &policy)? {
        println!("{path}");
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
