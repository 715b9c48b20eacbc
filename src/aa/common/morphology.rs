//! What the morphological techniques (MLAA and the SMAA family, Jimenez et al.'s
//! refinement of Reshetov's MLAA) share: the geometry of revectorised edge lines, from which
//! both precompute their area tables ([`Crossing`], [`polyline_area`]), and the three passes
//! both run on the GPU (edge detection marking edge pixels in a stencil, blending weights on
//! the marked pixels, neighbourhood blending): their pipelines, working targets and debug
//! views. And the preset names the SMAA family and CMAA 2 share ([`QualityPreset`]).

use super::pass::{PassDesc, STENCIL_FORMAT, Stencil, Vertex, bind_group, stencil_pass, target};
use super::{debug_texture, view_as};
use crate::graph::{MemoryItem, PassContext};

crate::named_enum! {
    /// The presets of the SMAA family and CMAA 2: four quality steps, each the technique's own
    /// (its settings say what each sets), and texture-safe, which leaves edges inside textures
    /// unblended (docs/hard-cases.md measures it).
    pub enum QualityPreset {
        /// Strong edges only, or the shortest searches: the fastest.
        Low => "low",
        /// Fainter edges or longer searches than low.
        Medium => "medium",
        /// The authors' default.
        High => "high",
        /// The faintest edges and the longest searches.
        Ultra => "ultra",
        /// High, set to leave texture detail sharp while geometric edges are still smoothed.
        TextureSafe => "texture-safe",
    }
}

/// Crossing edges at one end of an orthogonal edge run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Crossing {
    /// No crossing edge: the run ends flat (or was not searched to its end).
    None,
    /// A crossing edge in the current pixel's row: the outline turns towards the current side.
    Current,
    /// A crossing edge in the row across the edge.
    Opposite,
    /// Crossing edges on both sides: a junction.
    Both,
}

impl Crossing {
    /// Every value, in cell order of the current-side bit then the opposite-side bit.
    pub const ALL: [Self; 4] = [Self::None, Self::Current, Self::Opposite, Self::Both];

    /// The crossing from the two edges the shader reads.
    pub fn from_edges(current: bool, opposite: bool) -> Self {
        match (current, opposite) {
            (false, false) => Self::None,
            (true, false) => Self::Current,
            (false, true) => Self::Opposite,
            (true, true) => Self::Both,
        }
    }

    /// Cell index along one axis of the orthogonal part: `3 * current + opposite`.
    pub fn cell(self) -> u32 {
        match self {
            Self::None => 0,
            Self::Opposite => 1,
            Self::Current => 3,
            Self::Both => 4,
        }
    }

    /// Height of the revectorised line at this end, for single-sided crossings (MLAA's
    /// table uses it too, with no offset).
    pub(crate) fn height(self, offset: f32) -> Option<f32> {
        match self {
            Self::Current => Some(-0.5 + offset),
            Self::Opposite => Some(0.5 + offset),
            Self::None | Self::Both => None,
        }
    }

    /// The other side.
    pub(crate) fn flipped(self) -> Self {
        match self {
            Self::Current => Self::Opposite,
            Self::Opposite => Self::Current,
            other => other,
        }
    }
}

/// Area between y = 0 and a polyline over `[x0, x1]`: (below, above). The polyline
/// contributes nothing outside its own x range.
pub fn polyline_area(points: &[(f32, f32)], x0: f32, x1: f32) -> [f32; 2] {
    let mut area = [0.0f32; 2];
    let mut add = |xa: f32, ya: f32, xb: f32, yb: f32| {
        let trapezoid = (xb - xa) * (ya + yb) * 0.5;
        if trapezoid < 0.0 {
            area[0] -= trapezoid;
        } else {
            area[1] += trapezoid;
        }
    };
    for pair in points.windows(2) {
        let ((ax, ay), (bx, by)) = (pair[0], pair[1]);
        let (lo, hi) = (ax.max(x0), bx.min(x1));
        if hi <= lo {
            continue;
        }
        let at = |x: f32| ay + (by - ay) * (x - ax) / (bx - ax);
        let (ylo, yhi) = (at(lo), at(hi));
        if ylo * yhi < 0.0 {
            let zero = lo + (hi - lo) * ylo / (ylo - yhi);
            add(lo, ylo, zero, 0.0);
            add(zero, 0.0, hi, yhi);
        } else {
            add(lo, ylo, hi, yhi);
        }
    }
    area
}

/// What the three morphological passes (MLAA's and SMAA's) are built from: one WGSL module
/// with the entry points `edge_entry`, `fs_weights` and `fs_blend`, a layout per pass and the
/// override constants they share.
pub struct MorphologicalDesc<'a> {
    /// Starts the pipelines' labels (the technique's id).
    pub prefix: &'a str,
    /// The module with the three entry points.
    pub module: &'a wgpu::ShaderModule,
    /// The edge pass's entry point.
    pub edge_entry: &'a str,
    /// The edge, weight and blend passes' layouts.
    pub layouts: [&'a wgpu::BindGroupLayout; 3],
    /// WGSL override constants.
    pub constants: &'a [(&'a str, f64)],
    /// The blend pass's target format: display values, or radiance before the tonemapper
    /// (`super::output_format`).
    pub blend_format: wgpu::TextureFormat,
}

/// The pipelines of the three morphological passes.
pub struct MorphologicalPipelines {
    /// Finds the edges and marks them in the stencil.
    pub edges: wgpu::RenderPipeline,
    /// Computes the blending weights on the marked pixels.
    pub weights: wgpu::RenderPipeline,
    /// Blends each pixel with its neighbours by the weights.
    pub blend: wgpu::RenderPipeline,
}

impl Vertex {
    /// Builds the three morphological passes' pipelines.
    pub fn morphological(
        &self,
        device: &wgpu::Device,
        desc: &MorphologicalDesc<'_>,
    ) -> MorphologicalPipelines {
        let [edge_layout, weight_layout, blend_layout] = desc.layouts;
        let build = |pass: &str, entry_point: &str, layout, format, stencil| {
            self.pipeline(
                device,
                &PassDesc {
                    label: &format!("{} {pass}", desc.prefix),
                    module: desc.module,
                    entry_point,
                    layout,
                    format,
                    constants: desc.constants,
                    stencil,
                },
            )
        };
        MorphologicalPipelines {
            edges: build(
                "edges",
                desc.edge_entry,
                edge_layout,
                wgpu::TextureFormat::Rg8Unorm,
                Stencil::Mark,
            ),
            weights: build(
                "weights",
                "fs_weights",
                weight_layout,
                wgpu::TextureFormat::Rgba8Unorm,
                Stencil::Test,
            ),
            blend: build(
                "blend",
                "fs_blend",
                blend_layout,
                desc.blend_format,
                Stencil::None,
            ),
        }
    }

    /// The two debug-view pipelines of a morphological technique, `fs_debug_edges` and
    /// `fs_debug_weights` of `module`, each reading one texture through `layout` and writing
    /// encoded colour.
    pub fn debug_pipelines(
        &self,
        device: &wgpu::Device,
        module: &wgpu::ShaderModule,
        layout: &wgpu::BindGroupLayout,
    ) -> [wgpu::RenderPipeline; 2] {
        ["fs_debug_edges", "fs_debug_weights"].map(|entry_point| {
            self.pipeline(
                device,
                &PassDesc {
                    label: entry_point,
                    module,
                    entry_point,
                    layout,
                    format: crate::gpu::COLOR_FORMAT_ENCODED_VIEW,
                    constants: &[],
                    stencil: Stencil::None,
                },
            )
        })
    }
}

/// The working textures of the morphological passes, all of the output's size: the edges,
/// the stencil the edge pass marks them in, and the blending weights.
pub struct EdgeTargets {
    /// Their size.
    pub size: (u32, u32),
    /// Edges (red: left side, green: top side).
    pub edges: wgpu::Texture,
    /// The edge mask.
    pub stencil: wgpu::Texture,
    /// Blending weights.
    pub weights: wgpu::Texture,
}

/// Views of [`EdgeTargets`] for one run.
pub struct EdgeViews {
    /// The edges.
    pub edges: wgpu::TextureView,
    /// The edge mask.
    pub stencil: wgpu::TextureView,
    /// The blending weights.
    pub weights: wgpu::TextureView,
}

impl EdgeTargets {
    /// The targets at `size`, labelled after `prefix` (the technique's id).
    pub fn new(device: &wgpu::Device, prefix: &str, size: (u32, u32)) -> Self {
        let target =
            |name: &str, format| target(device, &format!("{prefix} {name}"), size, format, &[]);
        Self {
            size,
            edges: target("edges", wgpu::TextureFormat::Rg8Unorm),
            stencil: target("edge stencil", STENCIL_FORMAT),
            weights: target("weights", wgpu::TextureFormat::Rgba8Unorm),
        }
    }

    /// Views for one run.
    pub fn views(&self) -> EdgeViews {
        let view = |texture: &wgpu::Texture| texture.create_view(&Default::default());
        EdgeViews {
            edges: view(&self.edges),
            stencil: view(&self.stencil),
            weights: view(&self.weights),
        }
    }

    /// Their memory, labelled after `prefix`.
    pub fn memory(&self, prefix: &str) -> [MemoryItem; 3] {
        [
            MemoryItem::texture(format!("{prefix} edges"), &self.edges),
            MemoryItem::texture(format!("{prefix} edge stencil"), &self.stencil),
            MemoryItem::texture(format!("{prefix} weights"), &self.weights),
        ]
    }
}

/// Records the edge pass (it clears the stencil and marks the edge pixels) and the weight pass
/// (only on the marked pixels), named `{prefix}edges` and `{prefix}weights` in the timings.
pub fn edge_and_weight_passes(
    ctx: &mut PassContext<'_>,
    prefix: &str,
    views: &EdgeViews,
    pipelines: &MorphologicalPipelines,
    [edge_group, weight_group]: [&wgpu::BindGroup; 2],
) {
    stencil_pass(
        ctx,
        &format!("{prefix}edges"),
        &views.edges,
        &views.stencil,
        wgpu::LoadOp::Clear(0),
        (&pipelines.edges, edge_group),
    );
    stencil_pass(
        ctx,
        &format!("{prefix}weights"),
        &views.weights,
        &views.stencil,
        wgpu::LoadOp::Load,
        (&pipelines.weights, weight_group),
    );
}

/// The debug views of a morphological technique: its edges and blending weights as images.
pub struct EdgeDebugViews {
    /// The edges.
    pub edges: wgpu::Texture,
    /// The blending weights.
    pub weights: wgpu::Texture,
}

impl EdgeDebugViews {
    /// The views at `size`, labelled after `prefix`.
    pub fn new(device: &wgpu::Device, prefix: &str, size: (u32, u32)) -> Self {
        Self {
            edges: debug_texture(device, &format!("{prefix} edges view"), size),
            weights: debug_texture(device, &format!("{prefix} weights view"), size),
        }
    }

    /// Records both views of `targets`' last run with the [`Vertex::debug_pipelines`], which
    /// read their source at `binding`.
    pub fn encode(
        &self,
        ctx: &mut PassContext<'_>,
        targets: &EdgeTargets,
        pipelines: &[wgpu::RenderPipeline; 2],
        binding: u32,
    ) {
        let views = [
            ("debug edges", &targets.edges, &self.edges),
            ("debug weights", &targets.weights, &self.weights),
        ];
        for ((name, source, view), pipeline) in views.into_iter().zip(pipelines) {
            let source = source.create_view(&Default::default());
            let group = bind_group(
                &ctx.gpu.device,
                name,
                &pipeline.get_bind_group_layout(0),
                &[(binding, wgpu::BindingResource::TextureView(&source))],
            );
            let target = view_as(view, crate::gpu::COLOR_FORMAT_ENCODED_VIEW);
            ctx.fullscreen_pass(name, &target, pipeline, &group);
        }
    }

    /// Their memory, labelled after `prefix`.
    pub fn memory(&self, prefix: &str) -> [MemoryItem; 2] {
        [
            MemoryItem::texture(format!("{prefix} edges view"), &self.edges),
            MemoryItem::texture(format!("{prefix} weights view"), &self.weights),
        ]
    }
}
