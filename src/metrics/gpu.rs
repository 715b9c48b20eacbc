//! SSIM, MAE and PSNR on the GPU (`shaders/metrics_ssim.wgsl`), fast enough for the viewer to
//! measure every frame at 1080p. Three compute passes: a horizontal Gaussian pass writing the
//! local moments of both images' luma to float textures, a vertical pass computing the SSIM map
//! and per-workgroup sums, and a one-workgroup reduction to four totals, read back as 16 bytes.
//!
//! The definitions are those of the CPU reference ([`super::ssim`], [`super::pixel`]); the
//! GPU computes in `f32` with the luma shifted by -127.5 before squaring, and agrees with the
//! CPU to better than 1e-3 on the mean SSIM (tested). Use:
//! [`GpuMetrics::encode`] records the passes and the copy of the totals into any encoder (the
//! viewer's frame) through the caller's [`ReadbackBelt`], and [`PendingComparison::scores`]
//! reads the numbers from that frame's [`ReadbackFrame`]; [`GpuMetrics::compare`] does both on
//! a belt of its own (one submission, a blocking wait). Every readback goes through
//! [`crate::gpu::readback`].
//! Inputs are RGBA8 textures holding sRGB-encoded values (`Rgba8Unorm`, or `Rgba8UnormSrgb`
//! created with an `Rgba8Unorm` view format, as every technique output is), with
//! `TEXTURE_BINDING` usage.

use wgpu::util::DeviceExt;

use super::pixel::psnr_from_mse;
use super::ssim;
use super::{MetricsError, Plane};
use crate::gpu::readback::{
    ReadbackBelt, ReadbackError, ReadbackFrame, Region, Ticket, read_texture_bytes_with,
};
use crate::gpu::{COLOR_FORMAT, COLOR_FORMAT_ENCODED_VIEW, Gpu, shader};

/// Workgroup side of the per-pixel passes.
const TILE: u32 = 16;
/// Bytes of the four totals.
const TOTALS_BYTES: u64 = 16;

/// Errors of the GPU metrics.
#[derive(Debug, thiserror::Error)]
pub enum GpuMetricsError {
    /// Sizes disagree or are too small.
    #[error(transparent)]
    Metrics(#[from] MetricsError),
    /// A texture is not RGBA8.
    #[error("GPU metrics read RGBA8 textures, not {0:?}")]
    UnsupportedFormat(wgpu::TextureFormat),
    /// Nothing was encoded before reading.
    #[error("no comparison was encoded before reading GPU metrics")]
    NothingEncoded,
    /// Reading the results back failed.
    #[error(transparent)]
    Readback(#[from] ReadbackError),
    /// An image is larger than the adapter's largest texture.
    #[error(
        "the GPU path cannot take a {width}x{height} image: this adapter's largest texture side \
         is {limit} (the CPU figures do not have this limit)"
    )]
    TooLarge {
        /// Image width.
        width: u32,
        /// Image height.
        height: u32,
        /// The adapter's `max_texture_dimension_2d`.
        limit: u32,
    },
}

/// The scores the GPU computes.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct GpuComparison {
    /// Mean SSIM over the interior (as [`ssim::Ssim::mean`]).
    pub ssim: f64,
    /// Mean absolute error on R'G'B', 0..255.
    pub mae: f64,
    /// Mean squared error on R'G'B'.
    pub mse: f64,
}

impl GpuComparison {
    /// PSNR in dB (infinite for identical images).
    pub fn psnr(&self) -> f64 {
        psnr_from_mse(self.mse)
    }
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Params {
    size: [u32; 2],
    partial_count: u32,
    groups_x: u32,
    c1: f32,
    c2: f32,
    pad: [f32; 2],
    weights: [[f32; 4]; 3],
}

/// Size-dependent resources.
struct Targets {
    size: (u32, u32),
    groups: (u32, u32),
    params: wgpu::Buffer,
    moments: wgpu::Texture,
    cross: wgpu::Texture,
    ssim_map: wgpu::Texture,
    partials: wgpu::Buffer,
    totals: wgpu::Buffer,
}

/// A comparison recorded by [`GpuMetrics::encode`], waiting for its frame's readback.
#[derive(Clone, Copy, Debug)]
pub struct PendingComparison {
    totals: Ticket,
    size: (u32, u32),
}

impl PendingComparison {
    /// The scores, from the mapped readback frame the comparison was recorded in.
    pub fn scores(&self, frame: &ReadbackFrame) -> Result<GpuComparison, GpuMetricsError> {
        let bytes = frame.bytes(self.totals)?;
        let totals: [f32; 4] = bytemuck::pod_read_unaligned(
            bytes
                .get(..TOTALS_BYTES as usize)
                .ok_or(GpuMetricsError::Readback(ReadbackError::NoAnswer))?,
        );
        let pixels = f64::from(self.size.0) * f64::from(self.size.1);
        Ok(GpuComparison {
            ssim: f64::from(totals[0]) / f64::from(totals[3]).max(1.0),
            mae: f64::from(totals[1]) / pixels,
            mse: f64::from(totals[2]) / pixels,
        })
    }
}

/// An SSIM map copy recorded by [`GpuMetrics::copy_ssim_map`].
#[derive(Clone, Copy, Debug)]
pub struct PendingMap {
    map: Ticket,
    size: (u32, u32),
}

impl PendingMap {
    /// The SSIM map, from the mapped readback frame the copy was recorded in.
    pub fn plane(&self, frame: &ReadbackFrame) -> Result<Plane, GpuMetricsError> {
        let bytes = frame.bytes(self.map)?;
        Ok(Plane {
            width: self.size.0,
            height: self.size.1,
            data: bytemuck::pod_collect_to_vec(&bytes),
        })
    }
}

/// The GPU metrics pipelines and their working textures (see the module docs).
pub struct GpuMetrics {
    device: wgpu::Device,
    layouts: [wgpu::BindGroupLayout; 3],
    pipelines: [wgpu::ComputePipeline; 3],
    targets: Option<Targets>,
    encoded: bool,
    /// For [`GpuMetrics::compare`] and [`GpuMetrics::read_ssim_map`].
    belt: ReadbackBelt,
}

fn entry(binding: u32, ty: wgpu::BindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty,
        count: None,
    }
}

fn sampled(binding: u32, filterable: bool) -> wgpu::BindGroupLayoutEntry {
    entry(
        binding,
        wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
    )
}

fn storage_texture(binding: u32, format: wgpu::TextureFormat) -> wgpu::BindGroupLayoutEntry {
    entry(
        binding,
        wgpu::BindingType::StorageTexture {
            access: wgpu::StorageTextureAccess::WriteOnly,
            format,
            view_dimension: wgpu::TextureViewDimension::D2,
        },
    )
}

fn buffer(binding: u32, ty: wgpu::BufferBindingType) -> wgpu::BindGroupLayoutEntry {
    entry(
        binding,
        wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
    )
}

fn float_texture(
    device: &wgpu::Device,
    label: &str,
    size: (u32, u32),
    format: wgpu::TextureFormat,
) -> wgpu::Texture {
    crate::gpu::texture_2d(
        device,
        &crate::gpu::Texture2d::new(
            label,
            size,
            format,
            wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
        ),
    )
}

fn encoded_view(texture: &wgpu::Texture) -> Result<wgpu::TextureView, GpuMetricsError> {
    match texture.format() {
        COLOR_FORMAT | COLOR_FORMAT_ENCODED_VIEW => {
            Ok(texture.create_view(&wgpu::TextureViewDescriptor {
                format: Some(COLOR_FORMAT_ENCODED_VIEW),
                ..Default::default()
            }))
        }
        other => Err(GpuMetricsError::UnsupportedFormat(other)),
    }
}

impl GpuMetrics {
    /// Compiles the pipelines.
    pub fn new(gpu: &Gpu) -> Self {
        let device = &gpu.device;
        let module = shader::module(device, "metrics_ssim.wgsl");
        let uniform = buffer(0, wgpu::BufferBindingType::Uniform);
        let read_write = wgpu::BufferBindingType::Storage { read_only: false };
        let layout = |label: &str, entries: &[wgpu::BindGroupLayoutEntry]| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries,
            })
        };
        let layouts = [
            layout(
                "metrics horizontal",
                &[
                    uniform,
                    sampled(1, true),
                    sampled(2, true),
                    storage_texture(3, wgpu::TextureFormat::Rgba32Float),
                    storage_texture(4, wgpu::TextureFormat::R32Float),
                ],
            ),
            layout(
                "metrics vertical",
                &[
                    uniform,
                    sampled(1, true),
                    sampled(2, true),
                    sampled(5, false),
                    sampled(6, false),
                    storage_texture(7, wgpu::TextureFormat::R32Float),
                    buffer(8, read_write),
                ],
            ),
            layout(
                "metrics reduce",
                &[
                    uniform,
                    buffer(9, wgpu::BufferBindingType::Storage { read_only: true }),
                    buffer(10, read_write),
                ],
            ),
        ];
        let pipeline = |index: usize, entry_point: &str| {
            let layout = &layouts[index];
            let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(entry_point),
                bind_group_layouts: &[Some(layout)],
                immediate_size: 0,
            });
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry_point),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(entry_point),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let pipelines = [
            pipeline(0, "cs_horizontal"),
            pipeline(1, "cs_vertical"),
            pipeline(2, "cs_reduce"),
        ];
        Self {
            device: device.clone(),
            layouts,
            pipelines,
            targets: None,
            encoded: false,
            belt: ReadbackBelt::new(device),
        }
    }

    fn create_targets(device: &wgpu::Device, size: (u32, u32)) -> Targets {
        let groups = (size.0.div_ceil(TILE), size.1.div_ceil(TILE));
        let partial_count = groups.0 * groups.1;
        let weights = ssim::gaussian_weights();
        let mut packed = [[0.0f32; 4]; 3];
        for (i, w) in weights.iter().enumerate() {
            packed[i / 4][i % 4] = *w as f32;
        }
        let params = Params {
            size: [size.0, size.1],
            partial_count,
            groups_x: groups.0,
            c1: ssim::c1() as f32,
            c2: ssim::c2() as f32,
            pad: [0.0; 2],
            weights: packed,
        };
        let storage = |label: &str, bytes: u64, usage: wgpu::BufferUsages| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage,
                mapped_at_creation: false,
            })
        };
        Targets {
            size,
            groups,
            params: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("metrics params"),
                contents: bytemuck::bytes_of(&params),
                usage: wgpu::BufferUsages::UNIFORM,
            }),
            moments: float_texture(
                device,
                "metrics moments",
                size,
                wgpu::TextureFormat::Rgba32Float,
            ),
            cross: float_texture(device, "metrics cross", size, wgpu::TextureFormat::R32Float),
            ssim_map: float_texture(
                device,
                "metrics ssim map",
                size,
                wgpu::TextureFormat::R32Float,
            ),
            partials: storage(
                "metrics partials",
                u64::from(partial_count) * 16,
                wgpu::BufferUsages::STORAGE,
            ),
            totals: storage(
                "metrics totals",
                TOTALS_BYTES,
                wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            ),
        }
    }

    fn ensure_targets(&mut self, size: (u32, u32)) -> &Targets {
        if self.targets.as_ref().is_some_and(|t| t.size != size) {
            self.targets = None;
        }
        let device = &self.device;
        self.targets
            .get_or_insert_with(|| Self::create_targets(device, size))
    }

    /// Records the comparison of `test` against `reference` into `encoder`, and the copy of
    /// its totals into `belt`. After [`ReadbackBelt::finish`] and the submission, read the
    /// scores with [`PendingComparison::scores`]. The working textures are shared: encode the
    /// next comparison after this one's frame has been submitted.
    pub fn encode(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        belt: &mut ReadbackBelt,
        reference: &wgpu::Texture,
        test: &wgpu::Texture,
    ) -> Result<PendingComparison, GpuMetricsError> {
        self.encode_passes(encoder, reference, test)?;
        let t = self
            .targets
            .as_ref()
            .ok_or(GpuMetricsError::NothingEncoded)?;
        let totals = belt.copy_buffer(encoder, &t.totals, 0, TOTALS_BYTES)?;
        Ok(PendingComparison {
            totals,
            size: t.size,
        })
    }

    fn encode_passes(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        reference: &wgpu::Texture,
        test: &wgpu::Texture,
    ) -> Result<(), GpuMetricsError> {
        let size = (reference.width(), reference.height());
        ssim::check_sizes(size, (test.width(), test.height()))?;
        let reference_view = encoded_view(reference)?;
        let test_view = encoded_view(test)?;
        let device = self.device.clone();
        let layouts = self.layouts.clone();
        let pipelines = self.pipelines.clone();
        let t = self.ensure_targets(size);
        let view = |texture: &wgpu::Texture| texture.create_view(&Default::default());
        let (moments, cross, ssim_map) = (view(&t.moments), view(&t.cross), view(&t.ssim_map));
        let bind = |layout: &wgpu::BindGroupLayout, entries: &[(u32, wgpu::BindingResource)]| {
            let entries: Vec<wgpu::BindGroupEntry> = entries
                .iter()
                .map(|(binding, resource)| wgpu::BindGroupEntry {
                    binding: *binding,
                    resource: resource.clone(),
                })
                .collect();
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("metrics"),
                layout,
                entries: &entries,
            })
        };
        use wgpu::BindingResource::TextureView as Tv;
        let params = t.params.as_entire_binding();
        let groups = [
            bind(
                &layouts[0],
                &[
                    (0, params.clone()),
                    (1, Tv(&reference_view)),
                    (2, Tv(&test_view)),
                    (3, Tv(&moments)),
                    (4, Tv(&cross)),
                ],
            ),
            bind(
                &layouts[1],
                &[
                    (0, params.clone()),
                    (1, Tv(&reference_view)),
                    (2, Tv(&test_view)),
                    (5, Tv(&moments)),
                    (6, Tv(&cross)),
                    (7, Tv(&ssim_map)),
                    (8, t.partials.as_entire_binding()),
                ],
            ),
            bind(
                &layouts[2],
                &[
                    (0, params),
                    (9, t.partials.as_entire_binding()),
                    (10, t.totals.as_entire_binding()),
                ],
            ),
        ];
        let dispatches = [(t.groups.0, t.groups.1), (t.groups.0, t.groups.1), (1, 1)];
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("metrics"),
                timestamp_writes: None,
            });
            for ((pipeline, group), (x, y)) in pipelines.iter().zip(&groups).zip(dispatches) {
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, group, &[]);
                pass.dispatch_workgroups(x, y, 1);
            }
        }
        self.encoded = true;
        Ok(())
    }

    /// Encodes, submits and reads one comparison (one submission, a blocking wait).
    pub fn compare(
        &mut self,
        gpu: &Gpu,
        reference: &wgpu::Texture,
        test: &wgpu::Texture,
    ) -> Result<GpuComparison, GpuMetricsError> {
        let mut encoder = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("metrics"),
            });
        let mut belt = std::mem::replace(&mut self.belt, ReadbackBelt::new(&gpu.device));
        let pending = self.encode(&mut encoder, &mut belt, reference, test);
        let readback = belt.finish(&mut encoder);
        self.belt = belt;
        let pending = pending?;
        gpu.queue.submit([encoder.finish()]);
        pending.scores(&readback.wait()?)
    }

    /// The SSIM map of the last comparison (`R32Float`, one value per pixel), for live
    /// heatmaps.
    pub fn ssim_map(&self) -> Option<&wgpu::Texture> {
        self.targets.as_ref().map(|t| &t.ssim_map)
    }

    /// Records the copy of the last comparison's SSIM map into `belt` (in the same encoder as
    /// the comparison, or a later one); read it with [`PendingMap::plane`].
    pub fn copy_ssim_map(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        belt: &mut ReadbackBelt,
    ) -> Result<PendingMap, GpuMetricsError> {
        let t = self
            .targets
            .as_ref()
            .filter(|_| self.encoded)
            .ok_or(GpuMetricsError::NothingEncoded)?;
        let map = belt.copy_texture(encoder, &t.ssim_map, Region::whole(&t.ssim_map))?;
        Ok(PendingMap { map, size: t.size })
    }

    /// Reads the SSIM map of the last comparison back to the CPU (one submission, a blocking
    /// wait).
    pub fn read_ssim_map(&mut self, gpu: &Gpu) -> Result<Plane, GpuMetricsError> {
        let t = self
            .targets
            .as_ref()
            .filter(|_| self.encoded)
            .ok_or(GpuMetricsError::NothingEncoded)?;
        let bytes = read_texture_bytes_with(gpu, &mut self.belt, &t.ssim_map)?;
        Ok(Plane {
            width: t.size.0,
            height: t.size.1,
            data: bytemuck::pod_collect_to_vec(&bytes),
        })
    }
}

/// Uploads an sRGB-encoded image as a texture [`GpuMetrics`] can read; an image wider or
/// taller than the adapter's largest texture is refused.
pub fn upload_image(
    gpu: &Gpu,
    image: &image::RgbaImage,
    label: &str,
) -> Result<wgpu::Texture, GpuMetricsError> {
    let (width, height) = image.dimensions();
    let limit = gpu.caps.max_texture_dimension_2d;
    if width > limit || height > limit || width == 0 || height == 0 {
        return Err(GpuMetricsError::TooLarge {
            width,
            height,
            limit,
        });
    }
    Ok(gpu.device.create_texture_with_data(
        &gpu.queue,
        &crate::gpu::Texture2d::new(
            label,
            image.dimensions(),
            COLOR_FORMAT_ENCODED_VIEW,
            wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_SRC,
        )
        .descriptor(),
        wgpu::util::TextureDataOrder::LayerMajor,
        image.as_raw(),
    ))
}
