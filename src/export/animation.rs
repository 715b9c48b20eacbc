//! Looping animations of equally sized RGBA8 frames: animated PNG (lossless; when every frame
//! is opaque, frames after the first hold only the pixels that changed, every frame a full
//! `fcTL` + `IDAT`/`fdAT` image, `acTL` with `num_plays = 0`, i.e. forever, and the record in an
//! `aa-lab` text chunk like every PNG aa-lab writes) or GIF (256 colours per frame, quantised
//! with NeuQuant; loops forever). Both encoders are deterministic: the same frames give the
//! same bytes. Files are written atomically under the caller's overwrite policy.

use std::path::Path;

use super::png::RECORD_KEYWORD;
use crate::files::{self, Overwrite};

/// Errors of writing an animation.
#[derive(Debug, thiserror::Error)]
pub enum AnimationError {
    /// The file could not be written, or the overwrite policy refused it.
    #[error(transparent)]
    File(#[from] files::FileError),
    /// There is nothing to animate, or the frames differ in size.
    #[error("an animation needs at least one frame, all of one size")]
    Frames,
    /// A GIF side is limited to 65535 pixels.
    #[error("a GIF is at most 65535 pixels a side; this animation is {width}x{height}")]
    TooLargeForGif {
        /// Width.
        width: u32,
        /// Height.
        height: u32,
    },
}

/// Which container an output path asks for: GIF for a `.gif` extension (any case), else APNG.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum AnimationFormat {
    /// Animated PNG.
    Apng,
    /// GIF89a.
    Gif,
}

impl AnimationFormat {
    /// The format of an output path.
    pub fn of_path(path: &Path) -> Self {
        if path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("gif"))
        {
            Self::Gif
        } else {
            Self::Apng
        }
    }
}

fn check_frames(frames: &[image::RgbaImage]) -> Result<(u32, u32), AnimationError> {
    let size = frames.first().ok_or(AnimationError::Frames)?.dimensions();
    if size.0 == 0 || size.1 == 0 || frames.iter().any(|f| f.dimensions() != size) {
        return Err(AnimationError::Frames);
    }
    Ok(size)
}

/// Writes `frames` as a looping animated PNG at `fps` frames per second, with `record` in an
/// `aa-lab` text chunk; returns whether an existing file was replaced.
pub fn write_apng(
    path: &Path,
    frames: &[image::RgbaImage],
    fps: u16,
    record: Option<&str>,
    policy: &Overwrite,
) -> Result<bool, AnimationError> {
    let (width, height) = check_frames(frames)?;
    let count = u32::try_from(frames.len()).map_err(|_| AnimationError::Frames)?;
    let invalid = |e: ::png::EncodingError| std::io::Error::other(e.to_string());
    // Opaque frames (every aa-lab sheet) after the first are stored as the changes only: the
    // bounding box of the pixels that differ from the previous frame, unchanged pixels
    // transparent, blended over the previous frame.
    let opaque = frames.iter().all(|f| f.pixels().all(|p| p[3] == 255));
    Ok(files::write_atomic(path, policy, |out| {
        let mut encoder = ::png::Encoder::new(out, width, height);
        encoder.set_color(::png::ColorType::Rgba);
        encoder.set_depth(::png::BitDepth::Eight);
        encoder.set_source_srgb(::png::SrgbRenderingIntent::Perceptual);
        encoder.set_compression(::png::Compression::High);
        encoder.set_animated(count, 0).map_err(invalid)?;
        encoder.set_frame_delay(1, fps.max(1)).map_err(invalid)?;
        if let Some(record) = record {
            encoder
                .add_itxt_chunk(RECORD_KEYWORD.to_owned(), record.to_owned())
                .map_err(invalid)?;
        }
        let mut writer = encoder.write_header().map_err(invalid)?;
        let mut previous: Option<&image::RgbaImage> = None;
        for frame in frames {
            match previous.filter(|_| opaque) {
                None => writer.write_image_data(frame.as_raw()).map_err(invalid)?,
                Some(before) => {
                    let (x, y, w, h) = changed_box(before, frame);
                    let mut data = Vec::with_capacity(w as usize * h as usize * 4);
                    for py in y..y + h {
                        for px in x..x + w {
                            let now = frame.get_pixel(px, py);
                            if now == before.get_pixel(px, py) {
                                data.extend_from_slice(&[0, 0, 0, 0]);
                            } else {
                                data.extend_from_slice(&now.0);
                            }
                        }
                    }
                    writer.reset_frame_position().map_err(invalid)?;
                    writer.set_frame_dimension(w, h).map_err(invalid)?;
                    writer.set_frame_position(x, y).map_err(invalid)?;
                    writer.set_blend_op(::png::BlendOp::Over).map_err(invalid)?;
                    writer.write_image_data(&data).map_err(invalid)?;
                }
            }
            previous = Some(frame);
        }
        writer.finish().map_err(invalid)
    })?)
}

/// The smallest rectangle (x, y, width, height) holding every pixel that differs between two
/// images of one size; a 1x1 rectangle at the origin when none does.
fn changed_box(a: &image::RgbaImage, b: &image::RgbaImage) -> (u32, u32, u32, u32) {
    let (mut x0, mut y0, mut x1, mut y1) = (u32::MAX, u32::MAX, 0, 0);
    for (x, y, p) in b.enumerate_pixels() {
        if a.get_pixel(x, y) != p {
            x0 = x0.min(x);
            y0 = y0.min(y);
            x1 = x1.max(x);
            y1 = y1.max(y);
        }
    }
    if x0 == u32::MAX {
        (0, 0, 1, 1)
    } else {
        (x0, y0, x1 - x0 + 1, y1 - y0 + 1)
    }
}

/// Writes `frames` as a looping GIF at about `fps` frames per second (GIF delays are whole
/// hundredths of a second); returns whether an existing file was replaced.
pub fn write_gif(
    path: &Path,
    frames: &[image::RgbaImage],
    fps: u16,
    policy: &Overwrite,
) -> Result<bool, AnimationError> {
    use image::codecs::gif::{GifEncoder, Repeat};
    let (width, height) = check_frames(frames)?;
    if width > u32::from(u16::MAX) || height > u32::from(u16::MAX) {
        return Err(AnimationError::TooLargeForGif { width, height });
    }
    let invalid = |e: image::ImageError| std::io::Error::other(e.to_string());
    let delay = image::Delay::from_numer_denom_ms(1000, u32::from(fps.max(1)));
    Ok(files::write_atomic(path, policy, |out| {
        let mut encoder = GifEncoder::new_with_speed(out, 10);
        encoder.set_repeat(Repeat::Infinite).map_err(invalid)?;
        for frame in frames {
            encoder
                .encode_frame(image::Frame::from_parts(frame.clone(), 0, 0, delay))
                .map_err(invalid)?;
        }
        Ok(())
    })?)
}

/// The chunks of a PNG file in order (type and data), for checking an animation's structure;
/// `None` when the bytes are not a well-formed PNG chunk stream.
pub fn png_chunks(bytes: &[u8]) -> Option<Vec<([u8; 4], &[u8])>> {
    const SIGNATURE: [u8; 8] = [137, 80, 78, 71, 13, 10, 26, 10];
    let mut rest = bytes.strip_prefix(&SIGNATURE[..])?;
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

    /// Opaque frames where a few pixels change (and one frame repeats its predecessor).
    fn frames(n: u8) -> Vec<image::RgbaImage> {
        (0..n)
            .map(|i| {
                let v = if i == 2 { 1 } else { i };
                image::RgbaImage::from_fn(5, 3, |x, y| {
                    if x == u32::from(v) % 5 && y > 0 {
                        image::Rgba([v * 40, 0, 255 - v, 255])
                    } else {
                        image::Rgba([10, 20, 30, 255])
                    }
                })
            })
            .collect()
    }

    #[test]
    fn apng_loops_forever_with_one_control_chunk_per_frame() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.png");
        write_apng(&path, &frames(4), 30, Some("{}"), &Overwrite::new(false)).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        let chunks = png_chunks(&bytes).unwrap();
        let actl = chunks.iter().find(|(k, _)| k == b"acTL").unwrap().1;
        assert_eq!(u32::from_be_bytes(actl[0..4].try_into().unwrap()), 4);
        assert_eq!(u32::from_be_bytes(actl[4..8].try_into().unwrap()), 0);
        assert_eq!(chunks.iter().filter(|(k, _)| k == b"fcTL").count(), 4);
        // The first frame is the default image (its fcTL comes before IDAT); every fcTL and
        // fdAT carries the next sequence number in file order; every frame lasts 1/30 s.
        let position = |kind: &[u8; 4]| chunks.iter().position(|(k, _)| k == kind).unwrap();
        assert!(position(b"acTL") < position(b"fcTL"));
        assert!(position(b"fcTL") < position(b"IDAT"));
        let be16 = |b: &[u8]| u16::from_be_bytes(b.try_into().unwrap());
        let mut sequence = 0;
        for (kind, data) in &chunks {
            if kind == b"fcTL" || kind == b"fdAT" {
                assert_eq!(u32::from_be_bytes(data[0..4].try_into().unwrap()), sequence);
                sequence += 1;
            }
            if kind == b"fcTL" {
                assert_eq!((be16(&data[20..22]), be16(&data[22..24])), (1, 30));
            }
        }
        assert!(sequence > 4, "frames after the first are fdAT chunks");
        // Decodes back to the same frames.
        let decoder = image::codecs::png::PngDecoder::new(std::io::Cursor::new(&bytes)).unwrap();
        let decoded: Vec<_> = image::AnimationDecoder::into_frames(decoder.apng().unwrap())
            .collect_frames()
            .unwrap();
        assert_eq!(decoded.len(), 4);
        for (d, f) in decoded.iter().zip(frames(4)) {
            assert_eq!(d.buffer(), &f);
        }
    }

    #[test]
    fn gif_and_format_by_extension() {
        assert_eq!(
            AnimationFormat::of_path(Path::new("x/clip.GIF")),
            AnimationFormat::Gif
        );
        assert_eq!(
            AnimationFormat::of_path(Path::new("clip.png")),
            AnimationFormat::Apng
        );
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.gif");
        write_gif(&path, &frames(2), 25, &Overwrite::new(false)).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert!(bytes.starts_with(b"GIF89a"));
        assert!(matches!(
            write_gif(&path, &[], 25, &Overwrite::new(true)),
            Err(AnimationError::Frames)
        ));
    }
}
