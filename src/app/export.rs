//! Export: one action writes, into the export folder, the full frame of every enabled
//! technique (lossless PNG carrying its render record, plus the debug view on screen), the
//! magnifier sheet (every pane with its label and figures, laid out by `export::sheet`) and a
//! sidecar JSON that `aa-lab render --from` reproduces. Existing files are never overwritten:
//! the whole set takes the next free name (`atrium-f120-2-...`). The magnifier sheet can also
//! be copied to the clipboard.
//!
//! The frames are the engine's published CPU copies (the bytes on screen); a worker thread
//! encodes and writes the files, so the window keeps running while a large export is written.

use std::path::{Path, PathBuf};
use std::sync::{Arc, mpsc};

use super::app::{AaLabApp, DialogPurpose, Level};
use super::difference::lens_heatmap;
use super::magnifier::{Source, crop};
use crate::export::sheet::{self, Cell, Row};
use crate::export::write_png;
use crate::files::{self, Overwrite};
use crate::spec::{RenderSpec, TechniqueSpec};

/// The first name `stem`, `stem-2`, `stem-3`... for which none of the set's files exist.
pub fn free_stem(dir: &Path, stem: &str, suffixes: &[String]) -> String {
    (1..)
        .map(|n| {
            if n == 1 {
                stem.to_owned()
            } else {
                format!("{stem}-{n}")
            }
        })
        .find(|candidate| {
            suffixes
                .iter()
                .all(|s| !dir.join(format!("{candidate}{s}")).exists())
        })
        .unwrap_or_else(|| stem.to_owned())
}

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

/// Export jobs and the export-folder dialog.
#[derive(Default)]
pub struct ExportState {
    job: Option<mpsc::Receiver<Result<Vec<PathBuf>, String>>>,
    /// Files written by the last export.
    pub last: Vec<PathBuf>,
}

impl ExportState {
    /// Whether an export runs.
    pub fn running(&self) -> bool {
        self.job.is_some()
    }

    /// Collects a finished export; returns notices for the user.
    pub fn poll(&mut self) -> Vec<(Level, String)> {
        let Some(receiver) = &self.job else {
            return Vec::new();
        };
        let notice = match receiver.try_recv() {
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

fn write_in_background(plan: Plan) -> mpsc::Receiver<Result<Vec<PathBuf>, String>> {
    let (sender, receiver) = mpsc::channel();
    let spawned = std::thread::Builder::new()
        .name("aa-lab export".to_owned())
        .spawn({
            let sender = sender.clone();
            move || {
                let _ = sender.send(write_files(&plan));
            }
        });
    if let Err(err) = spawned {
        let _ = sender.send(Err(format!("export failed: cannot start a thread: {err}")));
    }
    receiver
}

/// Writes the PNGs, the sheet and the sidecar under the first free stem.
fn write_files(plan: &Plan) -> Result<Vec<PathBuf>, String> {
    let images = &plan.images;
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
    let stem = free_stem(&plan.dir, &plan.stem, &suffixes);
    // The stem is free; never replacing anything also guards against a file appearing meanwhile.
    let policy = Overwrite::new(false);
    let mut written = Vec::new();
    for (suffix, image) in images {
        let path = plan.dir.join(format!("{stem}-{suffix}.png"));
        write_png(&path, image, Some(&plan.record), &policy).map_err(|e| e.to_string())?;
        written.push(path);
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

impl AaLabApp {
    /// The render record of the displayed frame: `aa-lab render --from` reproduces it.
    pub fn current_spec(&self) -> Option<RenderSpec> {
        let engine = self.engine.as_ref()?;
        let camera = engine.displayed()?;
        let scene = self.scene.as_ref()?;
        let techniques = engine
            .entries()
            .iter()
            .filter(|e| e.enabled && engine.output(e.id).is_some())
            .map(|e| TechniqueSpec {
                id: e.id.to_owned(),
                settings: engine.param_map(e.id),
            })
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
        let (w, h) = self.viewport.render_size;
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
            images.push((entry.id.to_owned(), Arc::clone(output)));
            if let (Some(view), Some(image)) = (
                &entry.debug_view,
                engine.image(entry.id).and_then(|i| i.pixels.as_ref()),
            ) && !Arc::ptr_eq(image, output)
            {
                images.push((format!("{}-{view}", entry.id), Arc::clone(image)));
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
        self.export.job = Some(write_in_background(plan));
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

    /// Points exports at a folder (tests use a temporary one).
    pub fn set_export_dir(&mut self, dir: PathBuf) {
        self.settings.export_dir = dir;
    }

    /// Files written by the last finished export.
    pub fn last_export(&self) -> &[PathBuf] {
        &self.export.last
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn free_stem_never_reuses_a_taken_name() {
        let dir = tempfile::tempdir().unwrap();
        let suffixes = vec!["-none.png".to_owned(), ".json".to_owned()];
        assert_eq!(free_stem(dir.path(), "atrium-f3", &suffixes), "atrium-f3");
        std::fs::write(dir.path().join("atrium-f3.json"), "{}").unwrap();
        assert_eq!(free_stem(dir.path(), "atrium-f3", &suffixes), "atrium-f3-2");
        std::fs::write(dir.path().join("atrium-f3-2-none.png"), "").unwrap();
        assert_eq!(free_stem(dir.path(), "atrium-f3", &suffixes), "atrium-f3-3");
    }
}
