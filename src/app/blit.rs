//! How technique images reach the screen: [`DisplayTexture`]s on eframe's device, drawn by a
//! paint callback ([`paint`]) that loads exactly one texel per screen pixel (nearest
//! neighbour), instead of egui's own image path.
//!
//! Why not egui's textured rectangles: egui's shader interpolates a vertex colour, samples
//! through a sampler, multiplies and blends, which is cheap on a GPU but not on a software
//! rasteriser. Measured on lavapipe with egui_kittest (a 1280x720 image filling a 1900x1000
//! window): 47.5 ms per paint through egui's image path against 10.5 ms through this callback,
//! of which ~8 ms is the harness's fixed cost (readback of the window). A viewer that shows four
//! technique images and a magnifier paints that many pixels every frame, so the paint decided
//! the UI's frame time on software adapters; on a GPU both paths cost nothing measurable.
//!
//! The callback maps each framebuffer pixel to a texel from the image's placement on screen
//! (rectangle in physical pixels and the UV rectangle shown), so crops (magnifier), cropped
//! tiles and wipes (egui's clip rectangle becomes the scissor) draw exact pixels. Texels hold
//! sRGB-encoded bytes: on egui's usual non-sRGB framebuffer they are copied unchanged through
//! an `Rgba8Unorm` view; on an sRGB framebuffer an sRGB view decodes them and the target
//! encodes them again, so the screen shows the same bytes either way.

use std::collections::HashMap;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use egui::Rect;
use wgpu::util::DeviceExt;

// The pipeline draws into egui's render pass, which has one sample unless eframe multisamples.
const _: () = assert!(
    matches!(super::EGUI_MULTISAMPLING, 0 | 1),
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
}

impl Uploader {
    /// The uploader for eframe's render state.
    pub fn new(state: &egui_wgpu::RenderState) -> Self {
        Self {
            device: state.device.clone(),
            queue: state.queue.clone(),
            srgb_target: state.target_format.is_srgb(),
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
        Arc::new(DisplayTexture::new(texture, format))
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
}

impl Placement {
    fn key(&self) -> [u32; 8] {
        bytemuck::cast(*self)
    }
}

type BindKey = (u64, [u32; 8]);

/// The pipeline and the bind groups of the images drawn lately (in egui's callback resources).
struct Resources {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    bindings: HashMap<BindKey, (wgpu::BindGroup, u64)>,
    frame: u64,
}

/// Creates the pipeline in eframe's renderer; [`paint`] draws nothing until this ran.
pub fn install(state: &egui_wgpu::RenderState) {
    let device = &state.device;
    let module = crate::gpu::shader::module(device, "viewer_blit.wgsl");
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("display blit"),
        entries: &[
            wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 1,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            },
        ],
    });
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("display blit"),
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("display blit"),
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
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: None,
        // egui's render pass is single-sampled (see the assertion below).
        multisample: wgpu::MultisampleState::default(),
        multiview_mask: None,
        cache: None,
    });
    state.renderer.write().callback_resources.insert(Resources {
        pipeline,
        layout,
        bindings: HashMap::new(),
        frame: 0,
    });
}

/// One image drawn by the callback.
struct Blit {
    texture: Arc<DisplayTexture>,
    placement: Placement,
    frame: u64,
}

impl Blit {
    fn key(&self) -> BindKey {
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
        let Some(resources) = resources.get_mut::<Resources>() else {
            return Vec::new();
        };
        if self.frame != resources.frame {
            resources.frame = self.frame;
            let oldest = self.frame.saturating_sub(KEEP_FRAMES);
            resources.bindings.retain(|_, (_, used)| *used >= oldest);
        }
        let layout = &resources.layout;
        let entry = resources.bindings.entry(self.key()).or_insert_with(|| {
            let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("display placement"),
                contents: bytemuck::bytes_of(&self.placement),
                usage: wgpu::BufferUsages::UNIFORM,
            });
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
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
            });
            (group, self.frame)
        });
        entry.1 = self.frame;
        Vec::new()
    }

    fn paint(
        &self,
        _info: egui::PaintCallbackInfo,
        pass: &mut wgpu::RenderPass<'static>,
        resources: &egui_wgpu::CallbackResources,
    ) {
        let Some(resources) = resources.get::<Resources>() else {
            return;
        };
        let Some((group, _)) = resources.bindings.get(&self.key()) else {
            return;
        };
        pass.set_pipeline(&resources.pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.draw(0..3, 0..1);
    }
}

/// Draws the `uv` part of `texture` into `rect` (points) with `painter`'s clip rectangle,
/// nearest-neighbour, exactly the texture's bytes.
pub fn paint(painter: &egui::Painter, texture: &Arc<DisplayTexture>, rect: Rect, uv: Rect) {
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
