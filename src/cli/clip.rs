//! `aa-lab clip`: renders a camera motion ([`Motion`]) through several techniques and the
//! supersampled reference, frame after frame through one frame graph (temporal techniques run
//! with their real history, after `--warmup` frames to fill it), and writes the labelled,
//! nearest-neighbour zoomed panes side by side (the magnifier's layout; a full-frame grid
//! without `--region`) as a looping animation or a video ([`ClipFormat`], by the extension,
//! refused before any work when aa-lab cannot write it), plus `<out>.json`: the full recipe
//! and, per technique, the temporal figures of [`crate::metrics::stability`] over the whole
//! frame and, with a region, over the region alone (the captions show those: what the
//! animation shows). `--html` adds a self-contained comparison page ([`HtmlPage`]).
//!
//! Every frame goes to the encoder as it renders ([`ClipWriter`]), which compresses it on a
//! pool of threads while the next frames render: memory holds a few frames, whatever the
//! clip's length. The captions' figures are known only after the last frame, so frames are
//! composed with empty captions as they render and the first frame is composed again with the
//! figures at the end: later frames are stored as changes from the first, and captions never
//! change (see [`crate::export::animation`]).
//!
//! The output is a pure function of the command line (and the adapter): no timestamps, so the
//! same command writes the same bytes, whatever `--threads`.

use std::path::{Path, PathBuf};

use anyhow::{Context, bail};
use indicatif::{ProgressBar, ProgressStyle};

use super::camera::CameraMotion;
use super::clip_record::{ClipRecord, JodSetting};
use super::clip_record::{print_table, technique_figures};
use super::render::{
    SceneSource, TechniqueArgs, load_scene, output_policy, spec_for_scene, technique_specs,
};
use crate::aa::FrameInfo;
use crate::bench::reference_spec;
use crate::clip_recorder::{ClipFrames, ClipRecorder, FrameImages, ScoredFrame};
use crate::export::animation::{self, AnimationFormat, AnimationOptions};
use crate::export::apng::Compression;
use crate::export::clip;
use crate::export::clip_writer::{ClipFormat, ClipWriter};
use crate::export::html::HtmlPage;
use crate::export::sheet::{self, Rect};
use crate::export::write_png;
use crate::files;
use crate::gpu::{Gpu, read_texture_rgba8};
use crate::graph::{FrameGraph, FrameScope};
use crate::metrics::jod::{self, JodScorer};
use crate::metrics::stability::{ClipMetrics, TemporalScores};
use crate::scene::Scene;
use crate::scene::motion::{DEFAULT_SPEED_PX, Motion};
use crate::spec;

/// Most frames of a clip.
pub const MAX_CLIP_FRAMES: u32 = 600;
/// Most warm-up frames before a clip.
pub const MAX_WARMUP_FRAMES: u32 = 1000;
/// Largest zoom.
pub const MAX_ZOOM: u32 = 64;
/// Fastest `--speed`, pixels per frame.
pub const MAX_SPEED_PX: f32 = 64.0;
/// Version of the record `aa-lab clip` writes.
pub const SCHEMA: &str = "aa-lab clip 1";

/// Arguments of `aa-lab clip`.
#[derive(Debug, clap::Args)]
pub struct ClipArgs {
    /// Scene, size (--region is in pixels of this image) and the camera the motion starts
    /// from.
    #[command(flatten)]
    pub scene: SceneSource,
    /// Techniques and their settings.
    #[command(flatten)]
    pub techniques: TechniqueArgs,
    /// Frames of the clip (1 to 600).
    #[arg(long, default_value_t = 24, value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_CLIP_FRAMES)))]
    pub frames: u32,
    /// Frames rendered before the clip so temporal techniques start with a full history (0 to
    /// 1000); the clip is frames WARMUP..WARMUP+FRAMES of the motion.
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u32).range(0..=i64::from(MAX_WARMUP_FRAMES)))]
    pub warmup: u32,
    /// Camera motion: orbit (the scene's path), pan (turn in place), dolly (toward the
    /// target), still (only temporal jitter moves).
    #[arg(long, value_enum, default_value_t = Motion::Pan)]
    pub motion: Motion,
    /// Speed of pan and dolly in pixels per frame (sub-pixel motion reveals crawling and
    /// shimmer; more than 0, at most 64).
    #[arg(long, default_value_t = DEFAULT_SPEED_PX, value_name = "PX")]
    pub speed: f32,
    /// The region shown, X,Y,W,H in pixels of the rendered image; without it every pane is
    /// the whole frame, laid out in a grid.
    #[arg(long, value_name = "X,Y,W,H")]
    pub region: Option<String>,
    /// Nearest-neighbour zoom of the panes (1 to 64; default 4 with --region, 1 without).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_ZOOM)))]
    pub zoom: Option<u32>,
    /// Playback rate of the animation, frames per second (1 to 100).
    #[arg(long, default_value_t = 30, value_parser = clap::value_parser!(u16).range(1..=100))]
    pub fps: u16,
    /// Output: animated PNG (.png, .apng), GIF (.gif), or video a browser plays through the
    /// system's ffmpeg: MP4 (.mp4, H.264 4:2:0, every pixel doubled) or WebM (.webm, VP9
    /// 4:4:4); the record and figures go beside it with the extension .json.
    #[arg(long, short, default_value = "clip.png")]
    pub out: PathBuf,
    /// Compression of the animated PNG: fast (fdeflate), or best (zlib's best level: smaller,
    /// several times slower).
    #[arg(long, value_enum, default_value_t = Compression::Fast)]
    pub compression: Compression,
    /// Also write <out>.html: one self-contained page that plays the panes in lockstep, with a
    /// wipe between any two, a synchronised zoom, the figures and the recipe (keep it small
    /// with --region: every frame is embedded losslessly).
    #[arg(long)]
    pub html: bool,
    /// Also write every pane's clip frames, whole, as numbered PNGs: DIR/<technique>/0000.png
    /// and on, the reference's in DIR/reference/ (for other tools, or `aa-lab compare` on
    /// sequences).
    #[arg(long, value_name = "DIR")]
    pub frames_dir: Option<PathBuf>,
    /// Also score every technique with ColorVideoVDP: how visible its difference from the
    /// reference is to a person watching the clip, in JOD (10: none). Keeps the clip's whole
    /// frames in memory and takes seconds per technique.
    #[arg(long)]
    pub jod: bool,
    /// The display model --jod scores for: one of ColorVideoVDP's standard displays (e.g.
    /// standard_fhd, standard_4k, standard_phone, standard_hmd).
    #[arg(long, default_value = jod::DEFAULT_DISPLAY, value_name = "NAME", requires = "jod")]
    pub jod_display: String,
    /// Threads compressing frames while the next ones render (default: one per core).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// Replace existing output files (without it, aa-lab never replaces a file).
    #[arg(long)]
    pub force: bool,
}

/// Parses `X,Y,W,H` and checks it against the render size: refused when any part lies
/// outside (a clip's figures and panes must show what was asked for).
fn parse_region(text: &str, size: (u32, u32)) -> anyhow::Result<Rect> {
    let rect = super::sheet::parse_rect(text, text)?;
    let Rect {
        x,
        y,
        width,
        height,
    } = rect;
    if u64::from(x) + u64::from(width) > u64::from(size.0)
        || u64::from(y) + u64::from(height) > u64::from(size.1)
    {
        bail!(
            "--region {text} lies outside the {}x{} render (--size): X+W must be at most {} and Y+H at most {}",
            size.0,
            size.1,
            size.0,
            size.1
        );
    }
    Ok(rect)
}

/// `<out>` with the extension `.json`.
fn json_path(out: &Path) -> PathBuf {
    out.with_extension("json")
}

/// Frame `number` of a pane's folder in `--frames-dir`.
fn frame_path(dir: &Path, number: usize) -> PathBuf {
    dir.join(format!("{number:04}.png"))
}

/// Each pane's folder in `dir` (`--frames-dir`): the technique's id as a file name, and
/// `reference` for the last pane; created here once every frame's path has passed `policy`.
fn pane_dirs(
    dir: &Path,
    ids: &[String],
    frames: u32,
    policy: &files::Overwrite,
) -> anyhow::Result<Vec<PathBuf>> {
    let count = ids.len();
    let dirs: Vec<PathBuf> = ids
        .iter()
        .enumerate()
        .map(|(i, id)| match i + 1 == count {
            true => dir.join("reference"),
            false => dir.join(crate::aa::user::file_name_part(id).as_ref()),
        })
        .collect();
    let paths: Vec<PathBuf> = dirs
        .iter()
        .flat_map(|d| (0..frames as usize).map(|n| frame_path(d, n)))
        .collect();
    policy.check_all(paths.iter().map(PathBuf::as_path))?;
    for d in &dirs {
        std::fs::create_dir_all(d)
            .with_context(|| format!("cannot create directory {}", d.display()))?;
    }
    Ok(dirs)
}

/// `<out>` with the extension `.html`.
fn html_path(out: &Path) -> PathBuf {
    out.with_extension("html")
}

/// What the render loop needs besides the graph: the motion, the region and the animation
/// being written.
struct Recording<'a> {
    args: &'a ClipArgs,
    gpu: &'a Gpu,
    scene: &'a Scene,
    region: Option<Rect>,
    /// The layout with the figures' captions left empty: every frame is composed with it as
    /// it renders, and the first is composed again with the figures at the end.
    pending_layout: clip::Layout,
    format: ClipFormat,
    options: AnimationOptions,
    policy: &'a files::Overwrite,
    /// With `--frames-dir`, the folder of each pane's frames (the reference's last).
    pane_dirs: Option<Vec<PathBuf>>,
}

/// The figures of a recorded clip, and the first frame's panes (composed again with them).
struct Recorded {
    writer: ClipWriter,
    page: Option<HtmlPage>,
    metrics: ClipMetrics,
    region_metrics: Option<ClipMetrics>,
    first_crops: Vec<image::RgbaImage>,
    /// With `--jod`, every clip frame's whole panes (the reference's last).
    whole_frames: Vec<Vec<image::RgbaImage>>,
}

/// The progress bar of a clip: frames rendered (warm-up included) with an ETA.
fn progress_bar(total: u64) -> ProgressBar {
    let bar = ProgressBar::new(total);
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] [{bar:32}] {pos}/{len} frames, eta {eta}  {msg}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> "),
    );
    bar.enable_steady_tick(std::time::Duration::from_millis(200));
    bar
}

/// A clip frame as the command line reads it: every pane's whole image (the reference's
/// last) and, with a region, the panes cropped to it.
struct PaneImages {
    whole: Vec<image::RgbaImage>,
    crops: Option<Vec<image::RgbaImage>>,
}

/// Techniques' images and the reference's (the last pane).
fn split_reference(images: &[image::RgbaImage]) -> FrameImages<'_> {
    let (reference, techniques) = match images.split_last() {
        Some((reference, techniques)) => (Some(reference), techniques),
        None => (None, images),
    };
    FrameImages {
        techniques: techniques.iter().collect(),
        reference,
    }
}

impl ScoredFrame for PaneImages {
    fn whole(&self) -> FrameImages<'_> {
        split_reference(&self.whole)
    }

    fn region(&self) -> Option<FrameImages<'_>> {
        self.crops.as_deref().map(split_reference)
    }
}

/// The command line's side of the recorder: renders through `graph`, reads every output
/// back, shows progress, and hands each frame's composed panes to the encoder (which
/// compresses while the next frames render) and to the HTML page.
struct CliFrames<'a> {
    rec: &'a Recording<'a>,
    graph: &'a mut FrameGraph,
    bar: ProgressBar,
    writer: Option<ClipWriter>,
    page: Option<HtmlPage>,
    first_crops: Vec<image::RgbaImage>,
    /// With `--jod`, every clip frame's whole panes (the reference's last).
    whole_frames: Vec<Vec<image::RgbaImage>>,
}

impl CliFrames<'_> {
    /// Says what the next frame is, then renders it with `scope`.
    fn render(&mut self, frame: &FrameInfo, scope: FrameScope) -> anyhow::Result<()> {
        let args = self.rec.args;
        let phase = if scope == FrameScope::TemporalOnly {
            "warm-up".to_owned()
        } else {
            let encoded = self.writer.as_mut().map_or(0, ClipWriter::written);
            format!("clip, {encoded} encoded")
        };
        self.bar
            .set_message(format!("{} {}: {phase}", self.rec.scene.name, args.motion));
        self.graph.render(frame, scope)?;
        self.graph.finish();
        self.bar.inc(1);
        Ok(())
    }
}

impl ClipFrames for CliFrames<'_> {
    type Frame = PaneImages;
    type Error = anyhow::Error;

    fn warm_up(&mut self, frame: &FrameInfo) -> anyhow::Result<()> {
        self.render(frame, FrameScope::TemporalOnly)
    }

    fn capture(&mut self, frame: &FrameInfo) -> anyhow::Result<PaneImages> {
        self.render(frame, FrameScope::All)?;
        let whole = self
            .graph
            .slots()
            .iter()
            .map(|slot| {
                let output = slot
                    .output()
                    .with_context(|| format!("{} produced no image", slot.technique.label()))?;
                Ok(read_texture_rgba8(self.rec.gpu, output)?)
            })
            .collect::<anyhow::Result<Vec<_>>>()?;
        let crops = self.rec.region.map(|region| {
            whole
                .iter()
                .map(|image| {
                    image::imageops::crop_imm(
                        image,
                        region.x,
                        region.y,
                        region.width,
                        region.height,
                    )
                    .to_image()
                })
                .collect()
        });
        Ok(PaneImages { whole, crops })
    }

    fn deliver(&mut self, number: usize, frame: PaneImages) -> anyhow::Result<()> {
        if let Some(dirs) = &self.rec.pane_dirs {
            for (dir, image) in dirs.iter().zip(&frame.whole) {
                write_png(&frame_path(dir, number), image, None, self.rec.policy)?;
            }
        }
        let panes = match (frame.crops, self.rec.args.jod) {
            (Some(crops), true) => {
                self.whole_frames.push(frame.whole);
                crops
            }
            (Some(crops), false) => crops,
            (None, true) => {
                self.whole_frames.push(frame.whole.clone());
                frame.whole
            }
            (None, false) => frame.whole,
        };
        let refs: Vec<&image::RgbaImage> = panes.iter().collect();
        if let Some(page) = &mut self.page {
            page.push(&refs)?;
        }
        let rec = self.rec;
        let composed = rec
            .pending_layout
            .compose(number, rec.args.frames as usize, &refs)?;
        ClipWriter::push_or_start(
            &mut self.writer,
            &rec.args.out,
            rec.policy,
            rec.format,
            rec.options,
            composed,
        )?;
        if number == 0 {
            self.first_crops = panes;
        }
        Ok(())
    }
}

/// Renders the warm-up and the clip through `graph` with the library's [`ClipRecorder`],
/// scoring every clip frame, and encodes the frames as they come.
fn record(
    rec: &Recording,
    graph: &mut FrameGraph,
    page: Option<HtmlPage>,
) -> anyhow::Result<Recorded> {
    let args = rec.args;
    let total = u64::from(args.warmup) + u64::from(args.frames);
    let cameras = (0..total)
        .map(|frame| {
            args.motion
                .camera(&rec.scene.camera, args.scene.size, args.speed, frame)
        })
        .collect();
    let techniques = graph.slots().len().saturating_sub(1);
    let recorder = ClipRecorder::new(cameras, args.warmup as usize, techniques, true);
    let mut frames = CliFrames {
        rec,
        graph,
        bar: progress_bar(total),
        writer: None,
        page,
        first_crops: Vec::new(),
        whole_frames: Vec::new(),
    };
    let clip = recorder.record(&mut frames)?;
    frames.bar.finish_and_clear();
    if let Some(err) = clip.score_error {
        return Err(err).context("the clip's figures could not be computed");
    }
    Ok(Recorded {
        writer: frames.writer.context("the clip has no frame")?,
        page: frames.page,
        metrics: clip.metrics.context("the clip has no figures")?,
        region_metrics: clip.region_metrics,
        first_crops: frames.first_crops,
        whole_frames: frames.whole_frames,
    })
}

/// Each technique's JOD over the clip's whole frames against the reference's (the last
/// pane), played at the clip's rate.
fn jod_figures(
    scorer: &JodScorer,
    frames: &[Vec<image::RgbaImage>],
    labels: &[String],
    fps: u16,
) -> anyhow::Result<Vec<f64>> {
    let techniques = labels.len().saturating_sub(1);
    let reference: Vec<&image::RgbaImage> = frames.iter().filter_map(|f| f.last()).collect();
    (0..techniques)
        .map(|i| {
            eprintln!(
                "scoring {} with ColorVideoVDP ({}/{techniques})…",
                labels[i],
                i + 1
            );
            let test: Vec<&image::RgbaImage> = frames.iter().filter_map(|f| f.get(i)).collect();
            scorer
                .score(&test, &reference, f32::from(fps))
                .with_context(|| format!("the JOD of {}", labels[i]))
        })
        .collect()
}

/// The layout of every frame, with the captions left empty (the figures come at the end).
fn pending_layout(
    args: &ClipArgs,
    scene: &str,
    adapter: &str,
    labels: &[String],
    region: Option<Rect>,
    zoom: u32,
) -> clip::Layout {
    let motion_text = if args.motion.uses_speed() {
        format!("{} {} px/frame", args.motion, args.speed)
    } else {
        args.motion.to_string()
    };
    clip::Layout {
        title: format!("aa-lab clip: {scene}, {motion_text}"),
        scene: scene.to_owned(),
        region,
        zoom,
        footer: format!(
            "captions: temporal instability / ghosting (luma levels); {} on {adapter}",
            spec::build_id(),
        ),
        panes: labels
            .iter()
            .map(|label| clip::Pane {
                label: label.clone(),
                caption: String::new(),
            })
            .collect(),
    }
}

/// Captions every pane of `layout` with its figures, fitted to `width` pixels: the
/// techniques' `scores`, then the reference's mean change.
fn show_figures(
    layout: &mut clip::Layout,
    scores: &[TemporalScores],
    reference_change: Option<f64>,
    width: u32,
) {
    for (pane, scores) in layout.panes.iter_mut().zip(scores) {
        pane.caption = clip::fit(&[clip::caption(scores), clip::short_caption(scores)], width);
    }
    if let Some(reference_pane) = layout.panes.last_mut() {
        reference_pane.caption = clip::reference_caption(reference_change, width);
    }
}

/// Checks the arguments that need no GPU; returns the region, the zoom and the format.
fn check_args(args: &ClipArgs) -> anyhow::Result<(Option<Rect>, u32, ClipFormat)> {
    let format = ClipFormat::of_path(&args.out)?;
    if args.scene.camera.camera_motion != CameraMotion::Orbit {
        bail!(
            "clip moves the camera with --motion (orbit, pan, dolly, still), not --camera-motion"
        );
    }
    if !(args.speed.is_finite() && args.speed > 0.0 && args.speed <= MAX_SPEED_PX) {
        bail!(
            "--speed {}: pixels per frame must be more than 0 and at most {MAX_SPEED_PX}",
            args.speed
        );
    }
    if args.scene.size.0 == 0 || args.scene.size.1 == 0 {
        bail!("--size: width and height must be at least 1");
    }
    let region = args
        .region
        .as_deref()
        .map(|text| parse_region(text, args.scene.size))
        .transpose()?;
    let zoom = args.zoom.unwrap_or(if region.is_some() { 4 } else { 1 });
    Ok((region, zoom, format))
}

/// Runs `aa-lab clip`.
pub fn run(args: &ClipArgs) -> anyhow::Result<()> {
    let (region, zoom, format) = check_args(args)?;
    let json = json_path(&args.out);

    let gpu = Gpu::headless()?;
    let max_side = gpu.caps.max_texture_dimension_2d;
    if args.scene.size.0 > max_side || args.scene.size.1 > max_side {
        bail!(
            "--size {}x{}: {} renders at most {max_side} pixels a side",
            args.scene.size.0,
            args.scene.size.1,
            gpu.caps.adapter_name
        );
    }
    let techniques = technique_specs(&gpu, &args.techniques)?;
    let reference = reference_spec(&gpu)?;
    let scorer = args
        .jod
        .then(|| JodScorer::new(&args.jod_display))
        .transpose()?;
    let pane = region.unwrap_or(Rect {
        x: 0,
        y: 0,
        width: args.scene.size.0,
        height: args.scene.size.1,
    });
    clip::check(
        techniques.len() + 1,
        region.is_some(),
        (pane.width, pane.height),
        zoom,
    )?;

    let mut spec = spec_for_scene(&args.scene, u64::from(args.warmup), techniques.clone());
    spec.adapter = Some(format!("{} ({})", gpu.caps.adapter_name, gpu.caps.backend));
    let policy = output_policy(args.force, None, &spec);
    let html = args.html.then(|| html_path(&args.out));
    policy.check_all(
        [args.out.as_path(), json.as_path()]
            .into_iter()
            .chain(html.as_deref()),
    )?;
    let mut scene = load_scene(&spec, args.scene.strict)?;
    args.scene.camera.apply(&mut spec, &mut scene)?;

    let mut graph_spec = spec.clone();
    graph_spec.techniques.push(reference.clone());
    let mut graph = spec::build_graph(&gpu, &scene, &graph_spec)?;
    if let Some(reference_slot) = graph.slots_mut().last_mut() {
        reference_slot.reference = true;
    }
    let mut labels: Vec<String> = graph.slots().iter().map(|s| s.technique.label()).collect();
    if let Some(last) = labels.last_mut() {
        *last = format!("Reference ({last})");
    }
    let ids: Vec<String> = graph
        .slots()
        .iter()
        .map(|s| s.technique.id().to_owned())
        .collect();
    let adapter = spec.adapter.clone().unwrap_or_default();
    let mut layout = pending_layout(args, &scene.name, &adapter, &labels, region, zoom);
    if let Some(parent) = args.out.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent)
            .with_context(|| format!("cannot create directory {}", parent.display()))?;
    }
    let recording = Recording {
        args,
        gpu: &gpu,
        scene: &scene,
        region,
        pending_layout: layout.clone(),
        format,
        options: AnimationOptions {
            format: AnimationFormat::Apng,
            fps: args.fps,
            compression: args.compression,
            threads: args
                .threads
                .map_or_else(animation::default_threads, |t| t as usize),
        },
        policy: &policy,
        pane_dirs: args
            .frames_dir
            .as_deref()
            .map(|dir| pane_dirs(dir, &ids, args.frames, &policy))
            .transpose()?,
    };
    let page = html
        .as_deref()
        .map(|path| {
            let size = (pane.width, pane.height);
            HtmlPage::create(path, &policy, &layout.title, &labels, size, args.fps, zoom)
        })
        .transpose()?;
    let started = std::time::Instant::now();
    let recorded = record(&recording, &mut graph, page)?;
    let rendered = started.elapsed();
    drop(graph);

    let metrics = &recorded.metrics;
    let scores = metrics.scores();
    let region_scores = recorded.region_metrics.as_ref().map(ClipMetrics::scores);
    // The captions give the figures of what the animation shows.
    let shown_metrics = recorded.region_metrics.as_ref().unwrap_or(metrics);
    let shown_scores = region_scores.as_ref().unwrap_or(&scores);
    show_figures(
        &mut layout,
        shown_scores,
        shown_metrics.reference().mean_change(),
        pane.width * zoom,
    );
    let jods = match &scorer {
        Some(scorer) => Some(jod_figures(
            scorer,
            &recorded.whole_frames,
            &labels,
            args.fps,
        )?),
        None => None,
    };
    let first_refs: Vec<&image::RgbaImage> = recorded.first_crops.iter().collect();
    let first = layout.compose(0, args.frames as usize, &first_refs)?;

    let record = ClipRecord {
        schema: SCHEMA,
        spec,
        reference,
        motion: args.motion,
        speed_px: args.speed,
        warmup: args.warmup,
        frames: args.frames,
        fps: args.fps,
        region,
        zoom,
        format,
        definitions: clip::Definitions::over(
            "every pixel of the whole frame, frames warmup..warmup+frames; `region` figures and the captions: the --region pixels only".to_owned(),
        ),
        region_reference_mean_change: recorded
            .region_metrics
            .as_ref()
            .and_then(|m| m.reference().mean_change()),
        moving_fraction: metrics.moving_fraction(),
        reference_mean_change: metrics.reference().mean_change(),
        jod: scorer.as_ref().map(|s| JodSetting {
            display: s.display().to_owned(),
            model: jod::MODEL_VERSION,
        }),
        techniques: technique_figures(
            &ids,
            &labels,
            &scores,
            region_scores.as_deref(),
            jods.as_deref(),
        ),
    };
    let text = serde_json::to_string_pretty(&record)? + "\n";
    if matches!(format, ClipFormat::Video(_)) {
        eprintln!("encoding {} with ffmpeg…", args.out.display());
    }
    let replaced = recorded
        .writer
        .finish(Some(&first), Some(&text), sheet::BACKGROUND_RGBA)?;
    eprintln!(
        "rendered {} frames ({} of warm-up), compressing the clip's as they came, in {:.1} s; then {:.1} s to finish the file",
        u64::from(args.warmup) + u64::from(args.frames),
        args.warmup,
        rendered.as_secs_f64(),
        (started.elapsed() - rendered).as_secs_f64()
    );
    println!("{}", files::wrote_line(&args.out, replaced));
    let replaced = files::write_bytes(&json, &policy, text.as_bytes())?;
    println!("{}", files::wrote_line(&json, replaced));
    if let (Some(page), Some(path)) = (recorded.page, &html) {
        let replaced = page.finish(&serde_json::to_value(&record)?)?;
        println!("{}", files::wrote_line(path, replaced));
    }
    print_table(&record);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regions_must_lie_inside_the_render() {
        let size = (64, 48);
        assert_eq!(
            parse_region("8,4,16,12", size).unwrap(),
            Rect {
                x: 8,
                y: 4,
                width: 16,
                height: 12
            }
        );
        assert!(parse_region("0,0,64,48", size).is_ok());
        for bad in [
            "60,0,8,8",
            "0,40,8,9",
            "0,0,0,4",
            "1,2,3",
            "a,b,c,d",
            "0,0,4294967295,1",
        ] {
            assert!(parse_region(bad, size).is_err(), "{bad}");
        }
    }

    #[test]
    fn the_record_sits_beside_the_animation() {
        assert_eq!(json_path(Path::new("a/clip.png")), Path::new("a/clip.json"));
        assert_eq!(json_path(Path::new("clip.gif")), Path::new("clip.json"));
        assert_eq!(json_path(Path::new("clip")), Path::new("clip.json"));
    }
}
