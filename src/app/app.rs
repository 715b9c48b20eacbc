//! [`AaLabApp`], the `eframe::App`: owns the [`Workspace`] (the state the panels share) and
//! the panels, and runs one UI frame in a fixed order: finished background work first (scene
//! loads, file dialogs, dropped files, readbacks, exports), then shortcuts, then one engine
//! frame at the size the viewport had in the previous frame, then the panels around the
//! viewport and the viewport itself. It asks for another frame only while something is in
//! motion (time playing with something that changes, the reference accumulating, a job
//! running), so an idle viewer costs nothing. Shortcut keys are taken out of the raw input
//! before egui's pass (`raw_input_hook`, `key_events.rs`), so a key costs no settling frames,
//! and carried out with the frame's other shortcuts; their releases never reach eframe
//! (`event_filter.rs`), so they cost no paint either.
//!
//! Its public methods are the viewer's test API (tests/ui.rs, benches/viewer.rs): they read or
//! drive the workspace and the panels.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use super::bench::BenchFeature;
use super::blind;
use super::camera::CameraController;
use super::clip_bar;
use super::context::{Command, Context, Level, NOTICE_SECONDS, Notice};
use super::engine::DisplayPath;
use super::key_events::{HeldKeys, KeyIntake};
use super::magnifier::{MagnifierPanel, PanelInputs};
use super::metrics_panel;
use super::panels;
use super::quality::Figures;
use super::settings::{APP_ID, Layout, STORAGE_KEY, Settings};
use super::shortcuts::{self, Action};
use super::style;
use super::techniques_panel;
use super::viewport::ViewportPanel;
use super::workspace::Workspace;
use crate::gpu::Gpu;
use crate::spec::RenderSpec;

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
    /// Sequences to play instead of the scene (File > Open sequences).
    pub sequences: Vec<PathBuf>,
    /// The window clears itself to the panels' colour before each paint, as eframe's native
    /// window does (with [`eframe::App::clear_color`]); otherwise (egui_kittest, whose renderer
    /// clears to transparent) the app fills the background itself.
    pub window_clears: bool,
    /// The shortcut keys held, shared with the window's event filter (`event_filter.rs`).
    pub held_keys: HeldKeys,
}

/// Errors of creating the app.
#[derive(Debug, thiserror::Error)]
pub enum AppError {
    /// eframe runs without wgpu (it was built for another renderer).
    #[error("the viewer needs eframe's wgpu renderer, and this window has none")]
    NoWgpu,
}

/// The viewer application.
pub struct AaLabApp {
    /// The state the panels share.
    ws: Workspace,
    /// The panels that keep state of their own (the others are functions).
    viewport: ViewportPanel,
    magnifier: MagnifierPanel,
    /// The bench of the compared techniques (the metrics panel's section).
    bench: BenchFeature,
    /// The help overlay is open.
    help_open: bool,
    /// The side panels are hidden.
    panels_hidden: bool,
    /// Shortcut keys answered from the raw input, before egui's pass.
    keys: KeyIntake,
    /// The actions of those keys, carried out in the frame's `ui`.
    key_actions: Vec<Action>,
    /// Engine frames published so far.
    engine_frames: u64,
    #[cfg(feature = "profile")]
    profile: ProfileLog,
    styled: bool,
    /// The app fills the window's background (see [`LaunchOptions::window_clears`]).
    fill_background: bool,
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
        // Before the app opens devices of its own, whose rasteriser threads are idle-class.
        super::rasterizer_threads::spread_window_rasterizer_threads(&state.adapter.get_info());
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
        if let Some(scene) = &options.scene {
            settings.scene = scene.clone();
        }
        let mut ws = Workspace::new(Context::new(
            gpu,
            settings,
            notices,
            state,
            options.engine_frame_delay,
            options.display,
        ));
        let scene = ws.cx.settings.scene.clone();
        ws.cx.load_scene(&cc.egui_ctx, &scene);
        if !options.images.is_empty() {
            ws.cx.open_images(&cc.egui_ctx, options.images);
        }
        if !options.sequences.is_empty() {
            ws.cx.open_sequences(&cc.egui_ctx, options.sequences);
        }
        Ok(Self {
            ws,
            viewport: ViewportPanel::default(),
            magnifier: MagnifierPanel::default(),
            bench: BenchFeature::default(),
            help_open: false,
            panels_hidden: false,
            keys: KeyIntake::new(options.held_keys.clone()),
            key_actions: Vec::new(),
            engine_frames: 0,
            #[cfg(feature = "profile")]
            profile: ProfileLog {
                profile: crate::profile::UiProfile::start(),
                last: Instant::now(),
            },
            styled: false,
            fill_background: !options.window_clears,
        })
    }

    /// The settings (tests inspect them).
    pub fn settings(&self) -> &Settings {
        &self.ws.cx.settings
    }

    /// Mutable settings (tests drive them).
    pub fn settings_mut(&mut self) -> &mut Settings {
        &mut self.ws.cx.settings
    }

    /// Whether a scene is being loaded.
    pub fn loading(&self) -> bool {
        self.ws.cx.loader.loading().is_some()
    }

    /// Whether an export is running.
    pub fn exporting(&self) -> bool {
        self.ws.export.running()
    }

    /// The loaded scene's name.
    pub fn scene_name(&self) -> Option<&str> {
        self.ws.cx.scene.as_ref().map(|s| s.name.as_str())
    }

    /// Current notices, oldest first.
    pub fn notices(&self) -> &[Notice] {
        &self.ws.cx.notices
    }

    /// The camera (tests pause it).
    pub fn camera_mut(&mut self) -> &mut CameraController {
        &mut self.ws.cx.camera
    }

    /// The size the techniques render at (zero until the viewport has been laid out).
    pub fn render_size(&self) -> (u32, u32) {
        self.ws.cx.render_size
    }

    /// Whether every compared technique shows an image rendered at the current size and no
    /// frame is in flight, or an image set is shown (tests wait for this).
    pub fn frame_ready(&self) -> bool {
        if self.ws.cx.images.is_open() {
            return true;
        }
        let Some(engine) = &self.ws.cx.engine else {
            return false;
        };
        let size = self.ws.cx.render_size;
        let compared = self.ws.cx.compared();
        !engine.busy()
            && !compared.is_empty()
            && compared
                .iter()
                .all(|id| engine.image(id).is_some_and(|i| i.size() == size))
    }

    /// Whether a technique (or an image of the open set) has an image to show (of any size).
    pub fn has_image(&self, id: &str) -> bool {
        self.ws.cx.image_for(id).is_some()
    }

    /// The parameters of technique `id` as the render thread last reported them (none until it
    /// is built).
    pub fn technique_params(&self, id: &str) -> Vec<crate::aa::Param> {
        self.ws
            .cx
            .engine
            .as_ref()
            .map(|engine| engine.params(id))
            .unwrap_or_default()
    }

    /// The published output of a technique or image of the open set (the bytes on screen),
    /// when its pixels were read back.
    pub fn output_pixels(&self, id: &str) -> Option<std::sync::Arc<image::RgbaImage>> {
        self.ws.cx.output_for(id).and_then(|p| p.pixels.clone())
    }

    /// Where technique A's image was drawn in the last frame (points).
    pub fn image_rect(&self) -> Option<egui::Rect> {
        self.viewport.image_rect()
    }

    /// The published reference of the displayed view, or the reference image of the open set
    /// (the bytes the figures compare against).
    pub fn reference_pixels(&self) -> Option<std::sync::Arc<image::RgbaImage>> {
        self.ws
            .cx
            .reference_for()
            .and_then(|(p, _)| p.pixels.clone())
    }

    /// Samples the displayed reference rests on (0 when there is none; 1 for an image).
    pub fn reference_samples_done(&self) -> u32 {
        self.ws.cx.reference_for().map_or(0, |(_, p)| p.samples)
    }

    /// The techniques the GPU memory figures list, each with the scene input it reads.
    pub fn memory_listed(&self) -> Vec<(String, Option<String>)> {
        self.ws
            .cx
            .engine
            .as_ref()
            .and_then(|engine| engine.memory())
            .map(|report| {
                report
                    .techniques
                    .iter()
                    .map(|t| (t.technique.clone(), t.input.clone()))
                    .collect()
            })
            .unwrap_or_default()
    }

    /// The ids compared as A, B, C, D (see `Context::compared`).
    pub fn compared(&self) -> Vec<&'static str> {
        self.ws.cx.compared()
    }

    /// Adds the user technique in the WGSL file at `path` (see
    /// `Context::add_user_technique`).
    pub fn add_user_technique(&mut self, path: PathBuf) {
        self.ws.cx.add_user_technique(path);
    }

    /// Adds the combination `id` (`ID[@SCALE][:UPSCALER][+SHARPEN[=STRENGTH]]`) and compares
    /// it; its canonical id, or `None` (with a notice) when it is refused (see
    /// `Context::add_combination`).
    pub fn add_combination(&mut self, id: &str) -> Option<&'static str> {
        self.ws.cx.add_combination(id)
    }

    /// Removes the user technique or combination `id` (see
    /// `Context::remove_user_technique`).
    pub fn remove_user_technique(&mut self, id: &str) {
        self.ws.cx.remove_user_technique(id);
    }

    /// Opens up to five images of one size as panes and reference (see
    /// `Context::open_images`).
    pub fn open_images(&mut self, ctx: &egui::Context, paths: Vec<PathBuf>) {
        self.ws.cx.open_images(ctx, paths);
    }

    /// Opens up to five image sequences of one frame size as panes and reference (see
    /// `Context::open_sequences`).
    pub fn open_sequences(&mut self, ctx: &egui::Context, paths: Vec<PathBuf>) {
        self.ws.cx.open_sequences(ctx, paths);
    }

    /// The open sequence set's instant on screen and its number of instants (`None` without
    /// one, or while the frames of new offsets are read).
    pub fn sequence_position(&self) -> Option<(usize, usize)> {
        let sequences = self.ws.cx.images.open()?.sequences()?;
        Some((sequences.shown()?, sequences.len()))
    }

    /// The frame number (from the file name) each sequence of the open set shows, in pane
    /// order.
    pub fn sequence_frame_numbers(&self) -> Vec<Option<u64>> {
        self.ws
            .cx
            .images
            .open()
            .and_then(|set| set.sequences())
            .map_or_else(Vec::new, |s| s.shown_numbers())
    }

    /// The temporal figures of the open sequence set's frames played in a row up to the one
    /// shown: how many, and per sequence but the reference, in pane order.
    pub fn sequence_temporal(
        &self,
    ) -> Option<(usize, Vec<crate::metrics::stability::TemporalScores>)> {
        let run = self.ws.cx.images.open()?.sequences()?.played()?;
        Some((run.frames, run.scores.clone()))
    }

    /// Shows sequence `index` of the open set from its frame `offset` on.
    pub fn set_sequence_offset(&mut self, index: usize, offset: usize) {
        if let Some(sequences) = self.ws.cx.images.sequences_mut() {
            sequences.set_offset(index, offset);
        }
    }

    /// Closes the image set: the scene shows again.
    pub fn close_images(&mut self) {
        self.ws.cx.close_images();
    }

    /// Whether an image set is shown instead of the scene.
    pub fn image_set_open(&self) -> bool {
        self.ws.cx.images.is_open()
    }

    /// Whether images are being decoded.
    pub fn images_loading(&self) -> bool {
        self.ws.cx.images.loading()
    }

    /// The file names of the open set, in pane order, and the index of the reference.
    pub fn image_names(&self) -> Option<(Vec<String>, usize)> {
        self.ws.cx.image_names()
    }

    /// Makes image `index` of the open set the reference.
    pub fn set_image_reference(&mut self, index: usize) {
        self.ws.cx.images.set_reference(index);
    }

    /// The quality figures of a technique that describe what is on screen now (`None` while
    /// they are stale or being measured).
    pub fn quality_figures(&self, id: &str) -> Option<Figures> {
        self.ws.quality_figures(id)
    }

    /// In difference mode, the lens means of the magnifier panes' heatmaps (see
    /// `MagnifierState::difference_means`).
    pub fn difference_means(&self) -> Option<Vec<f64>> {
        self.ws.magnifier.difference_means(&self.ws.cx)
    }

    /// The lens in frame pixels: x, y, width, height.
    pub fn lens_region(&self) -> Option<(u32, u32, u32, u32)> {
        self.ws.cx.lens().map(|r| (r.x, r.y, r.width, r.height))
    }

    /// The render record of the displayed frame: `aa-lab render --from` reproduces it.
    pub fn current_spec(&self) -> Option<RenderSpec> {
        self.ws.cx.current_spec()
    }

    /// Points exports at a folder (tests use a temporary one).
    pub fn set_export_dir(&mut self, dir: PathBuf) {
        self.ws.cx.settings.export_dir = dir;
    }

    /// Files written by the last finished export.
    pub fn last_export(&self) -> &[PathBuf] {
        &self.ws.export.last
    }

    /// The clip's progress: frames recorded, and whether it is still recording (`None`: no
    /// clip).
    pub fn clip_progress(&self) -> Option<(usize, bool)> {
        self.ws.cx.clip_progress()
    }

    /// The clip's temporal figures per technique, once recorded with the reference.
    pub fn clip_scores(&self) -> Option<Vec<crate::metrics::stability::TemporalScores>> {
        self.ws.cx.clip_scores()
    }

    /// The ColorVideoVDP JOD of the technique (of the shown clip) in pane `slot`, or of
    /// sequence `slot` (in file order) of the open set, once scored (or why it has none).
    pub fn jod(&self, slot: usize) -> Option<Result<f64, String>> {
        self.ws.jod.figure(&self.ws.cx, slot).cloned()
    }

    /// Panes scored and to score while ColorVideoVDP scores.
    pub fn jod_progress(&self) -> Option<(usize, usize)> {
        self.ws.jod.progress()
    }

    /// ColorVideoVDP's distortion map of pane `id` (1 - JOD/10 per pixel, mean over the
    /// frames) once computed, or why there is none yet; `None` for panes not scored with maps.
    pub fn jod_map(
        &self,
        id: &str,
    ) -> Option<Result<std::sync::Arc<crate::metrics::Plane>, String>> {
        self.ws.cx.jod_maps.panes.get(id).cloned()
    }

    /// The index of the clip frame on screen (`None` when the live view is).
    pub fn shown_clip_frame(&self) -> Option<usize> {
        self.ws.cx.shown_clip_frame()
    }

    /// The answers file of the running blind session (tests read it).
    pub fn blind_file(&self) -> Option<&Path> {
        self.ws.cx.blind.file()
    }

    /// Whether the engine has a frame in flight.
    pub fn rendering(&self) -> bool {
        self.ws.cx.rendering()
    }

    /// The window's device (eframe's, which holds the display textures) and the engine's once
    /// its render thread has opened it (the same device on the native display path): tests
    /// read their live GPU object counts.
    pub fn gpu_devices(&self) -> (wgpu::Device, Option<wgpu::Device>) {
        let engine = self
            .ws
            .cx
            .engine
            .as_ref()
            .and_then(|engine| engine.render_device().cloned());
        (self.ws.cx.gpu.device.clone(), engine)
    }

    /// The fly camera is on (its keys move it instead of acting as shortcuts).
    fn flying(&self) -> bool {
        self.ws.cx.camera.mode == super::camera::CameraMode::Fly && !self.ws.cx.images.is_open()
    }

    /// Takes the keys of a blind comparison (answered at once) and of the shortcuts (returned)
    /// out of `events`; the caller checks that no text field has keyboard focus.
    fn take_keys(&mut self, events: &mut Vec<egui::Event>) -> Vec<Action> {
        self.ws.cx.blind_keys(events);
        shortcuts::take_actions(events, self.flying())
    }

    fn handle_action(&mut self, ctx: &egui::Context, action: Action) {
        match action {
            // The techniques are not shown while images are.
            Action::ToggleTechnique(_) if self.ws.cx.images.is_open() => {}
            Action::ToggleTechnique(n) => {
                let id = self.ws.cx.engine.as_ref().and_then(|e| {
                    e.entries()
                        .iter()
                        .filter(|t| t.available())
                        .nth(n)
                        .map(|t| (t.id, t.enabled))
                });
                if let Some((id, on)) = id {
                    self.ws.cx.set_technique_enabled(id, !on);
                }
            }
            Action::PlayPause => self.ws.cx.toggle_play(),
            Action::Step => {
                self.ws.cx.camera.playing = false;
                self.ws.cx.camera.step();
            }
            Action::AutoRotate => {
                self.ws.cx.camera.auto_rotate = !self.ws.cx.camera.auto_rotate;
                self.ws.cx.settings.auto_rotate = self.ws.cx.camera.auto_rotate;
            }
            Action::ResetView => self.ws.cx.camera.reset(),
            Action::FlyMode => self.ws.cx.camera.toggle_mode(),
            Action::AddBookmark => self.ws.cx.add_bookmark(),
            Action::GoToBookmark(n) => {
                if let Some(pose) = self.ws.cx.scene_bookmarks().get(n).map(|b| b.pose) {
                    self.ws.cx.camera.jump_to(pose);
                }
            }
            Action::Layout(layout) => self.ws.cx.settings.layout = layout,
            Action::ZoomIn => self
                .ws
                .magnifier
                .zoom_by(&mut self.ws.cx.settings.magnifier, 1),
            Action::ZoomOut => self
                .ws
                .magnifier
                .zoom_by(&mut self.ws.cx.settings.magnifier, -1),
            Action::PixelGrid => {
                self.ws.cx.settings.magnifier.pixel_grid =
                    !self.ws.cx.settings.magnifier.pixel_grid;
            }
            Action::Difference => {
                self.ws.cx.settings.magnifier.difference =
                    !self.ws.cx.settings.magnifier.difference;
            }
            Action::Export => self.ws.cx.request(Command::ExportFrame),
            Action::CopySheet => self.ws.cx.request(Command::CopySheet),
            Action::Open => self.ws.cx.open_file_dialog(ctx),
            Action::TogglePanels => self.panels_hidden = !self.panels_hidden,
            Action::Help => self.help_open = !self.help_open,
        }
    }

    /// Whether anything would show or measure the reference.
    fn reference_wanted(&self) -> bool {
        self.ws.cx.settings.quality
            || (self.ws.cx.settings.show_magnifier
                && (self.ws.cx.settings.magnifier.show_reference
                    || self.ws.cx.settings.magnifier.difference))
            || self.ws.cx.settings.layout == Layout::Flip
    }

    /// Whether anything reads the outputs' pixels on the CPU: the quality figures, the
    /// magnifier (pixel values, error maps) or an export.
    fn pixels_wanted(&self) -> bool {
        self.ws.cx.settings.quality
            || self.ws.cx.settings.show_magnifier
            || self.ws.export.running()
    }

    /// Whether time changes the image (so frames must keep coming while playing).
    fn time_changes_image(&self) -> bool {
        let Some(engine) = &self.ws.cx.engine else {
            return false;
        };
        if engine.live_paused() || self.ws.cx.images.is_open() {
            return false;
        }
        self.ws.cx.camera.moving_by_itself()
            || (self.ws.cx.camera.playing && (engine.animated() || engine.temporal_enabled()))
    }

    /// Publishes a finished engine frame and starts the next one when the engine is free.
    /// Returns whether more frames are wanted.
    fn engine_frame(&mut self) -> bool {
        profiling::function_scope!();
        let size = self.ws.cx.render_size;
        let want_reference = self.reference_wanted();
        let want_pixels = self.pixels_wanted();
        // The engine stays idle while images are shown, and while a bench times its frames.
        let idle = self.ws.cx.images.is_open() || self.bench.running();
        let Some(engine) = &mut self.ws.cx.engine else {
            return false;
        };
        let publication = engine.poll();
        let mut errors = publication.problems;
        // A user technique restored at start, or added again: its saved parameters.
        for id in publication.added_users {
            if let Some(map) = self.ws.cx.settings.technique_settings.get(id)
                && let Err(err) = engine.apply_param_map(id, map)
            {
                errors.push(format!("saved settings of {id} not applied: {err}"));
            }
        }
        if size.0 > 0 && size.1 > 0 && !engine.busy() && !engine.live_paused() && !idle {
            let (camera, cut) = self.ws.cx.camera.next_frame(size);
            if let Err(err) = engine.submit(camera, cut, want_reference, want_pixels) {
                errors.push(err.to_string());
            }
        }
        // (While a clip records or is shown the live view waits, its reference too: asking
        // for UI frames for it would only repaint in a loop, taking CPU from the recording.)
        let more = engine.reference_incomplete() && !idle && !engine.live_paused();
        self.ws.cx.clock.tick(publication.outputs);
        self.engine_frames += u64::from(publication.outputs);
        for err in errors {
            self.ws.cx.notify(Level::Error, err);
        }
        more
    }

    /// Engine frames whose technique outputs were published so far (the viewer benchmark counts
    /// them).
    pub fn engine_frames(&self) -> u64 {
        self.engine_frames
    }
}

fn stored_settings(storage: Option<&dyn eframe::Storage>) -> Option<String> {
    storage.and_then(|s| s.get_string(STORAGE_KEY))
}

/// eframe's settings file.
fn settings_file() -> Option<PathBuf> {
    Some(eframe::storage_dir(APP_ID)?.join("app.ron"))
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
        self.ws.poll_background(&ctx);
        if let Some((level, text)) = self.bench.poll() {
            self.ws.cx.notify(level, text);
        }
        // Keys the raw-input hook did not see (egui_kittest runs no hook) are taken here.
        let mut actions = std::mem::take(&mut self.key_actions);
        if !ctx.egui_wants_keyboard_input() {
            actions.extend(ctx.input_mut(|input| self.take_keys(&mut input.events)));
        }
        for action in actions {
            self.handle_action(&ctx, action);
        }
        let flying = self.flying();
        if flying {
            let input = shortcuts::fly_input(&ctx);
            if input.moving() {
                self.ws.cx.camera.fly(input, ctx.input(|i| i.stable_dt));
                ctx.request_repaint();
            }
        }
        if ctx.input(|i| i.key_pressed(egui::Key::Escape)) {
            self.help_open = false;
        }
        let more = self.engine_frame();
        self.ws.update(&ctx);

        profiling::scope!("panels");
        // The panels' background, under everything (the panels are transparent), where the
        // window does not clear to it.
        if self.fill_background {
            super::blit::fill(
                &ctx.layer_painter(egui::LayerId::background()),
                ctx.content_rect(),
                style::PANEL_FILL,
            );
        }
        panels::menu_bar(
            ui,
            &mut self.ws,
            &mut self.help_open,
            &mut self.panels_hidden,
        );
        panels::toolbar(ui, &mut self.ws, &mut self.help_open);
        let hover = self.viewport.hover_pixel().or(self.magnifier.hover());
        panels::status_bar(ui, &self.ws, hover);
        // Clips record the scene; images have none, sequences play in the clip bar.
        if !self.ws.cx.images.is_open() || self.ws.cx.images.has_sequences() {
            clip_bar::panel(ui, &mut self.ws.cx);
        }
        // A blind comparison's panel replaces those that name the techniques.
        let blind = self.ws.cx.blind.active();
        let show_side = !self.panels_hidden;
        if show_side
            && blind
            && let Some(action) = blind::panel(ui, &mut self.ws.cx.blind)
        {
            self.ws.cx.blind_act(action);
        }
        if show_side && !blind && self.ws.cx.settings.show_techniques {
            techniques_panel::ui(ui, &mut self.ws.cx);
        }
        if show_side && !blind && self.ws.cx.settings.show_metrics {
            metrics_panel::ui(ui, &mut self.ws, &mut self.bench);
        }
        if self.ws.cx.settings.show_magnifier {
            let figures = self.ws.pane_figures();
            let inputs = PanelInputs {
                state: &self.ws.magnifier,
                figures: &|id| figures.get(id).cloned(),
                viewport_hover: self.viewport.hover_pixel(),
            };
            self.magnifier.ui(ui, &mut self.ws.cx, inputs);
        }
        self.viewport.ui(ui, &mut self.ws.cx);
        shortcuts::help_overlay(&ctx, &mut self.help_open);
        self.ws.run_commands(&ctx);

        // (An open file dialog wakes the UI itself when answered.)
        let pending_jobs =
            self.loading() || self.ws.export.running() || self.ws.cx.images.loading();
        // Measurements wake the UI when they finish; this catches paced ones that wait.
        let measuring = self.ws.quality.waiting() || self.ws.magnifier.computing();
        if self.ws.cx.rendering() {
            // The render thread wakes the UI when the frame is back; until then a repaint
            // would show nothing new (the camera advances with each engine frame), and on a
            // software rasteriser each paint takes CPU from the engine.
        } else if more || self.time_changes_image() || self.viewport.resized() {
            super::repaint::request_one_frame(&ctx);
        } else if pending_jobs {
            ctx.request_repaint_after(Duration::from_millis(30));
        } else if measuring {
            ctx.request_repaint_after(Duration::from_millis(200));
        } else {
            self.ws.cx.clock.idle();
        }
        // The status bar changes when the oldest notice expires; nothing else about notices
        // needs a repaint.
        if let Some(oldest) = self.ws.cx.notices.iter().map(|n| n.at).min() {
            let left = NOTICE_SECONDS - oldest.elapsed().as_secs_f64();
            ctx.request_repaint_after(Duration::from_secs_f64(left.max(0.0)));
        }
    }

    /// The panels' background. A clear costs a software rasteriser next to nothing, where a
    /// fill of the window (even the viewer's untextured one) costs every pixel's fragment work
    /// in every paint: two thirds of the pixels a paint of the viewer draws.
    fn clear_color(&self, _visuals: &egui::Visuals) -> [f32; 4] {
        style::PANEL_FILL.to_normalized_gamma_f32()
    }

    /// Answers the shortcut keys before egui's pass sees them (see [`KeyIntake`]): a key then
    /// costs one painted frame instead of egui's settling frames after input.
    fn raw_input_hook(&mut self, ctx: &egui::Context, raw_input: &mut egui::RawInput) {
        if ctx.egui_wants_keyboard_input() {
            return;
        }
        let mut keys = std::mem::take(&mut self.keys);
        let actions = keys.take(&mut raw_input.events, |events| self.take_keys(events));
        self.keys = keys;
        self.key_actions.extend(actions);
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        storage.set_string(STORAGE_KEY, self.ws.cx.settings.to_stored());
    }
}
