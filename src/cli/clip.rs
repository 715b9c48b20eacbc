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

use super::camera::CameraMotion;
use super::clip_frames::{Recorded, Recording, pane_dirs, record};
use super::clip_record::{
    ClipFigures, ClipPanes, ClipRecord, ClipShape, JodDisplayArgs, RenderedPart, clip_record,
    jod_figures, jod_heatmap_paths, print_table, show_figures,
};
use super::clip_sequences::{ClipSequences, REFERENCE_LABEL};
use super::render::{
    SceneSource, TechniqueArgs, load_scene, output_policy, spec_for_scene, technique_specs,
};
use crate::bench::reference_spec;
use crate::export::animation::{self, AnimationFormat, AnimationOptions};
use crate::export::apng::Compression;
use crate::export::clip;
use crate::export::clip_writer::ClipFormat;
use crate::export::html::HtmlPage;
use crate::export::sheet::{self, Rect};
use crate::files;
use crate::gpu::Gpu;
use crate::graph::FrameGraph;
use crate::metrics::jod::JodScorer;
use crate::scene::Scene;
use crate::scene::motion::{DEFAULT_SPEED_PX, Motion};
use crate::spec::{self, RenderSpec, TechniqueSpec};

/// Most frames of a clip.
pub const MAX_CLIP_FRAMES: u32 = 600;
/// Most warm-up frames before a clip.
pub const MAX_WARMUP_FRAMES: u32 = 1000;
/// Largest zoom.
pub const MAX_ZOOM: u32 = 64;
/// Fastest `--speed`, pixels per frame.
pub const MAX_SPEED_PX: f32 = 64.0;

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
    /// Frames of the clip (1 to 600; default 24, or with sequences as many as the shortest
    /// has after its offset).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_CLIP_FRAMES)))]
    pub frames: Option<u32>,
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
    /// The display model and viewing distance of --jod.
    #[command(flatten)]
    pub jod_view: JodDisplayArgs,
    /// With --jod: also write every technique's ColorVideoVDP per-pixel distortion map (1 -
    /// JOD/10 over the whole frame, averaged over the clip's frames) as a heatmap with legend:
    /// DIR/<technique>-jod.png, each with its record (JOD, display model) embedded.
    #[arg(long, value_name = "DIR", requires = "jod")]
    pub jod_heatmap: Option<PathBuf>,
    /// Threads compressing frames while the next ones render (default: one per core).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// A captured image sequence as a pane, LABEL=PATH (a folder or a quoted glob of
    /// numbered PNG, JPEG or OpenEXR frames; repeatable). With sequences, techniques are
    /// rendered only when --technique names them. OpenEXR frames (linear light) are clamped
    /// to the display's white, or shown through the tonemapper --tonemap names, with
    /// --exposure.
    #[arg(long, value_name = "LABEL=PATH")]
    pub sequence: Vec<String>,
    /// A captured sequence every pane is scored against instead of the 64-sample render
    /// (which is then not rendered): the ground truth of the captures.
    #[arg(long, value_name = "PATH")]
    pub reference_sequence: Option<PathBuf>,
    /// Start sequence LABEL at its Nth frame (0-based; `reference` for --reference-sequence),
    /// LABEL=N (repeatable): lines up captures that start on different frames.
    #[arg(long, value_name = "LABEL=N")]
    pub offset: Vec<String>,
    /// Replace existing output files (without it, aa-lab never replaces a file).
    #[arg(long)]
    pub force: bool,
    /// Whether --technique was on the command line (set by [`super::parse`]): a clip of
    /// sequences renders techniques only then.
    #[arg(skip)]
    pub techniques_given: bool,
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

/// `<out>` with the extension `.html`.
fn html_path(out: &Path) -> PathBuf {
    out.with_extension("html")
}

/// The layout of every frame, with the captions left empty (the figures come at the end).
fn pending_layout(
    args: &ClipArgs,
    rendered: bool,
    name: &str,
    adapter: &str,
    labels: &[String],
    (region, zoom): (Option<Rect>, u32),
) -> clip::Layout {
    let motion_text = if args.motion.uses_speed() {
        format!("{} {} px/frame", args.motion, args.speed)
    } else {
        args.motion.to_string()
    };
    clip::Layout {
        title: match rendered {
            true => format!("aa-lab clip: {name}, {motion_text}"),
            false => format!("aa-lab clip: {name}"),
        },
        scene: name.to_owned(),
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

/// Checks the arguments that need no GPU against the clip's `size`; returns the region, the
/// zoom and the format.
fn check_args(
    args: &ClipArgs,
    size: (u32, u32),
) -> anyhow::Result<(Option<Rect>, u32, ClipFormat)> {
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
    if size.0 == 0 || size.1 == 0 {
        bail!("--size: width and height must be at least 1");
    }
    let region = args
        .region
        .as_deref()
        .map(|text| parse_region(text, size))
        .transpose()?;
    let zoom = args.zoom.unwrap_or(if region.is_some() { 4 } else { 1 });
    Ok((region, zoom, format))
}

/// The rendered side of a clip: the device, the techniques, the reference when it is rendered
/// and, once loaded, the scene and its frame graph.
struct Rendering {
    gpu: Gpu,
    spec: RenderSpec,
    /// The 64-sample reference, unless the reference is captured.
    reference: Option<TechniqueSpec>,
}

impl Rendering {
    /// Opens the device and sets up the techniques `--technique` names (none when
    /// `techniques` is false) and, when `reference`, the 64-sample reference.
    fn new(args: &ClipArgs, techniques: bool, reference: bool) -> anyhow::Result<Self> {
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
        let specs = match techniques {
            true => technique_specs(&gpu, &args.techniques)?,
            false => Vec::new(),
        };
        let reference = reference.then(|| reference_spec(&gpu)).transpose()?;
        let mut spec = spec_for_scene(&args.scene, u64::from(args.warmup), specs);
        spec.adapter = Some(format!("{} ({})", gpu.caps.adapter_name, gpu.caps.backend));
        Ok(Self {
            gpu,
            spec,
            reference,
        })
    }

    /// Loads the scene, points the camera and builds the frame graph of the techniques and
    /// the rendered reference (last).
    fn load(&mut self, args: &ClipArgs) -> anyhow::Result<(Scene, FrameGraph)> {
        let mut scene = load_scene(&self.spec, args.scene.strict)?;
        args.scene.camera.apply(&mut self.spec, &mut scene)?;
        let mut graph_spec = self.spec.clone();
        graph_spec.techniques.extend(self.reference.clone());
        let mut graph = spec::build_graph(&self.gpu, &scene, &graph_spec)?;
        // The rendered reference stays unfiltered (`--specular-aa` is for the techniques).
        if self.reference.is_some()
            && let Some(reference_slot) = graph.slots_mut().last_mut()
        {
            reference_slot.reference = true;
        }
        Ok((scene, graph))
    }
}

/// Every pane's label and id, in pane order: the rendered techniques', the sequences', the
/// reference's.
fn pane_names(graph: Option<&FrameGraph>, sequences: &ClipSequences) -> (Vec<String>, Vec<String>) {
    let mut names: Vec<(String, String)> = graph
        .map(|g| {
            g.slots()
                .iter()
                .map(|s| (s.technique.label(), s.technique.id().to_owned()))
                .collect()
        })
        .unwrap_or_default();
    let rendered_reference = match sequences.reference {
        Some(_) => None,
        None => names.pop(),
    };
    names.extend(
        sequences
            .panes
            .iter()
            .map(|p| (p.label.clone(), p.label.clone())),
    );
    names.push(match rendered_reference {
        Some((label, id)) => (format!("Reference ({label})"), id),
        None => (
            "Reference (captured)".to_owned(),
            REFERENCE_LABEL.to_owned(),
        ),
    });
    names.into_iter().unzip()
}

/// Runs `aa-lab clip`.
pub fn run(args: &ClipArgs) -> anyhow::Result<()> {
    // Captures are not known to be HDR: a named tonemapper shows OpenEXR frames through it,
    // `auto` and `none` clamp them.
    let capture_tonemap = (args.scene.tonemap).resolve(false, args.scene.exposure);
    let sequences = ClipSequences::open(
        &args.sequence,
        args.reference_sequence.as_deref(),
        &args.offset,
        capture_tonemap,
    )?;
    let renders_techniques = args.techniques_given || sequences.panes.is_empty();
    let size = clip_size(args, &sequences, renders_techniques)?;
    let (region, zoom, format) = check_args(args, size)?;
    let frames = sequences.clip_frames(args.frames, MAX_CLIP_FRAMES)?;
    let renders_reference = sequences.reference.is_none();
    let mut rendering = (renders_techniques || renders_reference)
        .then(|| Rendering::new(args, renders_techniques, renders_reference))
        .transpose()?;
    let json = json_path(&args.out);
    let policy = sequences.protect(match &rendering {
        Some(r) => output_policy(args.force, None, &r.spec),
        None => files::Overwrite::new(args.force),
    });
    let html = args.html.then(|| html_path(&args.out));
    policy.check_all(
        [args.out.as_path(), json.as_path()]
            .into_iter()
            .chain(html.as_deref()),
    )?;
    let (scene, mut graph) = match rendering.as_mut().map(|r| r.load(args)).transpose()? {
        Some((scene, graph)) => (Some(scene), Some(graph)),
        None => (None, None),
    };
    let (labels, ids) = pane_names(graph.as_ref(), &sequences);
    let pane = region.unwrap_or(Rect {
        x: 0,
        y: 0,
        width: size.0,
        height: size.1,
    });
    clip::check(
        labels.len(),
        region.is_some(),
        (pane.width, pane.height),
        zoom,
    )?;
    let scorer = args
        .jod
        .then(|| args.jod_view.scorer(args.jod_heatmap.is_some()))
        .transpose()?;
    let jod_maps = args
        .jod_heatmap
        .as_deref()
        .map(|dir| jod_heatmap_paths(dir, &ids, &policy))
        .transpose()?;
    let name = scene
        .as_ref()
        .map_or_else(|| "captured sequences".to_owned(), |s| s.name.clone());
    let adapter = rendering
        .as_ref()
        .and_then(|r| r.spec.adapter.clone())
        .unwrap_or_else(|| "the CPU (nothing rendered)".to_owned());
    let layout = pending_layout(
        args,
        rendering.is_some(),
        &name,
        &adapter,
        &labels,
        (region, zoom),
    );
    if let Some(parent) = args.out.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent)
            .with_context(|| format!("cannot create directory {}", parent.display()))?;
    }
    let recording = Recording {
        out: &args.out,
        jod: args.jod,
        motion: args.motion,
        speed: args.speed,
        warmup: args.warmup,
        scene: scene.as_ref(),
        name: &name,
        frames,
        size,
        sequences: &sequences,
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
            .map(|dir| pane_dirs(dir, &ids, frames, &policy))
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
    let renderer = match (&rendering, graph.as_mut()) {
        (Some(r), Some(graph)) => Some((&r.gpu, graph)),
        _ => None,
    };
    let recorded = record(&recording, renderer, labels.len(), page)?;
    let rendered = started.elapsed();
    let jods = scorer
        .as_ref()
        .map(|scorer| {
            let heatmaps = jod_maps.as_deref().map(|paths| (paths, &policy));
            jod_figures(scorer, &recorded.whole_frames, &labels, args.fps, heatmaps)
        })
        .transpose()?;
    let panes = ClipPanes {
        ids: &ids,
        labels: &labels,
        captured: &sequences,
    };
    let shape = ClipShape {
        frames,
        fps: args.fps,
        region,
        zoom,
        format,
    };
    let record = record_of(args, rendering, &panes, shape, &recorded, (jods, scorer))?;
    drop(graph);
    finish(
        args,
        &recording,
        recorded,
        layout,
        &record,
        (started, rendered),
    )
}

/// The size of every pane: the reference sequence's when nothing is rendered, else the
/// render's (`--size`); every sequence must have it.
fn clip_size(
    args: &ClipArgs,
    sequences: &ClipSequences,
    renders_techniques: bool,
) -> anyhow::Result<(u32, u32)> {
    match (&sequences.reference, renders_techniques) {
        (Some(reference), false) => {
            let size = reference.size();
            sequences.check_size(size, "the reference sequence")?;
            Ok(size)
        }
        _ => {
            sequences.check_size(args.scene.size, "the clip's render (--size)")?;
            Ok(args.scene.size)
        }
    }
}

/// The record of a recorded clip: the render's recipe (when anything was rendered), the
/// panes and their figures, and with `--jod` the panes' JOD and the scorer's setting.
fn record_of(
    args: &ClipArgs,
    rendering: Option<Rendering>,
    panes: &ClipPanes,
    shape: ClipShape,
    recorded: &Recorded,
    (jods, scorer): (Option<Vec<f64>>, Option<JodScorer>),
) -> anyhow::Result<ClipRecord> {
    let rendered = rendering.map(|r| RenderedPart {
        spec: r.spec,
        reference: r.reference,
        motion: args.motion,
        speed_px: args.speed,
        warmup: args.warmup,
    });
    let figures = ClipFigures {
        metrics: &recorded.metrics,
        region_metrics: recorded.region_metrics.as_ref(),
        series: &recorded.series,
        jods: jods.as_deref(),
        jod: scorer.as_ref().map(|s| s.setting(f32::from(args.fps))),
    };
    clip_record(rendered, panes, shape, &figures)
}

/// Composes the first frame again with the figures, finishes the animation, writes the
/// record and the page, and prints the table.
fn finish(
    args: &ClipArgs,
    rec: &Recording,
    recorded: Recorded,
    mut layout: clip::Layout,
    record: &ClipRecord,
    (started, rendered): (std::time::Instant, std::time::Duration),
) -> anyhow::Result<()> {
    let json = json_path(&args.out);
    let metrics = &recorded.metrics;
    // The captions give the figures of what the animation shows.
    let shown_metrics = recorded.region_metrics.as_ref().unwrap_or(metrics);
    show_figures(
        &mut layout,
        &shown_metrics.scores(),
        shown_metrics.reference().mean_change(),
        rec.pending_layout.region.map_or(rec.size.0, |r| r.width) * rec.pending_layout.zoom,
    );
    let first_refs: Vec<&image::RgbaImage> = recorded.first_crops.iter().collect();
    let first = layout.compose(0, rec.frames as usize, &first_refs)?;
    let text = serde_json::to_string_pretty(record)? + "\n";
    if matches!(rec.format, ClipFormat::Video(_)) {
        eprintln!("encoding {} with ffmpeg…", args.out.display());
    }
    let replaced = recorded
        .writer
        .finish(&first, Some(&text), sheet::BACKGROUND_RGBA)?;
    let warmup = if rec.scene.is_some() { args.warmup } else { 0 };
    eprintln!(
        "made {} frames ({} of warm-up), compressing the clip's as they came, in {:.1} s; then {:.1} s to finish the file",
        u64::from(warmup) + u64::from(rec.frames),
        warmup,
        rendered.as_secs_f64(),
        (started.elapsed() - rendered).as_secs_f64()
    );
    println!("{}", files::wrote_line(&args.out, replaced));
    let replaced = files::write_bytes(&json, rec.policy, text.as_bytes())?;
    println!("{}", files::wrote_line(&json, replaced));
    if let (Some(page), true) = (recorded.page, args.html) {
        let replaced = page.finish(&serde_json::to_value(record)?)?;
        println!("{}", files::wrote_line(&html_path(&args.out), replaced));
    }
    print_table(record);
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
