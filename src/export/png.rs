//! Lossless PNG output with an `aa-lab` text chunk holding the JSON record of how the image was
//! made (scene, frame, camera, technique settings, adapter, build), so any exported image can
//! be reproduced with `aa-lab render --from image.png`.
//!
//! Files are written atomically under the caller's overwrite policy ([`crate::files`]).
//! Reading is bounded: a record inflates to at most [`MAX_RECORD_BYTES`], and an image is
//! refused from its header when it has more than the caller's pixel limit.

use std::path::{Path, PathBuf};

use crate::files::{self, FileError, Overwrite};

/// Keyword of the PNG text chunk carrying the render record.
pub const RECORD_KEYWORD: &str = "aa-lab";

/// Largest render record read from a PNG (records are a few kilobytes of JSON).
pub const MAX_RECORD_BYTES: usize = 4 << 20;

/// Errors of writing or reading exported files.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    /// The file could not be read or written, or the overwrite policy refused it.
    #[error(transparent)]
    File(#[from] FileError),
    /// A record could not be serialised.
    #[error("cannot write the record {}: {source}", path.display())]
    Record {
        /// The record's path.
        path: PathBuf,
        /// serde_json's error.
        #[source]
        source: serde_json::Error,
    },
    /// The file could not be read or decoded.
    #[error("cannot read {}: {reason}", path.display())]
    Read {
        /// The path.
        path: PathBuf,
        /// What went wrong.
        reason: String,
    },
    /// The image has more pixels than the command can process in reasonable memory.
    #[error(
        "{} is {width}x{height} ({pixels} pixels); {purpose} handles at most {limit} pixels",
        path.display(),
        pixels = u64::from(*width) * u64::from(*height)
    )]
    TooManyPixels {
        /// The path.
        path: PathBuf,
        /// Width from the header.
        width: u32,
        /// Height from the header.
        height: u32,
        /// The limit in pixels.
        limit: u64,
        /// What the image was read for.
        purpose: &'static str,
    },
}

/// Writes an RGBA8 image (sRGB-encoded) as PNG, with `record` in an `aa-lab` text chunk,
/// atomically under `policy`; returns whether an existing file was replaced.
pub fn write_png(
    path: &Path,
    image: &image::RgbaImage,
    record: Option<&str>,
    policy: &Overwrite,
) -> Result<bool, ExportError> {
    let replaced = files::write_atomic(path, policy, |out| {
        encode_rgba8(out, image.as_raw(), image.dimensions(), None, record)
    })?;
    Ok(replaced)
}

/// Encodes sRGB-encoded RGBA8 `pixels` of `size` as a PNG into `out`, with `record` in an
/// `aa-lab` text chunk; `compression` `None` keeps the `png` crate's default level. Every PNG
/// aa-lab writes, still images and animation frames alike, is encoded here.
pub(crate) fn encode_rgba8(
    out: impl std::io::Write,
    pixels: &[u8],
    (width, height): (u32, u32),
    compression: Option<::png::Compression>,
    record: Option<&str>,
) -> std::io::Result<()> {
    let invalid = |e: ::png::EncodingError| std::io::Error::other(e.to_string());
    let mut encoder = ::png::Encoder::new(out, width, height);
    encoder.set_color(::png::ColorType::Rgba);
    encoder.set_depth(::png::BitDepth::Eight);
    encoder.set_source_srgb(::png::SrgbRenderingIntent::Perceptual);
    if let Some(compression) = compression {
        encoder.set_compression(compression);
    }
    if let Some(record) = record {
        encoder
            .add_itxt_chunk(RECORD_KEYWORD.to_owned(), record.to_owned())
            .map_err(invalid)?;
    }
    let mut writer = encoder.write_header().map_err(invalid)?;
    writer.write_image_data(pixels).map_err(invalid)?;
    writer.finish().map_err(invalid)
}

/// Reads the `aa-lab` record of a PNG written by [`write_png`], if it has one.
pub fn read_record(path: &Path) -> Result<Option<String>, ExportError> {
    let read = |reason: String| ExportError::Read {
        path: path.to_owned(),
        reason,
    };
    files::check_regular(path, files::MAX_IMAGE_FILE_BYTES, "an image")?;
    let file = std::fs::File::open(path).map_err(|e| read(e.to_string()))?;
    let decoder = ::png::Decoder::new(std::io::BufReader::new(file));
    let reader = decoder.read_info().map_err(|e| read(e.to_string()))?;
    let info = reader.info();
    let Some(chunk) = info
        .utf8_text
        .iter()
        .find(|chunk| chunk.keyword == RECORD_KEYWORD)
    else {
        return Ok(None);
    };
    // Inflate with a bound: a small compressed chunk can expand to gigabytes.
    let mut chunk = chunk.clone();
    chunk
        .decompress_text_with_limit(MAX_RECORD_BYTES)
        .map_err(|e| {
            read(format!(
                "its aa-lab record is not readable or larger than {MAX_RECORD_BYTES} bytes ({e})"
            ))
        })?;
    chunk.get_text().map(Some).map_err(|e| read(e.to_string()))
}

/// Decodes an image of at most `max_pixels` pixels (checked from its header before anything is
/// decoded), from a regular file of bounded size; `purpose` names the limit in the error.
pub fn read_dynamic_limited(
    path: &Path,
    max_pixels: u64,
    purpose: &'static str,
) -> Result<image::DynamicImage, ExportError> {
    let read = |reason: String| ExportError::Read {
        path: path.to_owned(),
        reason,
    };
    files::check_regular(path, files::MAX_IMAGE_FILE_BYTES, "an image")?;
    let reader = image::ImageReader::open(path)
        .and_then(image::ImageReader::with_guessed_format)
        .map_err(|e| read(e.to_string()))?;
    let (width, height) = reader.into_dimensions().map_err(|e| read(e.to_string()))?;
    if u64::from(width) * u64::from(height) > max_pixels {
        return Err(ExportError::TooManyPixels {
            path: path.to_owned(),
            width,
            height,
            limit: max_pixels,
            purpose,
        });
    }
    let mut reader = image::ImageReader::open(path)
        .and_then(image::ImageReader::with_guessed_format)
        .map_err(|e| read(e.to_string()))?;
    // The header was checked; lift the decoder's own default allocation cap to what it allows.
    let mut limits = image::Limits::default();
    limits.max_alloc = Some(max_pixels.saturating_mul(16));
    reader.limits(limits);
    reader.decode().map_err(|e| read(e.to_string()))
}

/// Reads any PNG/JPEG/TGA/OpenEXR image as RGBA8 (OpenEXR through [`crate::srgb::display_rgba8`]),
/// refusing from its header an image of more than
/// `max_pixels` pixels (`purpose` names the command in that message).
pub fn read_image_limited(
    path: &Path,
    max_pixels: u64,
    purpose: &'static str,
) -> Result<image::RgbaImage, ExportError> {
    read_dynamic_limited(path, max_pixels, purpose).map(crate::srgb::display_rgba8)
}

/// Most pixels [`read_image`] accepts: 16384 x 16384.
pub const MAX_IMAGE_PIXELS: u64 = 1 << 28;

/// Reads any PNG/JPEG/TGA image as RGBA8 (at most [`MAX_IMAGE_PIXELS`]).
pub fn read_image(path: &Path) -> Result<image::RgbaImage, ExportError> {
    read_image_limited(path, MAX_IMAGE_PIXELS, "aa-lab")
}

/// The eight bytes every PNG file starts with.
pub(crate) const PNG_SIGNATURE: [u8; 8] = [137, 80, 78, 71, 13, 10, 26, 10];

/// The chunks of a PNG file in order (type and data), for checking an animation's structure;
/// `None` when the bytes are not a well-formed PNG chunk stream.
pub fn png_chunks(bytes: &[u8]) -> Option<Vec<([u8; 4], &[u8])>> {
    let mut rest = bytes.strip_prefix(&PNG_SIGNATURE[..])?;
    let mut chunks = Vec::new();
    while !rest.is_empty() {
        let length = u32::from_be_bytes(rest.get(..4)?.try_into().ok()?) as usize;
        let kind: [u8; 4] = rest.get(4..8)?.try_into().ok()?;
        let data = rest.get(8..8 + length)?;
        chunks.push((kind, data));
        rest = rest.get(8 + length + 4..)?;
    }
    Some(chunks)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn record_round_trips_through_png() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("x.png");
        let image = image::RgbaImage::from_fn(3, 2, |x, y| {
            image::Rgba([x as u8 * 80, y as u8 * 100, 7, 255])
        });
        write_png(
            &path,
            &image,
            Some(r#"{"scene":"chart"}"#),
            &Overwrite::default(),
        )
        .unwrap();
        assert_eq!(
            read_record(&path).unwrap().as_deref(),
            Some(r#"{"scene":"chart"}"#)
        );
        assert_eq!(read_image(&path).unwrap(), image);
    }

    #[test]
    fn unwritable_path_names_the_file() {
        let err = write_png(
            Path::new("/nonexistent-dir/x.png"),
            &image::RgbaImage::new(1, 1),
            None,
            &Overwrite::default(),
        )
        .unwrap_err();
        assert!(err.to_string().contains("/nonexistent-dir/x.png"), "{err}");
    }

    /// A small PNG whose record inflates to far more than any record (issue 10, item 4)
    /// fails with the limit instead of inflating it all.
    #[test]
    fn an_inflating_record_is_refused_with_its_limit() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bomb.png");
        let file = std::fs::File::create(&path).unwrap();
        let mut encoder = ::png::Encoder::new(file, 1, 1);
        encoder.set_color(::png::ColorType::Rgba);
        let mut writer = encoder.write_header().unwrap();
        let mut chunk =
            ::png::text_metadata::ITXtChunk::new(RECORD_KEYWORD, " ".repeat(4 * MAX_RECORD_BYTES));
        chunk.compressed = true;
        chunk.compress_text().unwrap();
        writer.write_text_chunk(&chunk).unwrap();
        writer.write_image_data(&[0; 4]).unwrap();
        writer.finish().unwrap();
        // Only inflation can exceed the limit: the file itself is far smaller than it.
        assert!(std::fs::metadata(&path).unwrap().len() < MAX_RECORD_BYTES as u64 / 8);
        let err = read_record(&path).expect_err("the record is over the limit");
        assert!(
            err.to_string().contains(&MAX_RECORD_BYTES.to_string()),
            "{err}"
        );
    }

    #[test]
    fn images_over_the_pixel_limit_are_refused_from_the_header() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("wide.png");
        let image = image::RgbaImage::new(300, 200);
        write_png(&path, &image, None, &Overwrite::default()).unwrap();
        let err = read_image_limited(&path, 59_999, "this test").unwrap_err();
        assert!(
            err.to_string().contains("300x200") && err.to_string().contains("59999"),
            "{err}"
        );
        assert_eq!(
            read_image_limited(&path, 60_000, "this test").unwrap(),
            image
        );
    }
}
