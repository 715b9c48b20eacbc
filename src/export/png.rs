//! Lossless PNG output with an `aa-lab` text chunk holding the JSON record of how the image was
//! made (scene, frame, camera, technique settings, adapter, build), so any exported image can
//! be reproduced with `aa-lab render --from image.png`.

use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

/// Keyword of the PNG text chunk carrying the render record.
pub const RECORD_KEYWORD: &str = "aa-lab";

/// Errors of writing or reading exported files.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    /// The file could not be created or written.
    #[error("cannot write {path}: {source}")]
    Io {
        /// The path.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// The PNG encoder failed.
    #[error("cannot encode {path} as PNG: {source}")]
    Encode {
        /// The path.
        path: PathBuf,
        /// The encoder's error.
        source: ::png::EncodingError,
    },
    /// The file could not be read or decoded.
    #[error("cannot read {path}: {reason}")]
    Read {
        /// The path.
        path: PathBuf,
        /// What went wrong.
        reason: String,
    },
}

/// Writes an RGBA8 image (sRGB-encoded) as PNG, with `record` in an `aa-lab` text chunk.
pub fn write_png(
    path: &Path,
    image: &image::RgbaImage,
    record: Option<&str>,
) -> Result<(), ExportError> {
    let io = |source| ExportError::Io {
        path: path.to_owned(),
        source,
    };
    let encode = |source| ExportError::Encode {
        path: path.to_owned(),
        source,
    };
    let file = File::create(path).map_err(io)?;
    let mut encoder = ::png::Encoder::new(BufWriter::new(file), image.width(), image.height());
    encoder.set_color(::png::ColorType::Rgba);
    encoder.set_depth(::png::BitDepth::Eight);
    encoder.set_source_srgb(::png::SrgbRenderingIntent::Perceptual);
    if let Some(record) = record {
        encoder
            .add_itxt_chunk(RECORD_KEYWORD.to_owned(), record.to_owned())
            .map_err(encode)?;
    }
    let mut writer = encoder.write_header().map_err(encode)?;
    writer.write_image_data(image.as_raw()).map_err(encode)?;
    writer.finish().map_err(encode)
}

/// Reads the `aa-lab` record of a PNG written by [`write_png`], if it has one.
pub fn read_record(path: &Path) -> Result<Option<String>, ExportError> {
    let read = |reason: String| ExportError::Read {
        path: path.to_owned(),
        reason,
    };
    let file = File::open(path).map_err(|e| read(e.to_string()))?;
    let decoder = ::png::Decoder::new(std::io::BufReader::new(file));
    let reader = decoder.read_info().map_err(|e| read(e.to_string()))?;
    let info = reader.info();
    let text = info
        .utf8_text
        .iter()
        .find(|chunk| chunk.keyword == RECORD_KEYWORD)
        .map(|chunk| chunk.get_text().map_err(|e| read(e.to_string())))
        .transpose()?;
    Ok(text)
}

/// Reads any PNG/JPEG/TGA image as RGBA8.
pub fn read_image(path: &Path) -> Result<image::RgbaImage, ExportError> {
    image::open(path)
        .map(|i| i.to_rgba8())
        .map_err(|e| ExportError::Read {
            path: path.to_owned(),
            reason: e.to_string(),
        })
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
        write_png(&path, &image, Some(r#"{"scene":"chart"}"#)).unwrap();
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
        )
        .unwrap_err();
        assert!(err.to_string().contains("/nonexistent-dir/x.png"), "{err}");
    }
}
