//! The viewer's render thread: it owns the render device, the frame graph with every technique
//! and the progressive reference, and does every slow engine step off the UI thread: creating
//! the device and the techniques' pipelines, uploading scenes, resizing targets (inside the
//! graph's frame), recording and submitting frames, waiting for the GPU, reading the outputs
//! back and uploading them as display textures on eframe's device ([`super::blit`]).
//!
//! The UI talks to it through two channels. [`Command`]s (scene, settings changes, frames to
//! render) are handled in the order sent; each answer comes back as an [`Event`] and wakes the
//! UI. The UI keeps at most one [`FramePlan`] in flight and builds the next one from its newest
//! state only when the previous frame is back, so a request never waits behind an outdated one
//! and the thread never renders a frame nobody asked for. Techniques are addressed by their
//! registry index (the UI's entry index); a technique whose pipelines cannot be created here
//! is reported unavailable in [`Event::Ready`] and ignored afterwards. User techniques
//! ([`Command::AddUser`], `aa::user`) take the next indices after the registry's, in the order
//! added; their files are looked at about once a second and rebuilt when they change
//! ([`Event::UserTechnique`]), the last good build running on while a change does not compile.
//! A user technique is built on a thread of its own (`aa::user::build`): the thread announces
//! the build ([`Event::UserBuilding`]), goes on rendering the other techniques (and the last
//! good build of this one) and installs the result when the build finishes, however long the
//! driver takes to compile it. Combinations of a technique with a render scale, upscaler and
//! sharpening ([`Command::AddCombination`], `aa::combo`) are added the same way, created at
//! once (they have no file to build or watch).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, mpsc};
use std::time::Duration;

use crate::aa::user::PendingBuild;

use super::blit::{DisplayTexture, Uploader};
use super::reference::{ProgressiveReference, SharedControl};
use super::worker::EXIT_WAIT;
use crate::aa::ssaa::Progress;
use crate::aa::{self, ParamMap, ParamValue};
use crate::gpu::readback::{PendingReadback, ReadbackBelt, ReadbackError, Region, Ticket};
use crate::gpu::{Gpu, GpuError};
use crate::graph::params::Param;
use crate::graph::{FrameGraph, FrameInfo, FrameScope, FrameTimings, MemoryReport};
use crate::metrics::Plane;
use crate::metrics::stability::TemporalScores;
use crate::scene::Scene;
use crate::scene::camera::FrameCamera;

mod clip;
mod tickets;
mod users;

pub use clip::{ClipJob, ClipSummary};
use tickets::Tickets;

/// What the UI mirrors of a technique's settings.
#[derive(Clone, Debug)]
pub struct TechniqueSettings {
    /// Parameters with their current values.
    pub params: Vec<Param>,
    /// Named presets.
    pub presets: &'static [&'static str],
    /// The code path it runs on this adapter, when it has a choice.
    pub path_note: Option<String>,
    /// Whether it keeps state across frames.
    pub temporal: bool,
    /// Whether it reconstructs at the output size from a lower render itself (a temporal
    /// upscaler): a combination of it takes no upscaler.
    pub reconstructs_at_output: bool,
    /// The content hash of a user technique's file (see `aa::user`).
    pub source_hash: Option<String>,
}

impl TechniqueSettings {
    fn of(technique: &dyn aa::Technique) -> Self {
        Self {
            params: technique.params(),
            presets: technique.presets(),
            path_note: technique.path_note(),
            temporal: technique.temporal(),
            reconstructs_at_output: technique.reconstructs_at_output(),
            source_hash: technique.source_hash(),
        }
    }
}

/// A change of a technique's settings.
#[derive(Clone, Debug)]
pub enum SettingsChange {
    /// One parameter.
    Param(String, ParamValue),
    /// A whole saved map.
    Map(ParamMap),
    /// A named preset.
    Preset(String),
    /// Debug views on or off.
    DebugViews(bool),
}

/// What the reference does in a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReferenceRequest {
    /// Drop the accumulated samples first (the view changed).
    pub restart: bool,
    /// Samples to add.
    pub budget: u32,
}

/// One frame to render: plain data, decided by the UI's scheduler.
#[derive(Clone, Debug)]
pub struct FramePlan {
    /// Camera and history reset.
    pub frame: FrameInfo,
    /// Registry indices of the techniques that render.
    pub run: Vec<usize>,
    /// Registry indices whose outputs are read back to the CPU (rendered in this frame or
    /// not: a plan may only read).
    pub read: Vec<usize>,
    /// Hand out the output textures of the techniques that run (the window draws them
    /// directly).
    pub textures: bool,
    /// Registry indices (a subset of `run`) whose debug views are read back too.
    pub debug: Vec<usize>,
    /// The reference's part, if it renders.
    pub reference: Option<ReferenceRequest>,
    /// Registry indices of every technique the user has on, whether it renders in this frame
    /// or keeps its output from an earlier one (a technique added to a still view renders
    /// alone): the graph keeps their scene inputs and releases the others'.
    pub on: Vec<usize>,
    /// Whether the memory report (of everything the graph holds) comes back with the frame.
    pub report_memory: bool,
    /// Test hook: the thread waits this long before rendering (a deliberately slow frame).
    pub delay: Duration,
}

/// A finished image: the pixels (sRGB-encoded RGBA8) and the same bytes on eframe's device.
pub struct RenderedImage {
    /// The pixels.
    pub pixels: image::RgbaImage,
    /// The same pixels, ready to draw.
    pub texture: Arc<DisplayTexture>,
}

/// A technique's output in a [`FrameResult`].
pub struct FrameOutput {
    /// What to draw: the output texture itself when the plan asked for textures and the
    /// technique ran, else the upload of the read-back pixels (`None` when a plan for textures
    /// only read pixels back).
    pub display: Option<Arc<DisplayTexture>>,
    /// The pixels, when the plan asked for them.
    pub pixels: Option<image::RgbaImage>,
}

/// A rendered frame.
pub struct FrameResult {
    /// Technique outputs by registry index.
    pub outputs: Vec<(usize, FrameOutput)>,
    /// Debug views: registry index, name, description, image.
    pub debug: Vec<(usize, &'static str, &'static str, RenderedImage)>,
    /// The reference's progress and image, when it rendered.
    pub reference: Option<(Progress, RenderedImage)>,
    /// The graph's memory, when the plan asked for it.
    pub memory: Option<MemoryReport>,
    /// Scene renders of the techniques (the reference's own renders not counted).
    pub scene_renders: usize,
    /// GPU timings that became available with this frame.
    pub timings: Option<FrameTimings>,
}

/// Errors of the render thread.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The render device could not be created.
    #[error("the viewer's render device could not be created: {0}")]
    Device(#[from] GpuError),
    /// A frame failed.
    #[error(transparent)]
    Graph(#[from] crate::graph::GraphError),
    /// Reading a finished frame back failed.
    #[error(transparent)]
    Readback(#[from] ReadbackError),
}

/// Requests from the UI.
pub enum Command {
    /// Replace the scene.
    Scene(Arc<Scene>),
    /// Change a technique's settings (by registry index).
    Configure(usize, SettingsChange),
    /// Restart the reference with another sample count.
    ReferenceSamples(u32),
    /// Draw the UI overlay (or not) from the next frame on.
    Overlay(Option<crate::graph::overlay::OverlayOrder>),
    /// Geometric specular antialiasing on or off in every scene render but the reference's.
    SpecularAa(bool),
    /// Show the scene through this tonemap choice at this exposure (stops) from the next
    /// frame on.
    Tonemap(crate::graph::hdr::TonemapChoice, f32),
    /// Render a frame.
    Render(FramePlan),
    /// Record a clip.
    Clip(ClipJob),
    /// Add the user technique in this file (`aa::user`), or rebuild it if it is there.
    AddUser(std::path::PathBuf),
    /// Add the combination of a technique with a render scale, upscaler or sharpening
    /// (`aa::combo`, canonical id) at the next index, as a user technique is added: it is
    /// created here and answered with [`Event::UserTechnique`]. Adding it again is a no-op
    /// answered the same way.
    AddCombination(&'static str),
    /// Stop watching the file of the user technique at this index (the user removed it; its
    /// slot stays, switched off, so that indices keep their meaning, and adding the file again
    /// rebuilds it there).
    RemoveUser(usize),
}

/// Answers to the UI.
pub enum Event {
    /// The device and every technique exist: per registry index, the settings or why the
    /// technique cannot run here; and the device the thread renders on (the app's test API
    /// reads its live GPU object counts).
    Ready(Vec<Result<TechniqueSettings, String>>, wgpu::Device),
    /// A technique's settings after a [`Command::Configure`], and the error if the change was
    /// refused.
    Settings {
        /// Registry index.
        index: usize,
        /// Its settings now.
        settings: TechniqueSettings,
        /// Why the change was refused.
        error: Option<String>,
    },
    /// A frame finished (or failed).
    Frame(Result<FrameResult, RenderError>),
    /// The next frame of a clip: the outputs by registry index (in the job's order) and the
    /// reference.
    ClipFrame {
        /// Per technique.
        outputs: Vec<(usize, RenderedImage)>,
        /// When the job asked for it.
        reference: Option<RenderedImage>,
    },
    /// A clip ended (or failed).
    ClipEnd(Result<ClipSummary, RenderError>),
    /// The thread could not start; it has ended.
    Failed(RenderError),
    /// A user technique was added (`index` is the next one) or its file was rebuilt: its
    /// settings, or the error that stops it (a rebuild's error leaves the last good build
    /// running).
    UserTechnique {
        /// Registry index.
        index: usize,
        /// Its id (`user:PATH`).
        id: &'static str,
        /// Its display name.
        name: String,
        /// Its settings, or what is wrong with its file.
        result: Result<TechniqueSettings, String>,
    },
    /// A user technique's build started (`index` is the next one when it is new); its result
    /// comes as [`Event::UserTechnique`].
    UserBuilding {
        /// Registry index.
        index: usize,
        /// Its id (`user:PATH`).
        id: &'static str,
        /// Its display name.
        name: String,
    },
    /// A file given to [`Command::AddUser`] could not even be named (it does not exist).
    UserRefused(String),
}

/// How often the thread looks at the builds in progress while it has no command.
const BUILD_POLL: Duration = Duration::from_millis(20);

/// The device the thread renders on.
pub enum RenderDevice {
    /// A device of its own on this adapter (its queue never delays the UI's).
    Own(wgpu::Adapter),
    /// eframe's device, so that egui can draw the outputs without copies.
    Shared(Gpu),
}

/// The UI's handle: send commands, receive events. Dropping it ends the thread after the
/// command it is handling and waits for that, at most [`EXIT_WAIT`] (the engine lives as
/// long as the app; a new scene goes to the same thread).
pub struct RenderThread {
    commands: mpsc::Sender<Command>,
    events: mpsc::Receiver<Event>,
    /// Disconnects when the thread has released its GPU objects and ended.
    finished: mpsc::Receiver<()>,
}

impl RenderThread {
    /// Starts the thread: it opens `device`, creates the graph for `scene` and every registry
    /// technique that `available` allows, then answers [`Event::Ready`]. Read-back images are
    /// uploaded with `uploader`; `wake` is called after every event.
    pub fn spawn(
        device: RenderDevice,
        uploader: Uploader,
        scene: Arc<Scene>,
        available: Vec<bool>,
        reference_samples: u32,
        wake: impl Fn() + Send + 'static,
    ) -> std::io::Result<Self> {
        let (commands, command_receiver) = mpsc::channel();
        let (event_sender, events) = mpsc::channel();
        let (finishing, finished) = mpsc::channel::<()>();
        std::thread::Builder::new()
            .name("aa-lab render".to_owned())
            .spawn(move || {
                // Dropped last, after `state`: the channel disconnects once the GPU objects
                // are released.
                let _finishing = finishing;
                super::worker::lower_priority();
                let send = |event| {
                    let _ = event_sender.send(event);
                    wake();
                };
                let mut state =
                    match RenderState::new(device, uploader, &scene, &available, reference_samples)
                    {
                        Ok((state, ready)) => {
                            send(Event::Ready(ready, state.gpu.device.clone()));
                            state
                        }
                        Err(err) => {
                            send(Event::Failed(err));
                            return;
                        }
                    };
                loop {
                    let wait = if state.builds.is_empty() {
                        aa::user::watch::INTERVAL
                    } else {
                        BUILD_POLL
                    };
                    match command_receiver.recv_timeout(wait) {
                        Ok(command) => state.handle(command, &send),
                        Err(mpsc::RecvTimeoutError::Timeout) => {}
                        Err(mpsc::RecvTimeoutError::Disconnected) => break,
                    }
                    state.finish_user_builds(&send);
                    state.reload_user_techniques(&send);
                }
            })?;
        Ok(Self {
            commands,
            events,
            finished,
        })
    }

    /// Sends a command; `false` when the thread has ended.
    pub fn send(&self, command: Command) -> bool {
        self.commands.send(command).is_ok()
    }

    /// The events that arrived since the last call, oldest first.
    pub fn poll(&self) -> Vec<Event> {
        self.events.try_iter().collect()
    }
}

impl Drop for RenderThread {
    fn drop(&mut self) {
        // Replacing the sender drops the thread's only one: its loop ends at the next receive.
        self.commands = mpsc::channel().0;
        if let Err(mpsc::RecvTimeoutError::Timeout) = self.finished.recv_timeout(EXIT_WAIT) {
            log::warn!(
                "the render thread did not end within {} s; leaving it behind",
                EXIT_WAIT.as_secs()
            );
        }
    }
}

/// A device of its own for the adapter `adapter` stands for, opened on an instance of its own
/// (the same driver and device, found again by name, vendor, device id and backend). On a
/// software rasteriser this keeps the caller's work off the window's: lavapipe gives each
/// instance its own llvmpipe screen, whose rasteriser threads are started by the thread that
/// enumerates the adapters and inherit its CPU priority. A background thread calling this after
/// [`super::worker::lower_priority`] gets rasteriser threads at the lowest priority, and the
/// window's paint no longer queues behind one of its render passes. Where the new instance
/// does not list the same adapter, the device is opened on `adapter` itself.
pub fn open_device(adapter: &wgpu::Adapter) -> Result<Gpu, GpuError> {
    let adapter = same_adapter_on_own_instance(adapter).unwrap_or_else(|| adapter.clone());
    let (device, queue) =
        pollster::block_on(adapter.request_device(&crate::gpu::device_descriptor(&adapter)))
            .map_err(|source| GpuError::RequestDevice {
                adapter: adapter.get_info().name,
                source,
            })?;
    Ok(Gpu::from_parts(adapter, device, queue))
}

/// `adapter`'s device as a new instance lists it (see [`open_device`]).
fn same_adapter_on_own_instance(adapter: &wgpu::Adapter) -> Option<wgpu::Adapter> {
    let wanted = adapter.get_info();
    let backends = wgpu::Backends::from(wanted.backend);
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
        backends,
        ..wgpu::InstanceDescriptor::new_without_display_handle_from_env()
    });
    pollster::block_on(instance.enumerate_adapters(backends))
        .into_iter()
        .find(|candidate| {
            let info = candidate.get_info();
            info.name == wanted.name
                && info.vendor == wanted.vendor
                && info.device == wanted.device
                && info.driver_info == wanted.driver_info
        })
}

/// Everything the thread owns.
struct RenderState {
    gpu: Gpu,
    graph: FrameGraph,
    /// Graph slot per registry index (`None`: not available here).
    slots: Vec<Option<usize>>,
    reference_slot: usize,
    reference: SharedControl,
    reference_samples: u32,
    timings_serial: u64,
    /// Every image of a frame goes back through one staging buffer, mapped once.
    belt: ReadbackBelt,
    uploader: Uploader,
    /// User technique files, by registry index.
    watcher: aa::user::watch::Watcher,
    /// Registry index and id of every user technique.
    user_ids: Vec<(usize, &'static str)>,
    /// User technique builds in progress, by registry index (one per index: a newer build
    /// replaces an older one, whose result is dropped).
    builds: Vec<(usize, PendingBuild)>,
    /// The tonemap choice and exposure asked for, and whether the scene is HDR (which
    /// resolves `auto`).
    tonemap: (crate::graph::hdr::TonemapChoice, f32),
    scene_is_hdr: bool,
}

impl RenderState {
    fn new(
        device: RenderDevice,
        uploader: Uploader,
        scene: &Scene,
        available: &[bool],
        reference_samples: u32,
    ) -> Result<(Self, Vec<Result<TechniqueSettings, String>>), RenderError> {
        let gpu = match device {
            RenderDevice::Own(adapter) => open_device(&adapter)?,
            RenderDevice::Shared(gpu) => gpu,
        };
        let mut graph = FrameGraph::new(gpu.clone(), scene);
        let mut slots = Vec::new();
        let mut ready = Vec::new();
        for (info, &available) in aa::registry().iter().zip(available) {
            let created = if available {
                aa::create(&gpu, info.id).map_err(|e| e.to_string())
            } else {
                Err("not available on this adapter".to_owned())
            };
            match created {
                Ok(technique) => {
                    ready.push(Ok(TechniqueSettings::of(technique.as_ref())));
                    let slot = graph.add(technique);
                    graph.slots_mut()[slot].enabled = false;
                    slots.push(Some(slot));
                }
                Err(reason) => {
                    ready.push(Err(reason));
                    slots.push(None);
                }
            }
        }
        let (reference, control) = ProgressiveReference::new(&gpu, reference_samples);
        let reference_slot = graph.add(Box::new(reference));
        graph.slots_mut()[reference_slot].enabled = false;
        graph.slots_mut()[reference_slot].reference = true;
        let state = Self {
            belt: ReadbackBelt::new(&gpu.device),
            gpu,
            graph,
            slots,
            reference_slot,
            reference: control,
            reference_samples,
            timings_serial: 0,
            uploader,
            watcher: aa::user::watch::Watcher::default(),
            user_ids: Vec::new(),
            builds: Vec::new(),
            tonemap: (crate::graph::hdr::TonemapChoice::Auto, 0.0),
            scene_is_hdr: scene.is_hdr(),
        };
        Ok((state, ready))
    }

    /// Carries out `command`, answering through `send`.
    fn handle(&mut self, command: Command, send: &dyn Fn(Event)) {
        match command {
            Command::Scene(scene) => {
                self.graph.set_scene(&scene);
                self.scene_is_hdr = scene.is_hdr();
                self.apply_tonemap();
            }
            Command::Tonemap(choice, exposure) => {
                self.tonemap = (choice, exposure);
                self.apply_tonemap();
            }
            Command::Configure(index, change) => {
                if let Some(event) = self.configure(index, change) {
                    send(event);
                }
            }
            Command::ReferenceSamples(samples) => self.set_reference_samples(samples),
            Command::Overlay(order) => self.graph.set_overlay(order),
            Command::SpecularAa(on) => self.graph.set_specular_aa(on),
            Command::Render(plan) => {
                std::thread::sleep(plan.delay);
                send(Event::Frame(self.render(&plan)));
            }
            Command::Clip(job) => {
                let end = self.record_clip(&job, send);
                send(Event::ClipEnd(end));
            }
            Command::AddUser(path) => self.add_user(&path, send),
            Command::AddCombination(id) => self.add_combination(id, send),
            Command::RemoveUser(index) => {
                self.watcher.unwatch(index);
                // A build still running would list the technique again when it finished.
                self.builds.retain(|(building, _)| *building != index);
            }
        }
    }

    /// Replaces the reference with one of `samples` samples per pixel.
    /// Gives the graph the tonemap of the choice asked for and the current scene.
    fn apply_tonemap(&mut self) {
        let (choice, exposure) = self.tonemap;
        (self.graph).set_tonemap(choice.resolve(self.scene_is_hdr, exposure));
    }

    fn set_reference_samples(&mut self, samples: u32) {
        if samples != self.reference_samples {
            let (reference, control) = ProgressiveReference::new(&self.gpu, samples);
            self.graph.slots_mut()[self.reference_slot].technique = Box::new(reference);
            self.reference = control;
            self.reference_samples = samples;
        }
    }

    /// Runs exactly the slots of `run` (and the reference when `reference`) and keeps those
    /// of `on` (and the reference, which keeps accumulating across frames).
    fn enable(&mut self, run: &[usize], on: &[usize], reference: bool) {
        let slots_of = |indices: &[usize]| -> Vec<usize> {
            indices
                .iter()
                .filter_map(|&index| self.slots.get(index).copied().flatten())
                .collect()
        };
        let (running, kept) = (slots_of(run), slots_of(on));
        for (slot, state) in self.graph.slots_mut().iter_mut().enumerate() {
            state.enabled = running.contains(&slot);
            state.kept = kept.contains(&slot);
        }
        let reference_slot = &mut self.graph.slots_mut()[self.reference_slot];
        reference_slot.enabled = reference;
        reference_slot.kept = true;
    }

    fn configure(&mut self, index: usize, change: SettingsChange) -> Option<Event> {
        let slot = self.slots.get(index).copied().flatten()?;
        let technique = self.graph.slots_mut()[slot].technique.as_mut();
        let result = match change {
            SettingsChange::Param(key, value) => aa::set_param(technique, &key, value),
            SettingsChange::Map(map) => aa::apply_param_map(technique, &map),
            SettingsChange::Preset(name) => technique.apply_preset(&name),
            SettingsChange::DebugViews(on) => {
                technique.set_debug_views(on);
                Ok(())
            }
        };
        Some(Event::Settings {
            index,
            settings: TechniqueSettings::of(technique),
            error: result.err().map(|e| e.to_string()),
        })
    }

    fn render(&mut self, plan: &FramePlan) -> Result<FrameResult, RenderError> {
        profiling::function_scope!();
        if plan.run.is_empty() && plan.reference.is_none() {
            return self.read_only(plan);
        }
        let running: Vec<(usize, usize)> = plan
            .run
            .iter()
            .filter_map(|&index| Some((index, self.slots.get(index).copied().flatten()?)))
            .collect();
        self.enable(&plan.run, &plan.on, plan.reference.is_some());
        let before = self.reference.lock().progress;
        if let Some(request) = plan.reference {
            let mut control = self.reference.lock();
            control.restart = request.restart;
            control.budget = request.budget;
        }

        // The readback copies go into the frame's own encoder: one submission, one mapping.
        let slot_of = &self.slots;
        let belt = &mut self.belt;
        let reference_slot = self.reference_slot;
        let rendered = self
            .graph
            .render_with(&plan.frame, FrameScope::All, |encoder, slots| {
                let tickets = Tickets::record(belt, encoder, slots, plan, slot_of, reference_slot);
                (tickets, belt.finish(encoder))
            });
        let after = self.reference.lock().progress;
        let (tickets, pending) = rendered?;
        let tickets = tickets?;
        let reference_renders = match plan.reference {
            Some(r) if r.restart => after.samples,
            Some(_) => after.samples.saturating_sub(before.samples),
            None => 0,
        };
        let memory = plan.report_memory.then(|| self.graph.memory_report());
        let scene_renders = self
            .graph
            .scene_renders_last_frame()
            .saturating_sub(reference_renders as usize);
        let mut timings = None;
        if self.graph.timings_serial() != self.timings_serial {
            self.timings_serial = self.graph.timings_serial();
            timings = self.graph.timings().cloned();
        }
        let textures: Vec<(usize, wgpu::Texture)> = if plan.textures {
            running
                .iter()
                .filter_map(|&(index, slot)| {
                    Some((index, self.graph.slots()[slot].output()?.clone()))
                })
                .collect()
        } else {
            Vec::new()
        };
        let mut result = tickets.take(pending, &self.uploader, after, textures, !plan.textures)?;
        result.memory = memory;
        result.scene_renders = scene_renders;
        result.timings = timings;
        Ok(result)
    }

    /// A plan that renders nothing: copies of the current outputs only.
    fn read_only(&mut self, plan: &FramePlan) -> Result<FrameResult, RenderError> {
        let mut encoder = self
            .gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("viewer readback"),
            });
        let tickets = Tickets::record(
            &mut self.belt,
            &mut encoder,
            self.graph.slots(),
            plan,
            &self.slots,
            self.reference_slot,
        );
        let pending = self.belt.finish(&mut encoder);
        self.gpu.queue.submit([encoder.finish()]);
        tickets?.take(
            pending,
            &self.uploader,
            Progress::default(),
            Vec::new(),
            !plan.textures,
        )
    }
}
