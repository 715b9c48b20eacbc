//! SMAA settings: the quality presets of the paper and a texture-safe one (High with depth
//! predication tuned so that texture detail is left alone), every parameter as data for the CLI,
//! viewer and sidecars (its [`Tunable`] implementation; [`SmaaSettings::params_for`] those of
//! one mode), and the split between settings that change pipelines ([`PipelineKey`], WGSL
//! override constants) and those that only change a uniform.

use crate::aa::params::{Named, Param, ParamField, ParamValue, Tunable, as_i64};

use super::lut::MAX_DIAG_DISTANCE;
/// SMAA's presets (threshold / search steps / diagonal steps / corner rounding): Low
/// .15/4/off/off, Medium .10/8/off/off, High .10/16/8/25 (diagonals and sharp corners, the
/// reference implementation's default), Ultra .05/32/16/25; TextureSafe is High with depth
/// predication (depth step 0.001, scale 3, strength 0.7): edges inside textures need three
/// times the threshold, edges where depth steps 0.3 of that.
pub use crate::aa::common::morphology::QualityPreset as Preset;
use crate::graph::hdr::TonemapOrder;

crate::named_enum! {
    /// What the edge-detection pass compares between neighbours.
    pub enum EdgeMode {
        /// Perceived brightness of the sRGB-encoded colour (the recommended mode).
        Luma => "luma",
        /// The largest difference of the three sRGB-encoded channels.
        Color => "color",
        /// Scene depth: only geometric edges, no shading or texture edges.
        Depth => "depth",
    }
}

/// Largest orthogonal search, in steps of two pixels (the area table covers 225 pixels).
pub const MAX_SEARCH_STEPS: u32 = 112;

/// Every SMAA setting.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SmaaSettings {
    /// Edge-detection threshold on sRGB-encoded luma or colour (depth uses a tenth of it).
    pub threshold: f32,
    /// Orthogonal search steps per direction (two pixels each).
    pub max_search_steps: u32,
    /// Detect 45-degree staircases and blend them along the diagonal.
    pub diagonal_detection: bool,
    /// Diagonal search steps per direction (one pixel each).
    pub max_search_steps_diag: u32,
    /// Keep sharp corners of shapes sharp.
    pub corner_detection: bool,
    /// How much of a detected corner is still rounded, in percent.
    pub corner_rounding: u32,
    /// What the edge detection compares.
    pub edge_mode: EdgeMode,
    /// Local contrast adaptation: an edge is dropped when a neighbouring edge is more than
    /// this many times stronger.
    pub local_contrast_factor: f32,
    /// Use depth edges to lower the colour threshold where geometry meets (predication).
    pub predication: bool,
    /// Depth difference counted as a geometric edge for predication.
    pub predication_threshold: f32,
    /// Threshold scale away from geometric edges.
    pub predication_scale: f32,
    /// How much a geometric edge lowers the scaled threshold (0..1).
    pub predication_strength: f32,
    /// T2x: how fast the history weight drops when the speed of a pixel changes between
    /// frames (0 ignores velocity).
    pub reprojection_weight_scale: f32,
    /// T2x: texture mip bias of the jittered render (its two samples per pixel average away
    /// the extra texture aliasing of a sharper mip level).
    pub mip_bias: f32,
    /// In HDR frames, before or after the tonemapper (after, as engines run it).
    pub tonemap_order: TonemapOrder,
}

/// The settings only SMAA T2x has.
pub const TEMPORAL_KEYS: &[&str] = &["reprojection_weight_scale", "mip_bias"];

impl SmaaSettings {
    /// The settings of a preset.
    pub fn preset(preset: Preset) -> Self {
        let (threshold, max_search_steps, diagonal, corner) = match preset {
            Preset::Low => (0.15, 4, None, None),
            Preset::Medium => (0.10, 8, None, None),
            Preset::High | Preset::TextureSafe => (0.10, 16, Some(8), Some(25)),
            Preset::Ultra => (0.05, 32, Some(16), Some(25)),
        };
        let texture_safe = preset == Preset::TextureSafe;
        Self {
            threshold,
            max_search_steps,
            diagonal_detection: diagonal.is_some(),
            max_search_steps_diag: diagonal.unwrap_or(8),
            corner_detection: corner.is_some(),
            corner_rounding: corner.unwrap_or(25),
            edge_mode: EdgeMode::Luma,
            local_contrast_factor: 2.0,
            predication: texture_safe,
            predication_threshold: if texture_safe { 0.001 } else { 0.01 },
            predication_scale: if texture_safe { 3.0 } else { 2.0 },
            predication_strength: if texture_safe { 0.7 } else { 0.4 },
            reprojection_weight_scale: 30.0,
            mip_bias: -0.5,
            tonemap_order: TonemapOrder::After,
        }
    }

    /// The preset these settings equal, if any (otherwise they are custom); texture-safe
    /// before High, which it extends.
    pub fn matching_preset(&self) -> Option<Preset> {
        Preset::ALL.iter().rev().copied().find(|&p| {
            let mut probe = *self;
            probe.apply_preset(p);
            probe == *self
        })
    }

    /// Depth threshold of the depth edge mode (a tenth of the colour threshold, on reverse-Z
    /// depth, which differs from a conventional depth buffer only in sign).
    pub fn depth_threshold(&self) -> f32 {
        0.1 * self.threshold
    }

    /// Diagonal search steps the weight pass runs (0 when diagonals are off).
    pub fn diagonal_steps(&self) -> u32 {
        if self.diagonal_detection {
            self.max_search_steps_diag.min(MAX_DIAG_DISTANCE)
        } else {
            0
        }
    }

    /// The part of the settings compiled into pipelines.
    pub fn pipeline_key(&self) -> PipelineKey {
        PipelineKey {
            edge_mode: self.edge_mode,
            predication: self.predication && self.edge_mode != EdgeMode::Depth,
            max_search_steps: self.max_search_steps,
            diagonal_steps: self.diagonal_steps(),
            corner_detection: self.corner_detection,
        }
    }

    /// Every parameter with its current value; `temporal` adds the resolve settings of the
    /// temporal modes (T2x, 4x), which the others do not have.
    pub fn params_for(&self, temporal: bool) -> Vec<Param> {
        let mut params = vec![
            Param::float(
                "threshold",
                "Threshold",
                "Smallest brightness (or colour) step between neighbours that counts as an edge, on \
                 sRGB-encoded values. Lower finds more edges, including soft ones, at more cost. Presets: \
                 low 0.15, medium and high 0.10, ultra 0.05.",
                0.01,
                0.5,
                self.threshold,
            ),
            Param::int(
                "max_search_steps",
                "Search steps",
                "How far along an edge the pass looks for its ends, in steps of two pixels each way. Longer \
                 searches smooth longer, flatter staircases (nearly horizontal or vertical edges) correctly.",
                1,
                i64::from(MAX_SEARCH_STEPS),
                i64::from(self.max_search_steps),
            ),
            Param::bool(
                "diagonal_detection",
                "Diagonals",
                "Recognise 45-degree staircases and blend them along the diagonal, which keeps diagonal \
                 lines straight and sharp instead of wavy.",
                self.diagonal_detection,
            ),
            Param::int(
                "max_search_steps_diag",
                "Diagonal steps",
                "How far along a diagonal the pass looks for its ends, in pixels each way.",
                1,
                i64::from(MAX_DIAG_DISTANCE),
                i64::from(self.max_search_steps_diag),
            ),
            Param::bool(
                "corner_detection",
                "Sharp corners",
                "Recognise real corners of shapes (an edge turning for two pixels or more) and blend them \
                 less, so boxes and text keep their corners.",
                self.corner_detection,
            ),
            Param::int(
                "corner_rounding",
                "Corner rounding",
                "Percentage of the blending kept at a detected corner: 0 keeps corners perfectly sharp, \
                 100 rounds them like any other edge.",
                0,
                100,
                i64::from(self.corner_rounding),
            ),
            Param::named(
                "edge_detection",
                "Edge detection",
                "What is compared between neighbours: luma (brightness; finds shading and texture edges \
                 too, the recommended mode), color (largest channel step; a little more sensitive to \
                 chroma-only edges) or depth (geometric edges only; misses edges between surfaces at the \
                 same depth and inside textures).",
                self.edge_mode,
            ),
            Param::float(
                "local_contrast_factor",
                "Local contrast",
                "Local contrast adaptation: an edge is ignored when a neighbouring edge is more than this \
                 many times stronger, so that a faint edge beside a strong one is not blended. Large values \
                 switch it off.",
                1.0,
                100.0,
                self.local_contrast_factor,
            ),
            Param::bool(
                "predication",
                "Predication",
                "Luma and color modes: use depth as a hint. Away from geometric edges the threshold is \
                 raised (fewer false edges in textures); across them it is lowered (faint silhouettes \
                 are caught).",
                self.predication,
            ),
            Param::float(
                "predication_threshold",
                "Predication depth threshold",
                "Depth step (reverse-Z) that counts as a geometric edge for predication.",
                0.0,
                1.0,
                self.predication_threshold,
            ),
            Param::float(
                "predication_scale",
                "Predication scale",
                "Factor on the threshold with predication on.",
                1.0,
                5.0,
                self.predication_scale,
            ),
            Param::float(
                "predication_strength",
                "Predication strength",
                "How much a geometric edge lowers the scaled threshold again (0 none, 1 to zero).",
                0.0,
                1.0,
                self.predication_strength,
            ),
            self.tonemap_order.param(),
        ];
        if temporal {
            params.push(Param::float(
                "reprojection_weight_scale",
                "Velocity weighting",
                "The previous frame counts half, less where the pixel's speed changed between the two \
                 frames (it was probably covered by something else): higher values drop it sooner, 0 \
                 ignores velocity.",
                0.0,
                80.0,
                self.reprojection_weight_scale,
            ));
            params.push(Param::float(
                "mip_bias",
                "Texture mip bias",
                "Texture level-of-detail bias of the jittered render. A one-sample render filters \
                 textures to its pixel footprint, softer than a supersampled image; T2x averages \
                 two samples per pixel, which absorbs the extra aliasing of a sharper mip level, \
                 so a negative bias keeps its textures as sharp as the reference's.",
                -2.0,
                0.0,
                self.mip_bias,
            ));
        }
        params
    }
}

impl Tunable for SmaaSettings {
    type Preset = Preset;

    /// Every parameter, the temporal modes' included ([`SmaaSettings::params_for`]).
    fn params(&self) -> Vec<Param> {
        self.params_for(true)
    }

    fn set(&mut self, key: &str, value: &ParamValue) -> bool {
        let steps = |v: &ParamValue, max: u32| as_i64(v).clamp(1, i64::from(max)) as u32;
        match key {
            "max_search_steps" => self.max_search_steps = steps(value, MAX_SEARCH_STEPS),
            "max_search_steps_diag" => self.max_search_steps_diag = steps(value, MAX_DIAG_DISTANCE),
            "corner_rounding" => self.corner_rounding = as_i64(value).clamp(0, 100) as u32,
            "edge_detection" => self.edge_mode.assign(value),
            _ => {
                return crate::set_fields!(
                    self,
                    key,
                    value,
                    [
                        threshold,
                        diagonal_detection,
                        corner_detection,
                        local_contrast_factor,
                        predication,
                        predication_threshold,
                        predication_scale,
                        predication_strength,
                        reprojection_weight_scale,
                        mip_bias,
                        tonemap_order,
                    ]
                );
            }
        }
        true
    }

    /// Keeps the edge mode, reprojection and tonemap order choices, and the predication
    /// choices except in the texture-safe preset, which sets them.
    fn apply_preset(&mut self, preset: Preset) {
        let p = Self::preset(preset);
        if preset == Preset::TextureSafe {
            self.predication = p.predication;
            self.predication_threshold = p.predication_threshold;
            self.predication_scale = p.predication_scale;
            self.predication_strength = p.predication_strength;
        }
        self.threshold = p.threshold;
        self.max_search_steps = p.max_search_steps;
        self.diagonal_detection = p.diagonal_detection;
        self.max_search_steps_diag = p.max_search_steps_diag;
        self.corner_detection = p.corner_detection;
        self.corner_rounding = p.corner_rounding;
    }
}

impl Default for SmaaSettings {
    fn default() -> Self {
        Self::preset(Preset::High)
    }
}

/// Settings compiled into the pipelines as override constants; the pipelines are rebuilt
/// only when this changes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PipelineKey {
    /// Edge-detection entry point.
    pub edge_mode: EdgeMode,
    /// Predicated thresholds (never in depth mode).
    pub predication: bool,
    /// Orthogonal search loop bound.
    pub max_search_steps: u32,
    /// Diagonal search loop bound (0: no diagonal handling).
    pub diagonal_steps: u32,
    /// Corner detection on.
    pub corner_detection: bool,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::aa::params::parse_value;

    #[test]
    fn presets_follow_the_paper_and_are_recognised() {
        let low = SmaaSettings::preset(Preset::Low);
        assert_eq!((low.threshold, low.max_search_steps), (0.15, 4));
        assert!(!low.diagonal_detection && !low.corner_detection);
        let ultra = SmaaSettings::preset(Preset::Ultra);
        assert_eq!(
            (
                ultra.threshold,
                ultra.max_search_steps,
                ultra.max_search_steps_diag
            ),
            (0.05, 32, 16)
        );
        assert_eq!(ultra.corner_rounding, 25);
        assert_eq!(
            SmaaSettings::default().matching_preset(),
            Some(Preset::High)
        );
        let mut custom = SmaaSettings {
            threshold: 0.07,
            ..SmaaSettings::default()
        };
        assert_eq!(custom.matching_preset(), None);
        custom.apply_preset(Preset::Medium);
        assert_eq!(custom.matching_preset(), Some(Preset::Medium));
        custom.apply_preset(Preset::TextureSafe);
        assert_eq!(custom.matching_preset(), Some(Preset::TextureSafe));
        assert!(custom.predication && custom.predication_threshold == 0.001);
        // A quality preset keeps the predication choices: High with other predication values
        // is High, not texture-safe.
        custom.predication_scale = 4.0;
        assert_eq!(custom.matching_preset(), Some(Preset::High));
    }

    #[test]
    fn every_param_round_trips() {
        let mut s = SmaaSettings::default();
        for p in s.params() {
            let value = p
                .validate("smaa", p.value.clone())
                .expect("current value is valid");
            assert!(s.set(p.key, &value), "{} not settable", p.key);
        }
        assert_eq!(s, SmaaSettings::default());
        let edge = s
            .params_for(false)
            .into_iter()
            .find(|p| p.key == "edge_detection")
            .expect("edge param");
        let depth = edge
            .validate("smaa", parse_value("depth"))
            .expect("depth is valid");
        assert!(s.set("edge_detection", &depth));
        assert_eq!(s.edge_mode, EdgeMode::Depth);
        s.predication = true;
        assert!(!s.pipeline_key().predication, "depth mode never predicates");
        assert!(!s.set("nonsense", &depth));
        s.diagonal_detection = false;
        assert_eq!(s.pipeline_key().diagonal_steps, 0);
    }
}
