//! The user-interface overlay: a game-like heads-up display (text at two sizes, a translucent
//! panel, a one-pixel crosshair and a framed bar) composited over every frame, either
//! **before** the antialiasing (over the scene renders the techniques read, as an engine that
//! draws its UI before the post-process pass) or **after** it (over each technique's output,
//! where engines should draw it). Side by side the two show the blur and the smear a post or
//! temporal pass puts on UI drawn before it, and the metrics measure it.
//!
//! How: the HUD is drawn once per output size on the CPU ([`hud`], with egui's bundled Hack
//! font through [`crate::text`]) into an sRGB texture with straight alpha. A
//! full-screen pass blends it in linear light over a target: over every pooled scene input
//! (multisampled ones too: every sample gets the overlay, and their single-sample resolve is
//! redone by the pass) when it goes before, and over each technique's output when it goes
//! after. Techniques that render their own scene (SSAA, the 64-sample reference) read no pooled
//! input, so they get the overlay over their output in both orders: the reference always shows
//! the UI as a UI pass after the resolve draws it. The overlay writes no depth and no motion:
//! like an engine's UI drawn into the scene colour, it moves with the scene's motion vectors
//! under a temporal technique.

use image::{Rgba, RgbaImage};

use crate::gpu::{self, Gpu, fullscreen::Fullscreen};
use crate::text::Typeface;

crate::named_enum! {
    /// Where the UI overlay is drawn (see the module docs).
    #[derive(serde::Serialize, serde::Deserialize)]
    #[serde(rename_all = "lowercase")]
    pub enum OverlayOrder {
        /// Over the scene renders, before the antialiasing (post and temporal passes blur and
        /// smear it).
        Before => "before",
        /// Over each technique's output, after the antialiasing (the UI stays exact).
        After => "after",
    }
}

/// The overlay's texture and pipelines (one per target sample count).
pub(super) struct OverlayPass {
    order: Option<OverlayOrder>,
    layout: wgpu::BindGroupLayout,
    sampler: wgpu::Sampler,
    module: wgpu::ShaderModule,
    pipelines: Vec<(u32, wgpu::RenderPipeline)>,
    /// The HUD at an output size, uploaded, with its bind group.
    texture: Option<((u32, u32), wgpu::Texture, wgpu::BindGroup)>,
}

impl OverlayPass {
    pub(super) fn new(device: &wgpu::Device) -> Self {
        let entry = |binding, ty| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty,
            count: None,
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("overlay"),
            entries: &[
                entry(
                    0,
                    wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                ),
                entry(
                    1,
                    wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                ),
            ],
        });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("overlay"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        Self {
            order: None,
            layout,
            sampler,
            module: gpu::shader::module(device, "overlay.wgsl"),
            pipelines: Vec::new(),
            texture: None,
        }
    }

    pub(super) fn order(&self) -> Option<OverlayOrder> {
        self.order
    }

    /// Sets where the overlay goes (`None`: no overlay); its texture is released when off.
    pub(super) fn set_order(&mut self, order: Option<OverlayOrder>) {
        self.order = order;
        if order.is_none() {
            self.texture = None;
        }
    }

    /// Bytes of the uploaded HUD texture.
    pub(super) fn memory_bytes(&self) -> u64 {
        self.texture
            .as_ref()
            .map_or(0, |((w, h), _, _)| u64::from(*w) * u64::from(*h) * 4)
    }

    /// Makes sure the HUD of output size `size` is uploaded (drawn again only on a resize)
    /// and a pipeline exists for every sample count of `sample_counts`.
    pub(super) fn prepare(
        &mut self,
        gpu: &Gpu,
        fullscreen: &Fullscreen,
        size: (u32, u32),
        sample_counts: impl IntoIterator<Item = u32>,
    ) {
        if self.order.is_none() {
            return;
        }
        for samples in sample_counts {
            if !self.pipelines.iter().any(|(n, _)| *n == samples) {
                let pipeline = self.pipeline(gpu, fullscreen, samples);
                self.pipelines.push((samples, pipeline));
            }
        }
        if self.texture.as_ref().is_some_and(|(s, _, _)| *s == size) {
            return;
        }
        let texture = gpu::texture_2d(
            &gpu.device,
            &gpu::Texture2d::new(
                "overlay",
                size,
                gpu::COLOR_FORMAT,
                wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            ),
        );
        gpu::write_rgba8(gpu, &texture, &hud(size));
        let view = texture.create_view(&Default::default());
        let bind_group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("overlay"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&view),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::Sampler(&self.sampler),
                },
            ],
        });
        self.texture = Some((size, texture, bind_group));
    }

    fn pipeline(&self, gpu: &Gpu, fullscreen: &Fullscreen, samples: u32) -> wgpu::RenderPipeline {
        let layout = gpu
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("overlay"),
                bind_group_layouts: &[Some(&self.layout)],
                immediate_size: 0,
            });
        // Straight alpha over the target's colour; the target's alpha is kept.
        let blend = wgpu::BlendState {
            color: wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::SrcAlpha,
                dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
                operation: wgpu::BlendOperation::Add,
            },
            alpha: wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::Zero,
                dst_factor: wgpu::BlendFactor::One,
                operation: wgpu::BlendOperation::Add,
            },
        };
        let fragment = gpu::fullscreen::FragmentDesc {
            label: "overlay",
            module: &self.module,
            entry_point: "fs_overlay",
            targets: &[gpu::COLOR_FORMAT],
            constants: &[],
            layout: Some(&layout),
        };
        fullscreen.pipeline_blended(&gpu.device, &fragment, blend, samples)
    }

    /// Blends the overlay over `color` (its single-sample resolve, if any, is written again
    /// into `resolved`); nothing when the overlay is off or its pipeline was not prepared.
    pub(super) fn composite(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        color: &wgpu::Texture,
        resolved: Option<&wgpu::Texture>,
    ) {
        let Some((_, _, bind_group)) = &self.texture else {
            return;
        };
        let samples = color.sample_count();
        let Some((_, pipeline)) = self.pipelines.iter().find(|(n, _)| *n == samples) else {
            return;
        };
        let view = color.create_view(&Default::default());
        let resolve_view = resolved.map(|r| r.create_view(&Default::default()));
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("overlay"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &view,
                depth_slice: None,
                resolve_target: resolve_view.as_ref(),
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            ..Default::default()
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.draw(0..3, 0..1);
    }
}

/// The HUD at `size` (straight alpha, sRGB-encoded): laid out for 1280x720 and scaled with
/// the height, as games scale their UI, with text no smaller than 9 pixels.
pub fn hud((width, height): (u32, u32)) -> RgbaImage {
    let mut image = RgbaImage::new(width, height);
    let scale = height as f32 / 720.0;
    let at = |v: f32| (v * scale).round() as i64;
    let white = Rgba([255, 255, 255, 255]);
    // A translucent panel behind the top-left text.
    fill(
        &mut image,
        (at(16.0), at(16.0)),
        (at(420.0), at(108.0)),
        Rgba([10, 14, 24, 150]),
    );
    let large = (22.0 * scale).max(9.0);
    let small = (14.0 * scale).max(9.0);
    text(
        &mut image,
        "AA-LAB  UI OVERLAY",
        (at(28.0), at(24.0)),
        large,
        white,
    );
    text(
        &mut image,
        "FPS 144   6.9 ms   GPU 71%",
        (at(28.0), at(56.0)),
        small,
        white,
    );
    text(
        &mut image,
        "The quick brown fox jumps 0123456789",
        (at(28.0), at(80.0)),
        small,
        Rgba([255, 214, 90, 255]),
    );
    // A one-pixel crosshair with a gap, at the centre.
    let (cx, cy) = (i64::from(width / 2), i64::from(height / 2));
    let (gap, arm) = (at(5.0).max(2), at(16.0).max(4));
    for d in gap..=arm {
        for (x, y) in [(cx + d, cy), (cx - d, cy), (cx, cy + d), (cx, cy - d)] {
            put(&mut image, x, y, white);
        }
    }
    // A framed bar at the bottom: a one-pixel outline, two thirds filled.
    let (x0, y0) = (at(40.0), i64::from(height) - at(48.0));
    let (x1, y1) = (at(360.0), i64::from(height) - at(32.0));
    for x in x0..=x1 {
        put(&mut image, x, y0, white);
        put(&mut image, x, y1, white);
    }
    for y in y0..=y1 {
        put(&mut image, x0, y, white);
        put(&mut image, x1, y, white);
    }
    let filled = x0 + 2 + (x1 - x0 - 4) * 2 / 3;
    fill(
        &mut image,
        (x0 + 2, y0 + 2),
        (filled, y1 - 2),
        Rgba([220, 60, 60, 255]),
    );
    text(
        &mut image,
        "HP 67/100",
        (x1 + at(12.0), y0 - at(2.0)),
        small,
        white,
    );
    image
}

/// Draws `line` with its top-left corner at `(x, y)`, `px` pixels high.
fn text(image: &mut RgbaImage, line: &str, (x, y): (i64, i64), px: f32, colour: Rgba<u8>) {
    Typeface::mono().coverage(x as f32, y as f32, px, line, |px_x, px_y, coverage| {
        let mut covered = colour;
        covered[3] = (coverage.clamp(0.0, 1.0) * f32::from(colour[3])).round() as u8;
        over(image, px_x, px_y, covered);
    });
}

/// Fills the rectangle from `min` to `max` (inclusive) with `colour`.
fn fill(image: &mut RgbaImage, min: (i64, i64), max: (i64, i64), colour: Rgba<u8>) {
    for y in min.1..=max.1 {
        for x in min.0..=max.0 {
            put(image, x, y, colour);
        }
    }
}

/// Sets a pixel, ignoring positions outside the image.
fn put(image: &mut RgbaImage, x: i64, y: i64, colour: Rgba<u8>) {
    if let (Ok(x), Ok(y)) = (u32::try_from(x), u32::try_from(y))
        && x < image.width()
        && y < image.height()
    {
        image.put_pixel(x, y, colour);
    }
}

/// Draws `colour` (straight alpha) over a pixel of the overlay, keeping the result straight.
fn over(image: &mut RgbaImage, x: i64, y: i64, colour: Rgba<u8>) {
    let (Ok(ux), Ok(uy)) = (u32::try_from(x), u32::try_from(y)) else {
        return;
    };
    let Some(below) = image.get_pixel_checked(ux, uy).copied() else {
        return;
    };
    let (a, b) = (f32::from(colour[3]) / 255.0, f32::from(below[3]) / 255.0);
    let alpha = a + b * (1.0 - a);
    if alpha <= 0.0 {
        return;
    }
    let mut out = Rgba([0, 0, 0, (alpha * 255.0).round() as u8]);
    for c in 0..3 {
        let mixed = (f32::from(colour[c]) * a + f32::from(below[c]) * b * (1.0 - a)) / alpha;
        out[c] = mixed.round() as u8;
    }
    image.put_pixel(ux, uy, out);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hud_has_text_a_crosshair_and_transparent_space() {
        let image = hud((640, 360));
        let transparent = image.pixels().filter(|p| p[3] == 0).count();
        let partly = image.pixels().filter(|p| p[3] > 0 && p[3] < 255).count();
        let opaque_white = image
            .pixels()
            .filter(|p| p[3] == 255 && p[0] == 255 && p[1] == 255 && p[2] == 255)
            .count();
        assert!(
            transparent > image.len() / 4 * 3 / 4,
            "{transparent} transparent"
        );
        // Antialiased glyph edges and the panel are partly covered.
        assert!(partly > 1000, "{partly} partly covered");
        assert!(opaque_white > 200, "{opaque_white} white");
        // The crosshair's arms, not its centre.
        assert_eq!(image.get_pixel(320 + 6, 180)[3], 255);
        assert_eq!(image.get_pixel(320, 180)[3], 0);
    }

    #[test]
    fn the_hud_scales_with_the_height_and_survives_tiny_sizes() {
        let small = hud((320, 180));
        let large = hud((1280, 720));
        let covered = |i: &RgbaImage| i.pixels().filter(|p| p[3] > 0).count() as f64;
        let ratio = covered(&large) / covered(&small);
        assert!((10.0..22.0).contains(&ratio), "coverage ratio {ratio}");
        for size in [(1, 1), (7, 3)] {
            assert_eq!(hud(size).dimensions(), size);
        }
    }
}
