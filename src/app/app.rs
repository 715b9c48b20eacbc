//! [`AaLabApp`], the `eframe::App`: owns the settings, the engine, the camera and the
//! background jobs, and runs one UI frame in a fixed order: finished background work first
//! (scene loads, file dialogs, dropped files, readbacks, exports), then shortcuts, then one
//! engine frame at the size the viewport had in the previous frame, then the panels around the
//! viewport and the viewport itself. It asks for another frame only while something is in
//! motion (time playing with something that changes, the reference accumulating, a job
//! running), so an idle viewer costs nothing.

use std::path::PathBuf;
use std::sync::{Arc, mpsc};
use std::time::{Duration, Instant};

use super::blind::BlindState;
use super::camera::CameraController;
use super::engine::{Display, DisplayPath, Engine};
use super::export::ExportState;
use super::image_set::ImageSetState;
use super::magnifier::MagnifierState;
use super::quality::QualityTracker;
use super::scene_loader::SceneLoader;
use super::settings::{Bookmark, Layout, MAX_COMPARE, STORAGE_KEY, Settings};
use super::shortcuts::{self, Action};
use super::stats::FrameClock;
use super::style;
use super::viewport::ViewportState;
use crate::gpu::Gpu;
use crate::scene::{CameraRig, Scene};

/// How long a notice stays in the status bar.
const NOTICE_SECONDS: f64 = 12.0;

/// What the viewer opens with.
#[derive(Clone, Debug, Default)]
pub struct LaunchOptions {
    /// A built-in scene name or an OBJ path; `None` reopens the last scene (or the default).
    pub scene: Option<String>,
    /// Ignore saved settings (tests and screenshots start from the defaults).
    pub fresh_settings: bool,
    /// Every engine frame takes at least this long (tests of a slow engine; zero normally).
    pub engine_frame_delay: Duration,
    /// How the engine's images reach the screen.
    pub display: DisplayPath,
    /// Images to compare instead of the scene (File > Open images).
    pub images: Vec<PathBuf>,
}

/// Errors of creating the app.
#[derive(Debug, thiserror::Error)]
pub enum AppError {
    /// eframe runs without wgpu (it was built for another renderer).
    #[error("the viewer needs eframe's wgpu renderer, and this window has none")]
    NoWgpu,
}

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

/// The viewer application.
pub struct AaLabApp {
    pub(super) settings: Settings,
    /// eframe's device (the window); the engine renders on its own device.
    pub(super) gpu: Gpu,
    pub(super) engine: Option<Engine>,
    pub(super) scene: Option<SceneInfo>,
    pub(super) loader: SceneLoader,
    pub(super) camera: CameraController,
    pub(super) clock: FrameClock,
    pub(super) notices: Vec<Notice>,
    pub(super) viewport: ViewportState,
    pub(super) magnifier: MagnifierState,
    pub(super) quality: QualityTracker,
    pub(super) export: ExportState,
    /// Images shown instead of the scene (image_set.rs).
    pub(super) images: ImageSetState,
    /// The blind comparison (blind.rs).
    pub(super) blind: BlindState,
    pub(super) help_open: bool,
    pub(super) panels_hidden: bool,
    /// The open file dialog (on its own thread): what its answer is for, and the answer (the
    /// files picked).
    pub(super) file_dialog: Option<(DialogPurpose, mpsc::Receiver<Option<Vec<PathBuf>>>)>,
    engine_frame_delay: Duration,
    /// How the engine's images reach the screen.
    display: Display,
    /// Engine frames published so far.
    engine_frames: u64,
    #[cfg(feature = "profile")]
    profile: ProfileLog,
    styled: bool,
}

/// Logs the UI frame's CPU profile every few seconds (cargo feature `profile`).
#[cfg(feature = "profile")]
struct ProfileLog {
    profile: crate::profile::UiProfile,
    last: Instant,
}

#[cfg(feature = "profile")]
impl ProfileLog {
    const EVERY: Duration = Duration::from_secs(10);

    fn frame(&mut self) {
        crate::profile::UiProfile::new_frame();
        self.profile.collect();
        if self.last.elapsed() >= Self::EVERY {
            self.last = Instant::now();
            log::info!("{}", self.profile.report(25));
        }
    }
}

impl AaLabApp {
    /// Creates the app on eframe's wgpu device and starts loading the scene.
    pub fn new(cc: &eframe::CreationContext<'_>, options: LaunchOptions) -> Result<Self, AppError> {
        let state = cc.wgpu_render_state.as_ref().ok_or(AppError::NoWgpu)?;
        super::blit::install(state);
        let gpu = Gpu::from_parts(
            state.adapter.clone(),
            state.device.clone(),
            state.queue.clone(),
        );
        let mut notices = Vec::new();
        let (mut settings, notice) = if options.fresh_settings {
            (Settings::default(), None)
        } else {
            Settings::from_stored(
                stored_settings(cc.storage).as_deref(),
                settings_file().as_deref(),
            )
        };
        let fitted = settings.fit_to_adapter(gpu.caps.max_texture_dimension_2d);
        let warnings = notice
            .or_else(|| unreadable_storage_notice(cc.storage))
            .into_iter()
            .chain(fitted);
        for text in warnings {
            // The status bar shows it for a few seconds; the log keeps it.
            log::warn!("{text}");
            notices.push(Notice {
                level: Level::Warning,
                text,
                at: Instant::now(),
            });
        }
        if let Some(scene) = options.scene {
            settings.scene = scene;
        }
        let mut camera = CameraController::new(CameraRig::default());
        camera.auto_rotate = settings.auto_rotate;
        let mut app = Self {
            settings,
            gpu,
            engine: None,
            scene: None,
            loader: SceneLoader::default(),
            camera,
            clock: FrameClock::default(),
            notices,
            viewport: ViewportState::default(),
            magnifier: MagnifierState::default(),
            quality: QualityTracker::default(),
            export: ExportState::default(),
            images: ImageSetState::new(super::blit::Uploader::new(state)),
            blind: BlindState::default(),
            help_open: false,
            panels_hidden: false,
            file_dialog: None,
            engine_frame_delay: options.engine_frame_delay,
            display: Display::choose(state, options.display),
            engine_frames: 0,
            #[cfg(feature = "profile")]
            profile: ProfileLog {
                profile: crate::profile::UiProfile::start(),
                last: Instant::now(),
            },
            styled: false,
        };
        let scene = app.settings.scene.clone();
        app.load_scene(&cc.egui_ctx, &scene);
        if !options.images.is_empty() {
            app.open_images(&cc.egui_ctx, options.images);
        }
        Ok(app)
    }

    /// The settings (tests inspect them).
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// Mutable settings (tests drive them).
    pub fn settings_mut(&mut self) -> &mut Settings {
        &mut self.settings
    }

    /// Whether a scene is being loaded.
    pub fn loading(&self) -> bool {
        self.loader.loading().is_some()
    }

    /// Whether an export is running.
    pub fn exporting(&self) -> bool {
        self.export.running()
    }

    /// The loaded scene's name.
    pub fn scene_name(&self) -> Option<&str> {
        self.scene.as_ref().map(|s| s.name.as_str())
    }

    /// Current notices, oldest first.
    pub fn notices(&self) -> &[Notice] {
        &self.notices
    }

    /// The camera (tests pause it).
    pub fn camera_mut(&mut self) -> &mut CameraController {
        &mut self.camera
    }

    /// The size the techniques render at (zero until the viewport has been laid out).
    pub fn render_size(&self) -> (u32, u32) {
        self.viewport.render_size
    }

    /// Whether every compared technique shows an image rendered at the current size and no
    /// frame is in flight, or an image set is shown (tests wait for this).
    pub fn frame_ready(&self) -> bool {
        if self.images.is_open() {
            return true;
        }
        let Some(engine) = &self.engine else {
            return false;
        };
        let size = self.viewport.render_size;
        let compared = self.compared();
        !engine.busy()
            && !compared.is_empty()
            && compared
                .iter()
                .all(|id| engine.image(id).is_some_and(|i| i.size() == size))
    }

    /// Whether a technique (or an image of the open set) has an image to show (of any size).
    pub fn has_image(&self, id: &str) -> bool {
        self.image_for(id).is_some()
    }

    /// The parameters of technique `id` as the render thread last reported them (none until it
    /// is built).
    pub fn technique_params(&self, id: &str) -> Vec<crate::aa::Param> {
        self.engine
            .as_ref()
            .map(|engine| engine.params(id))
            .unwrap_or_default()
    }

    /// The published output of a technique or image of the open set (the bytes on screen),
    /// when its pixels were read back.
    pub fn output_pixels(&self, id: &str) -> Option<std::sync::Arc<image::RgbaImage>> {
        self.output_for(id).and_then(|p| p.pixels.clone())
    }

    /// Where technique A's image was drawn in the last frame (points).
    pub fn image_rect(&self) -> Option<egui::Rect> {
        self.viewport.image_rect
    }

    /// The published reference of the displayed view, or the reference image of the open set
    /// (the bytes the figures compare against).
    pub fn reference_pixels(&self) -> Option<std::sync::Arc<image::RgbaImage>> {
        self.reference_for().and_then(|(p, _)| p.pixels.clone())
    }

    /// Samples the displayed reference rests on (0 when there is none; 1 for an image).
    pub fn reference_samples_done(&self) -> u32 {
        self.reference_for().map_or(0, |(_, p)| p.samples)
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
    pub fn add_user_technique(&mut self, path: PathBuf) {
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
    pub fn remove_user_technique(&mut self, id: &str) {
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
    /// handled by [`AaLabApp::dialog_answered`]. One dialog at a time.
    pub(super) fn ask_for_path(
        &mut self,
        ctx: &egui::Context,
        purpose: DialogPurpose,
        dialog: impl FnOnce() -> Option<PathBuf> + Send + 'static,
    ) {
        self.ask_for_paths(ctx, purpose, move || dialog().map(|path| vec![path]));
    }

    /// [`AaLabApp::ask_for_path`] for a dialog that picks several files.
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
    pub fn compared(&self) -> Vec<&'static str> {
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

    fn poll_background(&mut self, ctx: &egui::Context) {
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

    fn handle_action(&mut self, ctx: &egui::Context, action: Action) {
        match action {
            // The techniques are not shown while images are.
            Action::ToggleTechnique(_) if self.images.is_open() => {}
            Action::ToggleTechnique(n) => {
                let id = self.engine.as_ref().and_then(|e| {
                    e.entries()
                        .iter()
                        .filter(|t| t.available())
                        .nth(n)
                        .map(|t| (t.id, t.enabled))
                });
                if let Some((id, on)) = id {
                    self.set_technique_enabled(id, !on);
                }
            }
            Action::PlayPause => self.toggle_play(),
            Action::Step => {
                self.camera.playing = false;
                self.camera.step();
            }
            Action::AutoRotate => {
                self.camera.auto_rotate = !self.camera.auto_rotate;
                self.settings.auto_rotate = self.camera.auto_rotate;
            }
            Action::ResetView => self.camera.reset(),
            Action::FlyMode => self.camera.toggle_mode(),
            Action::AddBookmark => self.add_bookmark(),
            Action::GoToBookmark(n) => {
                if let Some(pose) = self.scene_bookmarks().get(n).map(|b| b.pose) {
                    self.camera.jump_to(pose);
                }
            }
            Action::Layout(layout) => self.settings.layout = layout,
            Action::ZoomIn => self.magnifier.zoom_by(&mut self.settings.magnifier, 1),
            Action::ZoomOut => self.magnifier.zoom_by(&mut self.settings.magnifier, -1),
            Action::PixelGrid => {
                self.settings.magnifier.pixel_grid = !self.settings.magnifier.pixel_grid;
            }
            Action::Difference => {
                self.settings.magnifier.difference = !self.settings.magnifier.difference;
            }
            Action::Export => self.start_export(ctx),
            Action::CopySheet => self.copy_sheet(ctx),
            Action::Open => self.open_file_dialog(ctx),
            Action::TogglePanels => self.panels_hidden = !self.panels_hidden,
            Action::Help => self.help_open = !self.help_open,
        }
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

    /// Whether anything would show or measure the reference.
    fn reference_wanted(&self) -> bool {
        self.settings.quality
            || (self.settings.show_magnifier
                && (self.settings.magnifier.show_reference || self.settings.magnifier.difference))
            || self.settings.layout == Layout::Flip
    }

    /// Whether anything reads the outputs' pixels on the CPU: the quality figures, the
    /// magnifier (pixel values, error maps) or an export.
    fn pixels_wanted(&self) -> bool {
        self.settings.quality || self.settings.show_magnifier || self.export.running()
    }

    /// Whether time changes the image (so frames must keep coming while playing).
    fn time_changes_image(&self) -> bool {
        let Some(engine) = &self.engine else {
            return false;
        };
        if engine.live_paused() || self.images.is_open() {
            return false;
        }
        self.camera.moving_by_itself()
            || (self.camera.playing && (engine.animated() || engine.temporal_enabled()))
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

    /// Publishes a finished engine frame and starts the next one when the engine is free.
    /// Returns whether more frames are wanted.
    fn engine_frame(&mut self) -> bool {
        profiling::function_scope!();
        let size = self.viewport.render_size;
        let want_reference = self.reference_wanted();
        let want_pixels = self.pixels_wanted();
        // The engine stays idle while images are shown.
        let idle = self.images.is_open();
        let Some(engine) = &mut self.engine else {
            return false;
        };
        let publication = engine.poll();
        let mut errors = publication.problems;
        // A user technique restored at start, or added again: its saved parameters.
        for id in publication.added_users {
            if let Some(map) = self.settings.technique_settings.get(id)
                && let Err(err) = engine.apply_param_map(id, map)
            {
                errors.push(format!("saved settings of {id} not applied: {err}"));
            }
        }
        if size.0 > 0 && size.1 > 0 && !engine.busy() && !engine.live_paused() && !idle {
            let (camera, cut) = self.camera.next_frame(size);
            if let Err(err) = engine.submit(camera, cut, want_reference, want_pixels) {
                errors.push(err.to_string());
            }
        }
        // (While a clip records or is shown the live view waits, its reference too: asking
        // for UI frames for it would only repaint in a loop, taking CPU from the recording.)
        let more = engine.reference_incomplete() && !idle && !engine.live_paused();
        self.clock.tick(publication.outputs);
        self.engine_frames += u64::from(publication.outputs);
        for err in errors {
            self.notify(Level::Error, err);
        }
        more
    }

    /// Engine frames whose technique outputs were published so far (the viewer benchmark counts
    /// them).
    pub fn engine_frames(&self) -> u64 {
        self.engine_frames
    }

    /// Whether the engine has a frame in flight.
    pub fn rendering(&self) -> bool {
        self.engine.as_ref().is_some_and(Engine::busy)
    }
}

fn stored_settings(storage: Option<&dyn eframe::Storage>) -> Option<String> {
    storage.and_then(|s| s.get_string(STORAGE_KEY))
}

/// eframe's settings file.
fn settings_file() -> Option<PathBuf> {
    Some(eframe::storage_dir(super::APP_ID)?.join("app.ron"))
}

/// A notice when eframe's settings file exists but gave no settings (it could not be parsed).
fn unreadable_storage_notice(storage: Option<&dyn eframe::Storage>) -> Option<String> {
    let storage = storage?;
    if storage.get_string(STORAGE_KEY).is_some() {
        return None;
    }
    let path = settings_file()?;
    let size = std::fs::metadata(&path).ok()?.len();
    (size > 0).then(|| {
        format!(
            "The settings file {} could not be read; the defaults are in use and will replace it on exit.",
            path.display()
        )
    })
}

impl eframe::App for AaLabApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        #[cfg(feature = "profile")]
        self.profile.frame();
        profiling::function_scope!();
        let ctx = ui.ctx().clone();
        if !self.styled {
            style::apply(&ctx);
            self.styled = true;
        }
        self.poll_background(&ctx);
        self.blind_keys(&ctx);
        let flying = self.camera.mode == super::camera::CameraMode::Fly && !self.images.is_open();
        for action in shortcuts::pressed_actions(&ctx, flying) {
            self.handle_action(&ctx, action);
        }
        if flying {
            let input = shortcuts::fly_input(&ctx);
            if input.moving() {
                self.camera.fly(input, ctx.input(|i| i.stable_dt));
                ctx.request_repaint();
            }
        }
        if ctx.input(|i| i.key_pressed(egui::Key::Escape)) {
            self.help_open = false;
        }
        let more = self.engine_frame();
        self.tick_clip(&ctx);
        self.update_quality(&ctx);
        self.update_magnifier(&ctx);

        profiling::scope!("panels");
        // The panels' background, under everything (the panels are transparent).
        super::blit::fill(
            &ctx.layer_painter(egui::LayerId::background()),
            ctx.content_rect(),
            style::PANEL_FILL,
        );
        self.menu_bar(ui);
        self.toolbar(ui);
        self.status_bar(ui);
        // Clips record the scene; images have none.
        if !self.images.is_open() {
            self.clip_panel(ui);
        }
        // A blind comparison's panel replaces those that name the techniques.
        let blind = self.blind.active();
        let show_side = !self.panels_hidden;
        if show_side && blind {
            self.blind_panel(ui);
        }
        if show_side && !blind && self.settings.show_techniques {
            self.techniques_panel(ui);
        }
        if show_side && !blind && self.settings.show_metrics {
            self.metrics_panel(ui);
        }
        if self.settings.show_magnifier {
            self.magnifier_panel(ui);
        }
        self.viewport_panel(ui);
        shortcuts::help_overlay(&ctx, &mut self.help_open);

        // (An open file dialog wakes the UI itself when answered.)
        let pending_jobs = self.loading() || self.export.running() || self.images.loading();
        // Measurements wake the UI when they finish; this catches paced ones that wait.
        let measuring = self.quality.waiting() || self.magnifier.computing();
        if self.rendering() {
            // The render thread wakes the UI when the frame is back; until then a repaint
            // would show nothing new (the camera advances with each engine frame), and on a
            // software rasteriser each paint takes CPU from the engine.
        } else if more || self.time_changes_image() || self.viewport.resized {
            super::request_one_frame(&ctx);
        } else if pending_jobs {
            ctx.request_repaint_after(Duration::from_millis(30));
        } else if measuring {
            ctx.request_repaint_after(Duration::from_millis(200));
        } else {
            self.clock.idle();
        }
        // The status bar changes when the oldest notice expires; nothing else about notices
        // needs a repaint.
        if let Some(oldest) = self.notices.iter().map(|n| n.at).min() {
            let left = NOTICE_SECONDS - oldest.elapsed().as_secs_f64();
            ctx.request_repaint_after(Duration::from_secs_f64(left.max(0.0)));
        }
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        storage.set_string(STORAGE_KEY, self.settings.to_stored());
    }
}
