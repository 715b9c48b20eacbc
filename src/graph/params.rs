//! Technique settings as data: every technique describes its parameters (kind, range, help
//! text) and reads/writes them by key. One description serves the CLI (`--set fxaa.subpix=0.5`),
//! the viewer's settings panels, tooltips and the reproducibility sidecar, so adding a
//! parameter to a technique needs no front-end code. A settings type with named presets
//! implements [`Tunable`] once, and its technique's parameter methods only forward to it.

use std::collections::BTreeMap;
use std::fmt;

/// The type and range of one parameter.
#[derive(Clone, Debug, PartialEq)]
pub enum ParamKind {
    /// On/off.
    Bool,
    /// A real number in `min..=max`; `step` is a UI hint.
    Float {
        /// Smallest value.
        min: f32,
        /// Largest value.
        max: f32,
    },
    /// An integer in `min..=max`.
    Int {
        /// Smallest value.
        min: i64,
        /// Largest value.
        max: i64,
    },
    /// One of a fixed list of names.
    Choice(&'static [&'static str]),
}

/// A parameter value.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(untagged)]
pub enum ParamValue {
    /// On/off.
    Bool(bool),
    /// Integer.
    Int(i64),
    /// Real number.
    Float(f32),
    /// A choice, by name.
    Choice(String),
}

impl fmt::Display for ParamValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Bool(b) => write!(f, "{}", if *b { "on" } else { "off" }),
            Self::Int(i) => write!(f, "{i}"),
            Self::Float(x) => write!(f, "{x}"),
            Self::Choice(s) => f.write_str(s),
        }
    }
}

/// One parameter of a technique with its current value.
#[derive(Clone, Debug, PartialEq)]
pub struct Param {
    /// Key used on the command line and in sidecars (`subpix`, `pattern`, ...).
    pub key: &'static str,
    /// Short label for the UI.
    pub label: &'static str,
    /// What it does and what values mean: the UI tooltip and `aa-lab techniques --verbose`.
    pub help: &'static str,
    /// Type and range.
    pub kind: ParamKind,
    /// Current value.
    pub value: ParamValue,
}

/// Errors of setting a parameter.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ParamError {
    /// No parameter by that key.
    #[error("{technique} has no parameter `{key}`; its parameters are: {known}")]
    UnknownKey {
        /// Technique id.
        technique: String,
        /// The key asked for.
        key: String,
        /// Comma-separated valid keys.
        known: String,
    },
    /// The value does not parse or is out of range.
    #[error("{technique}.{key}: {reason}")]
    BadValue {
        /// Technique id.
        technique: String,
        /// Parameter key.
        key: String,
        /// What is wrong.
        reason: String,
    },
    /// The technique has no preset by that name.
    #[error("{technique} has no preset `{name}`; its presets are: {known}")]
    UnknownPreset {
        /// Technique id.
        technique: String,
        /// Preset asked for.
        name: String,
        /// Comma-separated valid presets.
        known: String,
    },
}

impl ParamError {
    /// The error for a key that is not among `params`.
    pub fn unknown_key(technique: &str, key: &str, params: &[Param]) -> Self {
        Self::UnknownKey {
            technique: technique.to_owned(),
            key: key.to_owned(),
            known: params.iter().map(|p| p.key).collect::<Vec<_>>().join(", "),
        }
    }
}

/// Finds `key` among `params` (the parameters of `technique`) and validates `value` against
/// it: the parameter's position and the value in its own form.
pub fn validate_setting(
    params: &[Param],
    technique: &str,
    key: &str,
    value: ParamValue,
) -> Result<(usize, ParamValue), ParamError> {
    let index = params
        .iter()
        .position(|p| p.key == key)
        .ok_or_else(|| ParamError::unknown_key(technique, key, params))?;
    Ok((index, params[index].validate(technique, value)?))
}

impl Param {
    /// A boolean parameter.
    pub fn bool(key: &'static str, label: &'static str, help: &'static str, value: bool) -> Self {
        Self {
            key,
            label,
            help,
            kind: ParamKind::Bool,
            value: ParamValue::Bool(value),
        }
    }

    /// A real parameter in `min..=max`.
    pub fn float(
        key: &'static str,
        label: &'static str,
        help: &'static str,
        min: f32,
        max: f32,
        value: f32,
    ) -> Self {
        Self {
            key,
            label,
            help,
            kind: ParamKind::Float { min, max },
            value: ParamValue::Float(value),
        }
    }

    /// An integer parameter in `min..=max`.
    pub fn int(
        key: &'static str,
        label: &'static str,
        help: &'static str,
        min: i64,
        max: i64,
        value: i64,
    ) -> Self {
        Self {
            key,
            label,
            help,
            kind: ParamKind::Int { min, max },
            value: ParamValue::Int(value),
        }
    }

    /// A choice among `options`.
    pub fn choice(
        key: &'static str,
        label: &'static str,
        help: &'static str,
        options: &'static [&'static str],
        value: &str,
    ) -> Self {
        Self {
            key,
            label,
            help,
            kind: ParamKind::Choice(options),
            value: ParamValue::Choice(value.to_owned()),
        }
    }

    /// A choice among the values of a [`Named`] enum.
    pub fn named<E: Named>(
        key: &'static str,
        label: &'static str,
        help: &'static str,
        value: E,
    ) -> Self {
        Self::choice(key, label, help, E::NAMES, value.name())
    }

    /// Checks `value` against this parameter's kind and range, converting text and
    /// compatible numbers (an integer given for a real, `true`/`on` for a bool).
    pub fn validate(&self, technique: &str, value: ParamValue) -> Result<ParamValue, ParamError> {
        let bad = |reason: String| ParamError::BadValue {
            technique: technique.to_owned(),
            key: self.key.to_owned(),
            reason,
        };
        match (&self.kind, value) {
            (ParamKind::Bool, ParamValue::Bool(b)) => Ok(ParamValue::Bool(b)),
            (ParamKind::Bool, ParamValue::Choice(s)) => match s.to_ascii_lowercase().as_str() {
                "on" | "true" | "yes" | "1" => Ok(ParamValue::Bool(true)),
                "off" | "false" | "no" | "0" => Ok(ParamValue::Bool(false)),
                _ => Err(bad(format!("`{s}` is not on/off"))),
            },
            (ParamKind::Bool, ParamValue::Int(i @ (0 | 1))) => Ok(ParamValue::Bool(i == 1)),
            (ParamKind::Float { min, max }, v) => {
                let x = match v {
                    ParamValue::Float(x) => x,
                    ParamValue::Int(i) => i as f32,
                    ParamValue::Choice(s) => s
                        .parse::<f32>()
                        .map_err(|_| bad(format!("`{s}` is not a number")))?,
                    ParamValue::Bool(_) => return Err(bad("expected a number".to_owned())),
                };
                if x.is_finite() && (*min..=*max).contains(&x) {
                    Ok(ParamValue::Float(x))
                } else {
                    Err(bad(format!("{x} is outside {min}..={max}")))
                }
            }
            (ParamKind::Int { min, max }, v) => {
                let i = match v {
                    ParamValue::Int(i) => i,
                    ParamValue::Float(x) if x.fract() == 0.0 => x as i64,
                    ParamValue::Choice(s) => s
                        .parse::<i64>()
                        .map_err(|_| bad(format!("`{s}` is not an integer")))?,
                    _ => return Err(bad("expected an integer".to_owned())),
                };
                if (*min..=*max).contains(&i) {
                    Ok(ParamValue::Int(i))
                } else {
                    Err(bad(format!("{i} is outside {min}..={max}")))
                }
            }
            (ParamKind::Choice(options), v) => {
                let s = match v {
                    ParamValue::Choice(s) => s,
                    ParamValue::Int(i) => i.to_string(),
                    other => {
                        return Err(bad(format!(
                            "`{other}` is not one of {}",
                            options.join(", ")
                        )));
                    }
                };
                options
                    .iter()
                    .find(|o| o.eq_ignore_ascii_case(&s))
                    .map(|o| ParamValue::Choice((*o).to_owned()))
                    .ok_or_else(|| bad(format!("`{s}` is not one of {}", options.join(", "))))
            }
            (_, v) => Err(bad(format!("`{v}` has the wrong type"))),
        }
    }
}

/// Parses the text form of a value (`0.5`, `on`, `halton`); the parameter's kind decides the
/// final type in [`Param::validate`].
pub fn parse_value(text: &str) -> ParamValue {
    if let Ok(i) = text.parse::<i64>() {
        ParamValue::Int(i)
    } else if let Ok(x) = text.parse::<f32>() {
        ParamValue::Float(x)
    } else {
        ParamValue::Choice(text.to_owned())
    }
}

/// A technique's settings as a key-value map, as sidecars store them.
pub type ParamMap = BTreeMap<String, ParamValue>;

/// Reads a validated float; the technique's own parameter list guarantees the type.
pub fn as_f32(value: &ParamValue) -> f32 {
    match value {
        ParamValue::Float(x) => *x,
        ParamValue::Int(i) => *i as f32,
        ParamValue::Bool(b) => f32::from(u8::from(*b)),
        ParamValue::Choice(_) => 0.0,
    }
}

/// Reads a validated integer.
pub fn as_i64(value: &ParamValue) -> i64 {
    match value {
        ParamValue::Int(i) => *i,
        ParamValue::Float(x) => *x as i64,
        ParamValue::Bool(b) => i64::from(*b),
        ParamValue::Choice(_) => 0,
    }
}

/// Reads a validated bool.
pub fn as_bool(value: &ParamValue) -> bool {
    matches!(value, ParamValue::Bool(true))
}

/// Reads a validated choice.
pub fn as_choice(value: &ParamValue) -> &str {
    match value {
        ParamValue::Choice(s) => s,
        _ => "",
    }
}

/// A settings enum with stable names: the one way a technique's typed choice becomes the
/// name the CLI's `--set`, the viewer's menus and the sidecars use, and back. Declare such an
/// enum with [`named_enum!`](crate::named_enum), which also keeps each variant's doc comment
/// as its description.
pub trait Named: Copy + PartialEq + 'static {
    /// Every value, in the order front ends list them.
    const ALL: &'static [Self];
    /// The names of [`Named::ALL`], in the same order.
    const NAMES: &'static [&'static str];
    /// The doc comments of [`Named::ALL`], in the same order.
    const DOCS: &'static [&'static str];

    /// Position in [`Named::ALL`] (also the value of the WGSL override constant that selects
    /// it, where a shader branches on it).
    fn index(self) -> usize {
        Self::ALL.iter().position(|v| *v == self).unwrap_or(0)
    }

    /// The name, as the CLI and the sidecars spell it.
    fn name(self) -> &'static str {
        Self::NAMES[self.index()]
    }

    /// What this value does (the variant's doc comment).
    fn doc(self) -> &'static str {
        Self::DOCS[self.index()].trim()
    }

    /// The value of a name (ASCII case-insensitive, as [`Param::validate`] accepts choices).
    fn from_name(name: &str) -> Option<Self> {
        Self::NAMES
            .iter()
            .position(|n| n.eq_ignore_ascii_case(name))
            .map(|i| Self::ALL[i])
    }
}

/// Declares a [`Named`] enum: each variant with its doc comment and its name.
///
/// ```
/// aa_lab::named_enum! {
///     /// Which way.
///     pub enum Way {
///         /// To the left.
///         Left => "left",
///         /// To the right.
///         Right => "right",
///     }
/// }
/// use aa_lab::graph::params::Named;
/// assert_eq!(Way::from_name("right"), Some(Way::Right));
/// assert_eq!(Way::Left.name(), "left");
/// assert_eq!(Way::Right.doc(), "To the right.");
/// ```
#[macro_export]
macro_rules! named_enum {
    (
        $(#[$meta:meta])*
        $vis:vis enum $enum:ident {
            $( $(#[doc = $doc:literal])* $variant:ident => $name:literal ),+ $(,)?
        }
    ) => {
        $(#[$meta])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        $vis enum $enum {
            $( $(#[doc = $doc])* $variant ),+
        }

        impl $crate::graph::params::Named for $enum {
            const ALL: &'static [Self] = &[$(Self::$variant),+];
            const NAMES: &'static [&'static str] = &[$($name),+];
            const DOCS: &'static [&'static str] = &[$(concat!($($doc),*)),+];
        }
    };
}

/// Reads a validated choice of a [`Named`] enum.
pub fn as_named<E: Named>(value: &ParamValue) -> Option<E> {
    E::from_name(as_choice(value))
}

/// A settings field a validated [`ParamValue`] can be assigned to: floats, bools and
/// [`Named`] choices (a name the enum does not know leaves the field as it was).
pub trait ParamField {
    /// Assigns `value`, already validated against the field's [`Param`].
    fn assign(&mut self, value: &ParamValue);
}

impl ParamField for f32 {
    fn assign(&mut self, value: &ParamValue) {
        *self = as_f32(value);
    }
}

impl ParamField for bool {
    fn assign(&mut self, value: &ParamValue) {
        *self = as_bool(value);
    }
}

impl<E: Named> ParamField for E {
    fn assign(&mut self, value: &ParamValue) {
        if let Some(named) = as_named(value) {
            *self = named;
        }
    }
}

/// The body of a [`Tunable::set`] that assigns each key to the field of the same name through
/// [`ParamField`]: `set_fields!(self, key, value, [gamma, rectify])`. Keys that need their own
/// conversion (a clamp, another field name) are matched before it.
#[macro_export]
macro_rules! set_fields {
    ($settings:expr, $key:expr, $value:expr, [$($field:ident),+ $(,)?]) => {{
        match $key {
            $(stringify!($field) => {
                $crate::graph::params::ParamField::assign(&mut $settings.$field, $value)
            })+
            _ => return false,
        }
        true
    }};
}

/// A technique's preset of a [`Named`] preset enum by name, or the error that names the
/// technique and lists its presets.
pub fn preset_named<E: Named>(technique: &str, name: &str) -> Result<E, ParamError> {
    E::from_name(name).ok_or_else(|| ParamError::UnknownPreset {
        technique: technique.to_owned(),
        name: name.to_owned(),
        known: E::NAMES.join(", "),
    })
}

/// A technique's settings seen as its parameters, with named presets: implemented once by each
/// settings type, so that the technique's `params`, `set_param`, `presets` and `apply_preset`
/// only forward to it (`aa::common::tunable_settings!` writes them).
pub trait Tunable {
    /// The named presets.
    type Preset: Named;

    /// Every parameter with its current value.
    fn params(&self) -> Vec<Param>;

    /// Applies a value already validated against [`Tunable::params`]; `false` for a key these
    /// settings do not have.
    fn set(&mut self, key: &str, value: &ParamValue) -> bool;

    /// Applies a preset (what it leaves alone is the settings type's to say).
    fn apply_preset(&mut self, preset: Self::Preset);

    /// [`Tunable::set`] as technique `technique` answers it: an unknown key is an error that
    /// lists the known ones.
    fn set_param(
        &mut self,
        technique: &str,
        key: &str,
        value: &ParamValue,
    ) -> Result<(), ParamError> {
        if self.set(key, value) {
            Ok(())
        } else {
            Err(ParamError::unknown_key(technique, key, &self.params()))
        }
    }

    /// Applies technique `technique`'s preset named `name`.
    fn apply_preset_named(&mut self, technique: &str, name: &str) -> Result<(), ParamError> {
        self.apply_preset(preset_named(technique, name)?);
        Ok(())
    }

    /// The presets' names.
    fn preset_names(&self) -> &'static [&'static str] {
        Self::Preset::NAMES
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validation_converts_and_checks_ranges() {
        let p = Param::float("subpix", "Subpixel", "", 0.0, 1.0, 0.75);
        assert_eq!(
            p.validate("fxaa", parse_value("0.5")),
            Ok(ParamValue::Float(0.5))
        );
        assert_eq!(
            p.validate("fxaa", parse_value("1")),
            Ok(ParamValue::Float(1.0))
        );
        assert!(p.validate("fxaa", parse_value("1.5")).is_err());
        assert!(p.validate("fxaa", parse_value("nan")).is_err());
        let c = Param::choice("pattern", "Pattern", "", &["grid", "halton"], "grid");
        assert_eq!(
            c.validate("ssaa", parse_value("Halton")),
            Ok(ParamValue::Choice("halton".into()))
        );
        let err = c
            .validate("ssaa", parse_value("poisson"))
            .unwrap_err()
            .to_string();
        assert!(err.contains("grid, halton"), "{err}");
        let b = Param::bool("a2c", "", "", false);
        assert_eq!(
            b.validate("msaa4", parse_value("on")),
            Ok(ParamValue::Bool(true))
        );
        let i = Param::int("samples", "", "", 1, 256, 16);
        assert!(i.validate("ssaa", parse_value("300")).is_err());
        assert_eq!(
            i.validate("ssaa", parse_value("64")),
            Ok(ParamValue::Int(64))
        );
    }
}
