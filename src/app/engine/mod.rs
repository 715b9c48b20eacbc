//! The viewer's side of the engine: the techniques as the UI sees them (on/off, settings
//! mirrored from the render thread, published images), the decisions of what to render
//! ([`super::schedule`]) and the hand-over of finished frames to egui.
//!
//! **Nothing waits.** The frame graph, its device and every technique live on the render
//! thread ([`super::render_thread`]); this side only sends commands and picks up events, so a
//! UI frame costs the same whether the engine is idle or busy with a frame that takes seconds
//! on a software rasteriser. Settings changes are validated here against the mirrored
//! parameter descriptions (immediate feedback), applied to the mirror at once, and sent to
//! the thread, which answers with the authoritative settings.
//!
//! **Two display paths** ([`Display`]), chosen by the adapter:
//! - *Native* (hardware adapters): the render thread renders on eframe's device and the window
//!   draws each technique's output texture directly ([`super::blit`], through the texture's
//!   `Rgba8Unorm` view, which holds the sRGB-encoded bytes; the magnifier draws UV crops of the
//!   same textures). Nothing is copied per displayed frame; pixels come back to the CPU only
//!   for what reads them (pixel values, error maps, quality figures, export), once the view is
//!   still, through a frame that only reads.
//! - *Readback* (software adapters): the render thread has a device of its own; every output
//!   is read back and uploaded by the render thread to a texture on eframe's device, drawn the
//!   same way; the magnifier, metrics and export use the read-back pixels as they are. Work
//!   on one queue runs in order, so on a software rasteriser the window's paint would wait
//!   behind the engine's frame on a shared queue, while the copies cost a few milliseconds of
//!   a CPU that renders anyway: the read-back path measured much faster there (figures:
//!   `docs/viewer.md`).
//!
//! One engine frame is in flight at a time; the camera keeps moving meanwhile and the next
//! frame renders where it has got to.

use std::sync::Arc;
use std::time::Duration;

use super::blit::{DisplayTexture, Uploader};
use super::reference::REFERENCE_ID;
use super::render_thread::{
    ClipJob, ClipSummary, Command, Event, FramePlan, FrameResult, ReferenceRequest, RenderDevice,
    RenderThread, RenderedImage, SettingsChange, TechniqueSettings,
};
use super::schedule::{self, Stamp, TechniqueState, ViewKey};
use super::stats::GpuStats;
use crate::aa::ssaa::Progress;
use crate::aa::{self, FrameInfo, Param, ParamError, ParamValue};
use crate::gpu::Capabilities;
use crate::graph::MemoryReport;
use crate::graph::hdr::TonemapChoice;
use crate::graph::overlay::OverlayOrder;
use crate::graph::params::validate_setting;
use crate::scene::Scene;
use crate::scene::camera::FrameCamera;

mod clip;
mod display;
mod player;
mod recording;
mod settings;

pub use display::{Display, DisplayPath, Published};
pub use player::{ClipPlayer, PlayRate};
pub use recording::{Clip, ClipFrame, ClipPath, ClipRecipe, ClipSettings, ClipStatus, MAX_FRAMES};
pub use settings::is_added;

/// GPU milliseconds the reference may add to a frame (it always adds at least one sample).
const REFERENCE_BUDGET_MS: f64 = 60.0;
/// Most reference samples per frame.
const MAX_REFERENCE_SAMPLES_PER_FRAME: u32 = 8;

/// What a published image shows: which view, which settings, which publication.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ImageStamp {
    /// The view it was rendered at ([`Engine::current_view`] at the time).
    pub view: u64,
    /// The settings revision of its technique ([`TechniqueEntry::revision`]; for the
    /// reference, the revision of its sample count).
    pub revision: u64,
    /// Unique per publication: new pixels, new serial.
    pub serial: u64,
}

/// One registry technique in the viewer.
pub struct TechniqueEntry {
    /// Registry id.
    pub id: &'static str,
    /// Display name.
    pub name: &'static str,
    /// Trade-off paragraph (tooltip).
    pub summary: &'static str,
    /// `Err(reason)` when this adapter cannot run it.
    pub availability: Result<(), String>,
    /// Whether the user switched it on.
    pub enabled: bool,
    /// The debug view shown instead of the output (by name), if any.
    pub debug_view: Option<String>,
    /// A user technique's file no longer builds (the last good build still runs): the error.
    pub problem: Option<String>,
    /// A user technique the user removed: off, not listed, its file no longer watched.
    pub removed: bool,
    /// A user technique whose build is running: since when (the row shows "compiling...").
    building: Option<std::time::Instant>,
    /// Its settings as the render thread last reported them (`None` until it is ready).
    settings: Option<TechniqueSettings>,
    rendered: Option<Stamp>,
    dirty: bool,
    revision: u64,
    output: Option<Published>,
    debug_images: Vec<(&'static str, &'static str, Option<Published>)>,
}

impl TechniqueEntry {
    /// An entry, switched off, with nothing rendered yet.
    fn new(
        id: &'static str,
        name: &'static str,
        summary: &'static str,
        availability: Result<(), String>,
    ) -> Self {
        Self {
            id,
            name,
            summary,
            availability,
            enabled: false,
            debug_view: None,
            problem: None,
            removed: false,
            building: None,
            settings: None,
            rendered: None,
            dirty: false,
            revision: 0,
            output: None,
            debug_images: Vec::new(),
        }
    }

    /// Counts its settings changes: outputs and figures of an older revision are out of date.
    pub fn revision(&self) -> u64 {
        self.revision
    }

    /// How long its user technique build has been running, while it runs.
    pub fn compiling_for(&self) -> Option<std::time::Duration> {
        self.building.map(|since| since.elapsed())
    }

    /// Whether it reconstructs at the output size from a lower render itself (see
    /// `aa::Technique::reconstructs_at_output`; `false` until the render thread is ready).
    pub fn reconstructs_at_output(&self) -> bool {
        self.settings
            .as_ref()
            .is_some_and(|s| s.reconstructs_at_output)
    }

    /// Whether it can run here.
    pub fn available(&self) -> bool {
        self.availability.is_ok()
    }

    /// Whether it can be switched on now: it can run here and is not a user technique whose
    /// first build is still compiling.
    pub fn switchable(&self) -> bool {
        self.available() && !(self.building.is_some() && self.settings.is_none())
    }

    /// The debug views the technique produced: (name, description).
    pub fn debug_views(&self) -> impl Iterator<Item = (&'static str, &'static str)> + '_ {
        self.debug_images.iter().map(|(n, d, _)| (*n, *d))
    }
}

/// Where the reference stands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReferenceState {
    /// Not wanted (no quality figures, no reference pane).
    Off,
    /// The view is changing; the reference waits for it to stop.
    Waiting,
    /// Accumulating or complete for the displayed view.
    Ready(Progress),
}

/// What [`Engine::poll`] published.
#[derive(Clone, Debug, Default)]
pub struct Publication {
    /// Technique outputs changed.
    pub outputs: bool,
    /// User techniques whose first working build arrived (their saved parameters can now be
    /// applied).
    pub added_users: Vec<&'static str>,
    /// The reference gained samples.
    pub reference: bool,
    /// What went wrong meanwhile (refused settings, failed frames), for the user.
    pub problems: Vec<String>,
}

/// Errors of the engine.
#[derive(Debug, thiserror::Error)]
pub enum EngineError {
    /// The render thread could not be started.
    #[error("the viewer's render thread could not be started: {0}")]
    Thread(#[from] std::io::Error),
    /// The render thread has ended.
    #[error("the viewer's render thread has stopped{0}")]
    Stopped(String),
}

/// The frame being rendered.
struct InFlight {
    camera: FrameCamera,
    key: ViewKey,
    view: u64,
    running: Vec<usize>,
    /// The view the reference accumulates for and the reference revision, when it renders.
    reference: Option<(ViewKey, u64)>,
    /// Whether every enabled technique renders in this frame.
    complete: bool,
}

/// See the module docs.
pub struct Engine {
    caps: Capabilities,
    display: Display,
    thread: RenderThread,
    /// Why the render thread ended, once it has.
    stopped: Option<String>,
    entries: Vec<TechniqueEntry>,
    reference_samples: u32,
    reference_image: Option<Published>,
    /// The view and progress of the published reference.
    reference_published: Option<(ViewKey, Progress)>,
    /// The view the accumulation on the GPU belongs to, and its progress.
    reference_accumulated: Option<(ViewKey, Progress)>,
    reference_wanted: bool,
    /// Revision of the reference's sample count.
    reference_revision: u64,
    scene_generation: u64,
    overlay: Option<OverlayOrder>,
    /// The tonemap choice and exposure every render follows.
    tonemap: (TonemapChoice, f32),
    /// Geometric specular antialiasing in the techniques' scene renders.
    specular_aa: bool,
    /// Counts view changes (see [`Engine::current_view`]).
    view_serial: u64,
    /// Counts publications.
    publish_serial: u64,
    animated: bool,
    last_key: Option<ViewKey>,
    displayed: Option<FrameCamera>,
    displayed_key: Option<ViewKey>,
    in_flight: Option<InFlight>,
    /// Samples the reference was last asked to add (its timing covers that many).
    reference_budget_sent: u32,
    /// Test hook: every frame takes at least this long on the render thread.
    frame_delay: Duration,
    /// GPU time statistics.
    pub gpu_stats: GpuStats,
    memory: Option<MemoryReport>,
    scene_renders: usize,
    /// The recorded (or recording) clip.
    clip: Option<Clip>,
    /// The clip is on screen instead of the live view.
    clip_shown: bool,
    /// The graph's state belongs to a clip: the next live frame starts over.
    after_clip: bool,
    /// The render thread's device once it has opened it (declared after `thread`, so that it
    /// is released after the thread has ended).
    render_device: Option<wgpu::Device>,
}

impl Engine {
    /// Starts the render thread for `display` (on a device with `caps`) with the graph for
    /// `scene`, every available technique (all switched off) and the reference with
    /// `reference_samples` samples. Returns at once; the techniques' settings arrive when the
    /// thread has created them.
    pub fn new(
        display: Display,
        caps: Capabilities,
        ctx: &egui::Context,
        scene: Arc<Scene>,
        reference_samples: u32,
        frame_delay: Duration,
    ) -> Result<Self, EngineError> {
        let entries: Vec<TechniqueEntry> = aa::registry()
            .into_iter()
            .map(|info| {
                TechniqueEntry::new(info.id, info.name, info.summary, (info.availability)(&caps))
            })
            .collect();
        let animated = scene.meshes.iter().any(|m| m.spin.is_some());
        let wake = ctx.clone();
        let device = match &display {
            Display::Readback(state) => RenderDevice::Own(state.adapter.clone()),
            Display::Native(state) => RenderDevice::Shared(crate::gpu::Gpu::from_parts(
                state.adapter.clone(),
                state.device.clone(),
                state.queue.clone(),
            )),
        };
        let thread = RenderThread::spawn(
            device,
            Uploader::new(display.state()),
            scene,
            entries.iter().map(TechniqueEntry::available).collect(),
            reference_samples,
            move || super::repaint::request_one_frame(&wake),
        )?;
        Ok(Self {
            caps,
            display,
            thread,
            stopped: None,
            entries,
            reference_samples,
            reference_image: None,
            reference_published: None,
            reference_accumulated: None,
            reference_wanted: false,
            reference_revision: 0,
            scene_generation: 0,
            overlay: None,
            tonemap: (TonemapChoice::Auto, 0.0),
            specular_aa: false,
            view_serial: 0,
            publish_serial: 0,
            animated,
            last_key: None,
            displayed: None,
            displayed_key: None,
            in_flight: None,
            reference_budget_sent: 1,
            frame_delay,
            gpu_stats: GpuStats::default(),
            memory: None,
            scene_renders: 0,
            clip: None,
            clip_shown: false,
            after_clip: false,
            render_device: None,
        })
    }

    /// What the render device can do.
    pub fn caps(&self) -> &Capabilities {
        &self.caps
    }

    /// Sends a command to the render thread, remembering when it has ended.
    fn send(&mut self, command: Command) -> bool {
        let sent = self.thread.send(command);
        if !sent && self.stopped.is_none() {
            self.stopped = Some(String::new());
        }
        sent
    }

    /// Replaces the scene (every output re-renders; the caller cuts the camera).
    pub fn set_scene(&mut self, scene: Arc<Scene>) {
        self.animated = scene.meshes.iter().any(|m| m.spin.is_some());
        self.send(Command::Scene(scene));
        self.scene_generation += 1;
        self.gpu_stats.clear();
        self.memory = None;
        self.discard_clip();
    }

    /// Whether the scene has moving objects (the view changes with every frame while playing).
    pub fn animated(&self) -> bool {
        self.animated
    }

    /// Whether a temporal technique is on (it changes with every frame while time runs).
    pub fn temporal_enabled(&self) -> bool {
        self.entries
            .iter()
            .any(|e| e.enabled && e.settings.as_ref().is_some_and(|s| s.temporal))
    }

    /// Every registry technique, in registry order.
    pub fn entries(&self) -> &[TechniqueEntry] {
        &self.entries
    }

    /// A technique by id.
    pub fn entry(&self, id: &str) -> Option<&TechniqueEntry> {
        self.entries.iter().find(|e| e.id == id)
    }

    fn index(&self, id: &str) -> Option<usize> {
        self.entries.iter().position(|e| e.id == id)
    }

    /// Changes the reference's sample count (it starts over).
    pub fn set_reference_samples(&mut self, samples: u32) {
        if samples == self.reference_samples {
            return;
        }
        self.send(Command::ReferenceSamples(samples));
        self.reference_samples = samples;
        self.reference_revision += 1;
        self.reference_accumulated = None;
        self.reference_published = None;
    }

    /// The image shown for a technique: its selected debug view, or its output (the shown
    /// clip frame's output while a clip is on screen).
    pub fn image(&self, id: &str) -> Option<&Published> {
        if let Some(clip) = self.shown_clip() {
            return clip.image(id);
        }
        let entry = self.entry(id).filter(|e| e.enabled)?;
        let debug = entry.debug_view.as_ref().and_then(|view| {
            entry
                .debug_images
                .iter()
                .find(|(n, _, _)| n == view)
                .and_then(|(_, _, image)| image.as_ref())
        });
        debug.or(entry.output.as_ref())
    }

    /// A technique's output (never a debug view), for metrics and export.
    pub fn output(&self, id: &str) -> Option<&Published> {
        if let Some(clip) = self.shown_clip() {
            return clip.image(id);
        }
        self.entry(id).filter(|e| e.enabled)?.output.as_ref()
    }

    /// The reference with its progress, when it belongs to the displayed view.
    pub fn reference(&self) -> Option<(&Published, Progress)> {
        if let Some(clip) = self.shown_clip() {
            let image = clip.shown()?.reference.as_ref()?;
            let total = clip.recipe.reference_samples?;
            let complete = Progress {
                samples: total,
                total,
            };
            return Some((image, complete));
        }
        let image = self.reference_image.as_ref()?;
        let (key, progress) = self.reference_published?;
        (Some(key) == self.displayed_key && progress.samples > 0).then_some((image, progress))
    }

    /// Where the reference stands.
    pub fn reference_state(&self) -> ReferenceState {
        match self.reference() {
            _ if !self.reference_wanted => ReferenceState::Off,
            Some((_, progress)) => ReferenceState::Ready(progress),
            None => ReferenceState::Waiting,
        }
    }

    /// The view being rendered now: a serial that changes whenever the camera, the size, the
    /// scene or (for animated scenes) the frame changes, or the camera cuts. Images stamped
    /// with an older view no longer show what the camera sees.
    pub fn current_view(&self) -> u64 {
        if let Some(frame) = self.shown_clip().and_then(Clip::shown) {
            return frame.view;
        }
        self.view_serial
    }

    /// The camera of the displayed outputs.
    pub fn displayed(&self) -> Option<FrameCamera> {
        self.displayed
    }

    /// Memory of the last frame that rendered every enabled technique.
    pub fn memory(&self) -> Option<&MemoryReport> {
        self.memory.as_ref()
    }

    /// Scene renders recorded by the last frame that rendered every enabled technique.
    pub fn scene_renders(&self) -> usize {
        self.scene_renders
    }

    /// The device the render thread renders on, once it has opened it.
    pub fn render_device(&self) -> Option<&wgpu::Device> {
        self.render_device.as_ref()
    }

    /// A frame is being rendered or read back.
    pub fn busy(&self) -> bool {
        self.in_flight.is_some()
    }

    /// Whether the render thread has created the techniques.
    pub fn ready(&self) -> bool {
        self.entries.iter().any(|e| e.settings.is_some())
    }

    /// Whether the reference still wants frames for the current view.
    pub fn reference_incomplete(&self) -> bool {
        self.reference_wanted
            && !matches!(self.reference_accumulated,
                Some((key, progress)) if Some(key) == self.last_key && progress.complete())
    }

    /// Picks up what the render thread finished and publishes its images.
    pub fn poll(&mut self) -> Publication {
        profiling::function_scope!();
        let mut publication = Publication::default();
        for event in self.thread.poll() {
            match event {
                Event::Ready(techniques, device) => {
                    self.render_device = Some(device);
                    self.ready_techniques(techniques);
                }
                Event::Settings {
                    index,
                    settings,
                    error,
                } => {
                    if let Some(entry) = self.entries.get_mut(index) {
                        entry.settings = Some(settings);
                    }
                    publication.problems.extend(error);
                }
                Event::Frame(result) => {
                    let Some(flight) = self.in_flight.take() else {
                        continue;
                    };
                    match result {
                        Ok(frame) => self.publish_frame(flight, frame, &mut publication),
                        Err(err) => publication.problems.push(err.to_string()),
                    }
                }
                Event::ClipFrame { outputs, reference } => {
                    self.receive_clip_frame(outputs, reference);
                    publication.outputs = true;
                }
                Event::ClipEnd(end) => {
                    self.end_clip(end);
                    publication.outputs = true;
                }
                Event::Failed(err) => {
                    self.in_flight = None;
                    self.stopped = Some(format!(": {err}"));
                }
                Event::UserTechnique {
                    index,
                    id,
                    name,
                    result,
                } => self.user_technique(index, id, &name, result, &mut publication),
                Event::UserBuilding { index, id, name } => {
                    if let Some(entry) = self.user_entry(index, id, &name) {
                        entry.building = Some(std::time::Instant::now());
                    }
                }
                Event::UserRefused(reason) => publication.problems.push(reason),
            }
        }
        if let Some(reason) = &self.stopped {
            publication
                .problems
                .push(EngineError::Stopped(reason.clone()).to_string());
        }
        publication
    }

    fn publish_frame(
        &mut self,
        flight: InFlight,
        frame: FrameResult,
        publication: &mut Publication,
    ) {
        if flight.key.scene != self.scene_generation {
            // Rendered before the scene changed: nobody will look at it.
            return;
        }
        if let Some(timings) = &frame.timings {
            self.gpu_stats.add(timings);
        }
        if let Some(report) = frame.memory {
            self.memory = Some(report);
        }
        if flight.complete {
            self.scene_renders = frame.scene_renders;
        }
        for (index, output) in frame.outputs {
            self.publish_serial += 1;
            let entry = &mut self.entries[index];
            let stamp = ImageStamp {
                view: flight.view,
                revision: entry.revision,
                serial: self.publish_serial,
            };
            let pixels = output.pixels.map(Arc::new);
            match output.display {
                Some(texture) => {
                    entry.output = Some(Published {
                        pixels,
                        stamp,
                        texture,
                    });
                }
                // Pixels read later of the texture on screen: same image, same stamp.
                None => {
                    if let Some(published) = &mut entry.output
                        && let Some(pixels) = pixels
                        && published.size() == pixels.dimensions()
                    {
                        published.pixels = Some(pixels);
                    }
                    continue;
                }
            }
            publication.outputs = true;
        }
        for (index, name, description, image) in frame.debug {
            self.publish_serial += 1;
            let entry = &mut self.entries[index];
            if entry.debug_view.is_none() {
                continue;
            }
            let position = match entry.debug_images.iter().position(|(n, _, _)| *n == name) {
                Some(position) => position,
                None => {
                    entry.debug_images.push((name, description, None));
                    entry.debug_images.len() - 1
                }
            };
            let stamp = ImageStamp {
                view: flight.view,
                revision: entry.revision,
                serial: self.publish_serial,
            };
            entry.debug_images[position].2 = Some(Published::new(image, stamp));
            if entry.debug_view.as_deref() == Some("") {
                entry.debug_view = Some(name.to_owned());
            }
            publication.outputs = true;
        }
        if let (Some((progress, image)), Some((key, revision))) =
            (frame.reference, flight.reference)
            && revision == self.reference_revision
        {
            self.publish_serial += 1;
            let stamp = ImageStamp {
                view: flight.view,
                revision,
                serial: self.publish_serial,
            };
            self.reference_image = Some(Published::new(image, stamp));
            self.reference_accumulated = Some((key, progress));
            self.reference_published = Some((key, progress));
            publication.reference = true;
        }
        if !flight.running.is_empty() {
            self.displayed = Some(flight.camera);
            self.displayed_key = Some(flight.key);
        }
    }

    /// Starts the next frame at `camera` when there is something to render (see
    /// [`schedule::schedule`]); `want_reference` says whether anything shows or measures the
    /// reference, `want_pixels` whether anything reads the outputs' pixels (on the native
    /// path, pixels are read back only then, and only once the view is still). Returns whether
    /// a frame was started.
    pub fn submit(
        &mut self,
        camera: FrameCamera,
        cut: bool,
        want_reference: bool,
        want_pixels: bool,
    ) -> Result<bool, EngineError> {
        profiling::function_scope!();
        if let Some(reason) = &self.stopped {
            return Err(EngineError::Stopped(reason.clone()));
        }
        if self.in_flight.is_some() || !self.ready() {
            return Ok(false);
        }
        if self.live_paused() {
            return Ok(false);
        }
        let after_clip = std::mem::take(&mut self.after_clip);
        if after_clip {
            // The graph's outputs, histories and reference samples are a clip's: all start
            // over.
            for entry in &mut self.entries {
                entry.rendered = None;
            }
            self.reference_accumulated = None;
        }
        let cut = cut || after_clip;
        let key = ViewKey {
            pose: camera.pose,
            size: camera.size,
            scene: self.scene_generation,
            animation: if self.animated { camera.frame } else { 0 },
        };
        let states: Vec<TechniqueState> = self
            .entries
            .iter()
            .map(|e| TechniqueState {
                enabled: e.enabled && e.settings.is_some(),
                temporal: e.settings.as_ref().is_some_and(|s| s.temporal),
                dirty: e.dirty,
                rendered: e.rendered,
            })
            .collect();
        self.reference_wanted = want_reference;
        let reference = schedule::ReferenceState {
            wanted: want_reference,
            accumulated_for: self.reference_accumulated.map(|(key, _)| key),
            complete: self
                .reference_accumulated
                .is_some_and(|(_, progress)| progress.complete()),
        };
        let plan = schedule::schedule(&states, reference, self.last_key, key, camera.frame, cut);
        self.last_key = Some(key);
        if !plan.still {
            self.view_serial += 1;
        }
        let read: Vec<usize> = if !self.display.is_native() {
            plan.run.clone()
        } else if want_pixels && plan.still {
            // Everything on screen whose pixels are not on the CPU yet.
            (0..states.len())
                .filter(|&i| states[i].enabled)
                .filter(|&i| {
                    plan.run.contains(&i)
                        || self.entries[i]
                            .output
                            .as_ref()
                            .is_some_and(|o| o.pixels.is_none())
                })
                .collect()
        } else {
            Vec::new()
        };
        if plan.is_empty() && read.is_empty() {
            return Ok(false);
        }
        let complete = states
            .iter()
            .enumerate()
            .all(|(i, s)| !s.enabled || plan.run.contains(&i));
        let request = FramePlan {
            frame: FrameInfo {
                camera,
                reset_history: cut,
            },
            debug: plan
                .run
                .iter()
                .copied()
                .filter(|&i| self.entries[i].debug_view.is_some())
                .collect(),
            run: plan.run.clone(),
            read,
            textures: self.display.is_native(),
            reference: plan.reference.map(|restart| ReferenceRequest {
                restart,
                budget: self.reference_budget(),
            }),
            on: (0..states.len()).filter(|&i| states[i].enabled).collect(),
            report_memory: !plan.run.is_empty(),
            delay: self.frame_delay,
        };
        if !self.send(Command::Render(request)) {
            return Err(EngineError::Stopped(String::new()));
        }
        for &i in &plan.run {
            let entry = &mut self.entries[i];
            entry.rendered = Some(Stamp {
                key,
                frame: camera.frame,
            });
            entry.dirty = false;
        }
        if plan.reference == Some(true) {
            self.reference_accumulated = None;
        }
        self.in_flight = Some(InFlight {
            camera,
            key,
            view: self.view_serial,
            running: plan.run,
            reference: plan.reference.map(|_| (key, self.reference_revision)),
            complete,
        });
        Ok(true)
    }

    /// Reference samples to add this frame, from the measured cost of one sample.
    fn reference_budget(&mut self) -> u32 {
        let last = self.reference_budget_sent.max(1);
        let budget = match self.gpu_stats.technique_ms(REFERENCE_ID) {
            Some(ms) if ms > 0.0 => ((REFERENCE_BUDGET_MS * f64::from(last) / ms).floor() as u32)
                .clamp(1, MAX_REFERENCE_SAMPLES_PER_FRAME),
            _ => 1,
        };
        self.reference_budget_sent = budget;
        budget
    }
}
