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
//! Exports are workspace commands ([`Workspace::start_export`], [`Workspace::export_clip`],
//! [`Workspace::copy_sheet`], ...): the menu bar, the toolbar, the clip bar, the magnifier and
//! the shortcuts start them, so the running job and the last files written ([`ExportState`])
//! are the workspace's too; export has no panel of its own.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, mpsc};
use std::time::Instant;

use super::clip::ClipRecipe;
use super::difference::lens_heatmap;
use super::magnifier::{Source, crop};
use super::workspace::{DialogPurpose, Level, Workspace};
use crate::export::animation::{AnimationFormat, AnimationOptions};
use crate::export::clip_writer::{ClipFormat, ClipWriter};
use crate::export::html::HtmlPage;
use crate::export::sheet::{self, Cell, Row};
use crate::export::write_png;
use crate::files::{self, Overwrite};
use crate::metrics::stability::TemporalScores;
use crate::spec::RenderSpec;

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
        let apng = ClipFormat::Animation(AnimationFormat::Apng);
        ClipWriter::push_or_start(&mut stream, &animation, &policy, apng, options, composed)
            .map_err(|e| e.to_string())?;
        progress.advance();
    }
    let (Some(stream), Some(page)) = (stream, page) else {
        return Err("clip export: the clip has no frame".to_owned());
    };
    // An animation has no odd sides to pad: the background is a video's alone.
    stream
        .finish(None, Some(record), [0; 4])
        .map_err(|e| e.to_string())?;
    let sidecar = dir.join(format!("{stem}.json"));
    files::write_bytes(&sidecar, &policy, record.as_bytes()).map_err(|e| e.to_string())?;
    let record: serde_json::Value = serde_json::from_str(record).map_err(|e| e.to_string())?;
    page.finish(&record).map_err(|e| e.to_string())?;
    Ok(vec![animation, sidecar, page_path])
}

impl Workspace {
    /// The render record of the displayed frame: `aa-lab render --from` reproduces it.
    pub(super) fn current_spec(&self) -> Option<RenderSpec> {
        let engine = self.engine.as_ref()?;
        let camera = engine.displayed()?;
        let scene = self.scene.as_ref()?;
        let techniques = engine
            .entries()
            .iter()
            .filter(|e| e.enabled && engine.output(e.id).is_some())
            .map(|e| engine.technique_spec(e.id))
            .collect();
        Some(RenderSpec {
            scene: scene.spec.clone(),
            density: 1.0,
            seed: crate::scene::procedural::SceneOptions::default().seed,
            width: camera.size.0,
            height: camera.size.1,
            frame: camera.frame,
            camera: Some(camera.pose),
            rig: None,
            image: None,
            techniques,
            adapter: Some(format!(
                "{} ({})",
                engine.caps().adapter_name,
                engine.caps().backend
            )),
            build: Some(crate::spec::build_id()),
        })
    }

    /// The magnifier sheet of the current lens, composed: every pane as the magnifier shows it
    /// (pixels, or heatmaps in difference mode), labelled, with its figures underneath.
    pub(super) fn magnifier_sheet(&self) -> Option<image::RgbaImage> {
        let lens = self.lens()?;
        let zoom = self.settings.magnifier.zoom;
        let metric = self.settings.magnifier.metric;
        let reference = self.source_image(Source::Reference);
        let mut columns = Vec::new();
        let mut cells = Vec::new();
        for source in self.magnifier_sources() {
            let Some(image) = self.source_image(source).and_then(|i| i.pixels.as_ref()) else {
                continue;
            };
            let reference = reference.and_then(|r| r.pixels.as_ref());
            let pixels = match reference {
                Some(reference)
                    if self.settings.magnifier.difference && source != Source::Reference =>
                {
                    lens_heatmap(metric, reference, image, lens).ok()?.to_rgba()
                }
                _ => crop(image, lens),
            };
            let whole = sheet::Rect {
                x: 0,
                y: 0,
                width: lens.width,
                height: lens.height,
            };
            let (letter, _, title) = self.source_label(source);
            columns.push(format!("{letter} · {title}"));
            let caption = self.pane_figures(source);
            cells.push(Cell {
                image: sheet::crop_zoom(&pixels, whole, zoom).ok()?,
                caption: (!caption.is_empty()).then_some(caption),
            });
        }
        if cells.is_empty() {
            return None;
        }
        let scene = self.scene.as_ref().map_or("", |s| s.name.as_str());
        let frame = self
            .engine
            .as_ref()
            .and_then(|e| e.displayed())
            .map_or(0, |c| c.frame);
        let (w, h) = self.render_size;
        let mode = if self.settings.magnifier.difference {
            format!(", {} against the reference", metric.label().to_lowercase())
        } else {
            String::new()
        };
        let what = match self.image_names() {
            Some((names, _)) => names.join(", "),
            None => format!("{scene}, frame {frame}"),
        };
        Some(sheet::compose(&sheet::Sheet {
            title: format!("{what}, {w}×{h}{mode}"),
            columns,
            rows: vec![Row {
                label: format!("lens {zoom}×"),
                detail: Some(format!(
                    "{}×{} at ({}, {})",
                    lens.width, lens.height, lens.x, lens.y
                )),
                cells,
            }],
            footer: Some(format!(
                "{} on {}",
                crate::spec::build_id(),
                self.gpu.caps.adapter_name
            )),
        }))
    }

    /// Starts an export of the displayed frame (see the module docs).
    pub(super) fn start_export(&mut self, _ctx: &egui::Context) {
        if self.export.running() {
            return;
        }
        if self.images.is_open() {
            self.notify(
                Level::Warning,
                "Export writes rendered frames; the open images are files already (Copy magnifier sheet copies their magnified panes)",
            );
            return;
        }
        let Some(spec) = self.current_spec() else {
            self.notify(
                Level::Warning,
                "Nothing to export yet: no frame has been rendered.",
            );
            return;
        };
        let Ok(record) = serde_json::to_string_pretty(&spec) else {
            self.notify(
                Level::Error,
                "export failed: the render record could not be written",
            );
            return;
        };
        let Some(engine) = &self.engine else { return };
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
        let scene = self.scene.as_ref().map_or("scene", |s| s.name.as_str());
        let plan = Plan {
            dir: self.settings.export_dir.clone(),
            stem: format!("{scene}-f{}", spec.frame),
            record,
            images,
            sheet: self
                .settings
                .show_magnifier
                .then(|| self.magnifier_sheet())
                .flatten(),
        };
        self.export.job = Some(in_background(move |progress| write_files(&plan, progress)));
    }

    /// Exports the clip as a looping animated PNG of the magnifier's panes (the lens region,
    /// zoomed as the magnifier shows it; whole frames in a grid when the magnifier is closed)
    /// with its temporal figures, the clip's record beside it and a self-contained HTML
    /// comparison page of the same panes, into the export folder.
    pub(super) fn export_clip(&mut self) {
        if self.export.running() {
            return;
        }
        let Some(clip) = self.engine.as_ref().and_then(|e| e.clip()) else {
            return;
        };
        let lens = self.settings.show_magnifier.then(|| self.lens()).flatten();
        let region = lens.map(|l| sheet::Rect {
            x: l.x,
            y: l.y,
            width: l.width,
            height: l.height,
        });
        let zoom = if region.is_some() {
            self.settings.magnifier.zoom
        } else {
            1
        };
        let size = clip.recipe.size;
        let pane_size = region.map_or(size, |r| (r.width, r.height));
        let panes = clip.techniques.len() + usize::from(clip.recipe.reference_samples.is_some());
        if let Err(err) = crate::export::clip::check(panes, region.is_some(), pane_size, zoom) {
            self.notify(Level::Error, format!("clip export: {err}"));
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
                label: self.shown_label(id),
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
        let scene = self.scene.as_ref().map_or("scene", |s| s.name.as_str());
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
            self.notify(
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
                    label: self.shown_label(id),
                    scores: *scores,
                })
                .collect(),
        };
        let Ok(text) = serde_json::to_string_pretty(&record) else {
            self.notify(Level::Error, "clip export: the record could not be written");
            return;
        };
        let plan = ClipPlan {
            dir: self.settings.export_dir.clone(),
            stem: format!("{scene}-clip"),
            layout,
            region,
            frames,
            fps,
            record: text,
        };
        self.export.job = Some(in_background(move |progress| write_clip(&plan, progress)));
    }

    /// Copies the magnifier sheet to the clipboard.
    pub(super) fn copy_sheet(&mut self, ctx: &egui::Context) {
        match self.magnifier_sheet() {
            Some(image) => {
                let size = [image.width() as usize, image.height() as usize];
                ctx.copy_image(egui::ColorImage::from_rgba_unmultiplied(
                    size,
                    image.as_raw(),
                ));
                self.notify(
                    Level::Info,
                    format!(
                        "Copied the magnifier sheet ({}×{}) to the clipboard",
                        size[0], size[1]
                    ),
                );
            }
            None => self.notify(
                Level::Warning,
                "The magnifier has no pixels yet: show the magnifier and wait for the first frame.",
            ),
        }
    }

    /// Asks for the export folder.
    pub(super) fn pick_export_dir(&mut self, ctx: &egui::Context) {
        let start = self.settings.export_dir.clone();
        self.ask_for_path(ctx, DialogPurpose::ExportFolder, move || {
            rfd::FileDialog::new()
                .set_title("Export folder")
                .set_directory(&start)
                .pick_folder()
        });
    }

    /// Sends exports to `dir` (a folder picked in the dialog).
    pub(super) fn use_export_dir(&mut self, dir: PathBuf) {
        self.notify(Level::Info, format!("Exports go to {}", dir.display()));
        self.settings.export_dir = dir;
    }
}
