//! MLAA settings: quality presets, every parameter as data for the CLI, viewer and sidecars
//! (its [`Tunable`] implementation), and the part compiled into pipelines
//! ([`PipelineKey`]).

use crate::aa::params::{Named, Param, ParamField, ParamValue, Tunable, as_i64};

use super::area::MAX_DISTANCE;
use crate::graph::hdr::TonemapOrder;

crate::named_enum! {
    /// Quality presets (threshold / search steps): Low .15/4, Medium .10/8 (the GPU Pro 2
    /// chapter's defaults), High .05/16.
    pub enum Preset {
        /// Fewer edges, short searches.
        Low => "low",
        /// The authors' defaults.
        Medium => "medium",
        /// Fainter edges and the longest searches the area table holds.
        High => "high",
    }
}

crate::named_enum! {
    /// What the edge-detection pass compares between a pixel and its left and top neighbours.
    pub enum EdgeMode {
        /// Perceived brightness of the sRGB-encoded colour.
        Luma => "luma",
        /// The largest step of the three sRGB-encoded channels.
        Color => "color",
    }
}

/// Longest search, in steps of two pixels (the area table holds [`MAX_DISTANCE`] pixels).
pub const MAX_SEARCH_STEPS: u32 = MAX_DISTANCE / 2;

/// Every MLAA setting.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MlaaSettings {
    /// Edge-detection threshold on sRGB-encoded luma or colour.
    pub threshold: f32,
    /// Search steps per direction along an edge (two pixels each).
    pub max_search_steps: u32,
    /// What the edge detection compares.
    pub edge_mode: EdgeMode,
    /// In HDR frames, before or after the tonemapper (after, as engines run it).
    pub tonemap_order: TonemapOrder,
}

impl MlaaSettings {
    /// The settings of a preset (luma edges).
    pub fn preset(preset: Preset) -> Self {
        let (threshold, max_search_steps) = match preset {
            Preset::Low => (0.15, 4),
            Preset::Medium => (0.10, 8),
            Preset::High => (0.05, MAX_SEARCH_STEPS),
        };
        Self {
            threshold,
            max_search_steps,
            edge_mode: EdgeMode::Luma,
            tonemap_order: TonemapOrder::After,
        }
    }

    /// The preset these settings equal, if any (otherwise they are custom).
    pub fn matching_preset(&self) -> Option<Preset> {
        Preset::ALL.iter().copied().find(|&p| {
            let mut probe = *self;
            probe.apply_preset(p);
            probe == *self
        })
    }

    /// The part of the settings compiled into pipelines.
    pub fn pipeline_key(&self) -> PipelineKey {
        PipelineKey {
            edge_mode: self.edge_mode,
            max_search_steps: self.max_search_steps,
        }
    }
}

impl Tunable for MlaaSettings {
    type Preset = Preset;

    fn params(&self) -> Vec<Param> {
        vec![
            Param::float(
                "threshold",
                "Edge threshold",
                "Smallest brightness (or colour) step between neighbours that counts as an edge, on \
                 sRGB-encoded values. Lower finds fainter edges, including texture detail, at more cost. \
                 Presets: low 0.15, medium 0.10, high 0.05.",
                0.01,
                0.5,
                self.threshold,
            ),
            Param::int(
                "max_search_steps",
                "Search steps",
                "How far along an edge the pass looks for its ends, in steps of two pixels each way \
                 (one bilinear fetch reads two pixels). Staircases of flatter edges have longer steps \
                 and need longer searches; an end beyond the search is treated as flat. Presets: low 4, \
                 medium 8, high 16.",
                1,
                i64::from(MAX_SEARCH_STEPS),
                i64::from(self.max_search_steps),
            ),
            Param::named(
                "edge_detection",
                "Edge detection",
                "What is compared between neighbours: luma (brightness, the authors' choice) or color \
                 (largest channel step; also finds edges between colours of equal brightness).",
                self.edge_mode,
            ),
            self.tonemap_order.param(),
        ]
    }

    fn set(&mut self, key: &str, value: &ParamValue) -> bool {
        match key {
            "max_search_steps" => {
                self.max_search_steps = as_i64(value).clamp(1, i64::from(MAX_SEARCH_STEPS)) as u32;
            }
            "edge_detection" => self.edge_mode.assign(value),
            _ => return crate::set_fields!(self, key, value, [threshold, tonemap_order]),
        }
        true
    }

    /// Keeps the edge mode and the tonemap order.
    fn apply_preset(&mut self, preset: Preset) {
        *self = Self {
            edge_mode: self.edge_mode,
            tonemap_order: self.tonemap_order,
            ..Self::preset(preset)
        };
    }
}

impl Default for MlaaSettings {
    fn default() -> Self {
        Self::preset(Preset::Medium)
    }
}

/// Settings compiled into the pipelines as override constants; the pipelines are rebuilt
/// only when this changes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PipelineKey {
    /// Edge-detection comparison.
    pub edge_mode: EdgeMode,
    /// Search loop bound.
    pub max_search_steps: u32,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::aa::params::parse_value;

    #[test]
    fn presets_are_recognised_and_keep_the_edge_mode() {
        assert_eq!(
            MlaaSettings::default().matching_preset(),
            Some(Preset::Medium)
        );
        let mut s = MlaaSettings {
            edge_mode: EdgeMode::Color,
            threshold: 0.07,
            ..MlaaSettings::default()
        };
        assert_eq!(s.matching_preset(), None);
        s.apply_preset(Preset::High);
        assert_eq!(s.matching_preset(), Some(Preset::High));
        assert_eq!((s.edge_mode, s.max_search_steps), (EdgeMode::Color, 16));
        assert!(s.apply_preset_named("mlaa", "ultra").is_err());
    }

    #[test]
    fn every_param_round_trips() {
        let mut s = MlaaSettings::default();
        for p in s.params() {
            let value = p.validate("mlaa", p.value.clone()).expect("valid");
            assert!(s.set(p.key, &value), "{} not settable", p.key);
        }
        assert_eq!(s, MlaaSettings::default());
        let edge = &s.params()[2];
        let color = edge.validate("mlaa", parse_value("color")).expect("valid");
        assert!(s.set("edge_detection", &color));
        assert_eq!(s.pipeline_key().edge_mode, EdgeMode::Color);
        assert!(
            !s.set("diagonal_detection", &color),
            "MLAA has no diagonals"
        );
    }
}
