//! The written form of a technique at a render scale, with an upscaler and sharpening:
//! `ID[@SCALE][:UPSCALER][+SHARPEN[=STRENGTH]]`, e.g. `smaa@performance:easu+rcas=0.2`.
//!
//! SCALE is a number in [[`MIN_SCALE`], 1] or one of the engines' presets (`native` 1,
//! `quality` 1/1.5, `balanced` 1/1.7, `performance` 1/2, `ultra-performance` 1/3, as AMD's
//! FSR 2 names them); UPSCALER one of [`Upscaler`]'s names (default: `easu`, the best); SHARPEN
//! `cas` or `rcas`, STRENGTH in [0, 1] (default [`DEFAULT_STRENGTH`]). A technique that
//! reconstructs at the output size itself (the temporal upscaler) takes no upscaler:
//! [`Combo::resolve`] refuses one there and fills in the default elsewhere. The same string is the
//! technique's id everywhere (command line, records, file names), so a record reproduces the
//! combination. [`Combo::id`] writes the one canonical form of a combination: the scale as a
//! preset name where it is one, else the shortest number that reads back to it; the upscaler
//! always when the scale is below 1 (unless the technique takes none) and never at native
//! (nothing is upscaled there); the strength always. A plain id (native, no sharpening) stays the technique's own.
//!
//! The modifiers are read from the right, and each only where its text has no `/`, so the id
//! of a user technique (`user:PATH`, whose path may hold `:` or `+`) keeps its path.

use crate::graph::params::Named;

/// The smallest render scale (a quarter of the output per axis).
pub const MIN_SCALE: f32 = 0.25;

/// Sharpening strength when a combination names none.
pub const DEFAULT_STRENGTH: f32 = 0.5;

crate::named_enum! {
    /// How a render below the output size is brought up to it.
    pub enum Upscaler {
        /// Bilinear: the four nearest render pixels weighted by distance; never leaves their
        /// range, and blurs most.
        Bilinear => "bilinear",
        /// Catmull-Rom bicubic over 4x4 render pixels: sharper than bilinear; its negative
        /// lobes may overshoot at edges.
        Bicubic => "bicubic",
        /// Lanczos-2 over 4x4 render pixels: sharper still; rings (overshoots) at hard edges.
        Lanczos => "lanczos",
        /// Edge-adaptive (after AMD FSR 1 EASU): a Lanczos-2-like kernel stretched along the
        /// local edge, clamped to the nearest 2x2 render pixels' range, so it cannot ring.
        Easu => "easu",
    }
}

crate::named_enum! {
    /// Sharpening after a technique (and its upscale).
    pub enum Sharpen {
        /// Contrast-adaptive sharpening (after AMD FidelityFX CAS): sharpens soft detail more
        /// than flat or already contrasted areas.
        Cas => "cas",
        /// Robust CAS (after AMD FSR 1 RCAS): the strongest sharpening that keeps every pixel
        /// inside its neighbours' range.
        Rcas => "rcas",
    }
}

crate::named_enum! {
    /// The engines' render-scale presets (per axis).
    pub enum ScalePreset {
        /// Scale 1: the output size.
        Native => "native",
        /// Scale 1/1.5.
        Quality => "quality",
        /// Scale 1/1.7.
        Balanced => "balanced",
        /// Scale 1/2.
        Performance => "performance",
        /// Scale 1/3.
        UltraPerformance => "ultra-performance",
    }
}

impl ScalePreset {
    /// The scale per axis.
    pub fn scale(self) -> f32 {
        match self {
            Self::Native => 1.0,
            Self::Quality => 1.0 / 1.5,
            Self::Balanced => 1.0 / 1.7,
            Self::Performance => 0.5,
            Self::UltraPerformance => 1.0 / 3.0,
        }
    }
}

/// Sharpening with its strength.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sharpening {
    /// Which filter.
    pub filter: Sharpen,
    /// 0 leaves the image unchanged, 1 is the filter's strongest.
    pub strength: f32,
}

/// A technique id with its render scale, upscaler and sharpening.
#[derive(Clone, Debug, PartialEq)]
pub struct Combo {
    /// The technique's own id (a registry id or `user:PATH`).
    pub base: String,
    /// Render scale per axis, in [`MIN_SCALE`, 1].
    pub scale: f32,
    /// The upscaler (unused at scale 1): `None` where the string names none, until
    /// [`Combo::resolve`] fills in the default, and always for a technique that reconstructs
    /// at the output size itself.
    pub upscaler: Option<Upscaler>,
    /// Sharpening after the upscale, if any.
    pub sharpen: Option<Sharpening>,
}

/// Why a combination string was refused: each names the part, what it is and what is accepted.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ComboError {
    /// SCALE is neither a number in range nor a preset.
    #[error(
        "`{id}`: render scale `{text}` {why}; a scale is a number from {MIN_SCALE} to 1 or one of \
         {presets}",
        presets = ScalePreset::NAMES.join(", ")
    )]
    Scale {
        /// The whole string.
        id: String,
        /// The scale's text.
        text: String,
        /// What is wrong with it.
        why: &'static str,
    },
    /// UPSCALER is not one of the upscalers.
    #[error(
        "`{id}`: unknown upscaler `{text}`; upscalers: {}",
        Upscaler::NAMES.join(", ")
    )]
    Upscaler {
        /// The whole string.
        id: String,
        /// The upscaler's text.
        text: String,
    },
    /// SHARPEN is not one of the filters.
    #[error(
        "`{id}`: unknown sharpening `{text}`; sharpening: {}",
        Sharpen::NAMES.join(", ")
    )]
    Sharpen {
        /// The whole string.
        id: String,
        /// The filter's text.
        text: String,
    },
    /// STRENGTH is not a number in [0, 1].
    #[error("`{id}`: sharpening strength `{text}` {why}; a strength is a number from 0 to 1")]
    Strength {
        /// The whole string.
        id: String,
        /// The strength's text.
        text: String,
        /// What is wrong with it.
        why: &'static str,
    },
    /// An upscaler after a technique that reconstructs at the output size itself.
    #[error(
        "`{id}`: {base} reconstructs at the output size itself and takes no upscaler; drop \
         `:{upscaler}`"
    )]
    OwnReconstruction {
        /// The whole string.
        id: String,
        /// The technique's own id.
        base: String,
        /// The upscaler's name.
        upscaler: &'static str,
    },
    /// Nothing before the modifiers.
    #[error("`{0}`: no technique id before the render scale, upscaler or sharpening")]
    NoBase(String),
}

/// The text after the last `separator` of `text`, when it holds no `/` (and so is not part
/// of a user technique's path), with the text before it.
fn modifier(text: &str, separator: char) -> Option<(&str, &str)> {
    let (head, tail) = text.rsplit_once(separator)?;
    (!tail.contains('/') && head != crate::aa::user::PREFIX.trim_end_matches(':'))
        .then_some((head, tail))
}

/// Reads the modifier after the last `separator` of `rest` with `read`, moving `rest` before
/// it. In a user technique's id (`lenient`) text that does not read as the modifier is left
/// as part of the file's path; elsewhere it is an error.
fn take<T>(
    rest: &mut &str,
    separator: char,
    lenient: bool,
    read: impl FnOnce(&str) -> Result<T, ComboError>,
) -> Result<Option<T>, ComboError> {
    let Some((head, tail)) = modifier(rest, separator) else {
        return Ok(None);
    };
    match read(tail) {
        Ok(value) => {
            *rest = head;
            Ok(Some(value))
        }
        Err(_) if lenient => Ok(None),
        Err(error) => Err(error),
    }
}

impl Combo {
    /// Reads a combination string (see the module docs).
    pub fn parse(id: &str) -> Result<Self, ComboError> {
        let lenient = crate::aa::user::is_user_id(id);
        let mut rest = id;
        let sharpen = take(&mut rest, '+', lenient, |text| parse_sharpening(id, text))?;
        let upscaler = take(&mut rest, ':', lenient, |text| {
            Upscaler::from_name(text).ok_or_else(|| ComboError::Upscaler {
                id: id.to_owned(),
                text: text.to_owned(),
            })
        })?;
        let scale = take(&mut rest, '@', lenient, |text| parse_scale(id, text))?;
        if rest.is_empty() {
            return Err(ComboError::NoBase(id.to_owned()));
        }
        Ok(Self {
            base: rest.to_owned(),
            scale: scale.unwrap_or(1.0),
            upscaler,
            sharpen,
        })
    }

    /// The combination for its technique: one that reconstructs at the output size itself
    /// refuses an upscaler (below native, where one would run); any other gets the default
    /// upscaler where none is named.
    pub fn resolve(mut self, reconstructs_at_output: bool) -> Result<Self, ComboError> {
        match (reconstructs_at_output, self.upscaler) {
            (true, Some(upscaler)) if self.scale < 1.0 => Err(ComboError::OwnReconstruction {
                id: self.id(),
                base: self.base,
                upscaler: upscaler.name(),
            }),
            (true, _) => {
                self.upscaler = None;
                Ok(self)
            }
            (false, _) => {
                self.upscaler.get_or_insert(Upscaler::Easu);
                Ok(self)
            }
        }
    }

    /// Whether the combination is the plain technique (native, no sharpening).
    pub fn is_plain(&self) -> bool {
        self.scale == 1.0 && self.sharpen.is_none()
    }

    /// The canonical string (see the module docs); parsing it gives this combination back.
    pub fn id(&self) -> String {
        let mut id = self.base.clone();
        if self.scale < 1.0 {
            let scale = ScalePreset::ALL
                .iter()
                .find(|p| p.scale() == self.scale)
                .map_or_else(|| self.scale.to_string(), |p| p.name().to_owned());
            id += &format!("@{scale}");
            if let Some(upscaler) = self.upscaler {
                id += &format!(":{}", upscaler.name());
            }
        }
        if let Some(s) = self.sharpen {
            id += &format!("+{}={}", s.filter.name(), s.strength);
        }
        id
    }

    /// The render size of an output size at this scale (each side rounded, at least 1).
    pub fn render_size(&self, output: (u32, u32)) -> (u32, u32) {
        if self.scale == 1.0 {
            return output;
        }
        let side = |n: u32| ((n as f32 * self.scale).round() as u32).clamp(1, n.max(1));
        (side(output.0), side(output.1))
    }

    /// The modifiers for labels (`@ 50% EASU + RCAS 0.2`), empty for a plain technique.
    pub fn label_suffix(&self) -> String {
        let mut suffix = String::new();
        if self.scale < 1.0 {
            suffix += &format!(" @ {:.0}%", self.scale * 100.0);
            if let Some(upscaler) = self.upscaler {
                suffix += &format!(" {}", upscaler.name().to_uppercase());
            }
        }
        if let Some(s) = self.sharpen {
            suffix += &format!(" + {} {}", s.filter.name().to_uppercase(), s.strength);
        }
        suffix
    }
}

fn parse_scale(id: &str, text: &str) -> Result<f32, ComboError> {
    if let Some(preset) = ScalePreset::from_name(text) {
        return Ok(preset.scale());
    }
    let error = |why| ComboError::Scale {
        id: id.to_owned(),
        text: text.to_owned(),
        why,
    };
    let scale: f32 = text
        .parse()
        .map_err(|_| error("is neither a number nor a preset"))?;
    if !(MIN_SCALE..=1.0).contains(&scale) {
        return Err(error("is out of range"));
    }
    Ok(scale)
}

fn parse_sharpening(id: &str, text: &str) -> Result<Sharpening, ComboError> {
    let (name, strength) = match text.split_once('=') {
        Some((name, strength)) => (name, Some(strength)),
        None => (text, None),
    };
    let filter = Sharpen::from_name(name).ok_or_else(|| ComboError::Sharpen {
        id: id.to_owned(),
        text: name.to_owned(),
    })?;
    let strength = match strength {
        None => DEFAULT_STRENGTH,
        Some(strength_text) => {
            let error = |why| ComboError::Strength {
                id: id.to_owned(),
                text: strength_text.to_owned(),
                why,
            };
            let value: f32 = strength_text
                .parse()
                .map_err(|_| error("is not a number"))?;
            if !(0.0..=1.0).contains(&value) {
                return Err(error("is out of range"));
            }
            value
        }
    };
    Ok(Sharpening { filter, strength })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_part_parses_and_the_canonical_form_reads_back() {
        let combo = Combo::parse("smaa@performance:bilinear+rcas=0.2").expect("valid");
        assert_eq!(combo.base, "smaa");
        assert_eq!(combo.scale, 0.5);
        assert_eq!(combo.upscaler, Some(Upscaler::Bilinear));
        assert_eq!(
            combo.sharpen,
            Some(Sharpening {
                filter: Sharpen::Rcas,
                strength: 0.2
            })
        );
        for text in [
            "smaa",
            "smaa@0.6",
            "taa@quality:lanczos",
            "fxaa+cas",
            "none@ultra-performance+rcas=1",
            "msaa4@0.37:bicubic+cas=0",
            "user:/tmp/a:b+c.wgsl@balanced",
            "user:edge.wgsl",
        ] {
            let combo = Combo::parse(text).unwrap_or_else(|e| panic!("{e}"));
            let canonical = combo.id();
            assert_eq!(Combo::parse(&canonical), Ok(combo), "{text} -> {canonical}");
        }
        assert_eq!(
            Combo::parse("smaa@native:bilinear").map(|c| c.id()),
            Ok("smaa".into())
        );
        assert_eq!(
            Combo::parse("smaa@0.5")
                .and_then(|c| c.resolve(false))
                .map(|c| c.id()),
            Ok("smaa@performance:easu".into())
        );
        assert_eq!(
            Combo::parse("user:/tmp/a:b+c.wgsl@balanced").map(|c| c.base),
            Ok("user:/tmp/a:b+c.wgsl".into())
        );
        assert!(Combo::parse("smaa").expect("plain").is_plain());
    }

    #[test]
    fn bad_strings_name_the_part_and_what_is_accepted() {
        for (text, needles) in [
            (
                "smaa@0",
                &["render scale `0`", "out of range", "0.25 to 1", "quality"][..],
            ),
            ("smaa@1.5", &["`1.5`", "out of range"]),
            (
                "smaa@fast",
                &["`fast`", "neither a number nor a preset", "performance"],
            ),
            (
                "smaa@quality:nearest",
                &["upscaler `nearest`", "bilinear, bicubic, lanczos, easu"],
            ),
            (
                "smaa+cas=abc",
                &["strength `abc`", "not a number", "0 to 1"],
            ),
            ("smaa+cas=2", &["strength `2`", "out of range"]),
            ("smaa+blur", &["sharpening `blur`", "cas, rcas"]),
            ("@0.5", &["no technique id"]),
        ] {
            let error = Combo::parse(text).expect_err(text).to_string();
            for needle in needles {
                assert!(error.contains(needle), "{text}: `{needle}` not in: {error}");
            }
        }
    }

    #[test]
    fn a_technique_that_reconstructs_itself_takes_no_upscaler() {
        let own = |text: &str| Combo::parse(text).and_then(|c| c.resolve(true));
        assert_eq!(
            own("taau@0.5").map(|c| c.id()),
            Ok("taau@performance".into())
        );
        assert_eq!(
            own("taau@quality+rcas").map(|c| c.id()),
            Ok("taau@quality+rcas=0.5".into())
        );
        assert_eq!(own("taau").map(|c| c.id()), Ok("taau".into()));
        let error = own("taau@quality:easu")
            .expect_err("an upscaler")
            .to_string();
        for needle in ["taau@quality:easu", "reconstructs", "drop `:easu`"] {
            assert!(error.contains(needle), "`{needle}` not in: {error}");
        }
        let canonical = own("taau@0.6+cas=1").expect("valid").id();
        assert_eq!(own(&canonical).map(|c| c.id()), Ok(canonical));
    }

    #[test]
    fn render_sizes_round_and_stay_at_least_one_pixel() {
        let at = |scale| Combo {
            base: "none".into(),
            scale,
            upscaler: Some(Upscaler::Easu),
            sharpen: None,
        };
        assert_eq!(at(0.5).render_size((1280, 720)), (640, 360));
        assert_eq!(at(1.0 / 1.5).render_size((1920, 1080)), (1280, 720));
        assert_eq!(at(0.25).render_size((2, 1)), (1, 1));
        assert_eq!(at(1.0).render_size((7, 3)), (7, 3));
    }
}
