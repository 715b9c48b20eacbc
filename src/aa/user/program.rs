//! A user technique's file turned into a checked program, without a GPU: the file is read
//! (bounded, UTF-8), placed between aa-lab's prelude and epilogue, parsed and validated with
//! naga, and its `override` constants become parameters. Every error names the user's file,
//! with the line and column in that file (the prelude's lines subtracted) when the compiler
//! points into it, the compiler's message and the offending line.

use std::fmt;
use std::path::{Path, PathBuf};

use crate::gpu::shader::Shader;
use crate::graph::hdr::TONEMAP_ORDER_KEY;
use crate::graph::params::{ParamKind, ParamValue};

/// aa-lab's code before the user's file: bindings and the `aa_*` functions.
pub const PRELUDE: Shader = crate::wgsl!("src/aa/user/prelude.wgsl");
/// aa-lab's code after the user's file: the fragment entry point that calls `aa_main`.
pub const EPILOGUE: Shader = crate::wgsl!("src/aa/user/epilogue.wgsl");
/// The fragment entry point defined by [`EPILOGUE`] for display values.
pub const ENTRY_POINT: &str = "aa_fragment";
/// The one for radiance, before the tonemapper of an HDR frame: it expands `aa_main`'s
/// Karis-compressed colour back to radiance.
pub const RADIANCE_ENTRY_POINT: &str = "aa_fragment_radiance";
/// The function the contract asks the user's file to define, as `docs/user-techniques.md`
/// states it.
pub const CONTRACT: &str = "fn aa_main(pixel: vec2<u32>, uv: vec2<f32>) -> vec4<f32>";
/// Largest user technique file aa-lab reads.
pub const MAX_SOURCE_BYTES: u64 = 1 << 20;

/// Why a user technique could not be loaded: the file, where in it (1-based line and column,
/// when known) and what is wrong.
#[derive(Clone, Debug, PartialEq)]
pub struct LoadError {
    /// The user's file.
    pub path: PathBuf,
    /// Line and column in the user's file (1-based, columns in bytes), when the error has one.
    pub location: Option<(u32, u32)>,
    /// The compiler's (or aa-lab's) message.
    pub message: String,
    /// The offending line with a caret under the column, when located.
    pub excerpt: Option<String>,
}

impl LoadError {
    fn whole_file(path: &Path, message: String) -> Self {
        Self {
            path: path.to_owned(),
            location: None,
            message,
            excerpt: None,
        }
    }
}

impl fmt::Display for LoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.location {
            Some((line, column)) => write!(
                f,
                "{}:{line}:{column}: {}",
                self.path.display(),
                self.message
            )?,
            None => write!(f, "{}: {}", self.path.display(), self.message)?,
        }
        if let Some(excerpt) = &self.excerpt {
            write!(f, "\n{excerpt}")?;
        }
        Ok(())
    }
}

impl std::error::Error for LoadError {}

/// The WGSL type of an `override` constant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OverrideType {
    /// `f32`.
    F32,
    /// `i32`.
    I32,
    /// `u32`.
    U32,
    /// `bool`.
    Bool,
}

/// One `override` constant of the user's file, exposed as a parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct OverrideParam {
    /// The constant's name (the parameter key).
    pub name: String,
    /// The key of its pipeline constant (`@id(n)` gives `n`, otherwise the name).
    pub constant_key: String,
    /// Its type.
    pub ty: OverrideType,
    /// Range and kind for the parameter.
    pub kind: ParamKind,
    /// The default from the file (zero or false when the file gives none).
    pub default: ParamValue,
    /// Help text: the declaration's trailing comment, after the optional range.
    pub help: String,
}

/// A user's file, checked and ready to become a pipeline.
#[derive(Clone, Debug)]
pub struct Program {
    /// The user's file (as given).
    pub path: PathBuf,
    /// The prelude, the user's source and the epilogue.
    pub combined: String,
    /// FNV-1a 64 of the file's bytes, as `fnv1a64:<16 hex digits>`.
    pub hash: String,
    /// The settable `override` constants, in declaration order.
    pub overrides: Vec<OverrideParam>,
    /// Whether the code reachable from `aa_main` reads depth.
    pub uses_depth: bool,
    /// Whether it reads motion vectors.
    pub uses_motion: bool,
}

/// The content hash recorded in sidecars: FNV-1a 64, stable across runs, platforms and Rust
/// versions (a change detector, not a security measure).
pub fn content_hash(bytes: &[u8]) -> String {
    let hash = bytes.iter().fold(0xcbf2_9ce4_8422_2325_u64, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    });
    format!("fnv1a64:{hash:016x}")
}

/// Reads the user's file and compiles it (see the module docs).
pub fn load(path: &Path) -> Result<Program, LoadError> {
    let bytes = crate::files::read_bounded(path, MAX_SOURCE_BYTES, "a user technique")
        .map_err(|e| LoadError::whole_file(path, e.to_string()))?;
    compile(path, &bytes)
}

/// Compiles a user technique's bytes, attributing errors to `path`.
pub fn compile(path: &Path, bytes: &[u8]) -> Result<Program, LoadError> {
    let source = std::str::from_utf8(bytes).map_err(|e| {
        let valid = &bytes[..e.valid_up_to()];
        let line = valid.iter().filter(|&&b| b == b'\n').count() as u32 + 1;
        let column = valid.iter().rev().take_while(|&&b| b != b'\n').count() as u32 + 1;
        LoadError {
            path: path.to_owned(),
            location: Some((line, column)),
            message: "the file is not UTF-8 text (WGSL sources are UTF-8)".to_owned(),
            excerpt: None,
        }
    })?;
    let combined = format!("{}{source}\n{}", PRELUDE.source, EPILOGUE.source);
    let layout = Layout {
        path,
        source,
        user_start: PRELUDE.source.len(),
        user_end: PRELUDE.source.len() + source.len(),
    };
    let module = naga::front::wgsl::parse_str(&combined).map_err(|e| {
        let mut message = e.message().to_owned();
        let labels: Vec<(naga::Span, String)> =
            e.labels().map(|(s, l)| (s, l.to_owned())).collect();
        if let Some(note) = e.notes().next() {
            message = format!("{message} ({note})");
        }
        layout.error(message, &labels)
    })?;
    let mut validator = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    );
    validator.validate(&module).map_err(|e| {
        let labels: Vec<(naga::Span, String)> = e.spans().cloned().collect();
        let mut message = e.as_inner().to_string();
        let mut source = std::error::Error::source(e.as_inner());
        while let Some(inner) = source {
            message = format!("{message}: {inner}");
            source = inner.source();
        }
        layout.error(message, &labels)
    })?;
    let overrides = overrides(&module, &layout)?;
    let mut reachable = module.clone();
    naga::compact::compact(&mut reachable, naga::compact::KeepUnused::No);
    let calls = |name: &str| {
        reachable
            .functions
            .iter()
            .any(|(_, f)| f.name.as_deref() == Some(name))
    };
    Ok(Program {
        path: path.to_owned(),
        hash: content_hash(bytes),
        uses_depth: calls("aa_depth"),
        uses_motion: calls("aa_motion"),
        combined,
        overrides,
    })
}

/// Where the user's source lies in the combined source, to map compiler spans back.
struct Layout<'a> {
    path: &'a Path,
    source: &'a str,
    user_start: usize,
    user_end: usize,
}

impl Layout<'_> {
    /// Line and column in the user's file of a byte offset into the combined source.
    fn location(&self, offset: usize) -> (u32, u32) {
        let local = offset
            .saturating_sub(self.user_start)
            .min(self.source.len());
        let before = &self.source[..floor_char_boundary(self.source, local)];
        let line = before.matches('\n').count() as u32 + 1;
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        (line, (before.len() - line_start) as u32 + 1)
    }

    /// The line of the user's file at `line` with a caret under `column`.
    fn excerpt(&self, line: u32, column: u32) -> Option<String> {
        let text = self.source.lines().nth(line as usize - 1)?;
        let pad: String = text
            .chars()
            .take(column as usize - 1)
            .map(|c| if c == '\t' { '\t' } else { ' ' })
            .collect();
        Some(format!("{line:>5} | {text}\n      | {pad}^"))
    }

    /// An error at the first label that points into the user's file; a label in the
    /// epilogue means the file breaks the contract around `aa_main`.
    fn error(&self, message: String, labels: &[(naga::Span, String)]) -> LoadError {
        let in_user = labels.iter().find_map(|(span, label)| {
            let range = span.to_range()?;
            (range.start >= self.user_start && range.start <= self.user_end)
                .then_some((range.start, label))
        });
        if let Some((offset, label)) = in_user {
            let (line, column) = self.location(offset);
            let message = if label.is_empty() || message.contains(label.as_str()) {
                message
            } else {
                format!("{message} ({label})")
            };
            return self.at(line, column, message);
        }
        let in_epilogue = labels
            .iter()
            .any(|(span, _)| span.to_range().is_some_and(|r| r.start > self.user_end));
        if in_epilogue {
            let message = format!("the file must define `{CONTRACT}`: {message}");
            return match find_declaration(self.source, "fn aa_main") {
                Some(offset) => {
                    let (line, column) = self.location(self.user_start + offset);
                    self.at(line, column, message)
                }
                None => LoadError::whole_file(
                    self.path,
                    format!("the file has no `{CONTRACT}` ({message})"),
                ),
            };
        }
        LoadError::whole_file(
            self.path,
            format!(
                "{message} (in the code aa-lab places before the file; names starting with \
                 `aa_` are aa-lab's)"
            ),
        )
    }

    fn at(&self, line: u32, column: u32, message: String) -> LoadError {
        LoadError {
            path: self.path.to_owned(),
            location: Some((line, column)),
            message,
            excerpt: self.excerpt(line, column),
        }
    }
}

fn floor_char_boundary(text: &str, mut index: usize) -> usize {
    while !text.is_char_boundary(index) {
        index -= 1;
    }
    index
}

/// Byte offset of `what` (e.g. `fn aa_main`) in the source outside line comments.
fn find_declaration(source: &str, what: &str) -> Option<usize> {
    let mut offset = 0;
    for line in source.split_inclusive('\n') {
        let code = line.split("//").next().unwrap_or("");
        if let Some(i) = code.find(what) {
            return Some(offset + i);
        }
        offset += line.len();
    }
    None
}

/// The settable `override` constants of a validated module: those with a literal default or
/// none (an override computed from others is not a parameter).
fn overrides(module: &naga::Module, layout: &Layout<'_>) -> Result<Vec<OverrideParam>, LoadError> {
    let mut params = Vec::new();
    for (handle, o) in module.overrides.iter() {
        let Some(name) = o.name.clone() else { continue };
        let span = module.overrides.get_span(handle);
        let offset = span.to_range().map_or(layout.user_start, |r| r.start);
        let (line, column) = layout.location(offset);
        if name == TONEMAP_ORDER_KEY {
            return Err(layout.at(
                line,
                column,
                format!(
                    "override `{name}`: the name is aa-lab's (every user technique's tonemap \
                     order, `--set user.{name}=before`); rename the constant"
                ),
            ));
        }
        let naga::TypeInner::Scalar(scalar) = module.types[o.ty].inner else {
            continue;
        };
        let ty = match (scalar.kind, scalar.width) {
            (naga::ScalarKind::Float, 4) => OverrideType::F32,
            (naga::ScalarKind::Sint, 4) => OverrideType::I32,
            (naga::ScalarKind::Uint, 4) => OverrideType::U32,
            (naga::ScalarKind::Bool, _) => OverrideType::Bool,
            _ => continue,
        };
        let default = match o.init.map(|init| &module.global_expressions[init]) {
            None => 0.0,
            Some(naga::Expression::Literal(literal)) => match *literal {
                naga::Literal::F32(x) => f64::from(x),
                naga::Literal::I32(i) => f64::from(i),
                naga::Literal::U32(u) => f64::from(u),
                naga::Literal::Bool(b) => f64::from(u8::from(b)),
                naga::Literal::AbstractFloat(x) => x,
                naga::Literal::AbstractInt(i) => i as f64,
                _ => continue,
            },
            Some(_) => continue,
        };
        let text = layout
            .source
            .lines()
            .nth(line as usize - 1)
            .unwrap_or_default();
        let comment = text.split_once("//").map_or("", |(_, c)| c.trim());
        let Annotation { range, help } = parse_range(comment)
            .map_err(|reason| layout.at(line, column, format!("override `{name}`: {reason}")))?;
        let kind = param_kind(ty, default, range);
        let default_value = match ty {
            OverrideType::F32 => ParamValue::Float(default as f32),
            OverrideType::I32 | OverrideType::U32 => ParamValue::Int(default as i64),
            OverrideType::Bool => ParamValue::Bool(default != 0.0),
        };
        let in_range = match &kind {
            ParamKind::Float { min, max } => (*min..=*max).contains(&(default as f32)),
            ParamKind::Int { min, max } => (*min..=*max).contains(&(default as i64)),
            _ => true,
        };
        if !in_range {
            return Err(layout.at(
                line,
                column,
                format!(
                    "override `{name}`: its default {default} is outside its range `{comment}`"
                ),
            ));
        }
        let help = if help.is_empty() {
            format!(
                "`override {name}` of {}",
                layout.path.file_name().map_or_else(
                    || layout.path.display().to_string(),
                    |n| n.to_string_lossy().into_owned()
                )
            )
        } else {
            help.to_owned()
        };
        params.push(OverrideParam {
            constant_key: o.id.map_or_else(|| name.clone(), |id| id.to_string()),
            name,
            ty,
            kind,
            default: default_value,
            help,
        });
    }
    Ok(params)
}

/// What a declaration's trailing comment says: an optional `[MIN, MAX]` range, then help.
struct Annotation<'a> {
    range: Option<(f64, f64)>,
    help: &'a str,
}

/// Splits a declaration's trailing comment into an optional `[MIN, MAX]` range and the help
/// text after it.
fn parse_range(comment: &str) -> Result<Annotation<'_>, String> {
    let Some(rest) = comment.strip_prefix('[') else {
        return Ok(Annotation {
            range: None,
            help: comment,
        });
    };
    let malformed = || format!("`{comment}` does not start with a range `[MIN, MAX]`");
    let (inside, help) = rest.split_once(']').ok_or_else(malformed)?;
    let (min, max) = inside.split_once(',').ok_or_else(malformed)?;
    let parse = |s: &str| s.trim().parse::<f64>().ok().filter(|x| x.is_finite());
    match (parse(min), parse(max)) {
        (Some(min), Some(max)) if min < max => Ok(Annotation {
            range: Some((min, max)),
            help: help.trim(),
        }),
        _ => Err(malformed()),
    }
}

/// The parameter kind of an override: its stated range, or one around its default
/// (`0..=max(1, 2 * default)` for reals, `0..=max(16, 2 * default)` for integers, reaching
/// down to twice a negative default).
fn param_kind(ty: OverrideType, default: f64, range: Option<(f64, f64)>) -> ParamKind {
    let (min, max) = range.unwrap_or_else(|| match ty {
        OverrideType::F32 => ((2.0 * default).min(0.0), (2.0 * default).max(1.0)),
        _ => ((2.0 * default).min(0.0), (2.0 * default).max(16.0)),
    });
    match ty {
        OverrideType::Bool => ParamKind::Bool,
        OverrideType::F32 => ParamKind::Float {
            min: min as f32,
            max: max as f32,
        },
        OverrideType::I32 => ParamKind::Int {
            min: min.ceil().max(f64::from(i32::MIN)) as i64,
            max: max.floor().min(f64::from(i32::MAX)) as i64,
        },
        OverrideType::U32 => ParamKind::Int {
            min: min.ceil().max(0.0) as i64,
            max: max.floor().min(f64::from(u32::MAX)) as i64,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn compile_text(text: &str) -> Result<Program, LoadError> {
        compile(Path::new("mine.wgsl"), text.as_bytes())
    }

    const PASS_THROUGH: &str = "fn aa_main(pixel: vec2<u32>, uv: vec2<f32>) -> vec4<f32> {\n    \
                                return aa_load(vec2<i32>(pixel));\n}\n";

    #[test]
    fn a_pass_through_compiles_and_reads_only_colour() {
        let program = compile_text(PASS_THROUGH).expect("compiles");
        assert!(!program.uses_depth && !program.uses_motion);
        assert!(program.overrides.is_empty());
        assert!(program.hash.starts_with("fnv1a64:"));
    }

    #[test]
    fn errors_carry_the_users_line_and_column() {
        let err = compile_text(
            "\n\nfn aa_main(pixel: vec2<u32>, uv: vec2<f32>) -> vec4<f32> {\n    return nope;\n}\n",
        )
        .expect_err("undefined name");
        assert_eq!(err.location, Some((4, 12)), "{err}");
        let text = err.to_string();
        assert!(text.starts_with("mine.wgsl:4:12: no definition"), "{text}");
        assert!(text.contains("return nope;"), "{text}");
    }

    #[test]
    fn contract_violations_are_named() {
        let missing = compile_text("fn main() {}\n").expect_err("no aa_main");
        assert!(missing.to_string().contains(CONTRACT), "{missing}");
        let wrong = compile_text(
            "\nfn aa_main(pixel: vec2<u32>, uv: vec2<f32>) -> f32 {\n    return 1.0;\n}\n",
        )
        .expect_err("wrong return type");
        assert_eq!(wrong.location.map(|l| l.0), Some(2), "{wrong}");
        let bytes = b"// caf\xe9\nfn aa_main";
        let err = compile(Path::new("x.wgsl"), bytes).expect_err("not UTF-8");
        assert_eq!(err.location, Some((1, 7)), "{err}");
    }

    #[test]
    fn overrides_become_parameters_with_ranges_and_reachability() {
        let program = compile_text(
            "override strength: f32 = 0.25; // [0, 4] How much to blur\n\
             override taps: u32 = 3u;\n\
             override enabled = true;\n\
             fn aa_main(pixel: vec2<u32>, uv: vec2<f32>) -> vec4<f32> {\n    \
             let p = vec2<i32>(pixel);\n    \
             let d = aa_depth(p) * f32(taps) * select(0.0, strength, enabled);\n    \
             return aa_load(p) + vec4<f32>(d * 0.0);\n}\n",
        )
        .expect("compiles");
        assert!(program.uses_depth && !program.uses_motion);
        let names: Vec<&str> = program.overrides.iter().map(|o| o.name.as_str()).collect();
        assert_eq!(names, ["strength", "taps", "enabled"]);
        assert_eq!(
            program.overrides[0].kind,
            ParamKind::Float { min: 0.0, max: 4.0 }
        );
        assert_eq!(program.overrides[0].help, "How much to blur");
        assert_eq!(program.overrides[1].default, ParamValue::Int(3));
        assert_eq!(program.overrides[2].default, ParamValue::Bool(true));
        let bad = compile_text(&format!("override k: f32 = 9.0; // [0, 1]\n{PASS_THROUGH}"))
            .expect_err("default outside range");
        assert_eq!(bad.location.map(|l| l.0), Some(1), "{bad}");
    }

    #[test]
    fn the_tonemap_order_is_not_a_constant_the_file_may_declare() {
        let err = compile_text(&format!(
            "\noverride tonemap_order: bool = true;\n{PASS_THROUGH}"
        ))
        .expect_err("the tonemap order is aa-lab's parameter");
        assert_eq!(err.location.map(|l| l.0), Some(2), "{err}");
        assert!(err.message.contains("is aa-lab's"), "{err}");
    }
}
