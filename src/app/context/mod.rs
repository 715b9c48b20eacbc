//! [`Context`], the part of the viewer every feature shares: the settings, eframe's device and
//! the engine (the UI's side of the render thread), the loaded scene and the camera, the open
//! image set, the blind comparison (whose session decides what every panel calls the panes),
//! the magnifier lens's size, the notices and the open file dialog.
//!
//! The features (the magnifier, the quality figures, exports, the bench, the panels) own their
//! own state and take the context as an argument; no feature calls into another. What one
//! feature asks of another goes through [`Command`]s that the context queues and the
//! workspace (`app/workspace.rs`, which holds the context and the features) carries out after
//! the panels, in the spirit of rerun's `SystemCommand` channel and egui's demo app, where
//! every view owns its state.
//!
//! The context's own commands and queries are methods: this file holds the core ones
//! (notices, file dialogs and what their answers do, what is compared and how it is labelled,
//! switching techniques, time, background work), and the files beside it the rest: scene
//! loading, user techniques and bookmarks (`scene.rs`), the lookups of what the panes show
//! (`shown.rs`), the image set and sequence set (`images.rs`), clips (`clip.rs`) and the blind session
//! (`blind.rs`).

use std::path::PathBuf;
use std::sync::mpsc;
use std::time::{Duration, Instant};

pub(super) use super::notice::{Level, NOTICE_SECONDS, Notice};

use super::blind::BlindState;
use super::camera::CameraController;
use super::engine::{Display, DisplayPath, Engine};
use super::image_set::ImageSetState;
use super::scene_loader::SceneLoader;
use super::settings::{Bookmark, MAX_COMPARE, Settings};
use super::stats::FrameClock;
use crate::gpu::Gpu;
use crate::scene::CameraRig;

mod blind;
mod clip;
mod images;
mod scene;
mod shown;

/// What a feature asks of another, carried out by the workspace after the panels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Command {
    /// What the panes show changed (another scene, another image set or reference): the
    /// quality figures and the magnifier's heatmaps of the old one are forgotten.
    ForgetMeasurements,
    /// Export the displayed frame (with the magnifier sheet when the magnifier is open).
    ExportFrame,
    /// Export the shown clip.
    ExportClip,
    /// Copy the magnifier sheet to the clipboard.
    CopySheet,
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
    /// Open the picked folders as sequences.
    OpenSequences,
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
pub(super) struct Context {
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
    /// Images shown instead of the scene (image_set.rs).
    pub(super) images: ImageSetState,
    /// The blind comparison: its session decides what every panel calls the panes.
    pub(super) blind: BlindState,
    /// The shown clip's ColorVideoVDP JOD per technique, as the clip's JOD feature last
    /// published it (blind answers record it).
    pub(super) clip_jod: std::collections::BTreeMap<&'static str, f64>,
    /// ColorVideoVDP's distortion maps of what is shown, as the JOD feature last published
    /// them (the magnifier's "JOD distortion" heatmap).
    pub(super) jod_maps: JodMaps,
    /// Frame pixels a magnifier pane covers (the magnifier sizes it to its panes): with the
    /// settings' centre it places the lens ([`Context::lens`]).
    pub(super) lens_side: u32,
    /// The open file dialog (on its own thread): what its answer is for, and the answer (the
    /// files picked).
    pub(super) file_dialog: Option<(DialogPurpose, mpsc::Receiver<Option<Vec<PathBuf>>>)>,
    /// Requests for the features, carried out by the workspace after the panels.
    commands: Vec<Command>,
    /// Every engine frame takes at least this long (tests of a slow engine).
    engine_frame_delay: Duration,
    /// How the engine's images reach the screen.
    display: Display,
}

/// ColorVideoVDP's per-pixel distortion maps of the panes shown (the JOD feature's, `jod.rs`).
#[derive(Clone, Default)]
pub struct JodMaps {
    /// Counts changes of the JOD feature's figures and maps.
    pub generation: u64,
    /// Per pane id: its map (1 - JOD/10 per pixel, mean over the frames), or why it has none
    /// yet. Panes that are not being scored are absent.
    pub panes: std::collections::BTreeMap<
        &'static str,
        Result<std::sync::Arc<crate::metrics::Plane>, String>,
    >,
}

impl Context {
    /// The context of a viewer on eframe's device `gpu` (its wgpu state `state`) with
    /// `settings`; `notices` are raised at start; every engine frame takes at least
    /// `engine_frame_delay`, and its images reach the screen by `display` where the device
    /// allows. No scene is loaded yet.
    pub(super) fn new(
        gpu: Gpu,
        settings: Settings,
        notices: Vec<Notice>,
        state: &egui_wgpu::RenderState,
        engine_frame_delay: Duration,
        display: DisplayPath,
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
            lens_side: 0,
            clip_jod: Default::default(),
            jod_maps: JodMaps::default(),
            images: ImageSetState::new(super::blit::Uploader::new(state)),
            blind: BlindState::default(),
            file_dialog: None,
            commands: Vec::new(),
            engine_frame_delay,
            display: Display::choose(state, display),
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

    /// Asks the OS for up to five images (PNG, JPEG) to open as panes and reference.
    pub(super) fn open_images_dialog(&mut self, ctx: &egui::Context) {
        self.ask_for_paths(ctx, DialogPurpose::OpenImages, || {
            rfd::FileDialog::new()
                .set_title(
                    "Open up to five images of one size: up to four to compare and their reference",
                )
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
    /// handled by [`Context::dialog_answered`]. One dialog at a time.
    pub(super) fn ask_for_path(
        &mut self,
        ctx: &egui::Context,
        purpose: DialogPurpose,
        dialog: impl FnOnce() -> Option<PathBuf> + Send + 'static,
    ) {
        self.ask_for_paths(ctx, purpose, move || dialog().map(|path| vec![path]));
    }

    /// [`Context::ask_for_path`] for a dialog that picks several files.
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
                super::repaint::request_one_frame(&ctx);
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
        match purpose {
            DialogPurpose::OpenImages => return self.open_images(ctx, paths),
            DialogPurpose::OpenSequences => return self.open_sequences(ctx, paths),
            _ => {}
        }
        let Some(path) = paths.pop() else { return };
        match purpose {
            DialogPurpose::OpenImages | DialogPurpose::OpenSequences => {}
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
        let now = Instant::now();
        self.notices
            .retain(|n| now.duration_since(n.at).as_secs_f64() < NOTICE_SECONDS);
    }

    /// Play or pause: the shown sequences' or clip's playback, else time (animation, temporal
    /// jitter).
    pub(super) fn toggle_play(&mut self) {
        if let Some(sequences) = self.images.sequences_mut() {
            sequences.player.playing = !sequences.player.playing;
            return;
        }
        match self
            .engine
            .as_mut()
            .and_then(|e| if e.clip_shown() { e.clip_mut() } else { None })
        {
            Some(clip) => clip.player.playing = !clip.player.playing,
            None => self.camera.playing = !self.camera.playing,
        }
    }

    /// Asks the workspace for `command` (carried out after the panels).
    pub(super) fn request(&mut self, command: Command) {
        if !self.commands.contains(&command) {
            self.commands.push(command);
        }
    }

    /// The commands asked for since the last call, oldest first.
    pub(super) fn take_commands(&mut self) -> Vec<Command> {
        std::mem::take(&mut self.commands)
    }

    /// Whether the engine has a frame in flight.
    pub(super) fn rendering(&self) -> bool {
        self.engine.as_ref().is_some_and(Engine::busy)
    }
}
