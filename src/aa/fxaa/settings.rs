//! FXAA's settings: Lottes' quality presets (the edge-search step lists, which become override
//! constants), the two contrast thresholds, the sub-pixel amount and its limit, the luma
//! choice, the named presets (aa-lab's defaults, Lottes' and Bevy's sensitivity levels), and
//! every parameter as data for
//! the CLI, viewer and sidecars (its [`Tunable`] implementation).

use crate::aa::common::color::LumaSource;
use crate::aa::params::{Param, ParamValue, Tunable};
use crate::graph::hdr::TonemapOrder;

/// Most search steps a preset has (the shader has this many step constants).
pub const MAX_STEPS: usize = 12;

crate::named_enum! {
    /// FXAA 3.11's quality presets (the `quality` parameter): 10-15 few steps ending in a long
    /// jump (medium dither), 20-29 more, shorter steps (less dither), 39 twelve short steps (no
    /// dither).
    pub enum Quality {
        /// Three steps, a 12-pixel last guess.
        Q10 => "10",
        /// Four steps, a 12-pixel last guess.
        Q11 => "11",
        /// Five steps, a 12-pixel last guess (Lottes' default).
        Q12 => "12",
        /// Six steps, a 12-pixel last guess.
        Q13 => "13",
        /// Seven steps, a 12-pixel last guess.
        Q14 => "14",
        /// Eight steps, a 12-pixel last guess.
        Q15 => "15",
        /// Three steps, an 8-pixel last guess.
        Q20 => "20",
        /// Four steps, an 8-pixel last guess.
        Q21 => "21",
        /// Five steps, an 8-pixel last guess.
        Q22 => "22",
        /// Six steps, an 8-pixel last guess.
        Q23 => "23",
        /// Seven steps, an 8-pixel last guess.
        Q24 => "24",
        /// Eight steps, an 8-pixel last guess.
        Q25 => "25",
        /// Nine steps, an 8-pixel last guess.
        Q26 => "26",
        /// Ten steps, an 8-pixel last guess.
        Q27 => "27",
        /// Eleven steps, an 8-pixel last guess.
        Q28 => "28",
        /// Twelve steps, an 8-pixel last guess.
        Q29 => "29",
        /// Twelve short steps, no dither.
        Q39 => "39",
    }
}

impl Quality {
    /// The edge-search step lengths of the preset, in pixels.
    pub fn search_steps(self) -> &'static [f32] {
        match self {
            Self::Q10 => &[1.5, 3.0, 12.0],
            Self::Q11 => &[1.0, 1.5, 3.0, 12.0],
            Self::Q12 => &[1.0, 1.5, 2.0, 4.0, 12.0],
            Self::Q13 => &[1.0, 1.5, 2.0, 2.0, 4.0, 12.0],
            Self::Q14 => &[1.0, 1.5, 2.0, 2.0, 2.0, 4.0, 12.0],
            Self::Q15 => &[1.0, 1.5, 2.0, 2.0, 2.0, 2.0, 4.0, 12.0],
            Self::Q20 => &[1.5, 2.0, 8.0],
            Self::Q21 => &[1.0, 1.5, 2.0, 8.0],
            Self::Q22 => &[1.0, 1.5, 2.0, 2.0, 8.0],
            Self::Q23 => &[1.0, 1.5, 2.0, 2.0, 2.0, 8.0],
            Self::Q24 => &[1.0, 1.5, 2.0, 2.0, 2.0, 3.0, 8.0],
            Self::Q25 => &[1.0, 1.5, 2.0, 2.0, 2.0, 2.0, 4.0, 8.0],
            Self::Q26 => &[1.0, 1.5, 2.0, 2.0, 2.0, 2.0, 2.0, 4.0, 8.0],
            Self::Q27 => &[1.0, 1.5, 2.0, 2.0, 2.0, 2.0, 2.0, 2.0, 4.0, 8.0],
            Self::Q28 => &[1.0, 1.5, 2.0, 2.0, 2.0, 2.0, 2.0, 2.0, 2.0, 4.0, 8.0],
            Self::Q29 => &[1.0, 1.5, 2.0, 2.0, 2.0, 2.0, 2.0, 2.0, 2.0, 2.0, 4.0, 8.0],
            Self::Q39 => &[1.0, 1.0, 1.0, 1.0, 1.0, 1.5, 2.0, 2.0, 2.0, 2.0, 4.0, 8.0],
        }
    }
}

crate::named_enum! {
    /// The named presets: aa-lab's defaults, Lottes' FXAA 3.11 defaults, then Bevy's
    /// sensitivity levels, which set the two contrast thresholds.
    pub enum Preset {
        /// aa-lab's defaults: quality 39, subpix 1 up to 0.33 of a pixel (1.3 times on strands,
        /// half beside clean edges), thresholds 0.166 / 0.0833.
        Default => "default",
        /// Lottes' FXAA 3.11 defaults: quality 12, subpix 0.75 without a limit, thresholds
        /// 0.166 / 0.0833.
        Lottes => "lottes",
        /// Thresholds 0.25 / 0.0833.
        Low => "low",
        /// Thresholds 0.166 / 0.0625.
        Medium => "medium",
        /// Thresholds 0.125 / 0.0312.
        High => "high",
        /// Thresholds 0.063 / 0.0156.
        Ultra => "ultra",
        /// Thresholds 0.031 / 0.0078.
        Extreme => "extreme",
    }
}

impl Preset {
    /// Bevy's sensitivity: (edge_threshold, edge_threshold_min); `None` for the presets that
    /// set every setting.
    pub fn thresholds(self) -> Option<(f32, f32)> {
        match self {
            Self::Default | Self::Lottes => None,
            Self::Low => Some((0.250, 0.0833)),
            Self::Medium => Some((0.166, 0.0625)),
            Self::High => Some((0.125, 0.0312)),
            Self::Ultra => Some((0.063, 0.0156)),
            Self::Extreme => Some((0.031, 0.0078)),
        }
    }
}

/// FXAA settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FxaaSettings {
    /// Quality preset.
    pub quality: Quality,
    /// Sub-pixel blending: 0 off, 1 softest.
    pub subpix: f32,
    /// The longest sub-pixel move of the read, in pixels (1: no limit, as Lottes').
    pub subpix_limit: f32,
    /// Factor on the sub-pixel amount of a pixel brighter or darker than both its neighbours
    /// across the edge (a strand or dot thinner than a pixel; 1: as Lottes').
    pub subpix_strands: f32,
    /// Factor on the sub-pixel amount of a pixel beside a clean edge: between its neighbours
    /// across the edge and matched by its neighbours along it (1: as Lottes').
    pub subpix_clean_edges: f32,
    /// Contrast needed to process a pixel, relative to the brightest luma of its cross.
    pub edge_threshold: f32,
    /// Contrast below which dark pixels are skipped regardless.
    pub edge_threshold_min: f32,
    /// How luma is computed.
    pub luma: LumaSource,
    /// In HDR frames, before or after the tonemapper (after, as engines run it).
    pub tonemap_order: TonemapOrder,
}

impl Default for FxaaSettings {
    /// aa-lab's defaults: Lottes' thresholds with a longer edge search and a stronger but
    /// limited sub-pixel blend (the measurements: `docs/techniques/fxaa.md`).
    fn default() -> Self {
        Self {
            quality: Quality::Q39,
            subpix: 1.0,
            subpix_limit: 0.33,
            subpix_strands: 1.3,
            subpix_clean_edges: 0.5,
            ..Self::lottes()
        }
    }
}

impl FxaaSettings {
    /// Lottes' FXAA 3.11 defaults.
    pub fn lottes() -> Self {
        Self {
            quality: Quality::Q12,
            subpix: 0.75,
            subpix_limit: 1.0,
            subpix_strands: 1.0,
            subpix_clean_edges: 1.0,
            edge_threshold: 0.166,
            edge_threshold_min: 0.0833,
            luma: LumaSource::Bt601,
            tonemap_order: TonemapOrder::After,
        }
    }
}

impl Tunable for FxaaSettings {
    type Preset = Preset;

    fn params(&self) -> Vec<Param> {
        let s = self;
        vec![
            Param::named(
                "quality",
                "Quality preset",
                "FXAA 3.11 quality preset: how far and in what steps the pass searches along an edge \
                 for its ends. 10-15: few steps ending in a long jump (fast, some dither on long \
                 edges); 20-29: more, shorter steps; 39: twelve short steps (no dither, slowest). \
                 Lottes' default is 12, aa-lab's 39.",
                s.quality,
            ),
            Param::float(
                "subpix",
                "Sub-pixel blending",
                "How much single pixels that stand out from their 3x3 neighbourhood are blended \
                 (sub-pixel aliasing): 0 off and sharpest, 1 the default and softest (Lottes' \
                 0.75).",
                0.0,
                1.0,
                s.subpix,
            ),
            Param::float(
                "subpix_limit",
                "Sub-pixel limit",
                "The furthest sub-pixel blending moves a pixel's read towards its neighbour, in \
                 pixels: 0.33 the default keeps one-pixel strands (hair, wires) visible, 1 no \
                 limit (Lottes').",
                0.0,
                1.0,
                s.subpix_limit,
            ),
            Param::float(
                "subpix_strands",
                "Sub-pixel on strands",
                "Factor on the sub-pixel blending of a pixel brighter or darker than both its \
                 neighbours across the edge: a strand, wire or dot thinner than a pixel, which the \
                 edge search cannot place. 1.3 the default, 1 as Lottes'.",
                0.0,
                2.0,
                s.subpix_strands,
            ),
            Param::float(
                "subpix_clean_edges",
                "Sub-pixel beside clean edges",
                "Factor on the sub-pixel blending of a pixel beside a clean edge (its neighbours \
                 along the edge match it): the edge search places such edges, and the sub-pixel \
                 term would only blur a pixel that lies wholly on one side. 0.5 the default, 1 \
                 as Lottes'.",
                0.0,
                1.0,
                s.subpix_clean_edges,
            ),
            Param::float(
                "edge_threshold",
                "Edge threshold",
                "Local contrast needed to treat a pixel as an edge, relative to the brightest luma \
                 around it: 0.333 too little, 0.25 low quality, 0.166 default, 0.125 high quality, \
                 0.063 overkill (more texture blur).",
                0.03,
                0.5,
                s.edge_threshold,
            ),
            Param::float(
                "edge_threshold_min",
                "Edge threshold (dark)",
                "Contrast below which pixels are left alone however dark they are: 0.0833 default, \
                 0.0625 high quality, 0.0312 visible limit (dark noise gets blurred).",
                0.0,
                0.1,
                s.edge_threshold_min,
            ),
            Param::named(
                "luma",
                "Luma",
                "Luma used for every test: bt601 weighs the sRGB-encoded red, green and blue \
                 (0.299, 0.587, 0.114); green uses the green channel alone (cheaper, misses \
                 edges between colours of equal green).",
                s.luma,
            ),
            s.tonemap_order.param(),
        ]
    }

    fn set(&mut self, key: &str, value: &ParamValue) -> bool {
        crate::set_fields!(
            self,
            key,
            value,
            [
                quality,
                subpix,
                subpix_limit,
                subpix_strands,
                subpix_clean_edges,
                edge_threshold,
                edge_threshold_min,
                luma,
                tonemap_order
            ]
        )
    }

    /// aa-lab's or Lottes' defaults, or a sensitivity level's two thresholds (the rest kept;
    /// the tonemap order is no part of a preset).
    fn apply_preset(&mut self, preset: Preset) {
        let tonemap_order = self.tonemap_order;
        match preset.thresholds() {
            None if preset == Preset::Lottes => {
                *self = Self {
                    tonemap_order,
                    ..Self::lottes()
                }
            }
            None => {
                *self = Self {
                    tonemap_order,
                    ..Self::default()
                }
            }
            Some((threshold, threshold_min)) => {
                self.edge_threshold = threshold;
                self.edge_threshold_min = threshold_min;
            }
        }
    }
}

impl FxaaSettings {
    /// The override constants of the quality preset and luma choice, and `RADIANCE` (the pass
    /// runs on radiance, before the tonemapper).
    pub(super) fn constants(&self, radiance: bool) -> Vec<(String, f64)> {
        let steps = self.quality.search_steps();
        let mut constants = vec![
            ("RADIANCE".to_owned(), f64::from(u8::from(radiance))),
            (
                "GREEN_AS_LUMA".to_owned(),
                f64::from(u8::from(self.luma == LumaSource::Green)),
            ),
            ("STEP_COUNT".to_owned(), steps.len() as f64),
        ];
        constants.extend((0..MAX_STEPS).map(|i| {
            (
                format!("STEP_{i}"),
                f64::from(steps.get(i).copied().unwrap_or(0.0)),
            )
        }));
        constants
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::graph::params::Named;

    #[test]
    fn every_quality_preset_has_a_step_list_within_the_shader_limit() {
        for quality in Quality::ALL {
            let steps = quality.search_steps();
            let name = quality.name();
            assert!((3..=MAX_STEPS).contains(&steps.len()), "{name}");
            // Medium-dither presets end in a 12-pixel guess, the others in 8.
            let last = *steps.last().expect("non-empty");
            assert_eq!(
                last,
                if name.starts_with('1') { 12.0 } else { 8.0 },
                "{name}"
            );
        }
        assert_eq!(Quality::Q12.search_steps(), &[1.0, 1.5, 2.0, 4.0, 12.0]);
        assert_eq!(Quality::Q39.search_steps().len(), 12);
        assert!(Quality::from_name("16").is_none());
        // Within each family a higher preset searches at least as far.
        let reach = |q: Quality| q.search_steps().iter().sum::<f32>();
        for pair in Quality::ALL.windows(2) {
            if pair[0].name().as_bytes()[0] == pair[1].name().as_bytes()[0] {
                assert!(reach(pair[1]) >= reach(pair[0]), "{pair:?}");
            }
        }
    }

    #[test]
    fn constants_fill_every_step_slot() {
        let settings = FxaaSettings {
            quality: Quality::Q20,
            luma: LumaSource::Green,
            ..FxaaSettings::default()
        };
        let constants = settings.constants(false);
        assert_eq!(constants.len(), 3 + MAX_STEPS);
        let get = |k: &str| constants.iter().find(|(n, _)| n == k).expect("constant").1;
        assert_eq!(get("GREEN_AS_LUMA"), 1.0);
        assert_eq!(get("STEP_COUNT"), 3.0);
        assert_eq!(
            (get("STEP_0"), get("STEP_1"), get("STEP_2")),
            (1.5, 2.0, 8.0)
        );
        assert_eq!(get("STEP_11"), 0.0);
    }

    #[test]
    fn lottes_preset_restores_fxaa_3_11_and_default_restores_aa_labs() {
        let mut settings = FxaaSettings {
            tonemap_order: TonemapOrder::Before,
            ..FxaaSettings::default()
        };
        settings.apply_preset(Preset::Lottes);
        assert_eq!(
            settings,
            FxaaSettings {
                tonemap_order: TonemapOrder::Before,
                ..FxaaSettings::lottes()
            }
        );
        assert_eq!(
            (
                settings.quality,
                settings.subpix,
                settings.subpix_limit,
                settings.subpix_strands,
                settings.subpix_clean_edges
            ),
            (Quality::Q12, 0.75, 1.0, 1.0, 1.0)
        );
        assert_eq!(settings.tonemap_order, TonemapOrder::Before);
        settings.apply_preset(Preset::Default);
        assert_eq!(
            settings,
            FxaaSettings {
                tonemap_order: TonemapOrder::Before,
                ..FxaaSettings::default()
            }
        );
        assert_eq!(settings.tonemap_order, TonemapOrder::Before);
    }

    #[test]
    fn sensitivity_presets_tighten_in_order() {
        let sensitivities: Vec<(f32, f32)> =
            Preset::ALL.iter().filter_map(|p| p.thresholds()).collect();
        assert_eq!(sensitivities.len(), Preset::ALL.len() - 2);
        for pair in sensitivities.windows(2) {
            assert!(pair[1].0 < pair[0].0 && pair[1].1 < pair[0].1);
        }
    }
}
