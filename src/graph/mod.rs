//! The frame graph: one frame of every enabled technique from as few scene renders as possible.
//!
//! Per frame it (1) asks every enabled technique for its [`SceneInput`], (2) renders each
//! distinct input once (No AA, FXAA and SMAA 1x share one 1x render; TAA and SMAA T2x share a
//! jittered render when their offsets agree), (3) runs each technique's passes into its own
//! output texture, all in one command encoder with a GPU timer around every pass. The same
//! graph serves the viewer and the headless CLI. Optionally (off by default) every render pass
//! also counts its fragment-shader invocations ([`FrameGraph::set_pipeline_statistics`]), a
//! user-interface overlay goes over the frames before or after the antialiasing
//! ([`FrameGraph::set_overlay`], [`overlay`]), and HDR scenes run each technique before or
//! after the tonemapper ([`FrameGraph::set_tonemap`], [`hdr`]).

mod context;
pub mod hdr;
mod memory;
pub mod overlay;
pub mod params;
mod pooled_input;
mod statistics;
pub mod technique;
mod timing;

pub use context::PassContext;
pub use memory::{MemoryItem, MemoryReport, TechniqueMemory};
pub use statistics::{FrameStatistics, PassInvocations};
pub use technique::{DebugView, FrameInfo, SceneInput, Technique};
pub use timing::{FrameTimings, PassTiming, median_of_sorted, split_pass_label};

use std::collections::HashMap;

use crate::gpu::{self, Gpu, fullscreen::Fullscreen};
use crate::scene::Scene;
use crate::scene::renderer::{PassQueries, SceneRenderer, SceneTargets, TargetDesc, Tonemap};
use hdr::{TonemapOrder, TonemapPass};
use overlay::{OverlayOrder, OverlayPass};
use pooled_input::PooledInput;
use statistics::StatisticsRecorder;

/// Errors of a frame.
#[derive(Debug, thiserror::Error)]
pub enum GraphError {
    /// A zero-sized image was asked for.
    #[error("cannot render a {0}x{1} image: width and height must be at least 1")]
    ZeroSize(u32, u32),
    /// The size exceeds what the adapter allows.
    #[error(
        "cannot render a {width}x{height} image: this adapter's largest texture side is {limit}"
    )]
    TooLarge {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
        /// The adapter's `max_texture_dimension_2d`.
        limit: u32,
    },
    /// The GPU reported an error while the frame ran (out of memory, device lost, validation).
    #[error("the GPU failed while rendering: {0}")]
    Device(String),
    /// A technique at a render scale asked for the scene input in image mode, where the
    /// finished image is the only input and has the output's size.
    #[error(
        "a technique at a render scale reads a {0}x{1} scene render, which a finished image of \
         the output's size cannot stand in for"
    )]
    ImageScaled(u32, u32),
    /// The image given as input does not have the frame's size.
    #[error("the input image is {0}x{1}, but the frame is {2}x{3}")]
    ImageSize(u32, u32, u32, u32),
}

/// A technique in the graph, with its output texture.
pub struct Slot {
    /// The technique.
    pub technique: Box<dyn Technique>,
    /// Whether it runs this frame.
    pub enabled: bool,
    /// Whether it is switched on although it may not run this frame (it keeps the image of an
    /// earlier frame, as the viewer's still techniques do): its scene input stays pooled and
    /// the memory report lists it with that input. An enabled slot is always kept.
    pub kept: bool,
    /// The reference: its own scene renders ignore [`FrameGraph::set_specular_aa`], so that it
    /// stays the ground truth of unfiltered shading the techniques are scored against.
    pub reference: bool,
    output: Option<wgpu::Texture>,
    /// The half-float output of a technique before the tonemapper (HDR frames only).
    hdr_output: Option<wgpu::Texture>,
}

impl Slot {
    /// Whether the graph holds this slot's scene input and reports it as on.
    fn held(&self) -> bool {
        self.enabled || (self.kept && self.output.is_some())
    }

    /// The technique's latest output, when it has rendered at the current size.
    pub fn output(&self) -> Option<&wgpu::Texture> {
        self.output.as_ref()
    }

    /// The technique's latest radiance, when it ran before the tonemapper of an HDR frame
    /// (half floats, [`gpu::HDR_FORMAT`]).
    pub fn hdr_output(&self) -> Option<&wgpu::Texture> {
        self.hdr_output.as_ref()
    }
}

/// Which techniques a frame runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameScope {
    /// Every enabled technique.
    All,
    /// Only enabled temporal techniques (warm-up frames before the frame that is kept).
    TemporalOnly,
}

/// A texture a technique's output can be written to: RGBA8 sRGB with its encoded view, usable
/// as a render target, a sampled texture and a copy's source or destination (the graph's
/// output of each technique, and the render-size image a technique at a render scale writes
/// before its upscale).
pub fn output_texture(gpu: &Gpu, label: &str, size: (u32, u32)) -> wgpu::Texture {
    gpu::texture_2d(
        &gpu.device,
        &gpu::Texture2d {
            view_formats: gpu::encoded_view_formats(&gpu.caps),
            ..gpu::Texture2d::new(label, size, gpu::COLOR_FORMAT, OUTPUT_USAGE)
        },
    )
}

/// What a technique's output (displayed or radiance) is used as: a render target, a sampled
/// texture, and a copy's source or destination.
const OUTPUT_USAGE: wgpu::TextureUsages = wgpu::TextureUsages::RENDER_ATTACHMENT
    .union(wgpu::TextureUsages::TEXTURE_BINDING)
    .union(wgpu::TextureUsages::COPY_SRC)
    .union(wgpu::TextureUsages::COPY_DST);

/// The frame graph. See the module docs.
pub struct FrameGraph {
    gpu: Gpu,
    scene: SceneRenderer,
    slots: Vec<Slot>,
    fullscreen: Fullscreen,
    profiler: wgpu_profiler::GpuProfiler,
    input_pool: HashMap<TargetDesc, Vec<SceneTargets>>,
    inputs_used: Vec<PooledInput>,
    /// Per slot, the index into `inputs_used` it read last frame.
    slot_inputs: Vec<Option<usize>>,
    size: (u32, u32),
    timings: Option<FrameTimings>,
    timings_serial: u64,
    scene_renders: usize,
    statistics: StatisticsRecorder,
    /// A finished image that stands in for the 1x scene render (image mode).
    image_input: Option<image::RgbaImage>,
    overlay: OverlayPass,
    tonemap: TonemapPass,
    /// Geometric specular antialiasing in every scene render but the reference's.
    specular_aa: bool,
}

impl FrameGraph {
    /// A graph drawing `scene` on `gpu`, with no techniques yet.
    pub fn new(gpu: Gpu, scene: &Scene) -> Self {
        let profiler = wgpu_profiler::GpuProfiler::new(
            &gpu.device,
            wgpu_profiler::GpuProfilerSettings {
                enable_timer_queries: gpu.caps.timestamps,
                enable_debug_groups: true,
                max_num_pending_frames: 4,
            },
        )
        .unwrap_or_else(|_| {
            // Only invalid settings make this fail, and the ones above are valid.
            wgpu_profiler::GpuProfiler::new(
                &gpu.device,
                wgpu_profiler::GpuProfilerSettings::default(),
            )
            .expect("default profiler settings are valid")
        });
        Self {
            scene: SceneRenderer::new(&gpu, scene),
            fullscreen: Fullscreen::new(&gpu.device),
            slots: Vec::new(),
            profiler,
            input_pool: HashMap::new(),
            inputs_used: Vec::new(),
            slot_inputs: Vec::new(),
            size: (0, 0),
            timings: None,
            timings_serial: 0,
            scene_renders: 0,
            statistics: StatisticsRecorder::new(),
            image_input: None,
            overlay: OverlayPass::new(&gpu.device),
            tonemap: TonemapPass::new(&gpu.device),
            specular_aa: false,
            gpu,
        }
    }

    /// Where the UI overlay goes from the next frame on (`None`: no overlay, the default).
    pub fn set_overlay(&mut self, order: Option<OverlayOrder>) {
        self.overlay.set_order(order);
    }

    /// Renders HDR from the next frame on with `Some(tonemap)` (see [`hdr`]): scenes as linear
    /// radiance, each technique before or after the tonemapper by its
    /// [`Technique::tonemap_order`]. `None` (the default) is the LDR path. Image mode ignores
    /// it: a finished image is already display-referred.
    pub fn set_tonemap(&mut self, tonemap: Option<Tonemap>) {
        (self.tonemap).set_tonemap(&self.gpu, &self.fullscreen, tonemap);
    }

    /// The tonemap this frame renders with: the one set, unless in image mode (`None`: LDR).
    fn frame_tonemap(&self) -> Option<Tonemap> {
        self.tonemap
            .tonemap()
            .filter(|_| self.image_input.is_none())
    }

    /// Whether the slot's technique runs on radiance this frame (HDR, before the tonemapper).
    fn on_radiance(&self, slot: &Slot) -> bool {
        self.frame_tonemap().is_some() && slot.technique.tonemap_order() == TonemapOrder::Before
    }

    /// Turns geometric specular antialiasing on or off in the scene renders of every technique
    /// but the [`Slot::reference`] (see `SceneRenderer::set_specular_aa`); off by default.
    pub fn set_specular_aa(&mut self, on: bool) {
        self.specular_aa = on;
    }

    /// Image mode: `Some(image)` makes every frame's [`SceneInput::Shared1x`] input this
    /// finished image (sRGB-encoded RGBA8, the frame's size) instead of a render of the scene,
    /// so the techniques that read only that input's colour (FXAA, SMAA 1x, No AA; see
    /// `image_refusal` in `aa/`) run on any picture, e.g. another engine's capture. Its
    /// bytes are uploaded unchanged, so aa-lab's own No AA image reproduces the scene path's
    /// outputs exactly. The input's depth is not written: techniques that read depth must not
    /// run in image mode. `None` renders the scene again.
    pub fn set_image_input(&mut self, image: Option<image::RgbaImage>) {
        self.image_input = image;
    }

    /// The device.
    pub fn gpu(&self) -> &Gpu {
        &self.gpu
    }

    /// The uploaded scene.
    pub fn scene(&self) -> &SceneRenderer {
        &self.scene
    }

    /// Replaces the scene; temporal techniques must be told with `reset_history` next frame.
    pub fn set_scene(&mut self, scene: &Scene) {
        self.scene = SceneRenderer::new(&self.gpu, scene);
    }

    /// Adds a technique (enabled) and returns its index.
    pub fn add(&mut self, technique: Box<dyn Technique>) -> usize {
        self.slots.push(Slot {
            technique,
            enabled: true,
            kept: false,
            reference: false,
            output: None,
            hdr_output: None,
        });
        self.slots.len() - 1
    }

    /// The techniques in the order they were added.
    pub fn slots(&self) -> &[Slot] {
        &self.slots
    }

    /// Mutable access to the techniques (settings, enabling).
    pub fn slots_mut(&mut self) -> &mut [Slot] {
        &mut self.slots
    }

    /// The slot of a technique by id.
    pub fn slot(&self, id: &str) -> Option<&Slot> {
        self.slots.iter().find(|s| s.technique.id() == id)
    }

    /// Number of scene renders the last frame recorded (shared inputs and the techniques' own).
    pub fn scene_renders_last_frame(&self) -> usize {
        self.scene_renders
    }

    /// GPU timings of the most recent frame whose queries have come back.
    pub fn timings(&self) -> Option<&FrameTimings> {
        self.timings.as_ref()
    }

    /// Turns fragment-invocation counting on or off (see `graph::statistics`); returns whether
    /// it is on, which needs the adapter's `PIPELINE_STATISTICS_QUERY`. While on, `render`
    /// waits for each frame's counts.
    pub fn set_pipeline_statistics(&mut self, enabled: bool) -> bool {
        let enabled = enabled && self.gpu.caps.pipeline_statistics;
        self.statistics.set_enabled(enabled);
        enabled
    }

    /// Fragment-shader invocations per pass of the last frame, when counting is on and the
    /// frame's passes fitted the query set.
    pub fn pipeline_statistics(&self) -> Option<&FrameStatistics> {
        self.statistics.last()
    }

    /// How many frames' timings have come back so far: a live view reads
    /// [`FrameGraph::timings`] again when this number changes.
    pub fn timings_serial(&self) -> u64 {
        self.timings_serial
    }

    fn check_size(&self, size: (u32, u32)) -> Result<(), GraphError> {
        let limit = self.gpu.caps.max_texture_dimension_2d;
        if size.0 == 0 || size.1 == 0 {
            Err(GraphError::ZeroSize(size.0, size.1))
        } else if size.0 > limit || size.1 > limit {
            Err(GraphError::TooLarge {
                width: size.0,
                height: size.1,
                limit,
            })
        } else {
            Ok(())
        }
    }

    /// Renders one frame of the techniques in `scope` and waits for nothing: outputs are ready
    /// for readback or display once the queue has run the submission.
    pub fn render(&mut self, frame: &FrameInfo, scope: FrameScope) -> Result<(), GraphError> {
        self.render_with(frame, scope, |_, _| ())
    }

    /// [`FrameGraph::render`], with `record` called on the frame's own encoder after every
    /// technique's passes and before the single submission, with the slots (whose outputs
    /// now hold this frame). This is where readback copies go: add them to a
    /// [`crate::gpu::ReadbackBelt`], call its `finish` on the encoder and return the
    /// [`crate::gpu::readback::PendingReadback`], so the frame costs one submission and one
    /// map. `record`'s result is returned when the frame succeeds.
    pub fn render_with<T>(
        &mut self,
        frame: &FrameInfo,
        scope: FrameScope,
        record: impl FnOnce(&mut wgpu::CommandEncoder, &[Slot]) -> T,
    ) -> Result<T, GraphError> {
        let size = frame.output_size();
        self.check_size(size)?;
        if let Some(image) = &self.image_input
            && image.dimensions() != size
        {
            return Err(GraphError::ImageSize(
                image.width(),
                image.height(),
                size.0,
                size.1,
            ));
        }
        if size != self.size {
            self.input_pool.clear();
            for slot in &mut self.slots {
                slot.output = None;
                slot.hdr_output = None;
            }
            self.size = size;
        }
        let device = self.gpu.device.clone();
        let error_scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let oom_scope = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);

        let camera = frame.camera;
        self.scene.begin_frame(
            &self.gpu,
            camera.frame as f32,
            camera.frame.saturating_sub(1) as f32,
        );
        let active: Vec<usize> = (0..self.slots.len())
            .filter(|&i| {
                let slot = &self.slots[i];
                slot.enabled && (scope == FrameScope::All || slot.technique.temporal())
            })
            .collect();

        self.plan_inputs(frame, &active)?;

        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("frame"),
        });
        self.scene_renders = 0;
        self.statistics.begin_frame(&device);
        let samples = self.inputs_used.iter().map(|u| u.desc.sample_count);
        (self.overlay).prepare(&self.gpu, &self.fullscreen, size, samples.chain([1]));
        self.scene.set_specular_aa(self.specular_aa);
        self.scene.set_tonemap(self.frame_tonemap());
        self.render_inputs(&mut encoder, &camera, size);
        // 3. Every running technique's passes (after 1, plan_inputs, and 2, render_inputs).
        for &i in &active {
            let on_radiance = self.on_radiance(&self.slots[i]);
            let slot = &mut self.slots[i];
            self.scene
                .set_specular_aa(self.specular_aa && !slot.reference);
            let id = slot.technique.id();
            if !on_radiance {
                // Radiance of an earlier HDR frame is released (and leaves the memory report).
                slot.hdr_output = None;
            }
            let output = slot
                .output
                .get_or_insert_with(|| output_texture(&self.gpu, &format!("{id} output"), size));
            let hdr_output = on_radiance.then(|| {
                &*slot.hdr_output.get_or_insert_with(|| {
                    hdr::hdr_output_texture(&self.gpu, &format!("{id} hdr output"), size)
                })
            });
            let input = self.slot_inputs[i].and_then(|n| {
                let used = &self.inputs_used[n];
                self.input_pool.get(&used.desc)?.get(used.index)
            });
            let mut ctx = PassContext {
                gpu: &self.gpu,
                encoder: &mut encoder,
                frame,
                fullscreen: &self.fullscreen,
                scene: &mut self.scene,
                profiler: &self.profiler,
                technique_id: slot.technique.id(),
                scene_renders: &mut self.scene_renders,
                statistics: &mut self.statistics,
            };
            slot.technique
                .encode(&mut ctx, input, hdr_output.unwrap_or(output));
            if let Some(radiance) = hdr_output {
                self.tonemap.encode(&mut ctx, radiance, output);
            }
            // Before: techniques that read no pooled input (SSAA, the reference) or read
            // radiance (the overlay is drawn on displayed values) get it here.
            let overlaid = match self.overlay.order() {
                Some(OverlayOrder::After) => true,
                Some(OverlayOrder::Before) => input.is_none_or(|t| t.desc.hdr),
                None => false,
            };
            if overlaid {
                self.overlay.composite(&mut encoder, output, None);
            }
        }
        let recorded = record(&mut encoder, &self.slots);
        self.profiler.resolve_queries(&mut encoder);
        let statistics = self.statistics.resolve(&mut encoder);
        self.gpu.queue.submit([encoder.finish()]);
        // The profiler only fails to end a frame when scopes were left open, which the
        // closures above make impossible; a dropped frame just means no timings.
        let _ = self.profiler.end_frame();

        let oom = pollster::block_on(oom_scope.pop());
        let validation = pollster::block_on(error_scope.pop());
        if let Some(err) = oom.or(validation) {
            return Err(GraphError::Device(err.to_string()));
        }
        statistics.map_err(GraphError::Device)?;
        self.statistics.finish_frame().map_err(GraphError::Device)?;
        self.collect_timings();
        Ok(recorded)
    }

    /// Records passes outside any technique with this graph's context (`id` prefixes their
    /// labels), submits them and waits for the GPU: for tools and tests that run one pass
    /// family on images of their own, such as the upscalers' tests on analytic images.
    pub fn run_passes(
        &mut self,
        frame: &FrameInfo,
        id: &'static str,
        record: impl FnOnce(&mut PassContext<'_>),
    ) -> Result<(), GraphError> {
        let device = self.gpu.device.clone();
        let error_scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let mut encoder =
            device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(id) });
        let mut scene_renders = 0;
        let mut statistics = StatisticsRecorder::new();
        record(&mut PassContext {
            gpu: &self.gpu,
            encoder: &mut encoder,
            frame,
            fullscreen: &self.fullscreen,
            scene: &mut self.scene,
            profiler: &self.profiler,
            technique_id: id,
            scene_renders: &mut scene_renders,
            statistics: &mut statistics,
        });
        self.profiler.resolve_queries(&mut encoder);
        self.gpu.queue.submit([encoder.finish()]);
        let _ = self.profiler.end_frame();
        self.finish();
        match pollster::block_on(error_scope.pop()) {
            Some(error) => Err(GraphError::Device(error.to_string())),
            None => Ok(()),
        }
    }

    /// Step 1 of a frame (see [`FrameGraph::render_with`]): the distinct inputs of every
    /// held technique (those that run and those that keep an earlier image), each assigned a
    /// pooled target of its description, and which of them the techniques of `active` make
    /// render this frame. The pool keeps nothing else, so what it holds is what the memory
    /// report lists. An input is the render a technique asks for at the size it renders at
    /// (its render scale).
    fn plan_inputs(&mut self, frame: &FrameInfo, active: &[usize]) -> Result<(), GraphError> {
        let size = frame.output_size();
        // Per slot: its input, the size it renders at, and whether as radiance.
        type Wanted = (SceneInput, (u32, u32), bool);
        let mut wanted: Vec<Option<Wanted>> = vec![None; self.slots.len()];
        self.inputs_used.clear();
        for (i, slot) in self.slots.iter().enumerate().filter(|(_, s)| s.held()) {
            let render_size = slot.technique.render_size(frame);
            let input = slot.technique.scene_input(frame);
            let hdr = self.on_radiance(slot);
            wanted[i] = input.map(|input| (input, render_size, hdr));
            if let Some(input) = input
                && !self
                    .inputs_used
                    .iter()
                    .any(|used| used.is(input, render_size, hdr))
            {
                let desc = TargetDesc {
                    size: render_size,
                    sample_count: input.sample_count(),
                    motion: input.motion(),
                    hdr,
                    reactive_mask: input.reactive_mask(),
                };
                let index = self.inputs_used.iter().filter(|u| u.desc == desc).count();
                self.inputs_used.push(PooledInput {
                    input,
                    desc,
                    index,
                    rendered: false,
                });
            }
        }
        self.slot_inputs = wanted
            .iter()
            .map(|w| {
                w.and_then(|(input, size, hdr)| {
                    self.inputs_used.iter().position(|u| u.is(input, size, hdr))
                })
            })
            .collect();
        for &i in active {
            if let Some(n) = self.slot_inputs[i] {
                self.inputs_used[n].rendered = true;
            }
        }
        if self.image_input.is_some()
            && let Some(scaled) = self.inputs_used.iter().find(|u| u.desc.size != size)
        {
            return Err(GraphError::ImageScaled(
                scaled.desc.size.0,
                scaled.desc.size.1,
            ));
        }
        self.pool_inputs();
        Ok(())
    }

    /// Step 2 of a frame: one scene render per distinct input a running technique reads (or
    /// the image given as input, written into its target), at `size` output pixels.
    fn render_inputs(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        camera: &crate::scene::camera::FrameCamera,
        size: (u32, u32),
    ) {
        for used in self.inputs_used.iter().filter(|u| u.rendered) {
            let (input, desc, index) = (&used.input, &used.desc, &used.index);
            let targets = &self.input_pool[desc][*index];
            if let (Some(image), SceneInput::Shared1x) = (&self.image_input, input) {
                crate::gpu::write_rgba8(&self.gpu, &targets.color, image);
                self.overlay_before(encoder, targets);
                continue;
            }
            let view = camera
                .at_render_size(desc.size)
                .params(input.offset(), input.mip_bias());
            let label = used.label(size);
            let query = self.profiler.begin_pass_query(label.clone(), encoder);
            let queries = PassQueries {
                timestamp_writes: query.render_pass_timestamp_writes(),
                statistics: self.statistics.allocate(&label),
            };
            self.scene
                .render_queried(&self.gpu, encoder, targets, &view, input.raster(), queries);
            self.profiler.end_query(encoder, query);
            self.scene_renders += 1;
            self.overlay_before(encoder, targets);
        }
    }

    /// The UI overlay over a scene input of display values, when it goes before the
    /// antialiasing (a technique on radiance gets it over its tonemapped output instead).
    fn overlay_before(&self, encoder: &mut wgpu::CommandEncoder, targets: &SceneTargets) {
        if self.overlay.order() == Some(OverlayOrder::Before) && !targets.desc.hdr {
            (self.overlay).composite(encoder, &targets.color, targets.resolved.as_ref());
        }
    }

    /// Picks up timer results that have arrived (non-blocking).
    fn collect_timings(&mut self) {
        let _ = self.gpu.device.poll(wgpu::PollType::Poll);
        let period = self.gpu.queue.get_timestamp_period();
        while let Some(results) = self.profiler.process_finished_frame(period) {
            self.timings = Some(FrameTimings::from_profiler(&results));
            self.timings_serial += 1;
        }
    }

    /// Waits for the GPU and collects the timings of everything submitted so far.
    pub fn finish(&mut self) {
        self.gpu.wait_idle();
        self.collect_timings();
    }

    /// Grows the pool to every input of `inputs_used` and releases the targets no held
    /// technique reads (a technique switched off, a sample count no longer asked for).
    fn pool_inputs(&mut self) {
        for used in &self.inputs_used {
            let pool = self.input_pool.entry(used.desc).or_default();
            while pool.len() <= used.index {
                pool.push(SceneTargets::new(
                    &self.gpu,
                    &used.label(self.size),
                    used.desc,
                ));
            }
        }
        let inputs_used = &self.inputs_used;
        self.input_pool.retain(|desc, pool| {
            pool.truncate(inputs_used.iter().filter(|u| u.desc == *desc).count());
            !pool.is_empty()
        });
    }

    /// Bytes of every scene-input target the graph holds (what the memory report counts as
    /// inputs, each once).
    pub fn pooled_input_bytes(&self) -> u64 {
        self.input_pool
            .values()
            .flatten()
            .flat_map(SceneTargets::textures)
            .map(|(_, texture)| gpu::texture_bytes(texture))
            .sum()
    }

    /// Scene inputs the held techniques read in the last frame, with the ids of their readers
    /// and, when `rendered_only`, only those rendered in it.
    fn input_users(
        &self,
        rendered_only: bool,
    ) -> Vec<(SceneInput, String, Vec<&'static str>, &SceneTargets)> {
        self.inputs_used
            .iter()
            .enumerate()
            .filter(|(_, used)| used.rendered || !rendered_only)
            .filter_map(|(n, used)| {
                let input = &used.input;
                let targets = self.input_pool.get(&used.desc)?.get(used.index)?;
                let users = self
                    .slots
                    .iter()
                    .zip(&self.slot_inputs)
                    .filter(|(_, used)| **used == Some(n))
                    .map(|(slot, _)| slot.technique.id())
                    .collect();
                Some((*input, used.label(self.size), users, targets))
            })
            .collect()
    }

    /// The distinct scene inputs of the last frame, in the order they were rendered (the order
    /// of their passes among the frame's non-technique passes in timings and statistics), each
    /// with the ids of the techniques that read it.
    pub fn scene_inputs_last_frame(&self) -> Vec<(SceneInput, Vec<&'static str>)> {
        self.input_users(true)
            .into_iter()
            .map(|(input, _, users, _)| (input, users))
            .collect()
    }

    /// The memory report of the last frame: every held technique's private resources and
    /// output, the scene inputs it reads (shared ones counted once in the total), the scene
    /// itself, and what switched-off techniques still hold.
    pub fn memory_report(&self) -> MemoryReport {
        let inputs: Vec<_> = self
            .input_users(false)
            .into_iter()
            .map(|(_, label, users, targets)| (label, users, targets))
            .collect();
        let scene_bytes = self.scene.memory_bytes() + self.overlay.memory_bytes();
        MemoryReport::build(&self.slots, &inputs, scene_bytes)
    }
}
