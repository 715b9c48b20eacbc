//! The viewer's side of the engine: one frame graph on eframe's device holding every
//! technique the adapter can run plus the progressive reference, and the decisions of what to
//! render each UI frame.
//!
//! A technique renders when its view changed (camera pose, size, scene, or the animation
//! frame of an animated scene), when its settings changed, when it has no current output, and,
//! for temporal techniques, whenever the clock advanced. Everything that renders in a frame
//! renders from one `FrameGraph::render` call, so all outputs show the same frame and the
//! shared scene inputs are drawn once. The reference adds a few samples per frame while the
//! view stays the same, and starts over when it changes.
//!
//! Every output (and selected debug view) is registered with egui's renderer through its
//! `Rgba8Unorm` view twice, with a linear and a nearest sampler; the ids are kept and pointed
//! at the new textures when the graph reallocates them (resize).

use std::cell::RefCell;
use std::rc::Rc;
use std::sync::Arc;

use egui::TextureId;
use egui::mutex::RwLock;

use super::reference::{ProgressiveReference, REFERENCE_ID, ReferenceControl};
use super::stats::GpuStats;
use crate::aa::ssaa::Progress;
use crate::aa::{self, FrameInfo, Param, ParamError, ParamValue};
use crate::gpu::{COLOR_FORMAT_ENCODED_VIEW, Capabilities, Gpu};
use crate::graph::{FrameGraph, FrameScope, MemoryReport};
use crate::scene::Scene;
use crate::scene::camera::{FrameCamera, OrbitPose};

/// GPU milliseconds the reference may add to a frame (it always adds at least one sample).
const REFERENCE_BUDGET_MS: f64 = 60.0;
/// Most reference samples per frame.
const MAX_REFERENCE_SAMPLES_PER_FRAME: u32 = 8;

/// A texture registered with egui twice.
#[derive(Clone, Debug)]
pub struct EguiImage {
    /// Sampled with a linear filter.
    pub linear: TextureId,
    /// Sampled with a nearest filter (1:1 display and magnified crops).
    pub nearest: TextureId,
    /// The texture registered.
    pub texture: wgpu::Texture,
}

impl EguiImage {
    /// Size in pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.texture.width(), self.texture.height())
    }
}

/// Keeps `image` pointing at `texture`: registers it the first time, re-points both ids when
/// the texture changed.
fn register(
    renderer: &RwLock<egui_wgpu::Renderer>,
    device: &wgpu::Device,
    image: &mut Option<EguiImage>,
    texture: &wgpu::Texture,
) {
    if image.as_ref().is_some_and(|i| i.texture == *texture) {
        return;
    }
    let view = texture.create_view(&wgpu::TextureViewDescriptor {
        label: Some("viewer egui view"),
        format: Some(COLOR_FORMAT_ENCODED_VIEW),
        ..Default::default()
    });
    let mut renderer = renderer.write();
    match image {
        Some(existing) => {
            renderer.update_egui_texture_from_wgpu_texture(
                device,
                &view,
                wgpu::FilterMode::Linear,
                existing.linear,
            );
            renderer.update_egui_texture_from_wgpu_texture(
                device,
                &view,
                wgpu::FilterMode::Nearest,
                existing.nearest,
            );
            existing.texture = texture.clone();
        }
        None => {
            *image = Some(EguiImage {
                linear: renderer.register_native_texture(device, &view, wgpu::FilterMode::Linear),
                nearest: renderer.register_native_texture(device, &view, wgpu::FilterMode::Nearest),
                texture: texture.clone(),
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
    output: Option<EguiImage>,
    debug_images: Vec<(&'static str, &'static str, Option<EguiImage>)>,
}

impl TechniqueEntry {
    /// Whether it can run here.
    pub fn available(&self) -> bool {
        self.availability.is_ok()
    }

    /// The debug views the technique produced last frame: (name, description).
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
    /// Accumulating or complete for the current view.
    Ready(Progress),
}

/// What a frame did.
#[derive(Clone, Copy, Debug, Default)]
pub struct FrameReport {
    /// The graph rendered something.
    pub rendered: bool,
    /// Technique outputs changed.
    pub outputs_changed: bool,
    /// The reference gained samples.
    pub reference_changed: bool,
    /// The reference wants more frames (not started or incomplete).
    pub busy: bool,
}

/// See the module docs.
pub struct Engine {
    gpu: Gpu,
    graph: FrameGraph,
    renderer: Arc<RwLock<egui_wgpu::Renderer>>,
    entries: Vec<TechniqueEntry>,
    reference_slot: usize,
    reference: Rc<RefCell<ReferenceControl>>,
    reference_samples: u32,
    reference_image: Option<EguiImage>,
    reference_key: Option<ViewKey>,
    reference_wanted: bool,
    scene_generation: u64,
    animated: bool,
    last_key: Option<ViewKey>,
    displayed: Option<FrameCamera>,
    timings_serial: u64,
    /// GPU time statistics.
    pub gpu_stats: GpuStats,
    memory: Option<MemoryReport>,
    scene_renders: usize,
}

impl Engine {
    /// Builds the graph on `gpu` (eframe's device) for `scene` with every available technique,
    /// all switched off, and the reference with `reference_samples` samples per pixel.
    pub fn new(
        gpu: Gpu,
        renderer: Arc<RwLock<egui_wgpu::Renderer>>,
        scene: &Scene,
        reference_samples: u32,
    ) -> Self {
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
                    output: None,
                    debug_images: Vec::new(),
                }
            })
            .collect();
        let (reference, control) = ProgressiveReference::new(&gpu, reference_samples);
        let reference_slot = graph.add(Box::new(reference));
        graph.slots_mut()[reference_slot].enabled = false;
        Self {
            gpu,
            graph,
            renderer,
            entries,
            reference_slot,
            reference: control,
            reference_samples,
            reference_image: None,
            reference_key: None,
            reference_wanted: false,
            scene_generation: 0,
            animated: scene.meshes.iter().any(|m| m.spin.is_some()),
            last_key: None,
            displayed: None,
            timings_serial: 0,
            gpu_stats: GpuStats::default(),
            memory: None,
            scene_renders: 0,
        }
    }

    /// What the adapter can do.
    pub fn caps(&self) -> &Capabilities {
        &self.gpu.caps
    }

    /// Replaces the scene (every output re-renders, temporal history resets by the caller's cut).
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

    /// Shows a debug view (by name) instead of a technique's output, or the output (`None`).
    /// The technique computes its debug views only while one is selected.
    pub fn set_debug_view(&mut self, id: &str, view: Option<String>) {
        let Some(entry) = self.entry_mut(id) else {
            return;
        };
        let on = view.is_some();
        let was_on = entry.debug_view.is_some() || !entry.debug_images.is_empty();
        entry.debug_view = view;
        if on != was_on
            && let Some(technique) = self.technique_mut(id)
        {
            technique.set_debug_views(on);
            self.changed(id);
            if !on && let Some(entry) = self.entry_mut(id) {
                entry.debug_images.clear();
            }
        }
    }

    /// Changes the reference's sample count (it starts over).
    pub fn set_reference_samples(&mut self, samples: u32) {
        if samples == self.reference_samples {
            return;
        }
        let (reference, control) = ProgressiveReference::new(&self.gpu, samples);
        self.graph.slots_mut()[self.reference_slot].technique = Box::new(reference);
        self.reference = control;
        self.reference_samples = samples;
        self.reference_key = None;
    }

    /// The image to show for a technique: its selected debug view, or its output.
    pub fn image(&self, id: &str) -> Option<&EguiImage> {
        let entry = self.entry(id)?;
        if !entry.enabled {
            return None;
        }
        match &entry.debug_view {
            Some(view) => entry
                .debug_images
                .iter()
                .find(|(n, _, _)| n == view)
                .and_then(|(_, _, image)| image.as_ref())
                .or(entry.output.as_ref()),
            None => entry.output.as_ref(),
        }
    }

    /// A technique's output (never a debug view), for metrics and export.
    pub fn output(&self, id: &str) -> Option<&EguiImage> {
        self.entry(id).filter(|e| e.enabled)?.output.as_ref()
    }

    /// The reference image with its progress, when it belongs to the displayed view.
    pub fn reference(&self) -> Option<(&EguiImage, Progress)> {
        let image = self.reference_image.as_ref()?;
        let progress = self.reference.borrow().progress;
        (self.reference_current() && progress.samples > 0).then_some((image, progress))
    }

    fn reference_current(&self) -> bool {
        self.reference_key.is_some() && self.reference_key == self.last_key
    }

    /// Where the reference stands.
    pub fn reference_state(&self) -> ReferenceState {
        if !self.reference_wanted {
            ReferenceState::Off
        } else if self.reference_current() && self.reference.borrow().progress.samples > 0 {
            ReferenceState::Ready(self.reference.borrow().progress)
        } else {
            ReferenceState::Waiting
        }
    }

    /// The camera of the displayed outputs.
    pub fn displayed(&self) -> Option<FrameCamera> {
        self.displayed
    }

    /// Memory of the last frame that rendered every enabled technique.
    pub fn memory(&self) -> Option<&MemoryReport> {
        self.memory.as_ref()
    }

    /// Scene renders recorded by the last full frame.
    pub fn scene_renders(&self) -> usize {
        self.scene_renders
    }

    /// Lets finished GPU work (readbacks, timings) report back without waiting.
    pub fn poll(&self) {
        let _ = self.gpu.device.poll(wgpu::PollType::Poll);
    }

    /// Renders what the frame needs (see the module docs). `want_reference` says whether
    /// anything shows or measures the reference.
    pub fn render(
        &mut self,
        camera: FrameCamera,
        cut: bool,
        want_reference: bool,
    ) -> Result<FrameReport, crate::graph::GraphError> {
        let key = ViewKey {
            pose: camera.pose,
            size: camera.size,
            scene: self.scene_generation,
            animation: if self.animated { camera.frame } else { 0 },
        };
        let still = !cut && self.last_key == Some(key);
        let stamp = Stamp {
            key,
            frame: camera.frame,
        };
        let mut report = FrameReport::default();

        // Which techniques run.
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
        let before = self.reference.borrow().progress;
        let restart = self.reference_key.is_none();
        let reference_runs = want_reference && still && (restart || !before.complete());
        if reference_runs {
            let budget = self.reference_budget();
            let mut control = self.reference.borrow_mut();
            control.restart = restart;
            control.budget = budget;
        }
        self.graph.slots_mut()[self.reference_slot].enabled = reference_runs;
        report.busy = want_reference && (restart || !before.complete());

        if running.is_empty() && !reference_runs {
            self.last_key = Some(key);
            return Ok(report);
        }
        let frame = FrameInfo {
            camera,
            reset_history: cut,
        };
        let result = self.graph.render(&frame, FrameScope::All);
        self.last_key = Some(key);
        result?;
        report.rendered = true;
        report.outputs_changed = !running.is_empty();
        let mut reference_renders = 0;
        if reference_runs {
            self.reference_key = Some(key);
            report.reference_changed = true;
            let after = self.reference.borrow().progress;
            reference_renders = after.samples - if restart { 0 } else { before.samples };
            report.busy = !after.complete();
        }

        let all_enabled_ran = self
            .entries
            .iter()
            .enumerate()
            .all(|(i, e)| !e.enabled || e.slot.is_none() || running.contains(&i));
        if !running.is_empty() {
            self.displayed = Some(camera);
            if all_enabled_ran {
                self.memory = Some(self.graph.memory_report());
                self.scene_renders = self
                    .graph
                    .scene_renders_last_frame()
                    .saturating_sub(reference_renders as usize);
            }
        }
        for i in running {
            let entry = &mut self.entries[i];
            entry.rendered = Some(stamp);
            entry.dirty = false;
        }
        self.register_images();
        if self.graph.timings_serial() != self.timings_serial {
            self.timings_serial = self.graph.timings_serial();
            if let Some(timings) = self.graph.timings() {
                self.gpu_stats.add(timings);
            }
        }
        for (slot, entry) in self.entries.iter().filter_map(|e| e.slot.map(|s| (s, e))) {
            self.graph.slots_mut()[slot].enabled = entry.enabled;
        }
        Ok(report)
    }

    /// Reference samples to add this frame, from the measured cost of one sample.
    fn reference_budget(&self) -> u32 {
        let per_sample = self
            .gpu_stats
            .technique_ms(REFERENCE_ID)
            .zip(Some(self.reference.borrow().budget.max(1)))
            .map(|(ms, budget)| ms / f64::from(budget));
        match per_sample {
            Some(ms) if ms > 0.0 => ((REFERENCE_BUDGET_MS / ms).floor() as u32)
                .clamp(1, MAX_REFERENCE_SAMPLES_PER_FRAME),
            _ => 1,
        }
    }

    /// Points the egui ids at the current output and debug textures.
    fn register_images(&mut self) {
        let device = self.gpu.device.clone();
        for entry in &mut self.entries {
            let Some(slot) = entry.slot else { continue };
            let slot = &self.graph.slots()[slot];
            if let Some(texture) = slot.output() {
                register(&self.renderer, &device, &mut entry.output, texture);
            }
            if entry.debug_view.is_some() {
                for view in slot.technique.debug_views() {
                    let index = match entry
                        .debug_images
                        .iter()
                        .position(|(n, _, _)| *n == view.name)
                    {
                        Some(index) => index,
                        None => {
                            entry.debug_images.push((view.name, view.description, None));
                            entry.debug_images.len() - 1
                        }
                    };
                    register(
                        &self.renderer,
                        &device,
                        &mut entry.debug_images[index].2,
                        view.texture,
                    );
                }
            }
        }
        if let Some(texture) = self.graph.slots()[self.reference_slot].output() {
            register(&self.renderer, &device, &mut self.reference_image, texture);
        }
    }
}
