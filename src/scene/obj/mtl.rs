//! Materials and their textures: the MTL libraries read on `tobj`'s behalf (bounded, checked
//! like the OBJ text, unused statements counted), texture references with their options, and
//! the decoded textures, with a `map_d` mask merged into the base texture's alpha and a
//! checker where a texture is missing or cannot be decoded.

use std::borrow::Cow;
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

use glam::Vec3;
use image::imageops::FilterType;
use image::{DynamicImage, GrayImage, RgbaImage};

use super::error::{MAX_MTL_BYTES, ObjError, ReadFailure, parse_number, read_text, syntax};
use crate::files;
use crate::scene::TextureImage;

const WHITE: image::Rgba<u8> = image::Rgba([255; 4]);

/// Material libraries read on `tobj`'s behalf while it parses the OBJ.
#[derive(Default)]
pub(super) struct Libraries {
    /// The MTL file of each material, in `tobj`'s material order.
    pub(super) sources: Vec<PathBuf>,
    /// The first library that failed; it fails the whole load.
    pub(super) error: Option<ObjError>,
    /// Keywords of the statements no material reads, with how often they occur.
    pub(super) ignored: BTreeMap<String, usize>,
}

impl Libraries {
    /// Loads the libraries of one `mtllib` record for `tobj`.
    pub(super) fn load(&mut self, obj: &Path, mtllib: &Path) -> tobj::MTLLoadResult {
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
pub(super) type MaterialNames = Vec<(String, usize)>;

/// Reads, validates and parses one MTL file.
pub(super) fn read_mtl(
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
pub(super) const READ_MTL_STATEMENTS: &[&str] =
    &["newmtl", "Kd", "Ks", "Ns", "d", "Tr", "map_Kd", "map_d"];

/// Validates MTL text and rewrites it into what `tobj` parses without surprises (see the
/// module docs); line numbers are kept. Keywords of statements that are not read are counted
/// in `ignored`.
pub(super) fn normalize_mtl(
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
pub(super) enum Channel {
    Red,
    Green,
    Blue,
    Alpha,
    Luminance,
}

/// A texture reference of an MTL `map_*` record.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub(super) struct TextureRef {
    /// Resolved file path.
    pub(super) path: PathBuf,
    /// Channel named by `-imfchan`.
    pub(super) channel: Option<Channel>,
}

/// Number of arguments of the MTL texture options; `None` for those with one to three numbers.
pub(super) fn option_arity(option: &str) -> Option<Option<usize>> {
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
pub(super) fn parse_texture_ref(spec: &str, dir: &Path) -> TextureRef {
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

pub(super) fn srgb_color(rgb: [f32; 3]) -> Vec3 {
    Vec3::from(rgb.map(|c| crate::srgb::decode(c.clamp(0.0, 1.0))))
}

/// Side of the fallback checker texture and of its squares, in pixels.
pub(super) const CHECKER_SIZE: u32 = 64;
pub(super) const CHECKER_SQUARE: u32 = 8;

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
pub(super) fn alpha_mask(image: &DynamicImage, channel: Option<Channel>) -> GrayImage {
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
pub(super) fn merge_alpha(base: RgbaImage, mask: &GrayImage) -> RgbaImage {
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
pub(super) struct Textures {
    pub(super) images: Vec<TextureImage>,
    /// Decoded files, or why they could not be decoded.
    pub(super) decoded: HashMap<PathBuf, Result<DynamicImage, String>>,
    /// Finished textures (index, whether it is the checker) by their (map_Kd, map_d) sources.
    pub(super) finished: HashMap<(Option<TextureRef>, Option<TextureRef>), (usize, bool)>,
}

impl Textures {
    /// The decoded image of a file; the first failure for a file is reported in `warnings`.
    pub(super) fn decode(
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
    pub(super) fn material_texture(
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
    fn alpha_merge_resamples_the_smaller_image() {
        let base = RgbaImage::from_pixel(4, 4, image::Rgba([10, 20, 30, 255]));
        let mask = GrayImage::from_fn(2, 2, |x, _| image::Luma([if x == 0 { 0 } else { 255 }]));
        let merged = merge_alpha(base, &mask);
        assert_eq!(merged.dimensions(), (4, 4));
        assert_eq!(merged.get_pixel(0, 0).0, [10, 20, 30, 0]);
        assert_eq!(merged.get_pixel(3, 3).0, [10, 20, 30, 255]);
    }
}
