//! The GIF side of [`super::animation::AnimationStream`]: a looping GIF89a whose first frame
//! is the whole image and whose later frames are the changes from the frame before (the
//! bounding box of the changed pixels, unchanged ones transparent, disposal "keep"), each
//! quantised to its own 256 colours with NeuQuant and LZW-compressed on a worker thread
//! (`gif::Frame::make_lzw_pre_encoded`, which the `gif` crate offers for parallel encoding),
//! then written in order.
//!
//! GIF delays are whole hundredths of a second: 1/`fps` s rounded down, at least 1.

use std::io::{self, Read, Write};

use super::animation::Change;

/// NeuQuant's sampling speed (1 best to 30 fastest): 10 is the `gif` crate's compromise.
const QUANTISER_SPEED: i32 = 10;

/// A frame after the first, quantised and compressed.
pub type GifFrame = gif::Frame<'static>;

fn delay(fps: u16) -> u16 {
    (100 / fps.max(1)).max(1)
}

fn side(value: u32) -> io::Result<u16> {
    u16::try_from(value).map_err(|_| io::Error::other("a GIF is at most 65535 pixels a side"))
}

/// Quantises and compresses RGBA8 pixels covering `rect` (x, y, width, height).
fn encode(mut pixels: Vec<u8>, rect: (u32, u32, u32, u32), fps: u16) -> io::Result<GifFrame> {
    let (x, y, width, height) = rect;
    let mut frame =
        gif::Frame::from_rgba_speed(side(width)?, side(height)?, &mut pixels, QUANTISER_SPEED);
    frame.left = side(x)?;
    frame.top = side(y)?;
    frame.delay = delay(fps);
    frame.dispose = gif::DisposalMethod::Keep;
    frame.make_lzw_pre_encoded();
    Ok(frame)
}

/// Quantises and compresses a frame's change.
pub fn encode_change(change: Change, fps: u16) -> io::Result<GifFrame> {
    encode(change.pixels, change.rect, fps)
}

fn gif_error(error: gif::EncodingError) -> io::Error {
    match error {
        gif::EncodingError::Io(error) => error,
        other => io::Error::other(other.to_string()),
    }
}

/// Writes a later frame's blocks (graphic control extension, image descriptor, colour table,
/// data).
pub fn write_frame(out: &mut impl Write, frame: &GifFrame, size: (u32, u32)) -> io::Result<()> {
    // The encoder writes a screen descriptor first and a trailer when dropped: only what it
    // writes for the frame is kept.
    let mut encoder =
        gif::Encoder::new(Vec::new(), side(size.0)?, side(size.1)?, &[]).map_err(gif_error)?;
    encoder.get_mut().clear();
    encoder
        .write_lzw_pre_encoded_frame(frame)
        .map_err(gif_error)?;
    out.write_all(encoder.get_ref())
}

/// Writes the file: header and loop extension, the first frame, `later` (the other frames'
/// blocks) and the trailer.
pub fn assemble(
    out: &mut impl Write,
    first: &image::RgbaImage,
    fps: u16,
    later: &mut impl Read,
) -> io::Result<()> {
    let size = first.dimensions();
    let mut encoder =
        gif::Encoder::new(out, side(size.0)?, side(size.1)?, &[]).map_err(gif_error)?;
    encoder
        .set_repeat(gif::Repeat::Infinite)
        .map_err(gif_error)?;
    let frame = encode(first.as_raw().clone(), (0, 0, size.0, size.1), fps)?;
    encoder
        .write_lzw_pre_encoded_frame(&frame)
        .map_err(gif_error)?;
    io::copy(later, encoder.get_mut())?;
    encoder.into_inner().map_err(gif_error)?;
    Ok(())
}
