//! The GPU passes of a scaled technique (`resample.wgsl`): upscaling a render to the output
//! size with one of the [`Upscaler`]s, nearest-neighbour upscaling of debug views, and
//! [`Sharpen`]ing. One bind-group layout (source, sampler, parameters) serves every entry
//! point; pipelines are built on first use and kept by entry point. Each pass has its own
//! parameter buffer, because the queue writes them all before the frame's one submission.

use crate::aa::combo::{Sharpen, Sharpening, Upscaler};
use crate::aa::common::pass::{self, Binding};
use crate::aa::common::{PipelineCache, bilinear_clamp_sampler, encoded_view};
use crate::gpu::fullscreen::FragmentDesc;
use crate::gpu::shader::Shader;
use crate::gpu::{COLOR_FORMAT_ENCODED_VIEW, Gpu};
use crate::graph::{MemoryItem, PassContext};

/// The upscale, nearest and sharpening passes.
pub const WGSL: Shader = crate::wgsl!("src/aa/scaled/resample.wgsl");

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ResampleUniform {
    sizes: [f32; 4],
    sharpen: [f32; 4],
}

/// Which parameter buffer a pass reads.
#[derive(Clone, Copy)]
enum Use {
    /// Render size to output size (upscale and debug views).
    Upscale,
    /// Output size to output size, with the strength.
    Sharpen,
}

/// The pipelines and parameters of the resampling passes.
pub struct Resampler {
    device: wgpu::Device,
    module: wgpu::ShaderModule,
    sampler: wgpu::Sampler,
    layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    upscale_params: wgpu::Buffer,
    sharpen_params: wgpu::Buffer,
    pipelines: PipelineCache<&'static str>,
}

impl Resampler {
    /// Compiles the module; pipelines are built when first used.
    pub fn new(gpu: &Gpu) -> Self {
        let device = &gpu.device;
        let layout = pass::layout(
            device,
            "resample",
            &[
                (0, Binding::Texture),
                (1, Binding::Sampler),
                (2, Binding::Uniform),
            ],
        );
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("resample"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        Self {
            module: WGSL.module(device),
            sampler: bilinear_clamp_sampler(device, "resample bilinear"),
            layout,
            pipeline_layout,
            upscale_params: pass::uniform_buffer::<ResampleUniform>(device, "upscale params"),
            sharpen_params: pass::uniform_buffer::<ResampleUniform>(device, "sharpen params"),
            pipelines: PipelineCache::default(),
            device: device.clone(),
        }
    }

    /// Upscales `source` (the render) into `target` (the output size), as the pass `upscale`.
    pub fn upscale(
        &mut self,
        ctx: &mut PassContext<'_>,
        upscaler: Upscaler,
        source: &wgpu::Texture,
        target: &wgpu::Texture,
    ) {
        let entry = match upscaler {
            Upscaler::Bilinear => "fs_bilinear",
            Upscaler::Bicubic => "fs_bicubic",
            Upscaler::Lanczos => "fs_lanczos",
            Upscaler::Easu => "fs_easu",
        };
        self.write(ctx, Use::Upscale, source, target, 0.0);
        self.run(ctx, "upscale", entry, Use::Upscale, source, target);
    }

    /// Shows `source`'s pixels at `target`'s size as they are (debug views), as the pass
    /// `pass`; `source` has the size of the frame's upscale source (they share parameters).
    pub fn nearest(
        &mut self,
        ctx: &mut PassContext<'_>,
        pass: &str,
        source: &wgpu::Texture,
        target: &wgpu::Texture,
    ) {
        self.write(ctx, Use::Upscale, source, target, 0.0);
        self.run(ctx, pass, "fs_nearest", Use::Upscale, source, target);
    }

    /// Sharpens `source` into `target` (same size), as the pass `sharpen`.
    pub fn sharpen(
        &mut self,
        ctx: &mut PassContext<'_>,
        sharpening: Sharpening,
        source: &wgpu::Texture,
        target: &wgpu::Texture,
    ) {
        let entry = match sharpening.filter {
            Sharpen::Cas => "fs_cas",
            Sharpen::Rcas => "fs_rcas",
        };
        self.write(ctx, Use::Sharpen, source, target, sharpening.strength);
        self.run(ctx, "sharpen", entry, Use::Sharpen, source, target);
    }

    fn buffer(&self, buffer: Use) -> &wgpu::Buffer {
        match buffer {
            Use::Upscale => &self.upscale_params,
            Use::Sharpen => &self.sharpen_params,
        }
    }

    fn write(
        &self,
        ctx: &PassContext<'_>,
        buffer: Use,
        source: &wgpu::Texture,
        target: &wgpu::Texture,
        strength: f32,
    ) {
        let uniform = ResampleUniform {
            sizes: [
                source.width() as f32,
                source.height() as f32,
                target.width() as f32,
                target.height() as f32,
            ],
            sharpen: [strength, 0.0, 0.0, 0.0],
        };
        ctx.gpu
            .queue
            .write_buffer(self.buffer(buffer), 0, bytemuck::bytes_of(&uniform));
    }

    fn run(
        &mut self,
        ctx: &mut PassContext<'_>,
        pass: &str,
        entry: &'static str,
        buffer: Use,
        source: &wgpu::Texture,
        target: &wgpu::Texture,
    ) {
        let (device, module, layout) = (&self.device, &self.module, &self.pipeline_layout);
        let pipeline = self.pipelines.get_or_build(entry, |entry| {
            ctx.fullscreen.pipeline(
                device,
                &FragmentDesc {
                    label: &format!("resample {entry}"),
                    module,
                    entry_point: entry,
                    targets: &[COLOR_FORMAT_ENCODED_VIEW],
                    constants: &[],
                    layout: Some(layout),
                },
            )
        });
        let source_view = encoded_view(source);
        let bind_group = pass::bind_group(
            &self.device,
            "resample",
            &self.layout,
            &[
                (0, wgpu::BindingResource::TextureView(&source_view)),
                (1, wgpu::BindingResource::Sampler(&self.sampler)),
                (2, self.buffer(buffer).as_entire_binding()),
            ],
        );
        ctx.fullscreen_pass(pass, &encoded_view(target), &pipeline, &bind_group);
    }

    /// The parameter buffers.
    pub fn memory(&self) -> Vec<MemoryItem> {
        vec![
            MemoryItem::buffer("upscale params", &self.upscale_params),
            MemoryItem::buffer("sharpen params", &self.sharpen_params),
        ]
    }
}
