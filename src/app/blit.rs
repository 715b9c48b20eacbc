//! How technique images reach the screen: [`DisplayTexture`]s on eframe's device, drawn by a
//! paint callback ([`paint`]) that loads exactly one texel per screen pixel (nearest
//! neighbour), instead of egui's own image path.
//!
//! Why not egui's textured rectangles: egui's shader interpolates a vertex colour, samples
//! through a sampler, multiplies and blends, which is cheap on a GPU but not on a software
//! rasteriser, where a full-window image cost several times as much through egui's image path
//! as through this callback (figures: `docs/viewer.md`). A viewer that shows four technique
//! images and a magnifier paints that many pixels every frame, so the paint decided the UI's
//! frame time on software adapters; on a GPU both paths cost nothing measurable.
//!
//! The callback maps each framebuffer pixel to a texel from the image's placement on screen
//! (rectangle in physical pixels and the UV rectangle shown), so crops (magnifier), cropped
//! tiles and wipes (egui's clip rectangle becomes the scissor) draw exact pixels. Texels hold
//! sRGB-encoded bytes: on egui's usual non-sRGB framebuffer they are copied unchanged through
//! an `Rgba8Unorm` view; on an sRGB framebuffer an sRGB view decodes them and the target
//! encodes them again, so the screen shows the same bytes either way.

use std::collections::HashMap;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use egui::Rect;
use wgpu::util::DeviceExt;

/// egui's own multisampling, which the window is created with. Off: egui feathers its shapes
/// itself, technique images are drawn as textured rectangles that multisampling would not
/// change, and counts other than the adapter's supported ones panic (8 on lavapipe).
pub(super) const EGUI_MULTISAMPLING: u16 = 0;

// The pipeline draws into egui's render pass, which has one sample unless eframe multisamples.
const _: () = assert!(
    matches!(EGUI_MULTISAMPLING, 0 | 1),
    "the blit pipeline is single-sampled"
);

/// Frames a cached bind group survives without being drawn.
const KEEP_FRAMES: u64 = 2;

/// An image on eframe's device, ready for [`paint`].
pub struct DisplayTexture {
    texture: wgpu::Texture,
    view: wgpu::TextureView,
    key: u64,
}

impl DisplayTexture {
    fn new(texture: wgpu::Texture, view_format: wgpu::TextureFormat) -> Self {
        static NEXT_KEY: AtomicU64 = AtomicU64::new(1);
        let view = texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some("display view"),
            format: Some(view_format),
            ..Default::default()
        });
        Self {
            texture,
            view,
            key: NEXT_KEY.fetch_add(1, Ordering::Relaxed),
        }
    }

    /// Size in pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.texture.width(), self.texture.height())
    }
}

/// Makes [`DisplayTexture`]s on eframe's device: from pixels (uploads, from any thread) or from
/// a technique's output texture on the same device (no copy).
#[derive(Clone)]
pub struct Uploader {
    device: wgpu::Device,
    queue: wgpu::Queue,
    srgb_target: bool,
    /// Uploads were made since the last [`Uploader::flush`] (shared by the clones).
    unflushed: Arc<AtomicBool>,
}

impl Uploader {
    /// The uploader for eframe's render state.
    pub fn new(state: &egui_wgpu::RenderState) -> Self {
        Self {
            device: state.device.clone(),
            queue: state.queue.clone(),
            srgb_target: state.target_format.is_srgb(),
            unflushed: Arc::new(AtomicBool::new(false)),
        }
    }

    /// A new texture holding `pixels` (sRGB-encoded RGBA8).
    pub fn upload(&self, pixels: &image::RgbaImage) -> Arc<DisplayTexture> {
        let format = if self.srgb_target {
            wgpu::TextureFormat::Rgba8UnormSrgb
        } else {
            wgpu::TextureFormat::Rgba8Unorm
        };
        let texture = self.device.create_texture_with_data(
            &self.queue,
            &wgpu::TextureDescriptor {
                label: Some("display image"),
                size: wgpu::Extent3d {
                    width: pixels.width(),
                    height: pixels.height(),
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            pixels.as_raw(),
        );
        self.unflushed.store(true, Ordering::Release);
        Arc::new(DisplayTexture::new(texture, format))
    }

    /// Starts the copies of the uploads made so far on the display queue now, from the calling
    /// thread, where there are any (the zero-copy display makes none). Left alone, they wait
    /// for the window's next paint, whose submit carries them and waits for them, which made
    /// that paint far slower on lavapipe (figures: `docs/viewer.md`).
    pub fn flush(&self) {
        if self.unflushed.swap(false, Ordering::AcqRel) {
            self.queue.submit(std::iter::empty());
        }
    }

    /// `texture` (an sRGB output that can be viewed as `Rgba8Unorm`) as it is.
    pub fn wrap(&self, texture: wgpu::Texture) -> Arc<DisplayTexture> {
        let format = if self.srgb_target {
            wgpu::TextureFormat::Rgba8UnormSrgb
        } else {
            wgpu::TextureFormat::Rgba8Unorm
        };
        Arc::new(DisplayTexture::new(texture, format))
    }
}

/// Where an image goes: the screen rectangle in physical pixels and the UV rectangle shown.
#[repr(C)]
#[derive(Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
struct Placement {
    rect_min: [f32; 2],
    rect_size: [f32; 2],
    uv_min: [f32; 2],
    uv_size: [f32; 2],
    /// Darkening of the pixel grid's lines (0: no grid).
    grid: f32,
    _pad: [f32; 3],
}

impl Placement {
    fn key(&self) -> [u32; 12] {
        bytemuck::cast(*self)
    }
}

type ImageKey = (u64, [u32; 12]);

/// A pipeline and the bind groups of what it drew lately.
struct Pass<K> {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    bindings: HashMap<K, (wgpu::BindGroup, u64)>,
}

impl<K: std::hash::Hash + Eq> Pass<K> {
    fn new(
        state: &egui_wgpu::RenderState,
        shader: &str,
        entries: &[wgpu::BindGroupLayoutEntry],
        blend: Option<wgpu::BlendState>,
    ) -> Self {
        let device = &state.device;
        let module = crate::gpu::shader::module(device, shader);
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(shader),
            entries,
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(shader),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(shader),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: state.target_format,
                    blend,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            // egui's render pass is single-sampled (see the assertion at the top).
            multisample: wgpu::MultisampleState::default(),
            multiview_mask: None,
            cache: None,
        });
        Self {
            pipeline,
            layout,
            bindings: HashMap::new(),
        }
    }

    /// Makes sure the bind group of `key` exists (created by `create` if not) and marks it
    /// used in `frame`.
    fn prepare(
        &mut self,
        key: K,
        frame: u64,
        create: impl FnOnce(&wgpu::BindGroupLayout) -> wgpu::BindGroup,
    ) {
        let layout = &self.layout;
        let entry = self
            .bindings
            .entry(key)
            .or_insert_with(|| (create(layout), frame));
        entry.1 = frame;
    }

    /// Draws the viewport-filling triangle with the bind group of `key`.
    fn draw(&self, key: &K, pass: &mut wgpu::RenderPass<'static>) {
        if let Some((group, _)) = self.bindings.get(key) {
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, group, &[]);
            pass.draw(0..3, 0..1);
        }
    }

    /// Drops the bind groups not used since `oldest`.
    fn evict(&mut self, oldest: u64) {
        self.bindings.retain(|_, (_, used)| *used >= oldest);
    }
}

/// The passes (in egui's callback resources) and the frame they last drew.
struct Resources {
    images: Pass<ImageKey>,
    /// Opaque fills, and translucent ones blended over what is under them ([`fill_pass`]).
    fills: [Pass<[u8; 4]>; 2],
    /// The framebuffer encodes to sRGB itself (fill colours are written linear then).
    srgb_target: bool,
    frame: u64,
}

impl Resources {
    /// Starts `frame`: bind groups unused for a while go.
    fn begin(&mut self, frame: u64) {
        if frame != self.frame {
            self.frame = frame;
            let oldest = frame.saturating_sub(KEEP_FRAMES);
            self.images.evict(oldest);
            self.fills.iter_mut().for_each(|pass| pass.evict(oldest));
        }
    }
}

fn uniform_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

fn uniform_buffer(device: &wgpu::Device, contents: &[u8]) -> wgpu::Buffer {
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("display uniform"),
        contents,
        usage: wgpu::BufferUsages::UNIFORM,
    })
}

/// Creates the pipelines in eframe's renderer; [`paint`] and [`fill`] draw nothing until this
/// ran.
pub fn install(state: &egui_wgpu::RenderState) {
    let texture = wgpu::BindGroupLayoutEntry {
        binding: 0,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: false },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    };
    let resources = Resources {
        images: Pass::new(
            state,
            "viewer_blit.wgsl",
            &[texture, uniform_entry(1)],
            None,
        ),
        // egui's framebuffer holds premultiplied alpha, as `Color32` does.
        fills: [None, Some(wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING)]
            .map(|blend| Pass::new(state, "viewer_fill.wgsl", &[uniform_entry(0)], blend)),
        srgb_target: state.target_format.is_srgb(),
        frame: 0,
    };
    state.renderer.write().callback_resources.insert(resources);
}

/// One image drawn by the callback.
struct Blit {
    texture: Arc<DisplayTexture>,
    placement: Placement,
    frame: u64,
}

impl Blit {
    fn key(&self) -> ImageKey {
        (self.texture.key, self.placement.key())
    }
}

impl egui_wgpu::CallbackTrait for Blit {
    fn prepare(
        &self,
        device: &wgpu::Device,
        _queue: &wgpu::Queue,
        _screen: &egui_wgpu::ScreenDescriptor,
        _encoder: &mut wgpu::CommandEncoder,
        resources: &mut egui_wgpu::CallbackResources,
    ) -> Vec<wgpu::CommandBuffer> {
        if let Some(resources) = resources.get_mut::<Resources>() {
            resources.begin(self.frame);
            resources.images.prepare(self.key(), self.frame, |layout| {
                let buffer = uniform_buffer(device, bytemuck::bytes_of(&self.placement));
                device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("display image"),
                    layout,
                    entries: &[
                        wgpu::BindGroupEntry {
                            binding: 0,
                            resource: wgpu::BindingResource::TextureView(&self.texture.view),
                        },
                        wgpu::BindGroupEntry {
                            binding: 1,
                            resource: buffer.as_entire_binding(),
                        },
                    ],
                })
            });
        }
        Vec::new()
    }

    fn paint(
        &self,
        _info: egui::PaintCallbackInfo,
        pass: &mut wgpu::RenderPass<'static>,
        resources: &egui_wgpu::CallbackResources,
    ) {
        if let Some(resources) = resources.get::<Resources>() {
            resources.images.draw(&self.key(), pass);
        }
    }
}

/// One solid rectangle drawn by the callback.
struct Fill {
    color: egui::Color32,
    frame: u64,
}

/// Which of [`Resources::fills`] draws `color`: translucent colours blend.
fn fill_pass(color: egui::Color32) -> usize {
    usize::from(!color.is_opaque())
}

impl egui_wgpu::CallbackTrait for Fill {
    fn prepare(
        &self,
        device: &wgpu::Device,
        _queue: &wgpu::Queue,
        _screen: &egui_wgpu::ScreenDescriptor,
        _encoder: &mut wgpu::CommandEncoder,
        resources: &mut egui_wgpu::CallbackResources,
    ) -> Vec<wgpu::CommandBuffer> {
        if let Some(resources) = resources.get_mut::<Resources>() {
            resources.begin(self.frame);
            let srgb_target = resources.srgb_target;
            resources.fills[fill_pass(self.color)].prepare(
                self.color.to_array(),
                self.frame,
                |layout| {
                    // The colour as the framebuffer takes it: encoded bytes on a linear target
                    // (egui's convention), linear light on an sRGB one; premultiplied.
                    let channel = |c: u8| {
                        if srgb_target {
                            egui::ecolor::linear_f32_from_gamma_u8(c)
                        } else {
                            f32::from(c) / 255.0
                        }
                    };
                    let [r, g, b, a] = self.color.to_array();
                    let color = [channel(r), channel(g), channel(b), f32::from(a) / 255.0];
                    let buffer = uniform_buffer(device, bytemuck::bytes_of(&color));
                    device.create_bind_group(&wgpu::BindGroupDescriptor {
                        label: Some("display fill"),
                        layout,
                        entries: &[wgpu::BindGroupEntry {
                            binding: 0,
                            resource: buffer.as_entire_binding(),
                        }],
                    })
                },
            );
        }
        Vec::new()
    }

    fn paint(
        &self,
        _info: egui::PaintCallbackInfo,
        pass: &mut wgpu::RenderPass<'static>,
        resources: &egui_wgpu::CallbackResources,
    ) {
        if let Some(resources) = resources.get::<Resources>() {
            resources.fills[fill_pass(self.color)].draw(&self.color.to_array(), pass);
        }
    }
}

/// Fills `rect` (points, within `painter`'s clip rectangle) with `color`, without egui's
/// per-pixel texture sampling: for the large backgrounds of the window, and (translucent,
/// blended) for dimming it under an overlay.
pub fn fill(painter: &egui::Painter, rect: Rect, color: egui::Color32) {
    let shown = rect.intersect(painter.clip_rect());
    if shown.is_positive() {
        painter.add(fill_shape(painter.ctx(), shown, color));
    }
}

/// The shape [`fill`] adds, for a place reserved in a painter before the rectangle was known.
pub fn fill_shape(ctx: &egui::Context, rect: Rect, color: egui::Color32) -> egui::Shape {
    let fill = Fill {
        color,
        frame: ctx.cumulative_frame_nr(),
    };
    egui_wgpu::Callback::new_paint_callback(rect, fill).into()
}

/// Draws the `uv` part of `texture` into `rect` (points) with `painter`'s clip rectangle,
/// nearest-neighbour, exactly the texture's bytes.
pub fn paint(painter: &egui::Painter, texture: &Arc<DisplayTexture>, rect: Rect, uv: Rect) {
    paint_placed(painter, texture, rect, uv, 0.0);
}

/// [`paint`] with a pixel grid: the first screen row and column of every texel after the
/// first darkened by `darken` (0..1), for magnified views. Drawn by the same pass: as egui
/// lines, the grid of a large lens was a large part of a frame on a software rasteriser.
pub fn paint_with_grid(
    painter: &egui::Painter,
    texture: &Arc<DisplayTexture>,
    rect: Rect,
    uv: Rect,
    darken: f32,
) {
    paint_placed(painter, texture, rect, uv, darken.clamp(0.0, 1.0));
}

fn paint_placed(
    painter: &egui::Painter,
    texture: &Arc<DisplayTexture>,
    rect: Rect,
    uv: Rect,
    grid: f32,
) {
    let shown = rect.intersect(painter.clip_rect());
    if !shown.is_positive() {
        return;
    }
    let ppp = painter.pixels_per_point();
    let placement = Placement {
        rect_min: (rect.min.to_vec2() * ppp).into(),
        rect_size: (rect.size() * ppp).into(),
        uv_min: uv.min.to_vec2().into(),
        uv_size: uv.size().into(),
        grid,
        _pad: [0.0; 3],
    };
    let blit = Blit {
        texture: Arc::clone(texture),
        placement,
        frame: painter.ctx().cumulative_frame_nr(),
    };
    // The callback's rectangle is only the part on screen: egui clamps it to the screen
    // and makes it the viewport, and the placement maps pixels wherever they are.
    painter.add(egui_wgpu::Callback::new_paint_callback(shown, blit));
}
