//! The HDR path of the frame graph: scenes rendered as linear radiance, shown through an
//! exposure and a tonemapping operator, with every technique run either **before** or
//! **after** the tonemapper (its [`TonemapOrder`]), so that the difference the order makes on
//! bright edges is visible side by side and measured.
//!
//! How a frame runs with a [`Tonemap`] set ([`super::FrameGraph::set_tonemap`]):
//! - A technique **after** the tonemapper (post-process antialiasing in an engine that runs it
//!   on the displayed image) reads a scene render into the usual 8-bit target whose fragment
//!   shader tonemaps the radiance it computes (`SceneOutput::Tonemapped`): per sample in a
//!   multisampled render, exactly what tonemapping the HDR samples would give. It writes its
//!   output as it always does.
//! - A technique **before** the tonemapper reads a render of linear radiance in half floats
//!   ([`crate::gpu::HDR_FORMAT`]) and writes a half-float output of the same kind; the graph
//!   then tonemaps that output into the technique's displayed one in a pass of the technique
//!   (`ID/tonemap`, timed with it). MSAA's resolve, supersampling (the 64-sample reference
//!   averages radiance, as a camera would) and the temporal techniques' blends then happen on
//!   radiance, where one very bright sample dominates a pixel's average: the antialiasing of a
//!   bright edge is lost unless the technique weights its samples (Karis' 1 / (1 + luma)).
//! - Inputs are shared within each order: two techniques before the tonemapper reading the
//!   same render share it, as do two after it; the two orders need two renders.
//!
//! Without a tonemap (the default) nothing here runs and every render is the LDR path, bit for
//! bit what the graph drew before HDR existed. The operators are in
//! `shaders/tonemap_operators.wgsl`, shared by the scene shader and this pass.

use crate::gpu::fullscreen::{FragmentDesc, Fullscreen};
use crate::gpu::{self, Gpu};
use crate::graph::params::Param;
use crate::scene::renderer::{Tonemap, Tonemapper};

crate::named_enum! {
    /// Where a technique runs relative to the tonemapper in an HDR frame (see the module
    /// docs). LDR frames ignore it.
    #[derive(serde::Serialize, serde::Deserialize)]
    #[serde(rename_all = "lowercase")]
    pub enum TonemapOrder {
        /// On linear radiance, before the tonemapper (bright samples dominate averages).
        Before => "before",
        /// On the tonemapped, displayed image.
        After => "after",
    }
}

crate::named_enum! {
    /// The tonemapping of a render as the command line, the viewer and records name it.
    #[derive(serde::Serialize, serde::Deserialize)]
    #[serde(rename_all = "lowercase")]
    pub enum TonemapChoice {
        /// HDR scenes (emitters brighter than white) through AgX, the others on the LDR path.
        Auto => "auto",
        /// The LDR path: display values clamped to [0, 1], as before HDR existed.
        None => "none",
        /// Reinhard, x / (1 + x) per channel.
        Reinhard => "reinhard",
        /// Narkowicz's fit of the ACES reference and sRGB output transforms.
        Aces => "aces",
        /// AgX, Blender 4's view transform.
        Agx => "agx",
        /// Khronos PBR Neutral.
        Neutral => "neutral",
    }
}

// `named_enum!` takes doc attributes only, so `#[default]` cannot go on the variant.
#[allow(clippy::derivable_impls)]
impl Default for TonemapChoice {
    fn default() -> Self {
        Self::Auto
    }
}

impl TonemapChoice {
    /// Whether this is [`TonemapChoice::Auto`] (records leave it out).
    pub fn is_auto(&self) -> bool {
        *self == Self::Auto
    }

    /// The tonemap of a render of a scene that `is_hdr` or not, at `exposure` stops (`None`:
    /// the LDR path).
    pub fn resolve(self, is_hdr: bool, exposure: f32) -> Option<Tonemap> {
        let operator = match self {
            Self::Auto if is_hdr => DEFAULT_TONEMAPPER,
            Self::Auto | Self::None => return None,
            Self::Reinhard => Tonemapper::Reinhard,
            Self::Aces => Tonemapper::Aces,
            Self::Agx => Tonemapper::Agx,
            Self::Neutral => Tonemapper::Neutral,
        };
        Some(Tonemap { operator, exposure })
    }
}

/// The parameter key of a technique's [`TonemapOrder`].
pub const TONEMAP_ORDER_KEY: &str = "tonemap_order";

impl TonemapOrder {
    /// The `tonemap_order` parameter of the techniques that can run on either side.
    pub fn param(self) -> Param {
        Param::named(
            TONEMAP_ORDER_KEY,
            "Tonemap order",
            "In HDR scenes (ignored in LDR ones): before runs the technique on linear radiance \
             and tonemaps its result, as engines do with MSAA resolves and TAA (a very bright \
             sample dominates every average, so bright edges stay aliased unless samples are \
             weighted); after runs it on the tonemapped, displayed image.",
            self,
        )
    }
}

/// The operator HDR scenes get when no tonemap is asked for.
pub const DEFAULT_TONEMAPPER: Tonemapper = Tonemapper::Agx;

/// The tonemap pass of outputs rendered before the tonemapper.
pub(super) struct TonemapPass {
    tonemap: Option<Tonemap>,
    module: wgpu::ShaderModule,
    exposure: wgpu::Buffer,
    /// The pipeline of the current operator.
    pipeline: Option<(Tonemapper, wgpu::RenderPipeline)>,
}

impl TonemapPass {
    pub(super) fn new(device: &wgpu::Device) -> Self {
        Self {
            tonemap: None,
            module: gpu::shader::module(device, "tonemap.wgsl"),
            exposure: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("tonemap exposure"),
                size: 16,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            pipeline: None,
        }
    }

    pub(super) fn tonemap(&self) -> Option<Tonemap> {
        self.tonemap
    }

    /// Sets the tonemap of the next frames (`None`: the LDR path) and makes its pipeline.
    pub(super) fn set_tonemap(
        &mut self,
        gpu: &Gpu,
        fullscreen: &Fullscreen,
        tonemap: Option<Tonemap>,
    ) {
        self.tonemap = tonemap;
        let Some(tonemap) = tonemap else { return };
        let scale = [tonemap.scale(), 0.0, 0.0, 0.0];
        gpu.queue
            .write_buffer(&self.exposure, 0, bytemuck::cast_slice(&scale));
        if self
            .pipeline
            .as_ref()
            .is_some_and(|(op, _)| *op == tonemap.operator)
        {
            return;
        }
        let operator = f64::from(tonemap.operator.shader_index());
        let pipeline = fullscreen.pipeline(
            &gpu.device,
            &FragmentDesc {
                label: &format!("tonemap {:?}", tonemap.operator),
                module: &self.module,
                entry_point: "fs_tonemap",
                targets: &[gpu::COLOR_FORMAT],
                constants: &[("OPERATOR", operator)],
                layout: None,
            },
        );
        self.pipeline = Some((tonemap.operator, pipeline));
    }

    /// Tonemaps `source` (radiance, [`gpu::HDR_FORMAT`]) into `target` (display values) as the
    /// pass `tonemap` of the technique `ctx` records for.
    pub(super) fn encode(
        &self,
        ctx: &mut super::PassContext<'_>,
        source: &wgpu::Texture,
        target: &wgpu::Texture,
    ) {
        let Some((_, pipeline)) = &self.pipeline else {
            return;
        };
        let source_view = source.create_view(&Default::default());
        let bind_group = ctx
            .gpu
            .device
            .create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("tonemap"),
                layout: &pipeline.get_bind_group_layout(0),
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::TextureView(&source_view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: self.exposure.as_entire_binding(),
                    },
                ],
            });
        let target_view = target.create_view(&Default::default());
        ctx.fullscreen_pass("tonemap", &target_view, pipeline, &bind_group);
    }
}

/// A half-float output of a technique that runs before the tonemapper.
pub(super) fn hdr_output_texture(gpu: &Gpu, label: &str, size: (u32, u32)) -> wgpu::Texture {
    gpu::texture_2d(
        &gpu.device,
        &gpu::Texture2d::new(label, size, gpu::HDR_FORMAT, super::OUTPUT_USAGE),
    )
}
