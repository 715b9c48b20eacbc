//! [`Workspace`], the state every panel reads or changes: the settings, the devices and the
//! engine, the loaded scene and the camera, the image set, the quality figures, the magnifier's
//! lens and heatmaps, the blind comparison, the exports, the notices and the open file dialog.
//!
//! The commands and queries more than one panel (or the shortcuts, or the background work)
//! use are methods of the workspace: this file holds the core ones (notices, scene loading,
//! file dialogs and what their answers do, switching and comparing techniques, user
//! techniques, bookmarks, time), and each feature module adds those of its feature (image
//! lookups and the image set in image_set.rs, the figures in quality.rs, the lens and its
//! heatmaps in magnifier.rs, exports in export.rs, clip recording in clip.rs, the blind
//! session in blind.rs). The panels only call them.

use std::path::PathBuf;
use std::sync::{Arc, mpsc};
use std::time::{Duration, Instant};

use super::blind::BlindState;
use super::camera::CameraController;
use super::engine::{Display, Engine};
use super::export::ExportState;
use super::image_set::ImageSetState;
use super::magnifier::MagnifierState;
use super::quality::QualityTracker;
use super::scene_loader::SceneLoader;
use super::settings::{Bookmark, MAX_COMPARE, Settings};
use super::stats::FrameClock;
use crate::gpu::Gpu;
use crate::scene::{CameraRig, Scene};

/// Largest bookmarks file read (thousands of bookmarks; anything larger is not ours).
const BOOKMARKS_LIMIT: u64 = 4 << 20;

/// How long a notice stays in the status bar.
pub(super) const NOTICE_SECONDS: f64 = 12.0;

/// Severity of a notice.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Level {
    /// Something finished.
    Info,
    /// Something is off but work continues.
    Warning,
    /// Something failed.
    Error,
}

/// A message for the user in the status bar (and the notices list).
#[derive(Clone, Debug)]
pub struct Notice {
    /// Severity.
    pub level: Level,
    /// Text.
    pub text: String,
    /// When it was raised.
    pub at: Instant,
}

/// What a file dialog's answer is for.
pub(super) enum DialogPurpose {
    /// Open a model.
    OpenModel,
    /// Write these bookmarks to the picked file.
    ExportBookmarks(Vec<Bookmark>),
    /// Add the bookmarks of the picked file to this scene (its spec).
    ImportBookmarks(String),
    /// Send exports to the picked folder.
    ExportFolder,
    /// Open the picked images as panes.
    OpenImages,
    /// Add the picked WGSL file as a user technique.
    AddTechnique,
}

/// Facts about the loaded scene.
#[derive(Clone, Debug)]
pub struct SceneInfo {
    /// What was loaded (built-in name or path).
    pub spec: String,
    /// The scene's name.
    pub name: String,
    /// Triangles.
    pub triangles: usize,
    /// Cameras the scene file defines (glTF), offered as views.
    pub views: Vec<crate::scene::SceneView>,
}

/// The shared state of the viewer (see the module docs).
pub(super) struct Workspace {
    /// Everything persisted: layout, comparison, magnifier, techniques' settings, folders.
    pub(super) settings: Settings,
    /// eframe's device (the window); the engine renders on its own device.
    pub(super) gpu: Gpu,
    /// The UI's side of the render thread (none until the first scene has loaded).
    pub(super) engine: Option<Engine>,
    /// The loaded scene.
    pub(super) scene: Option<SceneInfo>,
    /// The scene being loaded.
    pub(super) loader: SceneLoader,
    pub(super) camera: CameraController,
    /// Rendered frames per second.
    pub(super) clock: FrameClock,
    /// Notices shown in the status bar, oldest first.
    pub(super) notices: Vec<Notice>,
    /// The size the techniques render at, as the viewport last laid out its tiles (zero
    /// until then).
    pub(super) render_size: (u32, u32),
    /// The lens size and the magnifier's heatmaps (magnifier.rs).
    pub(super) magnifier: MagnifierState,
    /// The quality figures (quality.rs).
    pub(super) quality: QualityTracker,
    /// The running export and the files of the last one (export.rs).
    pub(super) export: ExportState,
    /// Images shown instead of the scene (image_set.rs).
    pub(super) images: ImageSetState,
    /// The blind comparison (blind.rs).
    pub(super) blind: BlindState,
    /// The open file dialog (on its own thread): what its answer is for, and the answer (the
    /// files picked).
    pub(super) file_dialog: Option<(DialogPurpose, mpsc::Receiver<Option<Vec<PathBuf>>>)>,
    /// Every engine frame takes at least this long (tests of a slow engine).
    engine_frame_delay: Duration,
    /// How the engine's images reach the screen.
    display: Display,
}

impl Workspace {
    /// The workspace of a viewer on eframe's device `gpu` (its wgpu state `state`) with
    /// `settings`; `notices` are raised at start. No scene is loaded yet.
    pub(super) fn new(
        gpu: Gpu,
        settings: Settings,
        notices: Vec<Notice>,
        state: &egui_wgpu::RenderState,
        options: &super::LaunchOptions,
    ) -> Self {
        let mut camera = CameraController::new(CameraRig::default());
        camera.auto_rotate = settings.auto_rotate;
        Self {
            settings,
            gpu,
            engine: None,
            scene: None,
            loader: SceneLoader::default(),
            camera,
            clock: FrameClock::default(),
            notices,
            render_size: (0, 0),
            magnifier: MagnifierState::default(),
            quality: QualityTracker::default(),
            export: ExportState::default(),
            images: ImageSetState::new(super::blit::Uploader::new(state)),
            blind: BlindState::default(),
            file_dialog: None,
            engine_frame_delay: options.engine_frame_delay,
            display: Display::choose(state, options.display),
        }
    }

    /// Raises a notice.
    pub(super) fn notify(&mut self, level: Level, text: impl Into<String>) {
        let text = text.into();
        if let Some(last) = self.notices.last_mut()
            && last.text == text
        {
            last.at = Instant::now();
            return;
        }
        log::log!(
            match level {
                Level::Info => log::Level::Info,
                Level::Warning => log::Level::Warn,
                Level::Error => log::Level::Error,
            },
            "{text}"
        );
        self.notices.push(Notice {
            level,
            text,
            at: Instant::now(),
        });
    }

    /// Starts loading a scene (built-in name or OBJ/glTF/GLB path) on the worker thread.
    pub(super) fn load_scene(&mut self, ctx: &egui::Context, spec: &str) {
        let ctx = ctx.clone();
        self.loader
            .load(spec, move || super::request_one_frame(&ctx));
    }

    /// Loads a scene the user asked for: an open image set gives way to it once it has
    /// loaded.
    pub(super) fn open_scene(&mut self, ctx: &egui::Context, spec: &str) {
        self.images.leave_for_scene();
        self.load_scene(ctx, spec);
    }

    /// Asks the OS for up to four images (PNG, JPEG) to open as panes.
    pub(super) fn open_images_dialog(&mut self, ctx: &egui::Context) {
        self.ask_for_paths(ctx, DialogPurpose::OpenImages, || {
            rfd::FileDialog::new()
                .set_title("Open up to four images of one size")
                .add_filter(
                    "Images (PNG, JPEG)",
                    &["png", "PNG", "jpg", "JPG", "jpeg", "JPEG"],
                )
                .pick_files()
        });
    }

    /// Asks the OS for a model file (OBJ, glTF, GLB) to open.
    pub(super) fn open_file_dialog(&mut self, ctx: &egui::Context) {
        self.ask_for_path(ctx, DialogPurpose::OpenModel, || {
            rfd::FileDialog::new()
                .set_title("Open a model")
                .add_filter(
                    "Models (OBJ, glTF, GLB)",
                    &["obj", "OBJ", "gltf", "GLTF", "glb", "GLB"],
                )
                .pick_file()
        });
    }

    /// Adds the user technique in the WGSL file at `path` (see `aa::user`; File > Add
    /// technique from file): the render thread builds it, and it appears in the techniques
    /// panel, switched on, or with its file's error. The file is remembered in the settings and
    /// added again at the next start.
    pub(super) fn add_user_technique(&mut self, path: PathBuf) {
        let Some(engine) = &mut self.engine else {
            return self.notify(
                Level::Warning,
                "techniques can be added once the scene has loaded".to_owned(),
            );
        };
        let path = std::fs::canonicalize(&path).unwrap_or(path);
        let remembered = path.display().to_string();
        engine.add_user_technique(path);
        if !self.settings.user_techniques.contains(&remembered) {
            self.settings.user_techniques.push(remembered);
        }
    }

    /// Removes the user technique `id`: off, out of the comparison and the techniques panel,
    /// forgotten by the settings (its file is left alone; adding it again brings it back).
    pub(super) fn remove_user_technique(&mut self, id: &str) {
        let Some(engine) = &mut self.engine else {
            return;
        };
        engine.remove_user_technique(id);
        if let Some(path) = crate::aa::user::path_of(id) {
            let path = path.display().to_string();
            self.settings.user_techniques.retain(|p| *p != path);
        }
        self.settings.enabled.retain(|e| e != id);
        self.settings.compare.retain(|c| c != id);
        self.settings.technique_settings.remove(id);
        self.settings.debug_views.remove(id);
    }

    /// Adds the user techniques the settings remember (at start, once the engine exists); a
    /// file that is gone is forgotten, with a notice.
    fn restore_user_techniques(&mut self) {
        let Some(engine) = &mut self.engine else {
            return;
        };
        let (present, gone): (Vec<String>, Vec<String>) =
            std::mem::take(&mut self.settings.user_techniques)
                .into_iter()
                .partition(|path| std::path::Path::new(path).is_file());
        for path in &present {
            engine.add_user_technique(PathBuf::from(path));
        }
        self.settings.user_techniques = present;
        for path in gone {
            self.notify(
                Level::Warning,
                format!("user technique {path} no longer exists; removed from the techniques"),
            );
        }
    }

    /// Asks the OS for a WGSL file to add as a user technique (see `aa::user`).
    pub(super) fn add_technique_dialog(&mut self, ctx: &egui::Context) {
        self.ask_for_path(ctx, DialogPurpose::AddTechnique, || {
            rfd::FileDialog::new()
                .set_title("Add a technique written in WGSL")
                .add_filter("WGSL shaders", &["wgsl", "WGSL"])
                .pick_file()
        });
    }

    /// Runs a file dialog on a helper thread (a dialog never blocks frames); its answer is
    /// handled by [`Workspace::dialog_answered`]. One dialog at a time.
    pub(super) fn ask_for_path(
        &mut self,
        ctx: &egui::Context,
        purpose: DialogPurpose,
        dialog: impl FnOnce() -> Option<PathBuf> + Send + 'static,
    ) {
        self.ask_for_paths(ctx, purpose, move || dialog().map(|path| vec![path]));
    }

    /// [`Workspace::ask_for_path`] for a dialog that picks several files.
    pub(super) fn ask_for_paths(
        &mut self,
        ctx: &egui::Context,
        purpose: DialogPurpose,
        dialog: impl FnOnce() -> Option<Vec<PathBuf>> + Send + 'static,
    ) {
        if self.file_dialog.is_some() {
            return;
        }
        let (sender, receiver) = mpsc::channel();
        let ctx = ctx.clone();
        let spawned = std::thread::Builder::new()
            .name("aa-lab file dialog".to_owned())
            .spawn(move || {
                let _ = sender.send(dialog());
                super::request_one_frame(&ctx);
            });
        match spawned {
            Ok(_) => self.file_dialog = Some((purpose, receiver)),
            Err(err) => self.notify(Level::Error, format!("cannot open a file dialog: {err}")),
        }
    }

    /// Acts on the paths a file dialog gave.
    fn dialog_answered(
        &mut self,
        ctx: &egui::Context,
        purpose: DialogPurpose,
        mut paths: Vec<PathBuf>,
    ) {
        if let DialogPurpose::OpenImages = purpose {
            self.open_images(ctx, paths);
            return;
        }
        let Some(path) = paths.pop() else { return };
        match purpose {
            DialogPurpose::OpenImages => {}
            DialogPurpose::OpenModel => self.open_scene(ctx, &path.display().to_string()),
            DialogPurpose::ExportBookmarks(marks) => self.write_bookmarks(&path, &marks),
            DialogPurpose::ImportBookmarks(scene) => self.read_bookmarks(&path, &scene),
            DialogPurpose::ExportFolder => self.use_export_dir(path),
            DialogPurpose::AddTechnique => self.add_user_technique(path),
        }
    }

    /// The ids compared as A, B, C, D: during a blind comparison its panes in their shuffled
    /// order; else the images of the open set in order; else the marked
    /// techniques that are on, then other techniques that are on, in panel order.
    pub(super) fn compared(&self) -> Vec<&'static str> {
        if let Some(panes) = self.blind.panes() {
            return panes;
        }
        if let Some(set) = self.images.open() {
            return set.ids();
        }
        let Some(engine) = &self.engine else {
            return Vec::new();
        };
        let on = |id: &str| engine.entry(id).is_some_and(|e| e.enabled && e.available());
        let mut ids: Vec<&'static str> = self
            .settings
            .compare
            .iter()
            .filter_map(|id| engine.entry(id))
            .filter(|e| on(e.id))
            .map(|e| e.id)
            .collect();
        for entry in engine.entries() {
            if ids.len() >= MAX_COMPARE {
                break;
            }
            if on(entry.id) && !ids.contains(&entry.id) {
                ids.push(entry.id);
            }
        }
        ids.truncate(MAX_COMPARE);
        ids
    }

    /// The label text of what a tile shows.
    pub(super) fn shown_label(&self, id: &str) -> String {
        if let Some(label) = self.blind.label(id) {
            return label;
        }
        if let Some(label) = self.image_label(id) {
            return label;
        }
        let Some(entry) = self.engine.as_ref().and_then(|e| e.entry(id)) else {
            return id.to_owned();
        };
        match &entry.debug_view {
            Some(view) => format!("{} · {view}", entry.name),
            None => entry.name.to_owned(),
        }
    }

    /// Switches a technique on or off and keeps the saved list in step.
    pub(super) fn set_technique_enabled(&mut self, id: &str, on: bool) {
        let Some(engine) = &mut self.engine else {
            return;
        };
        engine.set_enabled(id, on);
        let enabled = engine.entry(id).is_some_and(|e| e.enabled);
        self.settings.enabled.retain(|e| e != id);
        if enabled {
            self.settings.enabled.push(id.to_owned());
        }
    }

    /// Marks or unmarks a technique for comparison (at most four; the oldest mark makes room).
    pub(super) fn toggle_compare(&mut self, id: &str) {
        if self.settings.compare.iter().any(|c| c == id) {
            self.settings.compare.retain(|c| c != id);
        } else {
            if self.settings.compare.len() >= MAX_COMPARE {
                self.settings.compare.remove(MAX_COMPARE - 1);
            }
            self.settings.compare.push(id.to_owned());
            self.set_technique_enabled(id, true);
        }
    }

    /// Saves the technique's parameters into the settings.
    pub(super) fn remember_params(&mut self, id: &str) {
        if let Some(engine) = &self.engine {
            self.settings
                .technique_settings
                .insert(id.to_owned(), engine.param_map(id));
        }
    }

    fn finish_load(&mut self, ctx: &egui::Context) {
        let Some(loaded) = self.loader.poll() else {
            return;
        };
        match loaded.result {
            Ok(scene) => self.install_scene(ctx, &loaded.spec, scene),
            Err(err) => {
                self.images.stay();
                let kept = match &self.scene {
                    Some(s) => format!("; {} stays loaded", s.name),
                    None => String::new(),
                };
                self.notify(Level::Error, format!("{err}{kept}"));
                if self.scene.is_none() && loaded.spec != crate::scene::source::DEFAULT_SCENE {
                    // Nothing to show yet: fall back to the default scene.
                    self.load_scene(ctx, crate::scene::source::DEFAULT_SCENE);
                }
            }
        }
    }

    fn install_scene(&mut self, ctx: &egui::Context, spec: &str, scene: Scene) {
        for note in &scene.notes {
            self.notify(Level::Info, format!("{}: {note}", scene.name));
        }
        for warning in &scene.warnings {
            self.notify(Level::Warning, format!("{}: {warning}", scene.name));
        }
        let is_file = std::path::Path::new(spec).is_file();
        let spec = if is_file {
            std::fs::canonicalize(spec)
                .map_or_else(|_| spec.to_owned(), |p| p.display().to_string())
        } else {
            spec.to_owned()
        };
        let camera = scene.camera;
        let interior = scene.interior;
        let info = SceneInfo {
            spec: spec.clone(),
            name: scene.name.clone(),
            triangles: scene.triangle_count(),
            views: scene.views.clone(),
        };
        let scene = Arc::new(scene);
        match &mut self.engine {
            Some(engine) => engine.set_scene(scene),
            None => {
                let mut engine = match Engine::new(
                    self.display.clone(),
                    self.gpu.caps.clone(),
                    ctx,
                    scene,
                    self.settings.reference_samples,
                    self.engine_frame_delay,
                ) {
                    Ok(engine) => engine,
                    Err(err) => {
                        self.notify(Level::Error, err.to_string());
                        return;
                    }
                };
                let mut problems = Vec::new();
                for (id, map) in &self.settings.technique_settings {
                    if let Err(err) = engine.apply_param_map(id, map) {
                        problems.push(format!("saved settings of {id} not applied: {err}"));
                    }
                }
                for id in &self.settings.enabled {
                    engine.set_enabled(id, true);
                }
                for (id, view) in &self.settings.debug_views {
                    engine.set_debug_view(id, Some(view.clone()));
                }
                self.engine = Some(engine);
                for p in problems {
                    self.notify(Level::Warning, p);
                }
                self.restore_user_techniques();
            }
        }
        if is_file {
            self.settings.remember_recent(&spec);
        }
        self.settings.scene = spec;
        if self.images.take_leave() {
            self.close_images();
        }
        self.camera.set_rig(camera);
        self.camera.set_mode(if interior {
            super::camera::CameraMode::Fly
        } else {
            super::camera::CameraMode::Orbit
        });
        self.scene = Some(info);
        self.quality.clear();
        self.magnifier.clear();
        ctx.request_repaint();
    }

    /// Takes what finished in the background: scene and image loads, file dialogs, dropped
    /// files, exports; drops expired notices.
    pub(super) fn poll_background(&mut self, ctx: &egui::Context) {
        profiling::function_scope!();
        self.finish_load(ctx);
        self.finish_image_load();
        let answer = match &self.file_dialog {
            Some((_, receiver)) => match receiver.try_recv() {
                Ok(picked) => Some(picked),
                Err(mpsc::TryRecvError::Disconnected) => Some(None),
                Err(mpsc::TryRecvError::Empty) => None,
            },
            None => None,
        };
        if let Some(picked) = answer
            && let Some((purpose, _)) = self.file_dialog.take()
            && let Some(paths) = picked
        {
            self.dialog_answered(ctx, purpose, paths);
        }
        let dropped: Vec<PathBuf> = ctx.input(|i| {
            i.raw
                .dropped_files
                .iter()
                .map(|f| f.path().to_path_buf())
                .collect()
        });
        if !dropped.is_empty() {
            self.open_dropped(ctx, dropped);
        }
        let finished = self.export.poll();
        for (level, text) in finished {
            self.notify(level, text);
        }
        let now = Instant::now();
        self.notices
            .retain(|n| now.duration_since(n.at).as_secs_f64() < NOTICE_SECONDS);
    }

    /// The bookmarks of the loaded scene.
    pub(super) fn scene_bookmarks(&self) -> Vec<&Bookmark> {
        let scene = self.scene.as_ref().map(|s| s.spec.as_str()).unwrap_or("");
        self.settings
            .bookmarks
            .iter()
            .filter(|b| b.scene == scene)
            .collect()
    }

    pub(super) fn add_bookmark(&mut self) {
        let Some(scene) = &self.scene else { return };
        let n = self.scene_bookmarks().len() + 1;
        let bookmark = Bookmark {
            scene: scene.spec.clone(),
            name: format!("View {n}"),
            pose: self.camera.pose(),
        };
        self.notify(
            Level::Info,
            format!("Saved camera bookmark \"{}\"", bookmark.name),
        );
        self.settings.bookmarks.push(bookmark);
    }

    /// Asks where to write the loaded scene's bookmarks (JSON).
    pub(super) fn export_bookmarks(&mut self, ctx: &egui::Context) {
        let marks: Vec<_> = self.scene_bookmarks().into_iter().cloned().collect();
        let name = self.scene.as_ref().map_or("scene", |s| s.name.as_str());
        let file_name = format!("{name}-bookmarks.json");
        self.ask_for_path(ctx, DialogPurpose::ExportBookmarks(marks), move || {
            rfd::FileDialog::new()
                .set_title("Export camera bookmarks")
                .set_file_name(file_name)
                .add_filter("JSON", &["json"])
                .save_file()
        });
    }

    /// Writes bookmarks to `path` (atomically).
    fn write_bookmarks(&mut self, path: &std::path::Path, marks: &[Bookmark]) {
        let json = super::settings::bookmarks_to_json(marks);
        match super::settings::write_atomically(path, &json) {
            Ok(()) => self.notify(
                Level::Info,
                format!("Wrote {} bookmark(s) to {}", marks.len(), path.display()),
            ),
            Err(e) => self.notify(
                Level::Error,
                format!("cannot write {}: {e}", path.display()),
            ),
        }
    }

    /// Asks for a JSON file of bookmarks to add to the loaded scene.
    pub(super) fn import_bookmarks(&mut self, ctx: &egui::Context) {
        let Some(scene) = self.scene.as_ref().map(|s| s.spec.clone()) else {
            return;
        };
        self.ask_for_path(ctx, DialogPurpose::ImportBookmarks(scene), || {
            rfd::FileDialog::new()
                .set_title("Import camera bookmarks")
                .add_filter("JSON", &["json"])
                .pick_file()
        });
    }

    /// Adds the bookmarks of the file at `path` to `scene`.
    fn read_bookmarks(&mut self, path: &std::path::Path, scene: &str) {
        let loaded = crate::files::read_bounded(path, BOOKMARKS_LIMIT, "bookmarks file")
            .map_err(|e| e.to_string())
            .and_then(|bytes| String::from_utf8(bytes).map_err(|e| e.to_string()))
            .and_then(|text| super::settings::bookmarks_from_json(&text, scene));
        match loaded {
            Ok(marks) => {
                self.notify(
                    Level::Info,
                    format!(
                        "Imported {} bookmark(s) from {}",
                        marks.len(),
                        path.display()
                    ),
                );
                self.settings.bookmarks.extend(marks);
            }
            Err(e) => self.notify(Level::Error, format!("{}: {e}", path.display())),
        }
    }

    /// Play or pause: the shown clip's playback, else time (animation, temporal jitter).
    pub(super) fn toggle_play(&mut self) {
        match self
            .engine
            .as_mut()
            .and_then(|e| if e.clip_shown() { e.clip_mut() } else { None })
        {
            Some(clip) => clip.player.playing = !clip.player.playing,
            None => self.camera.playing = !self.camera.playing,
        }
    }

    /// Whether the engine has a frame in flight.
    pub(super) fn rendering(&self) -> bool {
        self.engine.as_ref().is_some_and(Engine::busy)
    }
}
