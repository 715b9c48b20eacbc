//! CMAA 2 settings: Intel's four quality presets (they set the edge threshold) and a
//! texture-safe one (high with extra sharpness, docs/hard-cases.md measures it), the extra
//! sharpness switch (a second set of Intel's constants that keeps more text and shape detail),
//! the edge-detection input, every parameter as data for the CLI, viewer and sidecars (its
//! [`Tunable`] implementation), and the
//! uniform block the passes read. Nothing here selects a pipeline: every setting is a uniform
//! value used in arithmetic or `select`, so changing one costs no pipeline build.

use crate::aa::params::{Param, ParamValue, Tunable};
use crate::graph::hdr::TonemapOrder;

crate::named_enum! {
    /// Intel's quality presets, which differ only in the edge threshold.
    pub enum Quality {
        /// Threshold 0.15: only strong edges.
        Low => "low",
        /// Threshold 0.10.
        Medium => "medium",
        /// Threshold 0.07 (Intel's default).
        High => "high",
        /// Threshold 0.05: faint edges too.
        Ultra => "ultra",
    }
}

/// CMAA 2's presets: Intel's four qualities (the edge threshold), and texture-safe, quality
/// high with Intel's extra sharpness.
pub use crate::aa::common::morphology::QualityPreset as Preset;

impl From<Preset> for Quality {
    fn from(preset: Preset) -> Self {
        match preset {
            Preset::Low => Self::Low,
            Preset::Medium => Self::Medium,
            Preset::High | Preset::TextureSafe => Self::High,
            Preset::Ultra => Self::Ultra,
        }
    }
}

impl Quality {
    /// Smallest difference of sRGB-encoded luma (or colour) between two pixels that counts as
    /// an edge.
    pub fn edge_threshold(self) -> f32 {
        match self {
            Self::Low => 0.15,
            Self::Medium => 0.10,
            Self::High => 0.07,
            Self::Ultra => 0.05,
        }
    }
}

crate::named_enum! {
    /// What the edge detection compares between neighbours (both on sRGB-encoded values).
    pub enum EdgeDetection {
        /// The difference of BT.601 luma (Intel's default path).
        Luma => "luma",
        /// The luma-weighted sum of the three channel differences (also finds edges between
        /// colours of equal luma).
        Color => "color",
    }
}

/// Every CMAA 2 setting.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Cmaa2Settings {
    /// Quality preset (the edge threshold).
    pub quality: Quality,
    /// Intel's `CMAA2_EXTRA_SHARPNESS`: stronger local contrast adaptation, gentler corner
    /// blends, shorter blend ramps.
    pub extra_sharpness: bool,
    /// What edge detection compares.
    pub edge_detection: EdgeDetection,
    /// In HDR frames, before or after the tonemapper (after, as engines run it).
    pub tonemap_order: TonemapOrder,
}

impl Default for Cmaa2Settings {
    /// Intel's defaults: quality high, normal sharpness, luma edges.
    fn default() -> Self {
        Self {
            quality: Quality::High,
            extra_sharpness: false,
            edge_detection: EdgeDetection::Luma,
            tonemap_order: TonemapOrder::After,
        }
    }
}

/// Intel's constants of one sharpness setting.
struct Sharpness {
    /// How much a stronger edge touching an edge's ends raises its threshold (times its
    /// contrast).
    local_contrast_adaptation: f32,
    /// Strength of the corner (simple-shape) blend.
    simple_shape_blur: f32,
    /// Corner blends fade out as `base - edges around / divisor` (busy regions keep detail).
    neighbour_damping: (f32, f32),
    /// The edge trace stops when the longer run exceeds this times the shorter one.
    run_ratio: f32,
    /// Z-ramp strength per pixel of run length (short runs blend less).
    z_damping: f32,
    /// Shape quality rounded (true) or floored from the Z score.
    round_shape_quality: bool,
}

const NORMAL: Sharpness = Sharpness {
    local_contrast_adaptation: 0.10,
    simple_shape_blur: 0.10,
    neighbour_damping: (1.30, 10.0),
    run_ratio: 1.3,
    z_damping: 0.15,
    round_shape_quality: false,
};

const SHARP: Sharpness = Sharpness {
    local_contrast_adaptation: 0.15,
    simple_shape_blur: 0.07,
    neighbour_damping: (1.15, 8.0),
    run_ratio: 1.25,
    z_damping: 0.11,
    round_shape_quality: true,
};

/// The uniform block of `cmaa2.wgsl` (`Params`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Cmaa2Uniform {
    size: [u32; 4],
    edges: [f32; 4],
    shapes: [f32; 4],
    lines: [f32; 4],
}

impl Cmaa2Settings {
    /// The uniform block for an image of `size`.
    pub fn uniform(&self, size: (u32, u32)) -> Cmaa2Uniform {
        let s = if self.extra_sharpness { SHARP } else { NORMAL };
        let flag = |on: bool| f32::from(u8::from(on));
        Cmaa2Uniform {
            size: [size.0, size.1, size.0 * size.1, 0],
            edges: [
                self.quality.edge_threshold(),
                s.local_contrast_adaptation,
                flag(self.edge_detection == EdgeDetection::Color),
                0.0,
            ],
            shapes: [
                s.simple_shape_blur,
                s.neighbour_damping.0,
                s.neighbour_damping.1,
                flag(s.round_shape_quality),
            ],
            lines: [s.run_ratio, s.z_damping, 0.0, 0.0],
        }
    }
}

impl Tunable for Cmaa2Settings {
    type Preset = Preset;

    fn params(&self) -> Vec<Param> {
        vec![
            Param::named(
                "quality",
                "Quality preset",
                "Intel's presets, which set the edge threshold on sRGB-encoded luma: low 0.15 \
                 (strong edges only), medium 0.10, high 0.07 (default), ultra 0.05 (faint edges \
                 too, a little more texture touched).",
                self.quality,
            ),
            Param::bool(
                "extra_sharpness",
                "Extra sharpness",
                "Intel's extra-sharpness constants: stronger local contrast adaptation, gentler \
                 corner blends and shorter blend ramps keep more text and shape detail for a \
                 little less antialiasing.",
                self.extra_sharpness,
            ),
            Param::named(
                "edge_detection",
                "Edge detection",
                "luma compares the BT.601 luma of neighbours (Intel's default); color sums their \
                 luma-weighted channel differences and also finds edges between colours of equal \
                 brightness.",
                self.edge_detection,
            ),
            self.tonemap_order.param(),
        ]
    }

    fn set(&mut self, key: &str, value: &ParamValue) -> bool {
        crate::set_fields!(
            self,
            key,
            value,
            [quality, extra_sharpness, edge_detection, tonemap_order]
        )
    }

    /// Sets the quality (the edge threshold), keeping the edge input and the tonemap order;
    /// Intel's four keep the sharpness too, texture-safe turns extra sharpness on.
    fn apply_preset(&mut self, preset: Preset) {
        self.quality = preset.into();
        if preset == Preset::TextureSafe {
            self.extra_sharpness = true;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::aa::params::Named;

    #[test]
    fn presets_lower_the_threshold_in_order_and_keep_the_other_settings() {
        let thresholds: Vec<f32> = Quality::ALL.iter().map(|q| q.edge_threshold()).collect();
        assert_eq!(thresholds, [0.15, 0.10, 0.07, 0.05]);
        for name in Quality::NAMES {
            assert!(Preset::NAMES.contains(name));
            let mut settings = Cmaa2Settings {
                extra_sharpness: true,
                edge_detection: EdgeDetection::Color,
                ..Cmaa2Settings::default()
            };
            settings
                .apply_preset_named("cmaa2", name)
                .expect("listed preset");
            assert_eq!(settings.quality.name(), *name);
            assert!(settings.extra_sharpness);
            assert_eq!(settings.edge_detection, EdgeDetection::Color);
        }
        assert!(
            Cmaa2Settings::default()
                .apply_preset_named("cmaa2", "extreme")
                .is_err()
        );
        let mut safe = Cmaa2Settings::default();
        safe.apply_preset_named("cmaa2", "texture-safe")
            .expect("listed preset");
        assert_eq!((safe.quality, safe.extra_sharpness), (Quality::High, true));
        assert_eq!(Cmaa2Settings::default().quality, Quality::High);
    }

    #[test]
    fn the_uniform_carries_size_threshold_and_sharpness_constants() {
        let mut settings = Cmaa2Settings::default();
        let normal = settings.uniform((640, 360));
        assert_eq!(normal.size, [640, 360, 640 * 360, 0]);
        assert_eq!(normal.edges[0], 0.07);
        settings.extra_sharpness = true;
        settings.edge_detection = EdgeDetection::Color;
        let sharp = settings.uniform((640, 360));
        assert!(sharp.edges[1] > normal.edges[1], "stronger adaptation");
        assert!(sharp.shapes[0] < normal.shapes[0], "gentler corners");
        assert_eq!((sharp.edges[2], sharp.shapes[3]), (1.0, 1.0));
    }
}
