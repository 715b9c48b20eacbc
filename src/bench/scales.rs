//! The render scales of a sweep over scales (`aa-lab bench --sweep scale`), and the techniques
//! it measures: every technique at every scale, written in the combination grammar of
//! [`crate::aa::combo`] (`smaa` at 1/2 is `smaa@performance:easu`), so any technique that
//! accepts `@SCALE`, temporal ones and upscalers included, sweeps without being named here.
//! A technique keeps its settings, its upscaler and its sharpening at every scale; one whose
//! id already names a scale is measured at that scale only. All of them run in one frame
//! graph at the output size and are scored against the native reference, so native and
//! upscaled techniques share one Pareto front of quality against cost.

use crate::aa::combo::{Combo, ComboError, MIN_SCALE, ScalePreset};
use crate::graph::params::Named;
use crate::spec::TechniqueSpec;

/// The scales a sweep runs unless told otherwise: the engines' presets, native to
/// ultra-performance.
pub fn default_scales() -> Vec<f32> {
    ScalePreset::ALL.iter().map(|p| p.scale()).collect()
}

/// Why a list of scales was refused.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ScaleListError {
    /// An item is neither a number in range nor a preset.
    #[error(
        "scale `{text}` {why}; a scale is a number from {MIN_SCALE} to 1 (per axis) or one of \
         {presets}",
        presets = ScalePreset::NAMES.join(", ")
    )]
    Item {
        /// The item.
        text: String,
        /// What is wrong with it.
        why: &'static str,
    },
    /// Two items are the same scale.
    #[error("scales `{first}` and `{second}` are the same scale ({scale}); give each once")]
    Repeated {
        /// The first item.
        first: String,
        /// The later item.
        second: String,
        /// Their scale.
        scale: f32,
    },
    /// The list has no item.
    #[error("no scale given; give numbers from {MIN_SCALE} to 1 or presets, comma-separated")]
    Empty,
}

/// One scale: a preset's name or a number in [[`MIN_SCALE`], 1].
fn parse_scale(text: &str) -> Result<f32, ScaleListError> {
    if let Some(preset) = ScalePreset::from_name(text) {
        return Ok(preset.scale());
    }
    let refused = |why| ScaleListError::Item {
        text: text.to_owned(),
        why,
    };
    match text.parse::<f32>() {
        Err(_) => Err(refused("is neither a number nor a preset")),
        Ok(scale) if (MIN_SCALE..=1.0).contains(&scale) => Ok(scale),
        Ok(_) => Err(refused("is out of range")),
    }
}

/// A comma-separated list of scales (`native,0.75,performance`), in the order given; empty
/// items are skipped, and a scale given twice is refused.
pub fn parse_scales(list: &str) -> Result<Vec<f32>, ScaleListError> {
    let mut scales: Vec<(&str, f32)> = Vec::new();
    for text in list.split(',').map(str::trim).filter(|t| !t.is_empty()) {
        let scale = parse_scale(text)?;
        if let Some((first, _)) = scales.iter().find(|(_, s)| *s == scale) {
            return Err(ScaleListError::Repeated {
                first: (*first).to_owned(),
                second: text.to_owned(),
                scale,
            });
        }
        scales.push((text, scale));
    }
    if scales.is_empty() {
        return Err(ScaleListError::Empty);
    }
    Ok(scales.into_iter().map(|(_, s)| s).collect())
}

/// Whether a technique id, as written, names a render scale (`fxaa@native` does; its canonical
/// form `fxaa`, like plain `fxaa`, does not).
pub fn names_a_scale(written: &str) -> Result<bool, ComboError> {
    let combo = Combo::parse(written)?;
    // The modifiers follow the technique's own id, the scale first: `ID@SCALE...`.
    Ok(written[combo.base.len()..].starts_with('@'))
}

/// `technique`, written `written` on the command line, at each of `scales` (same settings;
/// its upscaler and sharpening kept), or only as it is when `written` names a scale.
pub fn at_scales(
    written: &str,
    technique: &TechniqueSpec,
    scales: &[f32],
) -> Result<Vec<TechniqueSpec>, ComboError> {
    if names_a_scale(written)? {
        return Ok(vec![technique.clone()]);
    }
    // As written: at native, the technique's canonical id drops the upscaler.
    let combo = Combo::parse(written)?;
    Ok(scales
        .iter()
        .map(|&scale| TechniqueSpec {
            id: Combo {
                scale,
                ..combo.clone()
            }
            .id(),
            ..technique.clone()
        })
        .collect())
}

/// Every technique of `techniques` (each with its id as written) at every scale of `scales`
/// (see [`at_scales`]), technique by technique, each id once.
pub fn sweep_techniques(
    techniques: &[(&str, &TechniqueSpec)],
    scales: &[f32],
) -> Result<Vec<TechniqueSpec>, ComboError> {
    let mut swept: Vec<TechniqueSpec> = Vec::new();
    for (written, technique) in techniques {
        for scaled in at_scales(written, technique, scales)? {
            if !swept.iter().any(|s| s.id == scaled.id) {
                swept.push(scaled);
            }
        }
    }
    Ok(swept)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scale_lists_read_numbers_and_presets_in_order() {
        assert_eq!(
            parse_scales("native, 0.75,performance,,0.25"),
            Ok(vec![1.0, 0.75, 0.5, 0.25])
        );
        assert_eq!(
            parse_scales("ultra-performance,quality"),
            Ok(vec![1.0 / 3.0, 1.0 / 1.5])
        );
        assert_eq!(default_scales().len(), ScalePreset::ALL.len());
        assert_eq!(default_scales()[0], 1.0);
    }

    #[test]
    fn bad_scale_lists_say_what_is_wrong_and_what_is_accepted() {
        for (list, needles) in [
            (
                "native,fast",
                &[
                    "scale `fast`",
                    "neither a number nor a preset",
                    "0.25 to 1",
                    "balanced",
                ][..],
            ),
            ("0.1", &["scale `0.1`", "out of range"]),
            ("1.5", &["scale `1.5`", "out of range"]),
            ("NaN", &["scale `NaN`", "out of range"]),
            ("-0.5", &["`-0.5`", "out of range"]),
            (
                "performance,0.5",
                &["`performance` and `0.5`", "same scale"],
            ),
            (" , ,", &["no scale given"]),
            ("", &["no scale given"]),
        ] {
            let error = parse_scales(list).expect_err(list).to_string();
            for needle in needles {
                assert!(error.contains(needle), "{list}: `{needle}` not in: {error}");
            }
        }
    }

    fn spec(id: &str) -> TechniqueSpec {
        TechniqueSpec {
            id: id.to_owned(),
            settings: Default::default(),
            source_hash: None,
        }
    }

    /// The ids of `techniques`, each in the canonical form of its combination.
    fn ids(techniques: &[TechniqueSpec]) -> Vec<String> {
        techniques.iter().map(|t| canonical(&t.id)).collect()
    }

    fn canonical(id: &str) -> String {
        Combo::parse(id).expect("a valid id").id()
    }

    #[test]
    fn every_technique_runs_at_every_scale_with_its_upscaler_and_sharpening() {
        let scales = [1.0, 0.5, 0.4];
        // As written on the command line, and as the techniques write their ids.
        let techniques = [
            ("taa", spec("taa")),
            ("smaa:bilinear+rcas=0.2", spec("smaa+rcas=0.2")),
            ("fxaa@quality", spec(&canonical("fxaa@quality"))),
            ("none@native", spec("none")),
            ("taa@0.5", spec(&canonical("taa@0.5"))),
        ];
        let pairs: Vec<(&str, &TechniqueSpec)> = techniques.iter().map(|(w, t)| (*w, t)).collect();
        let swept = sweep_techniques(&pairs, &scales).expect("valid ids");
        let expected = [
            "taa",
            "taa@performance",
            "taa@0.4",
            "smaa+rcas=0.2",
            "smaa@performance:bilinear+rcas=0.2",
            "smaa@0.4:bilinear+rcas=0.2",
            // An id that names a scale keeps it (native too); one already swept is not
            // repeated.
            "fxaa@quality",
            "none",
        ];
        assert_eq!(ids(&swept), expected.map(canonical));
        let user = "user:/tmp/a@b/edge.wgsl";
        assert_eq!(
            ids(&at_scales(user, &spec(user), &[0.5]).unwrap()),
            [canonical("user:/tmp/a@b/edge.wgsl@performance")]
        );
        assert!(!names_a_scale(user).unwrap());
        assert!(at_scales("smaa+blur", &spec("smaa"), &scales).is_err());
    }
}
