//! Export: one action writes, into the export folder, the full frame of every enabled
//! technique (lossless PNG carrying its render record, plus the debug view on screen), the
//! magnifier sheet (every pane with its label and figures, laid out by `export::sheet`) and a
//! sidecar JSON that `aa-lab render --from` reproduces. Existing files are never overwritten:
//! the whole set takes the next free name (`atrium-f120-2-...`). The magnifier sheet can also
//! be copied to the clipboard.
//!
//! The frames are the engine's published CPU copies (the bytes on screen); a worker thread
//! encodes and writes the files, so the window keeps running while a large export is written.
//! A clip is composed frame by frame into a streamed animation (compressed on every core,
//! [`crate::export::animation`]) and a self-contained HTML comparison page
//! ([`crate::export::html`]). The job reports its progress (the toolbar shows it with the
//! time left) and can be cancelled; closing the viewer cancels it and waits for it, and either
//! way the temporary file it was writing is removed.
//!
//! The menu bar, the toolbar, the clip bar and the shortcuts ask for an export with a command
//! (`context::Command::ExportFrame`, `ExportClip`); the workspace composes the magnifier sheet
//! and starts it here ([`ExportState::start_export`], [`ExportState::export_clip`]), which
//! keeps the running job and the last files written. Export has no panel of its own.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, mpsc};
use std::time::Instant;

use super::context::{Context, Level};
use super::engine::ClipRecipe;
use crate::export::animation::{AnimationFormat, AnimationOptions};
use crate::export::clip_writer::{ClipFormat, ClipWriter};
use crate::export::html::HtmlPage;
use crate::export::sheet;
use crate::export::write_png;
use crate::files::{self, Overwrite};
use crate::metrics::stability::TemporalScores;

/// What an export writes.
struct Plan {
    dir: PathBuf,
    stem: String,
    record: String,
    /// (file suffix, pixels) of every frame.
    images: Vec<(String, Arc<image::RgbaImage>)>,
    /// The magnifier sheet, composed.
    sheet: Option<image::RgbaImage>,
}

/// How far the running export is (items written of all), shared with its thread, and the
/// request to cancel it.
#[derive(Default)]
pub struct ExportProgress {
    done: AtomicUsize,
    total: AtomicUsize,
    cancelled: AtomicBool,
}

impl ExportProgress {
    fn set_total(&self, total: usize) {
        self.total.store(total, Ordering::Relaxed);
    }

    fn advance(&self) {
        self.done.fetch_add(1, Ordering::Relaxed);
    }

    /// Whether the export was asked to stop; the job checks between items and returns
    /// [`CANCELLED`] (dropping what it was writing removes the temporary file).
    fn cancelled(&self) -> bool {
        self.cancelled.load(Ordering::Relaxed)
    }
}

/// The error a cancelled export returns.
const CANCELLED: &str = "export cancelled";

/// A running export.
struct ExportJob {
    result: mpsc::Receiver<Result<Vec<PathBuf>, String>>,
    progress: Arc<ExportProgress>,
    started: Instant,
    thread: Option<std::thread::JoinHandle<()>>,
}

/// Export jobs and the export-folder dialog.
#[derive(Default)]
pub struct ExportState {
    job: Option<ExportJob>,
    /// Files written by the last export.
    pub last: Vec<PathBuf>,
}

impl ExportState {
    /// Whether an export runs.
    pub fn running(&self) -> bool {
        self.job.is_some()
    }

    /// The running export's progress: `Exporting 12/48 frames, about 5 s left`.
    pub fn status(&self) -> Option<String> {
        let job = self.job.as_ref()?;
        let done = job.progress.done.load(Ordering::Relaxed);
        let total = job.progress.total.load(Ordering::Relaxed);
        if job.progress.cancelled() {
            return Some("Cancelling export…".to_owned());
        }
        if total == 0 {
            return Some("Exporting…".to_owned());
        }
        let elapsed = job.started.elapsed().as_secs_f64();
        let left = (done > 0).then(|| elapsed / done as f64 * (total - done.min(total)) as f64);
        Some(match left {
            Some(left) => format!("Exporting {done}/{total}, about {left:.0} s left"),
            None => format!("Exporting 0/{total}…"),
        })
    }

    /// Asks the running export to stop: it removes what it was writing.
    pub fn cancel(&self) {
        if let Some(job) = &self.job {
            job.progress.cancelled.store(true, Ordering::Relaxed);
        }
    }

    /// Collects a finished export; returns notices for the user.
    pub fn poll(&mut self) -> Vec<(Level, String)> {
        let Some(job) = &self.job else {
            return Vec::new();
        };
        let notice = match job.result.try_recv() {
            Ok(Ok(paths)) => {
                let dir = paths
                    .first()
                    .and_then(|p| p.parent())
                    .map_or_else(String::new, |d| d.display().to_string());
                let notice = (
                    Level::Info,
                    format!("Exported {} files to {dir}", paths.len()),
                );
                self.last = paths;
                notice
            }
            Ok(Err(err)) if err == CANCELLED => (
                Level::Info,
                "Export cancelled: the file being written was removed".to_owned(),
            ),
            Ok(Err(err)) => (Level::Error, err),
            Err(mpsc::TryRecvError::Empty) => return Vec::new(),
            Err(mpsc::TryRecvError::Disconnected) => (
                Level::Error,
                "export failed: the writer thread stopped".to_owned(),
            ),
        };
        self.job = None;
        vec![notice]
    }
}

impl Drop for ExportState {
    /// Closing the viewer mid-export cancels it and waits for its thread, which removes the
    /// temporary file it was writing (it stops within a frame).
    fn drop(&mut self) {
        self.cancel();
        if let Some(thread) = self.job.as_mut().and_then(|job| job.thread.take()) {
            let _ = thread.join();
        }
    }
}

/// Runs `job` (composing, encoding and writing files) on a thread of its own.
fn in_background(
    job: impl FnOnce(&ExportProgress) -> Result<Vec<PathBuf>, String> + Send + 'static,
) -> ExportJob {
    let (sender, result) = mpsc::channel();
    let progress = Arc::new(ExportProgress::default());
    let spawned = std::thread::Builder::new()
        .name("aa-lab export".to_owned())
        .spawn({
            let sender = sender.clone();
            let progress = Arc::clone(&progress);
            move || {
                let _ = sender.send(job(&progress));
            }
        });
    let thread = match spawned {
        Ok(thread) => Some(thread),
        Err(err) => {
            let _ = sender.send(Err(format!("export failed: cannot start a thread: {err}")));
            None
        }
    };
    ExportJob {
        result,
        progress,
        started: Instant::now(),
        thread,
    }
}

/// Writes the PNGs, the sheet and the sidecar under the first free stem.
fn write_files(plan: &Plan, progress: &ExportProgress) -> Result<Vec<PathBuf>, String> {
    let images = &plan.images;
    progress.set_total(images.len() + usize::from(plan.sheet.is_some()));
    std::fs::create_dir_all(&plan.dir).map_err(|e| {
        format!(
            "cannot create the export folder {}: {e}",
            plan.dir.display()
        )
    })?;
    let mut suffixes: Vec<String> = images.iter().map(|(s, _)| format!("-{s}.png")).collect();
    suffixes.push(".json".to_owned());
    if plan.sheet.is_some() {
        suffixes.push("-magnifier.png".to_owned());
    }
    let stem = files::free_stem(&plan.dir, &plan.stem, &suffixes);
    // The stem is free; never replacing anything also guards against a file appearing meanwhile.
    let policy = Overwrite::new(false);
    let mut written = Vec::new();
    for (suffix, image) in images {
        if progress.cancelled() {
            return Err(CANCELLED.to_owned());
        }
        let path = plan.dir.join(format!("{stem}-{suffix}.png"));
        write_png(&path, image, Some(&plan.record), &policy).map_err(|e| e.to_string())?;
        written.push(path);
        progress.advance();
    }
    if let Some(sheet) = &plan.sheet {
        let path = plan.dir.join(format!("{stem}-magnifier.png"));
        write_png(&path, sheet, Some(&plan.record), &policy).map_err(|e| e.to_string())?;
        written.push(path);
    }
    let sidecar = plan.dir.join(format!("{stem}.json"));
    files::write_bytes(&sidecar, &policy, plan.record.as_bytes()).map_err(|e| e.to_string())?;
    written.push(sidecar);
    Ok(written)
}

/// Version of the record beside a clip exported from the viewer.
const CLIP_SCHEMA: &str = "aa-lab viewer clip 1";

/// The record beside an exported clip.
#[derive(serde::Serialize)]
struct ClipExportRecord {
    schema: &'static str,
    /// Scene, camera path, size, techniques with their settings, reference, adapter, build.
    recipe: ClipRecipe,
    /// Frames in the animation (fewer than the recipe's when the recording was cancelled).
    recorded_frames: usize,
    /// Playback rate of the animation.
    fps: u16,
    /// Region shown, pixels of the render (`None`: whole frames).
    region: Option<sheet::Rect>,
    /// Zoom of the panes.
    zoom: u32,
    definitions: crate::export::clip::Definitions,
    /// The reference's mean luma change per pixel and frame.
    reference_mean_change: Option<f64>,
    techniques: Vec<ClipExportTechnique>,
}

#[derive(serde::Serialize)]
struct ClipExportTechnique {
    id: &'static str,
    label: String,
    #[serde(flatten)]
    scores: TemporalScores,
}

/// What a clip export writes.
struct ClipPlan {
    dir: PathBuf,
    stem: String,
    layout: crate::export::clip::Layout,
    region: Option<sheet::Rect>,
    /// Pixels of every frame's panes, in pane order (the reference last).
    frames: Vec<Vec<Arc<image::RgbaImage>>>,
    fps: u16,
    record: String,
}

/// Composes the clip's frames one after the other into a streamed animated PNG and writes it
/// and its record under the first free stem in the export folder.
fn write_clip(plan: &ClipPlan, progress: &ExportProgress) -> Result<Vec<PathBuf>, String> {
    let ClipPlan {
        dir,
        stem,
        layout,
        region,
        frames,
        fps,
        record,
    } = plan;
    let (dir, region, fps) = (dir.as_path(), *region, *fps);
    std::fs::create_dir_all(dir)
        .map_err(|e| format!("cannot create the export folder {}: {e}", dir.display()))?;
    let suffixes = [".png", ".json", ".html"].map(str::to_owned);
    let stem = files::free_stem(dir, stem, &suffixes);
    let policy = Overwrite::new(false);
    let animation = dir.join(format!("{stem}.png"));
    let page_path = dir.join(format!("{stem}.html"));
    let options = AnimationOptions::new(AnimationFormat::Apng, fps);
    let labels: Vec<String> = layout.panes.iter().map(|p| p.label.clone()).collect();
    progress.set_total(frames.len());
    let mut stream = None;
    let mut page = None;
    // The stream does not keep the first frame it was given; this clip holds all of its
    // frames anyway, so one more composed frame costs little.
    let mut first = None;
    for (n, panes) in frames.iter().enumerate() {
        if progress.cancelled() {
            return Err(CANCELLED.to_owned());
        }
        let crops: Vec<image::RgbaImage> = panes
            .iter()
            .map(|image| match region {
                Some(r) => image::imageops::crop_imm(image.as_ref(), r.x, r.y, r.width, r.height)
                    .to_image(),
                None => image.as_ref().clone(),
            })
            .collect();
        let refs: Vec<&image::RgbaImage> = crops.iter().collect();
        let page = match &mut page {
            Some(page) => page,
            None => page.insert(
                HtmlPage::create(
                    &page_path,
                    &policy,
                    &layout.title,
                    &labels,
                    refs.first().map_or((1, 1), |c| c.dimensions()),
                    fps,
                    layout.zoom,
                )
                .map_err(|e| e.to_string())?,
            ),
        };
        page.push(&refs).map_err(|e| e.to_string())?;
        let composed = layout
            .compose(n, frames.len(), &refs)
            .map_err(|e| format!("clip export: {e}"))?;
        if n == 0 {
            first = Some(composed.clone());
        }
        let apng = ClipFormat::Animation(AnimationFormat::Apng);
        ClipWriter::push_or_start(&mut stream, &animation, &policy, apng, options, composed)
            .map_err(|e| e.to_string())?;
        progress.advance();
    }
    let (Some(stream), Some(page), Some(first)) = (stream, page, first) else {
        return Err("clip export: the clip has no frame".to_owned());
    };
    // An animation has no odd sides to pad: the background is a video's alone.
    stream
        .finish(&first, Some(record), [0; 4])
        .map_err(|e| e.to_string())?;
    let sidecar = dir.join(format!("{stem}.json"));
    files::write_bytes(&sidecar, &policy, record.as_bytes()).map_err(|e| e.to_string())?;
    let record: serde_json::Value = serde_json::from_str(record).map_err(|e| e.to_string())?;
    page.finish(&record).map_err(|e| e.to_string())?;
    Ok(vec![animation, sidecar, page_path])
}

impl ExportState {
    /// Starts an export of the displayed frame (see the module docs).
    pub(super) fn start_export(&mut self, cx: &mut Context, sheet: Option<image::RgbaImage>) {
        if self.running() {
            return;
        }
        if cx.images.is_open() {
            cx.notify(
                Level::Warning,
                "Export writes rendered frames; the open images are files already (Copy magnifier sheet copies their magnified panes)",
            );
            return;
        }
        let Some(spec) = cx.current_spec() else {
            cx.notify(
                Level::Warning,
                "Nothing to export yet: no frame has been rendered.",
            );
            return;
        };
        let Ok(record) = serde_json::to_string_pretty(&spec) else {
            cx.notify(
                Level::Error,
                "export failed: the render record could not be written",
            );
            return;
        };
        let Some(engine) = &cx.engine else { return };
        let mut images = Vec::new();
        for entry in engine.entries().iter().filter(|e| e.enabled) {
            let Some(output) = engine.output(entry.id).and_then(|o| o.pixels.as_ref()) else {
                continue;
            };
            let name = crate::aa::user::file_name_part(entry.id);
            images.push((name.to_string(), Arc::clone(output)));
            if let (Some(view), Some(image)) = (
                &entry.debug_view,
                engine.image(entry.id).and_then(|i| i.pixels.as_ref()),
            ) && !Arc::ptr_eq(image, output)
            {
                images.push((format!("{name}-{view}"), Arc::clone(image)));
            }
        }
        let scene = cx.scene.as_ref().map_or("scene", |s| s.name.as_str());
        let plan = Plan {
            dir: cx.settings.export_dir.clone(),
            stem: format!("{scene}-f{}", spec.frame),
            record,
            images,
            sheet,
        };
        self.job = Some(in_background(move |progress| write_files(&plan, progress)));
    }

    /// Exports the clip as a looping animated PNG of the magnifier's panes (the lens region,
    /// zoomed as the magnifier shows it; whole frames in a grid when the magnifier is closed)
    /// with its temporal figures, the clip's record beside it and a self-contained HTML
    /// comparison page of the same panes, into the export folder.
    pub(super) fn export_clip(&mut self, cx: &mut Context) {
        if self.running() {
            return;
        }
        let Some(clip) = cx.engine.as_ref().and_then(|e| e.clip()) else {
            return;
        };
        let lens = cx.settings.show_magnifier.then(|| cx.lens()).flatten();
        let region = lens.map(|l| sheet::Rect {
            x: l.x,
            y: l.y,
            width: l.width,
            height: l.height,
        });
        let zoom = if region.is_some() {
            cx.settings.magnifier.zoom
        } else {
            1
        };
        let size = clip.recipe.size;
        let pane_size = region.map_or(size, |r| (r.width, r.height));
        let panes = clip.techniques.len() + usize::from(clip.recipe.reference_samples.is_some());
        if let Err(err) = crate::export::clip::check(panes, region.is_some(), pane_size, zoom) {
            cx.notify(Level::Error, format!("clip export: {err}"));
            return;
        }
        let width = pane_size.0 * zoom;
        let no_scores = TemporalScores {
            mean_change: None,
            temporal_instability: None,
            ghosting: None,
        };
        let scores: Vec<TemporalScores> = (0..clip.techniques.len())
            .map(|i| {
                clip.scores
                    .as_ref()
                    .and_then(|s| s.get(i).copied())
                    .unwrap_or(no_scores)
            })
            .collect();
        let mut layout_panes: Vec<crate::export::clip::Pane> = clip
            .techniques
            .iter()
            .zip(&scores)
            .map(|(id, scores)| crate::export::clip::Pane {
                label: cx.shown_label(id),
                caption: crate::export::clip::fit(
                    &[
                        crate::export::clip::caption(scores),
                        crate::export::clip::short_caption(scores),
                    ],
                    width,
                ),
            })
            .collect();
        if let Some(samples) = clip.recipe.reference_samples {
            layout_panes.push(crate::export::clip::Pane {
                label: format!("Reference ({samples} spp)"),
                caption: crate::export::clip::reference_caption(clip.reference_change, width),
            });
        }
        let scene = cx.scene.as_ref().map_or("scene", |s| s.name.as_str());
        let layout = crate::export::clip::Layout {
            title: format!("aa-lab viewer clip: {}", clip.description),
            scene: scene.to_owned(),
            region,
            zoom,
            footer: format!(
                "captions: temporal instability / ghosting (luma levels); {} on {}",
                clip.recipe.build, clip.recipe.adapter
            ),
            panes: layout_panes,
        };
        // Pixels of every frame's panes, in pane order (the reference last).
        let frames: Vec<Vec<Arc<image::RgbaImage>>> = clip
            .frames
            .iter()
            .map(|frame| {
                frame
                    .outputs
                    .iter()
                    .chain(std::iter::once(&frame.reference).filter(|r| r.is_some()))
                    .filter_map(|image| image.as_ref()?.pixels.clone())
                    .collect()
            })
            .filter(|panes: &Vec<_>| panes.len() == layout.panes.len())
            .collect();
        if frames.is_empty() {
            cx.notify(
                Level::Warning,
                "The clip has no complete frame to export yet.",
            );
            return;
        }
        let fps = clip.player.rate.fps().round() as u16;
        let record = ClipExportRecord {
            schema: CLIP_SCHEMA,
            recipe: clip.recipe.clone(),
            recorded_frames: frames.len(),
            fps,
            region,
            zoom,
            definitions: crate::export::clip::Definitions::over(match region {
                Some(_) => "every pixel of the whole frame, every recorded frame (the animation shows the lens region)".to_owned(),
                None => "every pixel of the whole frame, every recorded frame".to_owned(),
            }),
            reference_mean_change: clip.reference_change,
            techniques: clip
                .techniques
                .iter()
                .zip(&scores)
                .map(|(id, scores)| ClipExportTechnique {
                    id,
                    label: cx.shown_label(id),
                    scores: *scores,
                })
                .collect(),
        };
        let Ok(text) = serde_json::to_string_pretty(&record) else {
            cx.notify(Level::Error, "clip export: the record could not be written");
            return;
        };
        let plan = ClipPlan {
            dir: cx.settings.export_dir.clone(),
            stem: format!("{scene}-clip"),
            layout,
            region,
            frames,
            fps,
            record: text,
        };
        self.job = Some(in_background(move |progress| write_clip(&plan, progress)));
    }
}
