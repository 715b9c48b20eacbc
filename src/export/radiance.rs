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

/// The linear RGB image of half-float RGBA texels (`gpu::HDR_FORMAT`, tightly packed rows),
/// or `None` when the byte count does not match the size.
pub fn from_half_floats(size: (u32, u32), bytes: &[u8]) -> Option<image::Rgb32FImage> {
    let texels = bytes.len() / 8;
    if texels != (size.0 as usize) * (size.1 as usize) || !bytes.len().is_multiple_of(8) {
        return None;
    }
    let values: Vec<f32> = bytes
        .chunks_exact(8)
        .flat_map(|texel| {
            (0..3).map(move |c| half::f16::from_le_bytes([texel[2 * c], texel[2 * c + 1]]).to_f32())
        })
        .collect();
    image::Rgb32FImage::from_raw(size.0, size.1, values)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn half_floats_decode_and_a_written_file_reads_back() {
        let texel = |v: f32| {
            let h = half::f16::from_f32(v).to_le_bytes();
            [h[0], h[1], h[0], h[1], h[0], h[1], 0, 0x3c]
        };
        let bytes: Vec<u8> = [0.5f32, 40.0].iter().flat_map(|&v| texel(v)).collect();
        let image = from_half_floats((2, 1), &bytes).expect("two texels");
        assert_eq!(image.get_pixel(1, 0).0, [40.0; 3]);
        assert!(from_half_floats((3, 1), &bytes).is_none());
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("r.exr");
        assert!(is_exr(&path));
        write_exr(&path, &image, &Overwrite::new(false)).expect("written");
        let back = read_radiance(&path, 16, "test").expect("read");
        assert_eq!(back, image);
        assert!(write_exr(&path, &image, &Overwrite::new(false)).is_err());
    }
}
