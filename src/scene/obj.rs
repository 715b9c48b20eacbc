//! Wavefront OBJ/MTL loading: [`load_obj`] turns an `.obj` file, its material libraries and
//! their textures into a [`Scene`] whose camera is framed to the model.
//!
//! The file is read whole, bounded ([`MAX_OBJ_BYTES`], [`MAX_MTL_BYTES`]) and required to be a
//! regular file of UTF-8 text, so a device or FIFO named as a model is refused instead of read
//! forever. `tobj` parses it, but only after a validation pass of our own: `tobj` reports errors
//! without line numbers, accepts `nan`/`inf` coordinates, turns 3-point polylines into faces and
//! can overflow on absurd relative indices, so this pass rejects malformed or non-finite records
//! and out-of-range indices naming the line, and rewrites what `tobj` would mishandle
//! (polylines, short faces, vertex colours, spacing of names), with one warning per kind. MTL
//! text gets the same treatment. Each `tobj` model then becomes vertices (UV `v` flipped to the
//! renderer's top-left origin; area-weighted normals generated where the model has none, smooth
//! across UV seams), merged into one [`Mesh`] per (object, material) pair.
//!
//! Materials map onto the renderer's [`Material`]: `Kd`/`Ks` are read as sRGB-encoded colours
//! (the usual reading of hand-written MTL files; a fixed convention beats guessing per file),
//! `Ns` as the Blinn-Phong exponent, `map_Kd` as the base texture and `map_d` as an alpha mask
//! merged into its alpha ([`AlphaMode::Mask`]). Translucency is not rendered (a warning says
//! so), a missing or undecodable texture draws a checker and is named in
//! [`Scene::warnings`] instead of failing the load, and the records that are ignored are
//! counted in [`Scene::notes`].
//!
//! The camera orbits the centre of the model's bounding box, slightly from above, at a
//! distance at which no orbit angle clips the model; a model that encloses that centre (a room,
//! a Cornell box: see [`super::interior`]) opens with an inside view instead, and
//! [`Scene::interior`] says so.
//!
//! Every rule in full (what each record means, texture options, the camera's framing):
//! `docs/content.md`, "How OBJ/MTL files are read".

use std::borrow::Cow;
use std::cell::RefCell;
use std::collections::{BTreeMap, HashMap, HashSet};
use std::io;
use std::path::{Path, PathBuf};

use glam::Vec3;
use image::imageops::FilterType;
use image::{DynamicImage, GrayImage, RgbaImage};

use crate::files::{self, FileError};

use super::{AlphaMode, CameraRig, DirectionalLight, Material, Mesh, Scene, TextureImage, Vertex};

/// Largest OBJ file read.
pub const MAX_OBJ_BYTES: u64 = 2 << 30;
/// Largest MTL file read.
pub const MAX_MTL_BYTES: u64 = 64 << 20;

/// Why an OBJ file could not be loaded. Every message names the file at fault.
#[derive(Debug, thiserror::Error)]
pub enum ObjError {
    /// The file is not a regular file or is too large to read.
    #[error(transparent)]
    File(FileError),
    /// The file could not be read (missing, a directory, no permission, ...).
    #[error("cannot read {}: {source}", path.display())]
    Io {
        /// File that was read.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: io::Error,
    },
    /// The file is binary data or not UTF-8 text.
    #[error("{} is not a text OBJ/MTL file: {reason}", path.display())]
    NotText {
        /// File that was read.
        path: PathBuf,
        /// What gave it away.
        reason: String,
    },
    /// The file has no faces to draw (it is empty, or holds only vertices or comments).
    #[error("{} has no faces: nothing to draw", path.display())]
    NoFaces {
        /// The OBJ file.
        path: PathBuf,
    },
    /// A record of the OBJ or MTL file is malformed.
    #[error("{}, line {line}: {message}", path.display())]
    Syntax {
        /// File with the record.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A face refers to a vertex, texture coordinate or normal that does not exist.
    #[error(
        "{}, line {line}: face refers to {kind} {index}, but only {count} are defined before it",
        path.display()
    )]
    IndexOutOfRange {
        /// The OBJ file.
        path: PathBuf,
        /// 1-based line number of the face.
        line: usize,
        /// `vertex`, `texture coordinate` or `normal`.
        kind: &'static str,
        /// The index as written (negative indices count back from the last element).
        index: i64,
        /// How many elements of that kind precede the face.
        count: usize,
    },
    /// A vertex, texture coordinate or normal has a NaN or infinite component.
    #[error("{}, line {line}: {kind} {index} has a non-finite component ({value})", path.display())]
    NonFinite {
        /// The OBJ file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// `vertex`, `texture coordinate` or `normal`.
        kind: &'static str,
        /// 1-based OBJ index of the element.
        index: usize,
        /// The offending value as written (or as computed, after a `w` division).
        value: String,
    },
    /// A material library named by `mtllib` could not be read.
    #[error(
        "cannot read material library {} (named by {}): {source}",
        mtl.display(),
        obj.display()
    )]
    MissingMtl {
        /// The OBJ file that names the library.
        obj: PathBuf,
        /// The path the library was looked for at.
        mtl: PathBuf,
        /// The operating system's error.
        #[source]
        source: io::Error,
    },
    /// `tobj` rejected a file the validation pass let through.
    #[error("{} could not be parsed: {source}", path.display())]
    Parse {
        /// The OBJ or MTL file.
        path: PathBuf,
        /// `tobj`'s error.
        #[source]
        source: tobj::LoadError,
    },
}

/// Loads an OBJ file (and its MTL and textures) into a Scene, camera framed to the bounds.
///
/// Problems that do not stop the load (missing or corrupt textures, unsupported translucency,
/// unknown material names, skipped records) are listed in [`Scene::warnings`].
pub fn load_obj(path: &Path) -> Result<Scene, ObjError> {
    let text = read_text(path, MAX_OBJ_BYTES, "an OBJ file")
        .map_err(|failure| failure.into_error(path))?;
    let checked = check_obj(path, &text)?;
    let mut warnings = checked.warnings;

    // `single_index` and `triangulate`, points and lines ignored.
    let options = tobj::GPU_LOAD_OPTIONS;
    let libraries = RefCell::new(Libraries::default());
    let loaded = tobj::load_obj_buf(&mut checked.text.as_bytes(), &options, |mtllib| {
        libraries.borrow_mut().load(path, mtllib)
    });
    let libraries = libraries.into_inner();
    if let Some(error) = libraries.error {
        return Err(error);
    }
    let parse_error = |source| ObjError::Parse {
        path: path.to_owned(),
        source,
    };
    let (models, materials) = loaded.map_err(parse_error)?;
    let materials = materials.map_err(parse_error)?;

    let known: HashSet<&str> = materials.iter().map(|m| m.name.as_str()).collect();
    let mut reported = HashSet::new();
    for (line, name) in &checked.usemtl {
        if !known.contains(name.as_str()) && reported.insert(name.as_str()) {
            warnings.push(format!(
                "{}, line {line}: usemtl '{name}' names no material of the material libraries; \
                 the default material is used",
                path.display()
            ));
        }
    }

    let mut builder = SceneBuilder {
        obj: path,
        library: &materials,
        sources: &libraries.sources,
        meshes: Vec::new(),
        mesh_slots: HashMap::new(),
        material_slots: HashMap::new(),
        materials: Vec::new(),
        textures: Textures::default(),
        warnings,
    };
    for model in &models {
        builder.add_model(model);
    }
    let mut scene = builder.finish();
    if !libraries.ignored.is_empty() {
        let list: Vec<String> = libraries
            .ignored
            .iter()
            .map(|(keyword, count)| format!("{keyword} ({count})"))
            .collect();
        scene.notes.push(format!(
            "{}: material statements aa-lab does not use were ignored: {}",
            path.display(),
            list.join(", ")
        ));
    }
    match bounding_sphere(&scene) {
        Some((center, radius)) if scene.triangle_count() > 0 => {
            let inside = super::interior::inside_view(&scene);
            Ok(Scene {
                camera: inside.unwrap_or_else(|| framed_camera(center, radius)),
                interior: inside.is_some(),
                ..scene
            })
        }
        _ => Err(ObjError::NoFaces {
            path: path.to_owned(),
        }),
    }
}

/// Background colour of OBJ scenes: a neutral mid-dark grey (linear RGB).
const CLEAR_COLOR: Vec3 = Vec3::splat(0.1);

/// Why a file could not be turned into text.
enum ReadFailure {
    Io(io::Error),
    File(FileError),
    NotText(String),
}

impl ReadFailure {
    fn into_error(self, path: &Path) -> ObjError {
        let path = path.to_owned();
        match self {
            Self::Io(source) => ObjError::Io { path, source },
            Self::File(error) => ObjError::File(error),
            Self::NotText(reason) => ObjError::NotText { path, reason },
        }
    }
}

/// Reads a whole regular file of at most `limit` bytes as UTF-8 text, rejecting binary data
/// and skipping a byte-order mark.
fn read_text(path: &Path, limit: u64, what: &'static str) -> Result<String, ReadFailure> {
    let bytes = files::read_bounded(path, limit, what).map_err(|error| match error {
        FileError::Read { source, .. } => ReadFailure::Io(source),
        other => ReadFailure::File(other),
    })?;
    if let Some(at) = bytes.iter().position(|&b| b == 0) {
        return Err(ReadFailure::NotText(format!(
            "NUL byte at offset {at} (binary data)"
        )));
    }
    let text = String::from_utf8(bytes).map_err(|e| {
        ReadFailure::NotText(format!(
            "invalid UTF-8 at byte offset {}",
            e.utf8_error().valid_up_to()
        ))
    })?;
    Ok(match text.strip_prefix('\u{feff}') {
        Some(rest) => rest.to_owned(),
        None => text,
    })
}

fn syntax(path: &Path, line: usize, message: String) -> ObjError {
    ObjError::Syntax {
        path: path.to_owned(),
        line,
        message,
    }
}

/// Parses a number of an OBJ/MTL record, naming the record in the error.
fn parse_number(path: &Path, line: usize, record: &str, word: &str) -> Result<f32, ObjError> {
    word.parse()
        .map_err(|_| syntax(path, line, format!("{record}: '{word}' is not a number")))
}

/// OBJ text that passed validation, ready for `tobj`.
struct CheckedObj<'a> {
    /// The text, with the records `tobj` would mishandle rewritten (line numbers kept).
    text: Cow<'a, str>,
    /// Every `usemtl` record: line number and material name.
    usemtl: Vec<(usize, String)>,
    /// Records that were skipped.
    warnings: Vec<String>,
}

/// How many vertices, texture coordinates and normals precede the current line.
#[derive(Default)]
struct ElementCounts {
    positions: usize,
    texcoords: usize,
    normals: usize,
}

/// The validation pass over the OBJ text (see the module docs).
fn check_obj<'a>(path: &Path, text: &'a str) -> Result<CheckedObj<'a>, ObjError> {
    let mut counts = ElementCounts::default();
    let mut faces = 0_usize;
    let mut usemtl = Vec::new();
    // Replacements of lines (by 0-based number) that tobj would mishandle.
    let mut rewritten: HashMap<usize, String> = HashMap::new();
    let (mut polylines, mut short_faces) = (0_usize, 0_usize);

    for (number, line) in text.lines().enumerate() {
        let line_no = number + 1;
        let mut words = line.split_whitespace();
        let Some(keyword) = words.next() else {
            continue;
        };
        let values: Vec<&str> = words.collect();
        match keyword {
            "v" => {
                counts.positions += 1;
                check_position(path, line_no, counts.positions, &values)?;
                // Vertex colours are not used, and tobj fails on files where only some
                // vertices have them.
                if let [x, y, z, _, _, _] = values.as_slice() {
                    rewritten.insert(number, format!("v {x} {y} {z}"));
                }
            }
            "vt" => {
                counts.texcoords += 1;
                check_finite(
                    path,
                    line_no,
                    "texture coordinate",
                    counts.texcoords,
                    &values,
                    2,
                )?;
            }
            "vn" => {
                counts.normals += 1;
                check_finite(path, line_no, "normal", counts.normals, &values, 3)?;
            }
            "f" | "l" => {
                for corner in &values {
                    check_corner(path, line_no, corner, &counts)?;
                }
                if keyword == "l" {
                    polylines += 1;
                    rewritten.insert(number, String::new());
                } else if values.len() < 3 {
                    short_faces += 1;
                    rewritten.insert(number, String::new());
                } else {
                    faces += 1;
                }
            }
            "usemtl" | "mtllib" if values.is_empty() => {
                return Err(syntax(path, line_no, format!("{keyword} needs a name")));
            }
            "usemtl" | "mtllib" | "o" | "g" => {
                // tobj finds these names by splitting at the first space of the raw line, so
                // indentation or a tab would change or lose them: write them its way.
                let name = line.trim().strip_prefix(keyword).unwrap_or_default().trim();
                let canonical = format!("{keyword} {name}");
                if keyword == "usemtl" {
                    usemtl.push((line_no, name.to_owned()));
                }
                if canonical != line {
                    rewritten.insert(number, canonical);
                }
            }
            _ => {}
        }
    }
    if faces == 0 {
        return Err(ObjError::NoFaces {
            path: path.to_owned(),
        });
    }

    let mut warnings = Vec::new();
    if polylines > 0 {
        warnings.push(format!(
            "{}: {polylines} polyline (l) records are not drawn",
            path.display()
        ));
    }
    if short_faces > 0 {
        warnings.push(format!(
            "{}: {short_faces} faces with fewer than three vertices are skipped",
            path.display()
        ));
    }
    let text = if rewritten.is_empty() {
        Cow::Borrowed(text)
    } else {
        Cow::Owned(
            text.lines()
                .enumerate()
                .map(|(n, line)| rewritten.get(&n).map_or(line, String::as_str))
                .collect::<Vec<_>>()
                .join("\n"),
        )
    };
    Ok(CheckedObj {
        text,
        usemtl,
        warnings,
    })
}

/// Checks a `v x y z [w | r g b]` record: finite coordinates, and a finite non-zero `w`.
fn check_position(path: &Path, line: usize, index: usize, values: &[&str]) -> Result<(), ObjError> {
    if !matches!(values.len(), 3 | 4 | 6) {
        return Err(syntax(
            path,
            line,
            format!(
                "v needs x y z, optionally followed by w or by r g b, but has {} values",
                values.len()
            ),
        ));
    }
    check_finite(path, line, "vertex", index, values, 3)?;
    if let [x, y, z, w] = values {
        let w = parse_number(path, line, "v", w)?;
        if w == 0.0 || !w.is_finite() {
            return Err(syntax(path, line, format!("v has a weight w of {w}")));
        }
        for word in [x, y, z] {
            let scaled = parse_number(path, line, "v", word)? / w;
            if !scaled.is_finite() {
                return Err(non_finite(path, line, "vertex", index, scaled.to_string()));
            }
        }
    }
    Ok(())
}

fn non_finite(
    path: &Path,
    line: usize,
    kind: &'static str,
    index: usize,
    value: String,
) -> ObjError {
    ObjError::NonFinite {
        path: path.to_owned(),
        line,
        kind,
        index,
        value,
    }
}

/// Checks that a record has at least `needed` numbers and that those are finite.
fn check_finite(
    path: &Path,
    line: usize,
    kind: &'static str,
    index: usize,
    values: &[&str],
    needed: usize,
) -> Result<(), ObjError> {
    if values.len() < needed {
        return Err(syntax(
            path,
            line,
            format!(
                "{kind} {index} needs {needed} numbers but has {}",
                values.len()
            ),
        ));
    }
    for word in &values[..needed] {
        if !parse_number(path, line, kind, word)?.is_finite() {
            return Err(non_finite(path, line, kind, index, (*word).to_owned()));
        }
    }
    Ok(())
}

/// Checks one face corner `v`, `v/vt`, `v//vn` or `v/vt/vn` against the elements defined so far.
fn check_corner(
    path: &Path,
    line: usize,
    corner: &str,
    counts: &ElementCounts,
) -> Result<(), ObjError> {
    let parts: Vec<&str> = corner.split('/').collect();
    if parts.len() > 3 || parts[0].is_empty() {
        return Err(syntax(
            path,
            line,
            format!("face corner '{corner}' is not of the form v, v/vt, v//vn or v/vt/vn"),
        ));
    }
    let kinds = [
        ("vertex", counts.positions),
        ("texture coordinate", counts.texcoords),
        ("normal", counts.normals),
    ];
    for (part, (kind, count)) in parts.iter().zip(kinds) {
        if part.is_empty() {
            continue;
        }
        let index: i64 = part.parse().map_err(|_| {
            syntax(
                path,
                line,
                format!("face corner '{corner}' has a {kind} index that is not an integer"),
            )
        })?;
        // Negative indices count back from the last element defined so far.
        let defined = i64::try_from(count).unwrap_or(i64::MAX);
        let resolved = if index < 0 {
            defined + index + 1
        } else {
            index
        };
        if index == 0 || !(1..=defined).contains(&resolved) {
            return Err(ObjError::IndexOutOfRange {
                path: path.to_owned(),
                line,
                kind,
                index,
                count,
            });
        }
    }
    Ok(())
}

/// Material libraries read on `tobj`'s behalf while it parses the OBJ.
#[derive(Default)]
struct Libraries {
    /// The MTL file of each material, in `tobj`'s material order.
    sources: Vec<PathBuf>,
    /// The first library that failed; it fails the whole load.
    error: Option<ObjError>,
    /// Keywords of the statements no material reads, with how often they occur.
    ignored: BTreeMap<String, usize>,
}

impl Libraries {
    /// Loads the libraries of one `mtllib` record for `tobj`.
    fn load(&mut self, obj: &Path, mtllib: &Path) -> tobj::MTLLoadResult {
        if self.error.is_some() {
            return Err(tobj::LoadError::OpenFileFailed);
        }
        let dir = obj.parent().unwrap_or(Path::new(""));
        let record = mtllib.to_string_lossy().replace('\\', "/");
        // `mtllib` may name several files; a single name may also contain spaces.
        let whole = dir.join(&record);
        let files = if whole.is_file() || !record.contains(char::is_whitespace) {
            vec![whole]
        } else {
            record
                .split_whitespace()
                .map(|name| dir.join(name))
                .collect()
        };

        let mut materials = Vec::new();
        let mut names = Vec::new();
        for file in files {
            match read_mtl(obj, &file, &mut self.ignored) {
                Ok((loaded, map)) => {
                    let offset = materials.len();
                    names.extend(map.into_iter().map(|(name, i)| (name, i + offset)));
                    self.sources.extend(std::iter::repeat_n(file, loaded.len()));
                    materials.extend(loaded);
                }
                Err(error) => {
                    self.error = Some(error);
                    return Err(tobj::LoadError::OpenFileFailed);
                }
            }
        }
        Ok((materials, names.into_iter().collect()))
    }
}

/// Material names of an MTL file with their indices in its material list.
type MaterialNames = Vec<(String, usize)>;

/// Reads, validates and parses one MTL file.
fn read_mtl(
    obj: &Path,
    mtl: &Path,
    ignored: &mut BTreeMap<String, usize>,
) -> Result<(Vec<tobj::Material>, MaterialNames), ObjError> {
    let text =
        read_text(mtl, MAX_MTL_BYTES, "a material library").map_err(|failure| match failure {
            ReadFailure::Io(source) => ObjError::MissingMtl {
                obj: obj.to_owned(),
                mtl: mtl.to_owned(),
                source,
            },
            other => other.into_error(mtl),
        })?;
    let text = normalize_mtl(mtl, &text, ignored)?;
    let (materials, names) =
        tobj::load_mtl_buf(&mut text.as_bytes()).map_err(|source| ObjError::Parse {
            path: mtl.to_owned(),
            source,
        })?;
    Ok((materials, names.into_iter().collect()))
}

/// MTL statements the loader reads; every other one is listed in a note.
const READ_MTL_STATEMENTS: &[&str] = &["newmtl", "Kd", "Ks", "Ns", "d", "Tr", "map_Kd", "map_d"];

/// Validates MTL text and rewrites it into what `tobj` parses without surprises (see the
/// module docs); line numbers are kept. Keywords of statements that are not read are counted
/// in `ignored`.
fn normalize_mtl(
    path: &Path,
    text: &str,
    ignored: &mut BTreeMap<String, usize>,
) -> Result<String, ObjError> {
    let mut out = Vec::new();
    for (number, line) in text.lines().enumerate() {
        let line_no = number + 1;
        let mut words = line.split_whitespace();
        let keyword = words.next().unwrap_or("");
        let values: Vec<&str> = words.collect();
        if !keyword.is_empty()
            && !keyword.starts_with('#')
            && !READ_MTL_STATEMENTS.contains(&keyword)
        {
            *ignored.entry(keyword.to_owned()).or_default() += 1;
        }
        let finite = |word: &str| -> Result<f32, ObjError> {
            let value = parse_number(path, line_no, keyword, word)?;
            if value.is_finite() {
                Ok(value)
            } else {
                Err(syntax(path, line_no, format!("{keyword} is {word}")))
            }
        };
        let rewritten = match keyword {
            "Ka" | "Kd" | "Ks" | "Ke" => {
                for word in &values {
                    finite(word)?;
                }
                match values.as_slice() {
                    [single] => Cow::Owned(format!("{keyword} {single} {single} {single}")),
                    [_, _, _] => Cow::Borrowed(line),
                    _ => {
                        return Err(syntax(
                            path,
                            line_no,
                            format!(
                                "{keyword} needs one or three numbers (r g b), found {}",
                                values.len()
                            ),
                        ));
                    }
                }
            }
            "Ns" | "Ni" | "d" | "Tr" => {
                match values.as_slice() {
                    [value, ..] => finite(value)?,
                    [] => return Err(syntax(path, line_no, format!("{keyword} needs a number"))),
                };
                Cow::Borrowed(line)
            }
            "illum" => Cow::Borrowed(""),
            "newmtl" | "map_Kd" | "map_d" | "map_Ka" | "map_Ks" | "map_Ns" | "map_Bump"
            | "map_bump" | "bump"
                if values.is_empty() =>
            {
                return Err(syntax(path, line_no, format!("{keyword} needs a name")));
            }
            _ => Cow::Borrowed(line),
        };
        out.push(rewritten);
    }
    Ok(out.join("\n"))
}

/// A colour channel an MTL scalar texture (`-imfchan`) is read from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Channel {
    Red,
    Green,
    Blue,
    Alpha,
    Luminance,
}

/// A texture reference of an MTL `map_*` record.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
struct TextureRef {
    /// Resolved file path.
    path: PathBuf,
    /// Channel named by `-imfchan`.
    channel: Option<Channel>,
}

/// Number of arguments of the MTL texture options; `None` for those with one to three numbers.
fn option_arity(option: &str) -> Option<Option<usize>> {
    match option {
        "-blendu" | "-blendv" | "-bm" | "-boost" | "-cc" | "-clamp" | "-imfchan" | "-texres"
        | "-type" => Some(Some(1)),
        "-mm" => Some(Some(2)),
        "-o" | "-s" | "-t" => Some(None),
        _ => None,
    }
}

/// Splits a `map_*` argument into its options and file name, resolving the name against the
/// MTL file's directory.
fn parse_texture_ref(spec: &str, dir: &Path) -> TextureRef {
    let mut rest = spec.trim();
    let mut channel = None;
    loop {
        let (word, after) = rest.split_once(char::is_whitespace).unwrap_or((rest, ""));
        let Some(arity) = option_arity(word) else {
            break;
        };
        rest = after.trim_start();
        // Options with optional arguments take numbers, but never the last word (the file).
        let max_args = arity.unwrap_or(3);
        for taken in 0..max_args {
            let (arg, after) = rest.split_once(char::is_whitespace).unwrap_or((rest, ""));
            let is_number = arg.parse::<f32>().is_ok();
            if after.is_empty() || (arity.is_none() && taken > 0 && !is_number) {
                break;
            }
            if word == "-imfchan" {
                channel = Some(match arg {
                    "r" => Channel::Red,
                    "g" => Channel::Green,
                    "b" => Channel::Blue,
                    "m" => Channel::Alpha,
                    _ => Channel::Luminance,
                });
            }
            rest = after.trim_start();
        }
    }
    TextureRef {
        path: dir.join(rest.replace('\\', "/")),
        channel,
    }
}

fn srgb_color(rgb: [f32; 3]) -> Vec3 {
    Vec3::from(rgb.map(|c| crate::srgb::decode(c.clamp(0.0, 1.0))))
}

/// Side of the fallback checker texture and of its squares, in pixels.
const CHECKER_SIZE: u32 = 64;
const CHECKER_SQUARE: u32 = 8;

/// The magenta/black checker drawn in place of a texture that could not be loaded.
pub(crate) fn checker_image() -> RgbaImage {
    RgbaImage::from_fn(CHECKER_SIZE, CHECKER_SIZE, |x, y| {
        if (x / CHECKER_SQUARE + y / CHECKER_SQUARE).is_multiple_of(2) {
            image::Rgba([255, 0, 255, 255])
        } else {
            image::Rgba([0, 0, 0, 255])
        }
    })
}

/// The alpha mask an MTL `map_d` image stands for.
fn alpha_mask(image: &DynamicImage, channel: Option<Channel>) -> GrayImage {
    let rgba = image.to_rgba8();
    let channel = channel.unwrap_or(
        if image.color().has_alpha() && rgba.pixels().any(|p| p[3] < 255) {
            Channel::Alpha
        } else {
            Channel::Luminance
        },
    );
    let index = match channel {
        Channel::Red => 0,
        Channel::Green => 1,
        Channel::Blue => 2,
        Channel::Alpha => 3,
        Channel::Luminance => return image.to_luma8(),
    };
    GrayImage::from_fn(rgba.width(), rgba.height(), |x, y| {
        image::Luma([rgba.get_pixel(x, y)[index]])
    })
}

/// `base` with `mask` as its alpha channel; the smaller of the two is resampled to the larger.
fn merge_alpha(base: RgbaImage, mask: &GrayImage) -> RgbaImage {
    let width = base.width().max(mask.width());
    let height = base.height().max(mask.height());
    let mut base = if base.dimensions() == (width, height) {
        base
    } else {
        image::imageops::resize(&base, width, height, FilterType::Triangle)
    };
    let mask = if mask.dimensions() == (width, height) {
        Cow::Borrowed(mask)
    } else {
        Cow::Owned(image::imageops::resize(
            mask,
            width,
            height,
            FilterType::Triangle,
        ))
    };
    for (pixel, alpha) in base.pixels_mut().zip(mask.pixels()) {
        pixel[3] = alpha[0];
    }
    base
}

/// Textures of the scene, with the decoded files and finished textures cached.
#[derive(Default)]
struct Textures {
    images: Vec<TextureImage>,
    /// Decoded files, or why they could not be decoded.
    decoded: HashMap<PathBuf, Result<DynamicImage, String>>,
    /// Finished textures (index, whether it is the checker) by their (map_Kd, map_d) sources.
    finished: HashMap<(Option<TextureRef>, Option<TextureRef>), (usize, bool)>,
}

impl Textures {
    /// The decoded image of a file; the first failure for a file is reported in `warnings`.
    fn decode(
        &mut self,
        texture: &TextureRef,
        usage: &str,
        warnings: &mut Vec<String>,
    ) -> Option<&DynamicImage> {
        let decoded = self.decoded.entry(texture.path.clone()).or_insert_with(|| {
            let decoded =
                files::check_regular(&texture.path, files::MAX_IMAGE_FILE_BYTES, "a texture")
                    .map_err(|e| e.to_string())
                    .and_then(|_| {
                        image::ImageReader::open(&texture.path)
                            .and_then(|reader| reader.with_guessed_format())
                            .map_err(|e| e.to_string())
                    })
                    .and_then(|reader| reader.decode().map_err(|e| e.to_string()));
            if let Err(reason) = &decoded {
                warnings.push(format!(
                    "texture {} ({usage}) could not be loaded: {reason}; \
                         a magenta/black checker is drawn instead",
                    texture.path.display()
                ));
            }
            decoded
        });
        decoded.as_ref().ok()
    }

    /// The texture for a material's base colour and alpha mask, and whether it is the
    /// fallback checker.
    fn material_texture(
        &mut self,
        base: Option<TextureRef>,
        mask: Option<TextureRef>,
        usage: &str,
        warnings: &mut Vec<String>,
    ) -> (usize, bool) {
        let key = (base, mask);
        if let Some(&found) = self.finished.get(&key) {
            return found;
        }
        let mut label = Vec::new();
        let mut failed = false;
        let base_image = key.0.as_ref().and_then(|base| {
            label.push(base.path.display().to_string());
            let image = self.decode(base, &format!("map_Kd of {usage}"), warnings);
            failed |= image.is_none();
            image.map(DynamicImage::to_rgba8)
        });
        let mask_image = key.1.as_ref().and_then(|mask| {
            label.push(format!("alpha {}", mask.path.display()));
            let image = self.decode(mask, &format!("map_d of {usage}"), warnings);
            failed |= image.is_none();
            image.map(|image| alpha_mask(image, mask.channel))
        });
        let image = match (failed, base_image, mask_image) {
            (true, _, _) => {
                label = vec![format!("checker in place of {}", label.join(" + "))];
                checker_image()
            }
            (false, Some(base), Some(mask)) => merge_alpha(base, &mask),
            (false, None, Some(mask)) => {
                let white = RgbaImage::from_pixel(mask.width(), mask.height(), WHITE);
                merge_alpha(white, &mask)
            }
            (false, Some(base), None) => base,
            (false, None, None) => RgbaImage::from_pixel(1, 1, WHITE),
        };
        let found = (self.images.len(), failed);
        self.images.push(TextureImage {
            label: label.join(" + "),
            image,
        });
        self.finished.insert(key, found);
        found
    }
}

const WHITE: image::Rgba<u8> = image::Rgba([255; 4]);

/// Turns `tobj`'s models and materials into the scene's meshes, materials and textures.
struct SceneBuilder<'a> {
    obj: &'a Path,
    /// Materials of all libraries, in `tobj`'s order.
    library: &'a [tobj::Material],
    /// MTL file of each library material.
    sources: &'a [PathBuf],
    meshes: Vec<Mesh>,
    /// Mesh of each (object name, scene material).
    mesh_slots: HashMap<(String, usize), usize>,
    /// Scene material of each library material (`None`: the default material).
    material_slots: HashMap<Option<usize>, usize>,
    materials: Vec<Material>,
    textures: Textures,
    warnings: Vec<String>,
}

impl SceneBuilder<'_> {
    fn add_model(&mut self, model: &tobj::Model) {
        if model.mesh.indices.is_empty() {
            return;
        }
        let material = self.material_slot(model.mesh.material_id);
        let vertices = self.model_vertices(model);
        let slot = *self
            .mesh_slots
            .entry((model.name.clone(), material))
            .or_insert_with(|| {
                self.meshes.push(Mesh {
                    name: model.name.clone(),
                    vertices: Vec::new(),
                    indices: Vec::new(),
                    material,
                    spin: None,
                });
                self.meshes.len() - 1
            });
        let mesh = &mut self.meshes[slot];
        let base = mesh.vertices.len() as u32;
        mesh.indices
            .extend(model.mesh.indices.iter().map(|&i| base + i));
        mesh.vertices.extend(vertices);
    }

    /// Vertices of a `tobj` model: flipped UVs, normals from the file or generated.
    fn model_vertices(&mut self, model: &tobj::Model) -> Vec<Vertex> {
        let mesh = &model.mesh;
        let positions: Vec<Vec3> = mesh
            .positions
            .chunks_exact(3)
            .map(Vec3::from_slice)
            .collect();
        let count = positions.len();
        let partial = |what: &str| {
            format!(
                "{}: object '{}' has {what} on only some face corners; ",
                self.obj.display(),
                model.name
            )
        };

        let texcoords = match mesh.texcoords.len() {
            n if n == 2 * count => Some(&mesh.texcoords),
            0 => None,
            _ => {
                self.warnings
                    .push(partial("texture coordinates") + "its texture coordinates are dropped");
                None
            }
        };
        let file_normals: Option<Vec<Option<Vec3>>> =
            (mesh.normals.len() == 3 * count).then(|| {
                mesh.normals
                    .chunks_exact(3)
                    .map(|n| Vec3::from_slice(n).try_normalize())
                    .collect()
            });
        if file_normals.is_none() && !mesh.normals.is_empty() {
            self.warnings
                .push(partial("normals") + "smooth normals are generated instead");
        }
        let generated = || smooth_normals(&positions, &mesh.indices);
        let normals: Vec<Vec3> = match file_normals {
            None => generated(),
            Some(file) if file.iter().all(Option::is_some) => file.into_iter().flatten().collect(),
            // Zero-length normals in the file: generated ones stand in for them.
            Some(file) => file
                .into_iter()
                .zip(generated())
                .map(|(file, generated)| file.unwrap_or(generated))
                .collect(),
        };

        positions
            .iter()
            .zip(normals)
            .enumerate()
            .map(|(i, (&position, normal))| {
                let uv = texcoords.map_or([0.0, 0.0], |t| [t[2 * i], 1.0 - t[2 * i + 1]]);
                Vertex::new(position, normal, uv)
            })
            .collect()
    }

    /// Index in the scene's materials of a library material (`None`: the default material).
    fn material_slot(&mut self, library_index: Option<usize>) -> usize {
        if let Some(&slot) = self.material_slots.get(&library_index) {
            return slot;
        }
        let material =
            match library_index.and_then(|i| Some((self.library.get(i)?, self.sources.get(i)?))) {
                Some((material, source)) => self.convert_material(material, source),
                None => Material::default(),
            };
        let slot = self.materials.len();
        self.materials.push(material);
        self.material_slots.insert(library_index, slot);
        slot
    }

    fn convert_material(&mut self, mtl: &tobj::Material, source: &Path) -> Material {
        let dir = source.parent().unwrap_or(Path::new(""));
        let usage = format!("material '{}' in {}", mtl.name, source.display());
        let base_map = mtl
            .diffuse_texture
            .as_deref()
            .map(|s| parse_texture_ref(s, dir));
        let mask_map = mtl
            .dissolve_texture
            .as_deref()
            .map(|s| parse_texture_ref(s, dir));
        let has_map = base_map.is_some();
        let masked = mask_map.is_some();

        let defaults = Material::default();
        let mut material = Material {
            name: mtl.name.clone(),
            base_color: match mtl.diffuse {
                Some(kd) => srgb_color(kd),
                None if has_map => Vec3::ONE,
                None => defaults.base_color,
            },
            specular: mtl.specular.map_or(defaults.specular, srgb_color),
            shininess: mtl.shininess.map_or(defaults.shininess, |ns| ns.max(0.0)),
            ..defaults
        };

        if has_map || masked {
            let (texture, failed) =
                self.textures
                    .material_texture(base_map, mask_map, &usage, &mut self.warnings);
            material.base_color_texture = Some(texture);
            if failed {
                // The checker must show at full strength whatever the material's colour.
                material.base_color = Vec3::ONE;
            } else if masked {
                material.alpha_mode = AlphaMode::Mask { cutoff: 0.5 };
            }
        }

        let dissolve = mtl.dissolve.filter(|&d| d < 1.0).map(|d| format!("d {d}"));
        let transparency = mtl
            .unknown_param
            .get("Tr")
            .and_then(|tr| tr.split_whitespace().next()?.parse::<f32>().ok())
            .filter(|&tr| tr > 0.0)
            .map(|tr| format!("Tr {tr}"));
        if let Some(record) = dissolve.or(transparency) {
            self.warnings.push(format!(
                "{usage} asks for translucency ({record}), which is not supported; \
                 it is drawn opaque"
            ));
        }
        material
    }

    fn finish(self) -> Scene {
        Scene {
            name: self
                .obj
                .file_stem()
                .map_or_else(|| "obj".to_owned(), |s| s.to_string_lossy().into_owned()),
            meshes: self.meshes,
            materials: self.materials,
            textures: self.textures.images,
            camera: CameraRig::default(),
            interior: false,
            light: DirectionalLight::default(),
            clear_color: CLEAR_COLOR,
            views: Vec::new(),
            notes: Vec::new(),
            warnings: self.warnings,
        }
    }
}

/// Area-weighted smooth vertex normals of a triangle list.
///
/// Face normals weighted by area (the un-normalised cross product) are summed over all
/// vertices at the same position, so seams in the texture coordinates do not show in the
/// shading. A vertex whose sum vanishes (only degenerate faces, or faces that cancel) takes
/// the normal of its first non-degenerate face, or +Y.
fn smooth_normals(positions: &[Vec3], indices: &[u32]) -> Vec<Vec3> {
    let mut groups: HashMap<[u32; 3], usize> = HashMap::new();
    let group_of: Vec<usize> = positions
        .iter()
        .map(|p| {
            // Adding zero turns -0.0 into 0.0, so both spellings of a position share a group.
            let key = (*p + Vec3::ZERO).to_array().map(f32::to_bits);
            let next = groups.len();
            *groups.entry(key).or_insert(next)
        })
        .collect();
    let mut sums = vec![Vec3::ZERO; groups.len()];
    let mut first_face: Vec<Option<Vec3>> = vec![None; groups.len()];
    for triangle in indices.chunks_exact(3) {
        let [a, b, c] = [triangle[0], triangle[1], triangle[2]].map(|i| i as usize);
        let weighted = (positions[b] - positions[a]).cross(positions[c] - positions[a]);
        let unit = weighted.try_normalize();
        for v in [a, b, c] {
            let group = group_of[v];
            sums[group] += weighted;
            if first_face[group].is_none() {
                first_face[group] = unit;
            }
        }
    }
    group_of
        .iter()
        .map(|&g| sums[g].try_normalize().or(first_face[g]).unwrap_or(Vec3::Y))
        .collect()
}

/// Vertical field of view of OBJ scenes, in degrees.
const FOV_Y_DEGREES: f32 = 45.0;
/// How much larger than the bounding sphere the framed view is.
const FRAME_MARGIN: f32 = 1.1;
/// Camera elevation above the target, in degrees.
const PITCH_DEGREES: f32 = 15.0;
/// Auto-rotation speed, in degrees per frame.
const ORBIT_DEGREES_PER_FRAME: f32 = 0.5;

/// The sphere about the centre of the scene's bounding box through its farthest vertex
/// (tighter than the box's own bounding sphere), or `None` without vertices.
pub(crate) fn bounding_sphere(scene: &Scene) -> Option<(Vec3, f32)> {
    let (lo, hi) = scene.bounds()?;
    let center = (lo + hi) * 0.5;
    let radius = scene
        .meshes
        .iter()
        .flat_map(|m| &m.vertices)
        .map(|v| Vec3::from(v.position).distance(center))
        .fold(0.0, f32::max);
    Some((center, radius))
}

/// A camera rig orbiting `target` that keeps a sphere of `radius` about it in view.
pub(crate) fn framed_camera(target: Vec3, radius: f32) -> CameraRig {
    // A model of zero size still needs a camera that is not inside it.
    let radius = radius.max(1e-6);
    let distance = radius * FRAME_MARGIN / (FOV_Y_DEGREES.to_radians() * 0.5).sin();
    CameraRig {
        target,
        distance,
        yaw_degrees: 0.0,
        pitch_degrees: PITCH_DEGREES,
        fov_y_degrees: FOV_Y_DEGREES,
        near: radius * 0.01,
        far: distance + radius * 100.0,
        orbit_degrees_per_frame: ORBIT_DEGREES_PER_FRAME,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texture_options_are_skipped() {
        let dir = Path::new("/m");
        let plain = parse_texture_ref("wood.png", dir);
        assert_eq!(plain.path, Path::new("/m/wood.png"));
        assert_eq!(plain.channel, None);

        let options = parse_texture_ref("-bm 1 -s 2 2 -clamp on -o 0.5 maps\\bark wood.tga", dir);
        assert_eq!(options.path, Path::new("/m/maps/bark wood.tga"));

        let channel = parse_texture_ref("-imfchan g -t 1 leaf.png", dir);
        assert_eq!(channel.path, Path::new("/m/leaf.png"));
        assert_eq!(channel.channel, Some(Channel::Green));

        // An option's argument is never taken for the file name.
        assert_eq!(parse_texture_ref("-s 2", dir).path, Path::new("/m/2"));
        // A name that only looks like an option's number stays the name.
        assert_eq!(
            parse_texture_ref("-s 1 1 1 7.png", dir).path,
            Path::new("/m/7.png")
        );
    }

    #[test]
    fn material_colours_are_decoded_and_clamped() {
        assert_eq!(srgb_color([2.0, -1.0, 0.0]), Vec3::new(1.0, 0.0, 0.0));
    }

    #[test]
    fn smooth_normals_weight_by_area_and_survive_degenerate_faces() {
        // A big triangle facing +Z and a small one facing +X share vertex 0.
        let positions = [
            Vec3::ZERO,
            Vec3::new(4.0, 0.0, 0.0),
            Vec3::new(0.0, 4.0, 0.0),
            Vec3::new(0.0, 0.0, -1.0),
            Vec3::new(0.0, 1.0, 0.0),
            // A face of three collinear points, alone.
            Vec3::new(5.0, 5.0, 5.0),
            Vec3::new(6.0, 6.0, 6.0),
            Vec3::new(7.0, 7.0, 7.0),
        ];
        let indices = [0, 1, 2, 0, 3, 4, 5, 6, 7];
        let normals = smooth_normals(&positions, &indices);
        assert!(
            normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-5),
            "{normals:?}"
        );
        assert!(normals[0].z > 0.9 && normals[0].x > 0.0, "{}", normals[0]);
        assert_eq!(normals[1], Vec3::Z);
        assert_eq!(normals[5], Vec3::Y);
    }

    #[test]
    fn smooth_normals_join_uv_seams() {
        // Two triangles of a bent strip meet at an edge duplicated for a UV seam.
        let positions = [
            Vec3::ZERO,
            Vec3::X,
            Vec3::Y,
            Vec3::X,
            Vec3::Y,
            Vec3::new(1.0, 1.0, 1.0),
        ];
        let normals = smooth_normals(&positions, &[0, 1, 2, 3, 5, 4]);
        assert!((normals[1] - normals[3]).length() < 1e-6);
        assert!((normals[2] - normals[4]).length() < 1e-6);
    }

    #[test]
    fn alpha_merge_resamples_the_smaller_image() {
        let base = RgbaImage::from_pixel(4, 4, image::Rgba([10, 20, 30, 255]));
        let mask = GrayImage::from_fn(2, 2, |x, _| image::Luma([if x == 0 { 0 } else { 255 }]));
        let merged = merge_alpha(base, &mask);
        assert_eq!(merged.dimensions(), (4, 4));
        assert_eq!(merged.get_pixel(0, 0).0, [10, 20, 30, 0]);
        assert_eq!(merged.get_pixel(3, 3).0, [10, 20, 30, 255]);
    }

    #[test]
    fn framing_fits_the_bounding_sphere() {
        let target = Vec3::new(1.0, 1.0, 0.0);
        let radius = 2.5;
        let rig = framed_camera(target, radius);
        assert_eq!(rig.target, target);
        let half_fov = (rig.fov_y_degrees.to_radians() * 0.5).sin();
        assert!(rig.distance * half_fov > radius);
        assert!(rig.distance * half_fov < radius * 1.2);
        assert!(rig.near > 0.0 && rig.near < rig.distance - radius);
        assert!(rig.far > rig.distance + radius);

        let point = framed_camera(Vec3::ONE, 0.0);
        assert!(point.distance.is_finite() && point.distance > 0.0 && point.near > 0.0);
    }
}
