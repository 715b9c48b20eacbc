//! The viewer's side of the engine: one frame graph holding every technique the adapter can
//! run plus the progressive reference, the decisions of what to render, and the hand-over of
//! finished frames to the UI.
//!
//! **What renders.** A technique renders when its view changed (camera pose, size, scene, or
//! the animation frame of an animated scene), when its settings changed, when it has no
//! output yet, and, for temporal techniques, whenever the clock advanced. Everything that
//! renders in a frame renders from one `FrameGraph::render` call, so all outputs show the same
//! frame and shared scene inputs are drawn once. The reference adds a few samples per frame
//! while the view stays the same and starts over when it changes.
//!
//! **Its own device.** The graph runs on a second device created on eframe's adapter, not on
//! eframe's device: a frame can take a second on a software rasteriser, and work on one queue
//! runs in order, so on a shared queue every UI frame (menus, sliders, the lens) would wait
//! for the rendering in flight. With its own queue the window stays responsive whatever the
//! techniques cost. Finished outputs are read back without blocking (a waiter thread wakes
//! the UI when the GPU is done) and published as CPU images and egui textures holding the very
//! same bytes (sRGB-encoded RGBA8, nearest sampling, no dithering), which the magnifier,
//! metrics and export then use without further readbacks. One engine frame is in flight at a
//! time; the camera keeps moving meanwhile and the next frame renders where it has got to.

use std::sync::{Arc, mpsc};

use egui::{TextureHandle, TextureId, TextureOptions};

use super::readback::{PendingImage, Region};
use super::reference::{ProgressiveReference, REFERENCE_ID, SharedControl};
use super::stats::GpuStats;
use crate::aa::ssaa::Progress;
use crate::aa::{self, FrameInfo, Param, ParamError, ParamValue};
use crate::gpu::{Capabilities, Gpu, GpuError};
use crate::graph::{FrameGraph, FrameScope, GraphError, MemoryReport};
use crate::scene::Scene;
use crate::scene::camera::{FrameCamera, OrbitPose};

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

/// A finished image: its pixels on the CPU and an egui texture with the same bytes.
#[derive(Clone)]
pub struct Published {
    /// The pixels (sRGB-encoded RGBA8).
    pub pixels: Arc<image::RgbaImage>,
    /// What the pixels show.
    pub stamp: ImageStamp,
    handle: TextureHandle,
}

impl Published {
    /// The egui texture (nearest sampling).
    pub fn id(&self) -> TextureId {
        self.handle.id()
    }

    /// Size in pixels.
    pub fn size(&self) -> (u32, u32) {
        self.pixels.dimensions()
    }
}

/// Stores `pixels` in `slot`, updating its texture in place when there is one.
fn publish(
    ctx: &egui::Context,
    slot: &mut Option<Published>,
    name: &str,
    pixels: image::RgbaImage,
    stamp: ImageStamp,
) {
    let size = [pixels.width() as usize, pixels.height() as usize];
    let color = egui::ColorImage::from_rgba_unmultiplied(size, pixels.as_raw());
    match slot {
        Some(existing) => {
            existing.handle.set(color, TextureOptions::NEAREST);
            existing.pixels = Arc::new(pixels);
            existing.stamp = stamp;
        }
        None => {
            *slot = Some(Published {
                handle: ctx.load_texture(name, color, TextureOptions::NEAREST),
                pixels: Arc::new(pixels),
                stamp,
            });
        }
    }
}

/// What determines the image of a non-temporal technique.
#[derive(Clone, Copy, Debug, PartialEq)]
struct ViewKey {
    pose: OrbitPose,
    size: (u32, u32),
    scene: u64,
    /// The frame number for animated scenes, 0 for static ones.
    animation: u64,
}

/// The view and frame an output was rendered at.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Stamp {
    key: ViewKey,
    frame: u64,
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
    slot: Option<usize>,
    rendered: Option<Stamp>,
    dirty: bool,
    revision: u64,
    output: Option<Published>,
    debug_images: Vec<(&'static str, &'static str, Option<Published>)>,
}

impl TechniqueEntry {
    /// Counts its settings changes: outputs and figures of an older revision are out of date.
    pub fn revision(&self) -> u64 {
        self.revision
    }

    /// Whether it can run here.
    pub fn available(&self) -> bool {
        self.availability.is_ok()
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
#[derive(Clone, Copy, Debug, Default)]
pub struct Publication {
    /// Technique outputs changed.
    pub outputs: bool,
    /// The reference gained samples.
    pub reference: bool,
}

/// Errors of the engine.
#[derive(Debug, thiserror::Error)]
pub enum EngineError {
    /// The render device could not be created.
    #[error("the viewer's render device could not be created: {0}")]
    Device(#[from] GpuError),
    /// A frame failed.
    #[error(transparent)]
    Graph(#[from] GraphError),
    /// Reading a finished frame back failed.
    #[error(transparent)]
    Readback(#[from] super::readback::ReadbackError),
}

/// Which published image a readback fills.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Target {
    /// A technique's output, with the settings revision it rendered with.
    Output(usize, u64),
    Debug(usize, &'static str, &'static str),
    Reference,
}

/// The frame being rendered and read back.
struct InFlight {
    camera: FrameCamera,
    key: ViewKey,
    view: u64,
    running: Vec<usize>,
    reads: Vec<(Target, PendingImage)>,
    done: Vec<(Target, image::RgbaImage)>,
    reference: Option<(ViewKey, Progress)>,
}

/// See the module docs.
pub struct Engine {
    gpu: Gpu,
    graph: FrameGraph,
    entries: Vec<TechniqueEntry>,
    reference_slot: usize,
    reference: SharedControl,
    reference_samples: u32,
    reference_image: Option<Published>,
    /// The view and progress of the published reference.
    reference_published: Option<(ViewKey, Progress)>,
    /// The view the accumulation on the GPU belongs to.
    reference_key: Option<ViewKey>,
    reference_wanted: bool,
    /// Revision of the reference's sample count.
    reference_revision: u64,
    scene_generation: u64,
    /// Counts view changes (see [`Engine::current_view`]).
    view_serial: u64,
    /// Counts publications.
    publish_serial: u64,
    animated: bool,
    last_key: Option<ViewKey>,
    displayed: Option<FrameCamera>,
    displayed_key: Option<ViewKey>,
    in_flight: Option<InFlight>,
    waiter: mpsc::Sender<()>,
    timings_serial: u64,
    /// GPU time statistics.
    pub gpu_stats: GpuStats,
    memory: Option<MemoryReport>,
    scene_renders: usize,
}

/// A thread that waits for the render device to finish and wakes the UI.
fn spawn_waiter(device: wgpu::Device, ctx: egui::Context) -> mpsc::Sender<()> {
    let (sender, receiver) = mpsc::channel::<()>();
    let spawned = std::thread::Builder::new()
        .name("aa-lab gpu waiter".to_owned())
        .spawn(move || {
            while receiver.recv().is_ok() {
                let _ = device.poll(wgpu::PollType::wait_indefinitely());
                ctx.request_repaint();
            }
        });
    if let Err(err) = spawned {
        // Without the thread the UI still polls while a frame is in flight (see `busy`).
        log::warn!("no GPU waiter thread ({err}); polling instead");
    }
    sender
}

/// A device of its own on `adapter`, with the features the frame graph uses.
pub fn open_device(adapter: &wgpu::Adapter) -> Result<Gpu, GpuError> {
    let (device, queue) =
        pollster::block_on(adapter.request_device(&crate::gpu::device_descriptor(adapter)))
            .map_err(|source| GpuError::RequestDevice {
                adapter: adapter.get_info().name,
                source,
            })?;
    Ok(Gpu::from_parts(adapter.clone(), device, queue))
}

impl Engine {
    /// Creates the render device on `adapter` and the graph for `scene` with every available
    /// technique (all switched off) and the reference with `reference_samples` samples.
    pub fn new(
        adapter: &wgpu::Adapter,
        ctx: &egui::Context,
        scene: &Scene,
        reference_samples: u32,
    ) -> Result<Self, EngineError> {
        let gpu = open_device(adapter)?;
        let mut graph = FrameGraph::new(gpu.clone(), scene);
        let entries = aa::registry()
            .into_iter()
            .map(|info| {
                let availability = (info.availability)(&gpu.caps);
                let slot = availability.is_ok().then(|| {
                    let index = graph.add((info.create)(&gpu));
                    graph.slots_mut()[index].enabled = false;
                    index
                });
                TechniqueEntry {
                    id: info.id,
                    name: info.name,
                    summary: info.summary,
                    availability,
                    enabled: false,
                    debug_view: None,
                    slot,
                    rendered: None,
                    dirty: false,
                    revision: 0,
                    output: None,
                    debug_images: Vec::new(),
                }
            })
            .collect();
        let (reference, control) = ProgressiveReference::new(&gpu, reference_samples);
        let reference_slot = graph.add(Box::new(reference));
        graph.slots_mut()[reference_slot].enabled = false;
        Ok(Self {
            waiter: spawn_waiter(gpu.device.clone(), ctx.clone()),
            gpu,
            graph,
            entries,
            reference_slot,
            reference: control,
            reference_samples,
            reference_image: None,
            reference_published: None,
            reference_key: None,
            reference_wanted: false,
            reference_revision: 0,
            scene_generation: 0,
            view_serial: 0,
            publish_serial: 0,
            animated: scene.meshes.iter().any(|m| m.spin.is_some()),
            last_key: None,
            displayed: None,
            displayed_key: None,
            in_flight: None,
            timings_serial: 0,
            gpu_stats: GpuStats::default(),
            memory: None,
            scene_renders: 0,
        })
    }

    /// What the render device can do.
    pub fn caps(&self) -> &Capabilities {
        &self.gpu.caps
    }

    /// Replaces the scene (every output re-renders; the caller cuts the camera).
    pub fn set_scene(&mut self, scene: &Scene) {
        self.graph.set_scene(scene);
        self.scene_generation += 1;
        self.animated = scene.meshes.iter().any(|m| m.spin.is_some());
        self.gpu_stats.clear();
        self.memory = None;
    }

    /// Whether the scene has moving objects (the view changes with every frame while playing).
    pub fn animated(&self) -> bool {
        self.animated
    }

    /// Whether a temporal technique is on (it changes with every frame while time runs).
    pub fn temporal_enabled(&self) -> bool {
        self.entries.iter().any(|e| {
            e.enabled
                && e.slot
                    .is_some_and(|s| self.graph.slots()[s].technique.temporal())
        })
    }

    /// Every registry technique, in registry order.
    pub fn entries(&self) -> &[TechniqueEntry] {
        &self.entries
    }

    /// A technique by id.
    pub fn entry(&self, id: &str) -> Option<&TechniqueEntry> {
        self.entries.iter().find(|e| e.id == id)
    }

    fn entry_mut(&mut self, id: &str) -> Option<&mut TechniqueEntry> {
        self.entries.iter_mut().find(|e| e.id == id)
    }

    /// Switches a technique on or off (unavailable ones stay off).
    pub fn set_enabled(&mut self, id: &str, on: bool) {
        if let Some(entry) = self.entry_mut(id)
            && entry.available()
        {
            entry.enabled = on;
        }
    }

    fn technique_mut(&mut self, id: &str) -> Option<&mut dyn aa::Technique> {
        let slot = self.entry(id)?.slot?;
        Some(self.graph.slots_mut()[slot].technique.as_mut())
    }

    fn technique(&self, id: &str) -> Option<&dyn aa::Technique> {
        let slot = self.entry(id)?.slot?;
        Some(self.graph.slots()[slot].technique.as_ref())
    }

    /// A technique's parameters with their current values.
    pub fn params(&self, id: &str) -> Vec<Param> {
        self.technique(id).map(|t| t.params()).unwrap_or_default()
    }

    /// A technique's presets.
    pub fn presets(&self, id: &str) -> &'static [&'static str] {
        self.technique(id).map(|t| t.presets()).unwrap_or(&[])
    }

    /// Which code path a technique runs on this adapter, when it has a choice.
    pub fn path_note(&self, id: &str) -> Option<String> {
        self.technique(id).and_then(|t| t.path_note())
    }

    /// The settings of a technique as a map (sidecar form).
    pub fn param_map(&self, id: &str) -> aa::ParamMap {
        self.technique(id).map(aa::param_map).unwrap_or_default()
    }

    fn changed(&mut self, id: &str) {
        if let Some(entry) = self.entry_mut(id) {
            entry.dirty = true;
            entry.revision += 1;
        }
    }

    /// Sets one parameter (validated).
    pub fn set_param(&mut self, id: &str, key: &str, value: ParamValue) -> Result<(), ParamError> {
        let Some(technique) = self.technique_mut(id) else {
            return Ok(());
        };
        aa::set_param(technique, key, value)?;
        self.changed(id);
        Ok(())
    }

    /// Restores a whole settings map (from the saved settings).
    pub fn apply_param_map(&mut self, id: &str, map: &aa::ParamMap) -> Result<(), ParamError> {
        let Some(technique) = self.technique_mut(id) else {
            return Ok(());
        };
        aa::apply_param_map(technique, map)?;
        self.changed(id);
        Ok(())
    }

    /// Applies a preset.
    pub fn apply_preset(&mut self, id: &str, preset: &str) -> Result<(), ParamError> {
        let Some(technique) = self.technique_mut(id) else {
            return Ok(());
        };
        technique.apply_preset(preset)?;
        self.changed(id);
        Ok(())
    }

    /// Shows a debug view (by name; empty for the first one) instead of a technique's output,
    /// or the output (`None`). The technique computes its debug views only while one is shown.
    pub fn set_debug_view(&mut self, id: &str, view: Option<String>) {
        let Some(entry) = self.entry_mut(id) else {
            return;
        };
        let was_on = entry.debug_view.is_some();
        let on = view.is_some();
        entry.debug_view = view;
        if !on {
            entry.debug_images.clear();
        }
        if on != was_on
            && let Some(technique) = self.technique_mut(id)
        {
            technique.set_debug_views(on);
            self.changed(id);
        }
    }

    /// Changes the reference's sample count (it starts over).
    pub fn set_reference_samples(&mut self, samples: u32) {
        if samples == self.reference_samples || self.in_flight.is_some() {
            return;
        }
        let (reference, control) = ProgressiveReference::new(&self.gpu, samples);
        self.graph.slots_mut()[self.reference_slot].technique = Box::new(reference);
        self.reference = control;
        self.reference_samples = samples;
        self.reference_revision += 1;
        self.reference_key = None;
        self.reference_published = None;
    }

    /// The image shown for a technique: its selected debug view, or its output.
    pub fn image(&self, id: &str) -> Option<&Published> {
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
        self.entry(id).filter(|e| e.enabled)?.output.as_ref()
    }

    /// The reference with its progress, when it belongs to the displayed view.
    pub fn reference(&self) -> Option<(&Published, Progress)> {
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

    /// A frame is being rendered or read back.
    pub fn busy(&self) -> bool {
        self.in_flight.is_some()
    }

    /// Whether the reference still wants frames for the current view.
    pub fn reference_incomplete(&self) -> bool {
        self.reference_wanted
            && !(self.reference_key.is_some()
                && self.reference_key == self.last_key
                && self.reference.lock().progress.complete())
    }

    /// Collects the frame in flight once the GPU has delivered it and publishes its images.
    pub fn poll(&mut self, ctx: &egui::Context) -> Result<Publication, EngineError> {
        let mut publication = Publication::default();
        let Some(flight) = &mut self.in_flight else {
            return Ok(publication);
        };
        let _ = self.gpu.device.poll(wgpu::PollType::Poll);
        let mut index = 0;
        while index < flight.reads.len() {
            match flight.reads[index].1.try_take() {
                Ok(Some(image)) => {
                    let (target, _) = flight.reads.remove(index);
                    flight.done.push((target, image));
                }
                Ok(None) => index += 1,
                Err(err) => {
                    self.in_flight = None;
                    return Err(err.into());
                }
            }
        }
        if !flight.reads.is_empty() {
            return Ok(publication);
        }
        let Some(flight) = self.in_flight.take() else {
            return Ok(publication);
        };
        for (target, pixels) in flight.done {
            self.publish_serial += 1;
            let stamp = |revision| ImageStamp {
                view: flight.view,
                revision,
                serial: self.publish_serial,
            };
            match target {
                Target::Output(i, revision) => {
                    let entry = &mut self.entries[i];
                    publish(ctx, &mut entry.output, entry.id, pixels, stamp(revision));
                    publication.outputs = true;
                }
                Target::Debug(i, name, description) => {
                    let entry = &mut self.entries[i];
                    let index = match entry.debug_images.iter().position(|(n, _, _)| *n == name) {
                        Some(index) => index,
                        None => {
                            entry.debug_images.push((name, description, None));
                            entry.debug_images.len() - 1
                        }
                    };
                    let revision = entry.revision;
                    publish(
                        ctx,
                        &mut entry.debug_images[index].2,
                        name,
                        pixels,
                        stamp(revision),
                    );
                    if entry.debug_view.as_deref() == Some("") {
                        entry.debug_view = Some(name.to_owned());
                    }
                    publication.outputs = true;
                }
                Target::Reference => {
                    let revision = self.reference_revision;
                    publish(
                        ctx,
                        &mut self.reference_image,
                        REFERENCE_ID,
                        pixels,
                        stamp(revision),
                    );
                    self.reference_published = flight.reference;
                    publication.reference = true;
                }
            }
        }
        if !flight.running.is_empty() {
            self.displayed = Some(flight.camera);
            self.displayed_key = Some(flight.key);
        }
        Ok(publication)
    }

    /// Starts the next frame at `camera` when there is something to render (see the module
    /// docs); `want_reference` says whether anything shows or measures the reference. Returns
    /// whether a frame was started.
    pub fn submit(
        &mut self,
        camera: FrameCamera,
        cut: bool,
        want_reference: bool,
    ) -> Result<bool, EngineError> {
        if self.in_flight.is_some() {
            return Ok(false);
        }
        let key = ViewKey {
            pose: camera.pose,
            size: camera.size,
            scene: self.scene_generation,
            animation: if self.animated { camera.frame } else { 0 },
        };
        let still = !cut && self.last_key == Some(key);
        self.last_key = Some(key);
        if !still {
            self.view_serial += 1;
        }

        let mut running = Vec::new();
        for (i, entry) in self.entries.iter().enumerate() {
            let Some(slot) = entry.slot else { continue };
            let temporal = self.graph.slots()[slot].technique.temporal();
            let stale = match entry.rendered {
                None => true,
                Some(done) => done.key != key || (temporal && done.frame != camera.frame),
            };
            let run = entry.enabled && (cut || entry.dirty || stale);
            self.graph.slots_mut()[slot].enabled = run;
            if run {
                running.push(i);
            }
        }

        // The reference: only on a still view, until complete.
        self.reference_wanted = want_reference;
        if self.reference_key != Some(key) {
            self.reference_key = None;
        }
        let before = self.reference.lock().progress;
        let restart = self.reference_key.is_none();
        let reference_runs = want_reference && still && (restart || !before.complete());
        if reference_runs {
            let budget = self.reference_budget();
            let mut control = self.reference.lock();
            control.restart = restart;
            control.budget = budget;
        }
        self.graph.slots_mut()[self.reference_slot].enabled = reference_runs;
        if running.is_empty() && !reference_runs {
            return Ok(false);
        }

        let frame = FrameInfo {
            camera,
            reset_history: cut,
        };
        let result = self.graph.render(&frame, FrameScope::All);
        let restore = |engine: &mut Self| {
            for (slot, enabled) in engine
                .entries
                .iter()
                .filter_map(|e| e.slot.map(|s| (s, e.enabled)))
                .collect::<Vec<_>>()
            {
                engine.graph.slots_mut()[slot].enabled = enabled;
            }
        };
        if let Err(err) = result {
            restore(self);
            return Err(err.into());
        }

        let mut reference = None;
        let mut reference_renders = 0;
        if reference_runs {
            self.reference_key = Some(key);
            let after = self.reference.lock().progress;
            reference_renders = after.samples - if restart { 0 } else { before.samples };
            reference = Some((key, after));
        }
        let all_enabled_ran = self
            .entries
            .iter()
            .enumerate()
            .all(|(i, e)| !e.enabled || e.slot.is_none() || running.contains(&i));
        if !running.is_empty() && all_enabled_ran {
            self.memory = Some(self.graph.memory_report());
            self.scene_renders = self
                .graph
                .scene_renders_last_frame()
                .saturating_sub(reference_renders as usize);
        }
        if self.graph.timings_serial() != self.timings_serial {
            self.timings_serial = self.graph.timings_serial();
            if let Some(timings) = self.graph.timings() {
                self.gpu_stats.add(timings);
            }
        }

        // Read back everything that rendered.
        let mut reads = Vec::new();
        let read = |texture: &wgpu::Texture| {
            PendingImage::start(
                &self.gpu.device,
                &self.gpu.queue,
                texture,
                Region::whole(texture),
            )
        };
        for &i in &running {
            let entry = &self.entries[i];
            let Some(slot) = entry.slot.map(|s| &self.graph.slots()[s]) else {
                continue;
            };
            if let Some(texture) = slot.output() {
                reads.push((Target::Output(i, entry.revision), read(texture)));
            }
            if entry.debug_view.is_some() {
                for view in slot.technique.debug_views() {
                    if view.texture.usage().contains(wgpu::TextureUsages::COPY_SRC) {
                        reads.push((
                            Target::Debug(i, view.name, view.description),
                            read(view.texture),
                        ));
                    }
                }
            }
        }
        if reference_runs && let Some(texture) = self.graph.slots()[self.reference_slot].output() {
            reads.push((Target::Reference, read(texture)));
        }
        for &i in &running {
            let entry = &mut self.entries[i];
            entry.rendered = Some(Stamp {
                key,
                frame: camera.frame,
            });
            entry.dirty = false;
        }
        restore(self);
        self.in_flight = Some(InFlight {
            camera,
            key,
            view: self.view_serial,
            running,
            reads,
            done: Vec::new(),
            reference,
        });
        let _ = self.waiter.send(());
        Ok(true)
    }

    /// Reference samples to add this frame, from the measured cost of one sample.
    fn reference_budget(&self) -> u32 {
        let budget = self.reference.lock().budget.max(1);
        match self.gpu_stats.technique_ms(REFERENCE_ID) {
            Some(ms) if ms > 0.0 => ((REFERENCE_BUDGET_MS * f64::from(budget) / ms).floor() as u32)
                .clamp(1, MAX_REFERENCE_SAMPLES_PER_FRAME),
            _ => 1,
        }
    }
}
