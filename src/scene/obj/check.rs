//! The validation pass an OBJ file goes through before `tobj` parses it: malformed and
//! non-finite records and out-of-range indices are refused naming the line, and what `tobj`
//! would mishandle (polylines, short faces, vertex colours, spacing of names) is rewritten in
//! place (line numbers kept), with one warning per kind.

use std::borrow::Cow;
use std::collections::HashMap;
use std::path::Path;

use super::error::{ObjError, parse_number, syntax};

/// OBJ text that passed validation, ready for `tobj`.
pub(super) struct CheckedObj<'a> {
    /// The text, with the records `tobj` would mishandle rewritten (line numbers kept).
    pub(super) text: Cow<'a, str>,
    /// Every `usemtl` record: line number and material name.
    pub(super) usemtl: Vec<(usize, String)>,
    /// Records that were skipped.
    pub(super) warnings: Vec<String>,
}

/// How many vertices, texture coordinates and normals precede the current line.
#[derive(Default)]
pub(super) struct ElementCounts {
    pub(super) positions: usize,
    pub(super) texcoords: usize,
    pub(super) normals: usize,
}

/// The validation pass over the OBJ text (see the module docs).
pub(super) fn check_obj<'a>(path: &Path, text: &'a str) -> Result<CheckedObj<'a>, ObjError> {
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
pub(super) fn check_position(
    path: &Path,
    line: usize,
    index: usize,
    values: &[&str],
) -> Result<(), ObjError> {
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

pub(super) fn non_finite(
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
pub(super) fn check_finite(
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
pub(super) fn check_corner(
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
