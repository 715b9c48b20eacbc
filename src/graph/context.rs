//! What a technique's passes are recorded with: [`PassContext`], the device, the frame's
//! encoder and camera, and the timed pass helpers that label every pass `technique/pass` in
//! the frame's GPU timings and pipeline statistics.

use super::FrameInfo;
use super::statistics::StatisticsRecorder;
use crate::gpu::{Gpu, fullscreen::Fullscreen};
use crate::scene::camera::ViewParams;
use crate::scene::renderer::{PassQueries, RasterOptions, SceneRenderer, SceneTargets};

/// Everything a technique's `encode` may use.
pub struct PassContext<'a> {
    /// Device and queue.
    pub gpu: &'a Gpu,
    /// The frame's command encoder.
    pub encoder: &'a mut wgpu::CommandEncoder,
    /// This frame's camera and flags.
    pub frame: &'a FrameInfo,
    /// Shared fullscreen-triangle vertex stage and pipeline helper.
    pub fullscreen: &'a Fullscreen,
    pub(super) scene: &'a mut SceneRenderer,
    pub(super) profiler: &'a wgpu_profiler::GpuProfiler,
    pub(super) technique_id: &'static str,
    pub(super) scene_renders: &'a mut usize,
    pub(super) statistics: &'a mut StatisticsRecorder,
}

impl PassContext<'_> {
    fn label(&self, pass: &str) -> String {
        debug_assert!(!pass.contains('/'), "pass names have no '/': {pass}");
        format!("{}/{pass}", self.technique_id)
    }

    /// Runs `record` with this context seeing `frame` instead (a technique that runs another
    /// at a render scale hands it the frame at the render size); passes stay the technique's.
    pub fn with_frame<R>(
        &mut self,
        frame: &FrameInfo,
        record: impl FnOnce(&mut PassContext<'_>) -> R,
    ) -> R {
        record(&mut PassContext {
            gpu: self.gpu,
            encoder: self.encoder,
            frame,
            fullscreen: self.fullscreen,
            scene: self.scene,
            profiler: self.profiler,
            technique_id: self.technique_id,
            scene_renders: self.scene_renders,
            statistics: self.statistics,
        })
    }

    /// The factor the frame's exposure multiplies radiance by before the tonemapper (1 on the
    /// LDR path): what a pass that judges radiance as the viewer will see it applies first.
    pub fn exposure_scale(&self) -> f32 {
        self.scene.tonemap().map_or(1.0, |t| t.scale())
    }

    /// Records a timed render pass named `pass` (shown as `technique/pass` in timings).
    pub fn render_pass(
        &mut self,
        pass: &str,
        color_attachments: &[Option<wgpu::RenderPassColorAttachment<'_>>],
        depth_stencil_attachment: Option<wgpu::RenderPassDepthStencilAttachment<'_>>,
        record: impl FnOnce(&mut wgpu::RenderPass<'_>),
    ) {
        let label = self.label(pass);
        let query = self.profiler.begin_pass_query(label.clone(), self.encoder);
        let statistics = self.statistics.allocate(&label);
        {
            let mut render_pass = self.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(&label),
                color_attachments,
                depth_stencil_attachment,
                timestamp_writes: query.render_pass_timestamp_writes(),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            if let Some((set, index)) = statistics {
                render_pass.begin_pipeline_statistics_query(set, index);
            }
            record(&mut render_pass);
            if statistics.is_some() {
                render_pass.end_pipeline_statistics_query();
            }
        }
        self.profiler.end_query(self.encoder, query);
    }

    /// Records a timed compute pass named `pass`.
    pub fn compute_pass(&mut self, pass: &str, record: impl FnOnce(&mut wgpu::ComputePass<'_>)) {
        let label = self.label(pass);
        let query = self.profiler.begin_pass_query(label.clone(), self.encoder);
        {
            let mut compute_pass = self
                .encoder
                .begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some(&label),
                    timestamp_writes: query.compute_pass_timestamp_writes(),
                });
            record(&mut compute_pass);
        }
        self.profiler.end_query(self.encoder, query);
    }

    /// Records a timed fullscreen pass: one triangle into `target` with `pipeline` and
    /// `bind_group` at group 0.
    pub fn fullscreen_pass(
        &mut self,
        pass: &str,
        target: &wgpu::TextureView,
        pipeline: &wgpu::RenderPipeline,
        bind_group: &wgpu::BindGroup,
    ) {
        let attachment = wgpu::RenderPassColorAttachment {
            view: target,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                store: wgpu::StoreOp::Store,
            },
        };
        self.render_pass(pass, &[Some(attachment)], None, |rp| {
            rp.set_pipeline(pipeline);
            rp.set_bind_group(0, bind_group, &[]);
            rp.draw(0..3, 0..1);
        });
    }

    /// Copies a whole texture into another of the same size and format, timed.
    pub fn copy_texture(
        &mut self,
        pass: &str,
        source: &wgpu::Texture,
        destination: &wgpu::Texture,
    ) {
        let label = self.label(pass);
        let query = self.profiler.begin_query(label, self.encoder);
        self.encoder.copy_texture_to_texture(
            source.as_image_copy(),
            destination.as_image_copy(),
            source.size(),
        );
        self.profiler.end_query(self.encoder, query);
    }

    /// Renders the scene (for techniques that produce their own scene renders, such as
    /// supersampling tiles and accumulation passes). Counted in the frame's scene renders.
    pub fn render_scene(
        &mut self,
        pass: &str,
        targets: &SceneTargets,
        view: &ViewParams,
        raster: RasterOptions,
    ) {
        let label = self.label(pass);
        let query = self.profiler.begin_pass_query(label.clone(), self.encoder);
        let queries = PassQueries {
            timestamp_writes: query.render_pass_timestamp_writes(),
            statistics: self.statistics.allocate(&label),
        };
        self.scene
            .render_queried(self.gpu, self.encoder, targets, view, raster, queries);
        self.profiler.end_query(self.encoder, query);
        *self.scene_renders += 1;
    }
}
