//! Linear radiance as OpenEXR files: the HDR outputs of techniques that ran before the
//! tonemapper (`render --exr`), and what `compare` reads to score two of them with HDR-FLIP
//! (`metrics::hdr_flip`). Files are written atomically under the overwrite policy, and read
//! within the same bounds as every image aa-lab reads.

use std::io::Cursor;
use std::path::Path;

use super::png::{ExportError, read_dynamic_limited};
use crate::files::{self, Overwrite};

/// Writes `image` (linear RGB) to `path` as OpenEXR; returns whether a file was replaced.
pub fn write_exr(
    path: &Path,
    image: &image::Rgb32FImage,
    policy: &Overwrite,
) -> Result<bool, ExportError> {
    let mut bytes = Vec::new();
    image
        .write_to(&mut Cursor::new(&mut bytes), image::ImageFormat::OpenExr)
        .map_err(|e| ExportError::Read {
            path: path.to_owned(),
            reason: format!("cannot encode OpenEXR: {e}"),
        })?;
    Ok(files::write_bytes(path, policy, &bytes)?)
}

/// Reads an image of at most `max_pixels` pixels as linear RGB (an OpenEXR file's radiance;
/// an 8-bit image is decoded from sRGB).
pub fn read_radiance(
    path: &Path,
    max_pixels: u64,
    purpose: &'static str,
) -> Result<image::Rgb32FImage, ExportError> {
    Ok(read_dynamic_limited(path, max_pixels, purpose)?.to_rgb32f())
}

/// Whether `path` names an OpenEXR file (by its extension).
pub fn is_exr(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_written_file_reads_back_and_is_never_replaced_without_force() {
        let image = image::Rgb32FImage::from_raw(2, 1, vec![0.5, 0.5, 0.5, 40.0, 40.0, 40.0])
            .expect("two pixels");
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("r.exr");
        assert!(is_exr(&path));
        write_exr(&path, &image, &Overwrite::new(false)).expect("written");
        let back = read_radiance(&path, 16, "test").expect("read");
        assert_eq!(back, image);
        assert!(write_exr(&path, &image, &Overwrite::new(false)).is_err());
    }
}
