//! `aa-lab clip`'s frame loop: renders each frame through the frame graph (when anything is
//! rendered) with the library's [`ClipRecorder`], reads every output back beside the captured
//! sequences' frames of the same clip frame ([`ClipSequences`]), scores it (temporal figures;
//! with sequences, every pane's SSIM, PSNR, MAE and FLIP against the reference's frame,
//! [`FrameSeries`]), writes the panes' frames for `--frames-dir`, and hands the composed frame
//! to the encoder (which compresses while the next frames render) and to the HTML page. A clip
//! that nothing renders plays the sequences' frames through the same steps without cameras
//! ([`RecordedClip::scored`]).

use std::path::{Path, PathBuf};

use anyhow::{Context, bail};
use indicatif::ProgressBar;

use super::clip_sequences::ClipSequences;
use super::render::progress_bar_with_eta;
use crate::aa::FrameInfo;
use crate::clip_recorder::{ClipFrames, ClipRecorder, FrameImages, RecordedClip, ScoredFrame};
use crate::export::animation::AnimationOptions;
use crate::export::clip;
use crate::export::clip_writer::{ClipFormat, ClipWriter};
use crate::export::html::HtmlPage;
use crate::export::sheet::Rect;
use crate::export::write_png;
use crate::files;
use crate::gpu::{Gpu, read_texture_rgba8};
use crate::graph::{FrameGraph, FrameScope};
use crate::metrics::series::FrameSeries;
use crate::metrics::stability::ClipMetrics;
use crate::scene::Scene;
use crate::scene::motion::Motion;

/// Frame `number` of a pane's folder in `--frames-dir`.
fn frame_path(dir: &Path, number: usize) -> PathBuf {
    dir.join(format!("{number:04}.png"))
}

/// Each pane's folder in `dir` (`--frames-dir`): the technique's id as a file name, and
/// `reference` for the last pane; created here once every frame's path has passed `policy`.
pub(super) fn pane_dirs(
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
    for (i, d) in dirs.iter().enumerate() {
        if let Some(other) = dirs[..i].iter().position(|o| o == d) {
            bail!(
                "--frames-dir: the panes {} and {} would both write into {}; label the sequence otherwise",
                ids[other],
                ids[i],
                d.display()
            );
        }
    }
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

/// What the frame loop needs besides the graph: the motion, the region, the captured panes and
/// the animation being written.
pub(super) struct Recording<'a> {
    /// The animation's path.
    pub out: &'a Path,
    /// Whether the whole frames are kept for `--jod`.
    pub jod: bool,
    /// The camera motion, its speed and the warm-up frames before the clip.
    pub motion: Motion,
    pub speed: f32,
    pub warmup: u32,
    /// The scene, when anything is rendered.
    pub scene: Option<&'a Scene>,
    /// The scene's name, or what the panes show when nothing is rendered.
    pub name: &'a str,
    pub frames: u32,
    pub size: (u32, u32),
    pub sequences: &'a ClipSequences,
    pub region: Option<Rect>,
    /// The layout with the figures' captions left empty: every frame is composed with it as
    /// it renders, and the first is composed again with the figures at the end.
    pub pending_layout: clip::Layout,
    pub format: ClipFormat,
    pub options: AnimationOptions,
    pub policy: &'a files::Overwrite,
    /// With `--frames-dir`, the folder of each pane's frames (the reference's last).
    pub pane_dirs: Option<Vec<PathBuf>>,
}

/// The figures of a recorded clip, and the first frame's panes (composed again with them).
pub(super) struct Recorded {
    pub writer: ClipWriter,
    pub page: Option<HtmlPage>,
    pub metrics: ClipMetrics,
    pub region_metrics: Option<ClipMetrics>,
    pub first_crops: Vec<image::RgbaImage>,
    /// With `--jod`, every clip frame's whole panes (the reference's last).
    pub whole_frames: Vec<Vec<image::RgbaImage>>,
    /// With sequences, every pane's image figures against the reference, frame by frame.
    pub series: Vec<FrameSeries>,
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

/// The command line's side of the recorder: renders through `graph` (when anything is
/// rendered), reads every output back and the captured panes' frames, shows progress, and
/// hands each frame's composed panes to the encoder (which compresses while the next frames
/// render) and to the HTML page.
struct CliFrames<'a> {
    rec: &'a Recording<'a>,
    renderer: Option<(&'a Gpu, &'a mut FrameGraph)>,
    bar: ProgressBar,
    writer: Option<ClipWriter>,
    page: Option<HtmlPage>,
    first_crops: Vec<image::RgbaImage>,
    /// With `--jod`, every clip frame's whole panes (the reference's last).
    whole_frames: Vec<Vec<image::RgbaImage>>,
    /// Clip frames read so far: the next frame of every sequence.
    read: usize,
    /// With sequences, every pane's image figures (the reference's left out).
    series: Vec<FrameSeries>,
}

impl CliFrames<'_> {
    /// Says what the next frame is, then renders it with `scope`.
    fn render(&mut self, frame: &FrameInfo, scope: FrameScope) -> anyhow::Result<()> {
        let phase = if scope == FrameScope::TemporalOnly {
            "warm-up".to_owned()
        } else {
            let encoded = self.writer.as_mut().map_or(0, ClipWriter::written);
            format!("clip, {encoded} encoded")
        };
        self.bar
            .set_message(format!("{} {}: {phase}", self.rec.name, self.rec.motion));
        let (_, graph) = self
            .renderer
            .as_mut()
            .context("a clip of sequences renders nothing")?;
        graph.render(frame, scope)?;
        graph.finish();
        self.bar.inc(1);
        Ok(())
    }

    /// The next clip frame's panes: the rendered techniques' `rendered` images (and the
    /// rendered reference's, last, when the reference is not captured), then every sequence's
    /// frame, then the reference's.
    fn panes(&mut self, mut rendered: Vec<image::RgbaImage>) -> anyhow::Result<PaneImages> {
        let index = self.read;
        self.read += 1;
        let sequences = self.rec.sequences;
        let reference = match &sequences.reference {
            Some(captured) => captured.frame(index)?,
            None => rendered.pop().context("the reference produced no image")?,
        };
        let mut whole = rendered;
        whole.extend(sequences.frames(index)?);
        whole.push(reference);
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

    /// Adds a frame's panes to their image figures against the reference (with sequences).
    fn score_images(&mut self, frame: &PaneImages) -> anyhow::Result<()> {
        let Some((reference, panes)) = frame.whole.split_last() else {
            return Ok(());
        };
        for (number, (series, pane)) in self.series.iter_mut().zip(panes).enumerate() {
            series.push(reference, pane).with_context(|| {
                format!(
                    "cannot score pane {} of clip frame {}",
                    number + 1,
                    self.read - 1
                )
            })?;
        }
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
        let (gpu, graph) = self
            .renderer
            .as_ref()
            .context("a clip of sequences renders nothing")?;
        let rendered = graph
            .slots()
            .iter()
            .map(|slot| {
                let output = slot
                    .output()
                    .with_context(|| format!("{} produced no image", slot.technique.label()))?;
                Ok(read_texture_rgba8(gpu, output)?)
            })
            .collect::<anyhow::Result<Vec<_>>>()?;
        self.panes(rendered)
    }

    fn deliver(&mut self, number: usize, frame: PaneImages) -> anyhow::Result<()> {
        if let Some(dirs) = &self.rec.pane_dirs {
            for (dir, image) in dirs.iter().zip(&frame.whole) {
                write_png(&frame_path(dir, number), image, None, self.rec.policy)?;
            }
        }
        self.score_images(&frame)?;
        let panes = match (frame.crops, self.rec.jod) {
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
            .compose(number, rec.frames as usize, &refs)?;
        ClipWriter::push_or_start(
            &mut self.writer,
            rec.out,
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

/// Plays a clip that nothing renders: every frame read from the sequences, scored and
/// delivered in order.
fn play_captured(frames: &mut CliFrames, techniques: usize) -> anyhow::Result<RecordedClip> {
    let mut clip = RecordedClip::scored(techniques);
    for number in 0..frames.rec.frames as usize {
        frames
            .bar
            .set_message(format!("{}: frame {number}", frames.rec.name));
        let frame = frames.panes(Vec::new())?;
        clip.add(&frame);
        frames.deliver(number, frame)?;
        frames.bar.inc(1);
    }
    Ok(clip)
}

/// Renders the warm-up and the clip through `graph` (when anything is rendered) with the
/// library's [`ClipRecorder`], reading the sequences' frames beside, scoring every clip frame,
/// and encodes the frames as they come.
pub(super) fn record(
    rec: &Recording,
    renderer: Option<(&Gpu, &mut FrameGraph)>,
    panes: usize,
    page: Option<HtmlPage>,
) -> anyhow::Result<Recorded> {
    let techniques = panes.saturating_sub(1);
    let warmup = if renderer.is_some() { rec.warmup } else { 0 };
    let total = u64::from(warmup) + u64::from(rec.frames);
    let mut frames = CliFrames {
        rec,
        renderer,
        bar: progress_bar_with_eta(total, "frames"),
        writer: None,
        page,
        first_crops: Vec::new(),
        whole_frames: Vec::new(),
        read: 0,
        series: match rec.sequences.is_empty() {
            true => Vec::new(),
            false => vec![FrameSeries::new(); techniques],
        },
    };
    let clip = match rec.scene {
        Some(scene) => {
            let cameras = (0..total)
                .map(|frame| rec.motion.camera(&scene.camera, rec.size, rec.speed, frame))
                .collect();
            ClipRecorder::new(cameras, warmup as usize, techniques, true).record(&mut frames)?
        }
        None => play_captured(&mut frames, techniques)?,
    };
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
        series: frames.series,
    })
}
