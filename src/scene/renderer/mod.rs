//! The forward scene renderer: uploads a [`Scene`] once and draws it into [`SceneTargets`]
//! of any sample count, with any projection jitter, optionally writing motion vectors.
//!
//! Everything a technique may want from the scene render is chosen per call through
//! [`RasterOptions`] (sample-rate shading, centroid texture coordinates, alpha-to-coverage) and
//! [`ViewParams`] (jitter, tile, mip bias). Pipelines are built on first use and cached by
//! [`PipelineKey`]. Per-call view uniforms live in a ring of dynamic-offset slots so that many
//! renders (supersampling tiles, accumulation passes) can be recorded into one encoder.
//!
//! Materials are sampled as their [`TextureSampler`] says (trilinearly, repeating, unless a
//! glTF sampler asks otherwise). Where every filter is linear and mipmapped
//! ([`filtered_anisotropically`]) the scene shader filters anisotropically itself, with up to
//! eight trilinear probes along the major axis of the pixel's footprint (`sample_base_color`
//! in `shaders/scene.wgsl`; after the multi-probe schemes of Schilling et al.'s Texram, 1996,
//! McCormack et al.'s Feline, 1999, and Mavridis and Papaioannou, "High quality elliptical
//! texture filtering on GPU", 2011), and the samplers' hardware anisotropy is off on every
//! adapter. Two reasons. Quality figures must not depend on the adapter: a GPU's hardware
//! filter (8x) and a software rasteriser's differ, and Mesa's llvmpipe (lavapipe) cannot be
//! given one at all: it filters anisotropically by scanning every texel of the footprint
//! ellipse's bounding box, with no bound from the anisotropy clamp or the texture size, and
//! where a quad's texture-coordinate derivatives are extreme (sliver triangles seen edge-on,
//! whose helper lanes extrapolate the coordinates far out, as in the hairball's sub-pixel
//! tubes) that box spans millions of texels per axis and one fragment never finishes. The
//! shader's filter is bounded by its probe count, so every adapter runs the same one and a
//! software render predicts a GPU's, up to filtering precision. The price on a GPU is up to
//! eight texture lookups where its hardware filter took one instruction (docs/gpu-figures.md).
//!
//! Alpha-blended materials are drawn last, back to front, by a second set of pipelines
//! (premultiplied alpha, depth test without depth or motion writes; see [`blend`] for the
//! order and its limits). A target description can ask for a reactive mask
//! ([`TargetDesc::reactive_mask`]): an extra single-channel target into which blended surfaces
//! write how much they cover each pixel (their alphas composited over one another), for
//! temporal techniques to trust their history less there. Without blended materials, or
//! without the mask, the pipelines and draws are those of a renderer without either.

use std::collections::HashMap;

use glam::{Mat4, Vec3, Vec4};
use wgpu::util::DeviceExt;

use super::camera::ViewParams;
use super::{Filter, Scene, TextureImage, TextureSampler, Vertex, Wrap};
use crate::gpu::{self, COLOR_FORMAT, DEPTH_FORMAT, Gpu, MOTION_FORMAT};
use crate::srgb;

mod blend;
mod materials;
mod output;
mod pipeline;
mod textures;

pub use output::{SceneOutput, Tonemap, Tonemapper};
pub use pipeline::PipelineKey;

use materials::{GpuMaterial, upload_materials};
pub use textures::{downsample_srgb, filtered_anisotropically, mip_level_count};

/// Where varyings are evaluated inside a multisampled pixel.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
pub enum ShadingRate {
    /// Once per pixel at the pixel centre (ordinary MSAA).
    #[default]
    Pixel,
    /// Once per pixel, texture coordinates at the centroid of the covered samples.
    Centroid,
    /// Once per covered sample (sample-rate shading: MSAA becomes SSAA).
    Sample,
}

/// Rasterisation choices of one scene render.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct RasterOptions {
    /// Where varyings are evaluated.
    pub shading: ShadingRate,
    /// Alpha-masked materials drive sample coverage instead of discarding (only meaningful with
    /// more than one sample).
    pub alpha_to_coverage: bool,
}

/// What the render targets of a scene render hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TargetDesc {
    /// Width and height in pixels (never zero).
    pub size: (u32, u32),
    /// Samples per pixel.
    pub sample_count: u32,
    /// Whether a motion-vector target is written.
    pub motion: bool,
    /// Whether the colour holds linear radiance in [`gpu::HDR_FORMAT`] (an HDR render for a
    /// technique before the tonemapper) instead of display values in [`COLOR_FORMAT`].
    pub hdr: bool,
    /// Whether a reactive-mask target is written ([`REACTIVE_FORMAT`]: the coverage of
    /// alpha-blended surfaces, 0 where there are none).
    pub reactive_mask: bool,
}

/// Format of the reactive mask: one linear channel.
pub const REACTIVE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R8Unorm;

/// Render targets of one scene render: colour, depth and optional motion, each with
/// `sample_count` samples, plus a single-sample resolve of the colour when multisampled.
#[derive(Debug)]
pub struct SceneTargets {
    /// What the targets were created for.
    pub desc: TargetDesc,
    /// Colour, `sample_count` samples (sRGB format, encoded-view compatible; half floats when
    /// `desc.hdr`).
    pub color: wgpu::Texture,
    /// Single-sample resolve of `color` (only when multisampled).
    pub resolved: Option<wgpu::Texture>,
    /// Depth (reverse-Z), `sample_count` samples.
    pub depth: wgpu::Texture,
    /// Motion vectors in UV units (previous to current position), when requested.
    pub motion: Option<wgpu::Texture>,
    /// The reactive mask, when requested.
    pub reactive: Option<wgpu::Texture>,
}

fn target_texture(
    gpu: &Gpu,
    label: &str,
    desc: &TargetDesc,
    sample_count: u32,
    format: wgpu::TextureFormat,
) -> wgpu::Texture {
    let view_formats = if format == COLOR_FORMAT {
        gpu::encoded_view_formats(&gpu.caps)
    } else {
        &[]
    };
    let usage = wgpu::TextureUsages::RENDER_ATTACHMENT
        | wgpu::TextureUsages::TEXTURE_BINDING
        | if sample_count == 1 {
            // COPY_DST: image mode uploads a finished image into the 1x colour target.
            wgpu::TextureUsages::COPY_SRC | wgpu::TextureUsages::COPY_DST
        } else {
            wgpu::TextureUsages::empty()
        };
    crate::gpu::texture_2d(
        &gpu.device,
        &crate::gpu::Texture2d {
            sample_count,
            view_formats,
            ..crate::gpu::Texture2d::new(label, desc.size, format, usage)
        },
    )
}

impl SceneTargets {
    /// Creates targets; `label` prefixes every texture label.
    pub fn new(gpu: &Gpu, label: &str, desc: TargetDesc) -> Self {
        let n = desc.sample_count;
        let color_format = if desc.hdr {
            gpu::HDR_FORMAT
        } else {
            COLOR_FORMAT
        };
        Self {
            desc,
            color: target_texture(gpu, &format!("{label} color"), &desc, n, color_format),
            resolved: (n > 1)
                .then(|| target_texture(gpu, &format!("{label} resolved"), &desc, 1, color_format)),
            depth: target_texture(gpu, &format!("{label} depth"), &desc, n, DEPTH_FORMAT),
            motion: desc
                .motion
                .then(|| target_texture(gpu, &format!("{label} motion"), &desc, n, MOTION_FORMAT)),
            reactive: desc.reactive_mask.then(|| {
                target_texture(gpu, &format!("{label} reactive"), &desc, n, REACTIVE_FORMAT)
            }),
        }
    }

    /// The single-sample colour image (the resolve when multisampled).
    pub fn color_1x(&self) -> &wgpu::Texture {
        self.resolved.as_ref().unwrap_or(&self.color)
    }

    /// Every texture with a short name (`color`, `resolve`, `depth`, `motion`, `reactive`), for memory
    /// reports.
    pub fn textures(&self) -> Vec<(&'static str, &wgpu::Texture)> {
        [
            Some(("color", &self.color)),
            self.resolved.as_ref().map(|t| ("resolve", t)),
            Some(("depth", &self.depth)),
            self.motion.as_ref().map(|t| ("motion", t)),
            self.reactive.as_ref().map(|t| ("reactive", t)),
        ]
        .into_iter()
        .flatten()
        .collect()
    }
}

/// Queries recorded around one scene render pass.
#[derive(Default)]
pub struct PassQueries<'a> {
    /// Timestamps at the pass's start and end (per-pass GPU time).
    pub timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'a>>,
    /// A pipeline-statistics query set and the index to record into.
    pub statistics: Option<(&'a wgpu::QuerySet, u32)>,
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ViewUniform {
    view_proj: [[f32; 4]; 4],
    unjittered_view_proj: [[f32; 4]; 4],
    prev_view_proj: [[f32; 4]; 4],
    eye: [f32; 4],
    light_direction: [f32; 4],
    light_color: [f32; 4],
    ambient: [f32; 4],
    params: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ObjectUniform {
    model: [[f32; 4]; 4],
    prev_model: [[f32; 4]; 4],
    normal_matrix: [[f32; 4]; 4],
}

/// Stride of the view-uniform ring: one whole `ViewUniform` rounded up to the largest
/// dynamic-offset alignment wgpu may demand (256), so that no slot overlaps the next.
const UNIFORM_SLOT: u64 = (std::mem::size_of::<ViewUniform>() as u64).next_multiple_of(256);

struct Draw {
    first_index: u32,
    index_count: u32,
    base_vertex: i32,
    material: usize,
    object: usize,
}

/// A scene uploaded to the GPU, with its pipelines.
pub struct SceneRenderer {
    vertex_buffer: wgpu::Buffer,
    index_buffer: wgpu::Buffer,
    draws: Vec<Draw>,
    blended: blend::BlendOrder,
    materials: Vec<GpuMaterial>,
    object_buffer: wgpu::Buffer,
    object_bind_group: wgpu::BindGroup,
    object_transforms: Vec<Option<super::Spin>>,
    view_layout: wgpu::BindGroupLayout,
    view_ring: Option<(wgpu::Buffer, wgpu::BindGroup, u64)>,
    next_view_slot: u64,
    pipeline_layout: wgpu::PipelineLayout,
    shader: wgpu::ShaderModule,
    pipelines: HashMap<PipelineKey, wgpu::RenderPipeline>,
    light: super::DirectionalLight,
    clear_color: Vec3,
    specular_aa: bool,
    tonemap: Option<Tonemap>,
    triangles: usize,
    bytes: u64,
}

fn mat(m: Mat4) -> [[f32; 4]; 4] {
    m.to_cols_array_2d()
}

fn uniform_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
    dynamic: bool,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: dynamic,
            min_binding_size: None,
        },
        count: None,
    }
}

/// The scene's meshes in one vertex and one index buffer, with a draw per mesh.
struct Geometry {
    vertex_buffer: wgpu::Buffer,
    index_buffer: wgpu::Buffer,
    draws: Vec<Draw>,
    bytes: u64,
}

impl Geometry {
    /// Concatenates every non-empty mesh of `scene` and uploads it.
    fn upload(device: &wgpu::Device, scene: &Scene) -> Self {
        let mut vertices: Vec<Vertex> = Vec::with_capacity(scene.vertex_count());
        let mut indices: Vec<u32> = Vec::with_capacity(scene.triangle_count() * 3);
        let mut draws = Vec::with_capacity(scene.meshes.len());
        for (object, mesh) in scene.meshes.iter().enumerate() {
            if mesh.indices.is_empty() {
                continue;
            }
            draws.push(Draw {
                first_index: indices.len() as u32,
                index_count: mesh.indices.len() as u32,
                base_vertex: vertices.len() as i32,
                material: mesh.material.min(scene.materials.len().saturating_sub(1)),
                object,
            });
            vertices.extend_from_slice(&mesh.vertices);
            indices.extend_from_slice(&mesh.indices);
        }
        // wgpu refuses zero-sized vertex buffers; an empty scene still clears its targets.
        let vertex_bytes: &[u8] = if vertices.is_empty() {
            &[0; 32]
        } else {
            bytemuck::cast_slice(&vertices)
        };
        let index_bytes: &[u8] = if indices.is_empty() {
            &[0; 4]
        } else {
            bytemuck::cast_slice(&indices)
        };
        let vertex_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("scene vertices"),
            contents: vertex_bytes,
            usage: wgpu::BufferUsages::VERTEX,
        });
        let index_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("scene indices"),
            contents: index_bytes,
            usage: wgpu::BufferUsages::INDEX,
        });
        Self {
            vertex_buffer,
            index_buffer,
            draws,
            bytes: vertex_bytes.len() as u64 + index_bytes.len() as u64,
        }
    }
}

/// The scene pipeline's bind group layouts: the view (per pass), the material, the object.
struct Layouts {
    view: wgpu::BindGroupLayout,
    material: wgpu::BindGroupLayout,
    object: wgpu::BindGroupLayout,
}

impl Layouts {
    fn new(device: &wgpu::Device) -> Self {
        let view = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("scene view"),
            entries: &[uniform_entry(0, wgpu::ShaderStages::VERTEX_FRAGMENT, true)],
        });
        let material = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("scene material"),
            entries: &[
                uniform_entry(0, wgpu::ShaderStages::FRAGMENT, false),
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            ],
        });
        let object = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("scene object"),
            entries: &[uniform_entry(0, wgpu::ShaderStages::VERTEX, true)],
        });
        Self {
            view,
            material,
            object,
        }
    }
}

impl SceneRenderer {
    /// Uploads `scene`: geometry, textures with full mip chains, materials.
    pub fn new(gpu: &Gpu, scene: &Scene) -> Self {
        let device = &gpu.device;
        let geometry = Geometry::upload(device, scene);
        let layouts = Layouts::new(device);
        let (materials, texture_bytes) = upload_materials(gpu, scene, &layouts.material);
        let object_count = scene.meshes.len().max(1) as u64;
        let object_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("scene objects"),
            size: object_count * UNIFORM_SLOT,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let object_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("scene objects"),
            layout: &layouts.object,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: &object_buffer,
                    offset: 0,
                    size: wgpu::BufferSize::new(std::mem::size_of::<ObjectUniform>() as u64),
                }),
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("scene"),
            bind_group_layouts: &[
                Some(&layouts.view),
                Some(&layouts.material),
                Some(&layouts.object),
            ],
            immediate_size: 0,
        });
        let renderer = Self {
            blended: blend::BlendOrder::new(scene, &geometry.draws),
            vertex_buffer: geometry.vertex_buffer,
            index_buffer: geometry.index_buffer,
            draws: geometry.draws,
            materials,
            object_buffer,
            object_bind_group,
            object_transforms: scene.meshes.iter().map(|m| m.spin).collect(),
            view_layout: layouts.view,
            view_ring: None,
            next_view_slot: 0,
            pipeline_layout,
            shader: gpu::shader::module(device, "scene.wgsl"),
            pipelines: HashMap::new(),
            light: scene.light,
            clear_color: scene.clear_color,
            specular_aa: false,
            tonemap: None,
            triangles: scene.triangle_count(),
            bytes: geometry.bytes + texture_bytes,
        };
        renderer.write_objects(gpu, 0.0, 0.0);
        renderer
    }

    /// Triangles drawn per render.
    pub fn triangle_count(&self) -> usize {
        self.triangles
    }

    /// Bytes of GPU memory the uploaded scene occupies (geometry and textures with mips).
    pub fn memory_bytes(&self) -> u64 {
        self.bytes
    }

    /// Background colour (linear).
    pub fn clear_color(&self) -> Vec3 {
        self.clear_color
    }

    /// Turns geometric specular antialiasing on or off for the renders recorded from now on
    /// (off after [`SceneRenderer::new`]): every specular lobe is widened by the variance of
    /// the shading normal across the pixel (`filtered_lobe` in `shaders/scene.wgsl`). Off,
    /// the pipelines are those of a renderer without the option, so renders are unchanged.
    pub fn set_specular_aa(&mut self, on: bool) {
        self.specular_aa = on;
    }

    /// Renders HDR from now on with `Some(tonemap)`: 8-bit targets receive tonemapped radiance
    /// and HDR targets ([`TargetDesc::hdr`]) radiance; `None` (after
    /// [`SceneRenderer::new`]) is the LDR path, display values clamped to [0, 1], whose
    /// pipelines are those of a renderer without HDR, so renders are unchanged.
    pub fn set_tonemap(&mut self, tonemap: Option<Tonemap>) {
        self.tonemap = tonemap;
    }

    /// The tonemap of the renders recorded now (`None`: the LDR path).
    pub fn tonemap(&self) -> Option<Tonemap> {
        self.tonemap
    }

    fn write_objects(&self, gpu: &Gpu, frame: f32, prev_frame: f32) {
        let mut data = vec![0u8; self.object_transforms.len().max(1) * UNIFORM_SLOT as usize];
        for (i, spin) in self.object_transforms.iter().enumerate() {
            let model = spin.map_or(Mat4::IDENTITY, |s| s.transform_at(frame));
            let prev = spin.map_or(Mat4::IDENTITY, |s| s.transform_at(prev_frame));
            let uniform = ObjectUniform {
                model: mat(model),
                prev_model: mat(prev),
                normal_matrix: mat(model.inverse().transpose()),
            };
            let at = i * UNIFORM_SLOT as usize;
            data[at..at + std::mem::size_of::<ObjectUniform>()]
                .copy_from_slice(bytemuck::bytes_of(&uniform));
        }
        gpu.queue.write_buffer(&self.object_buffer, 0, &data);
    }

    /// Starts a new frame: object transforms for `view`'s frame numbers, and the view-uniform
    /// ring rewound. Every `render` of the frame must use the same frame numbers.
    pub fn begin_frame(&mut self, gpu: &Gpu, frame: f32, prev_frame: f32) {
        self.next_view_slot = 0;
        if self.object_transforms.iter().any(Option::is_some) {
            self.write_objects(gpu, frame, prev_frame);
        }
    }

    fn view_slot(&mut self, gpu: &Gpu, uniform: &ViewUniform) -> (wgpu::BindGroup, u32) {
        let slot = self.next_view_slot;
        self.next_view_slot += 1;
        let capacity = self.view_ring.as_ref().map_or(0, |r| r.2);
        if slot >= capacity {
            let new_capacity = (slot + 1).next_power_of_two().max(16);
            let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("scene views"),
                size: new_capacity * UNIFORM_SLOT,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let bind_group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("scene views"),
                layout: &self.view_layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: &buffer,
                        offset: 0,
                        size: wgpu::BufferSize::new(std::mem::size_of::<ViewUniform>() as u64),
                    }),
                }],
            });
            // Slots written earlier this frame live in the old buffer, which the already
            // recorded passes keep alive; only later slots go to the new one.
            self.view_ring = Some((buffer, bind_group, new_capacity));
        }
        let (buffer, bind_group, _) = self.view_ring.as_ref().expect("view ring allocated above");
        gpu.queue
            .write_buffer(buffer, slot * UNIFORM_SLOT, bytemuck::bytes_of(uniform));
        (bind_group.clone(), (slot * UNIFORM_SLOT) as u32)
    }

    fn pipeline(&mut self, device: &wgpu::Device, key: PipelineKey) -> wgpu::RenderPipeline {
        let (layout, shader) = (&self.pipeline_layout, &self.shader);
        self.pipelines
            .entry(key)
            .or_insert_with(|| pipeline::create(device, layout, shader, key))
            .clone()
    }

    /// Records one render of the scene into `targets`: clears them, draws every mesh and, when
    /// multisampled, resolves colour with the hardware box filter into `targets.resolved`.
    pub fn render(
        &mut self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        targets: &SceneTargets,
        view: &ViewParams,
        raster: RasterOptions,
        timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) {
        let queries = PassQueries {
            timestamp_writes,
            statistics: None,
        };
        self.render_queried(gpu, encoder, targets, view, raster, queries);
    }

    /// [`SceneRenderer::render`] with queries around the pass: timestamps, and a
    /// pipeline-statistics query (the frame graph's fragment-invocation counts).
    pub fn render_queried(
        &mut self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        targets: &SceneTargets,
        view: &ViewParams,
        raster: RasterOptions,
        queries: PassQueries<'_>,
    ) {
        let uniform = ViewUniform {
            view_proj: mat(view.view_proj),
            unjittered_view_proj: mat(view.unjittered_view_proj),
            prev_view_proj: mat(view.prev_view_proj),
            eye: view.eye.extend(1.0).to_array(),
            light_direction: self.light.direction.extend(0.0).to_array(),
            light_color: self.light.color.extend(1.0).to_array(),
            ambient: self.light.ambient.extend(1.0).to_array(),
            params: [
                view.mip_bias,
                if targets.desc.motion { 1.0 } else { 0.0 },
                self.tonemap.map_or(1.0, |t| t.scale()),
                0.0,
            ],
        };
        let (view_bind_group, view_offset) = self.view_slot(gpu, &uniform);
        let color_view = targets.color.create_view(&Default::default());
        let resolve_view = targets
            .resolved
            .as_ref()
            .map(|t| t.create_view(&Default::default()));
        let depth_view = targets.depth.create_view(&Default::default());
        let motion_view = targets
            .motion
            .as_ref()
            .map(|t| t.create_view(&Default::default()));
        // The background is radiance too: a tonemapped render clears to its tonemapped value,
        // as the graph's tonemap pass gives a render of radiance.
        let c = match SceneOutput::of(targets.color.format(), self.tonemap.as_ref()) {
            SceneOutput::Tonemapped(_) => {
                (self.tonemap).map_or(self.clear_color, |t| t.apply(self.clear_color))
            }
            SceneOutput::Display | SceneOutput::Radiance => self.clear_color,
        };
        let color_attachment = wgpu::RenderPassColorAttachment {
            view: &color_view,
            depth_slice: None,
            resolve_target: resolve_view.as_ref(),
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color {
                    r: c.x.into(),
                    g: c.y.into(),
                    b: c.z.into(),
                    a: 1.0,
                }),
                store: wgpu::StoreOp::Store,
            },
        };
        let motion_attachment = motion_view.as_ref().map(gpu::cleared_attachment);
        let reactive_view = targets
            .reactive
            .as_ref()
            .map(|t| t.create_view(&Default::default()));
        let reactive_attachment = reactive_view.as_ref().map(gpu::cleared_attachment);
        // Opaque and masked draws in scene order, then the blended ones back to front.
        let order: Vec<usize> = (0..self.draws.len())
            .filter(|&i| !self.blended.contains(i))
            .chain(self.blended.back_to_front(view.eye, view.frame))
            .collect();
        let keys: Vec<PipelineKey> = order
            .iter()
            .map(|&i| PipelineKey {
                sample_count: targets.desc.sample_count,
                motion: targets.desc.motion,
                raster,
                cull_back: self.materials[self.draws[i].material].cull_back,
                anisotropic: self.materials[self.draws[i].material].anisotropic,
                detail: self.materials[self.draws[i].material].detail,
                specular_aa: self.specular_aa,
                output: SceneOutput::of(targets.color.format(), self.tonemap.as_ref()),
                blend: self.blended.contains(i),
                reactive_mask: targets.desc.reactive_mask,
            })
            .collect();
        let pipelines: Vec<wgpu::RenderPipeline> = keys
            .into_iter()
            .map(|k| self.pipeline(&gpu.device, k))
            .collect();
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("scene"),
            color_attachments: &[
                Some(color_attachment),
                motion_attachment,
                reactive_attachment,
            ][..if targets.desc.reactive_mask { 3 } else { 2 }],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: queries.timestamp_writes,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        if let Some((set, index)) = queries.statistics {
            pass.begin_pipeline_statistics_query(set, index);
        }
        pass.set_vertex_buffer(0, self.vertex_buffer.slice(..));
        pass.set_index_buffer(self.index_buffer.slice(..), wgpu::IndexFormat::Uint32);
        pass.set_bind_group(0, &view_bind_group, &[view_offset]);
        for (draw, pipeline) in order.iter().map(|&i| &self.draws[i]).zip(&pipelines) {
            pass.set_pipeline(pipeline);
            pass.set_bind_group(1, &self.materials[draw.material].bind_group, &[]);
            pass.set_bind_group(
                2,
                &self.object_bind_group,
                &[(draw.object as u64 * UNIFORM_SLOT) as u32],
            );
            pass.draw_indexed(
                draw.first_index..draw.first_index + draw.index_count,
                draw.base_vertex,
                0..1,
            );
        }
        if queries.statistics.is_some() {
            pass.end_pipeline_statistics_query();
        }
    }
}
