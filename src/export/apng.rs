//! The animated PNG side of [`super::animation::AnimationStream`]: how a frame's change is
//! compressed (on a worker thread), how the compressed frames are written in order, and how
//! the file is assembled around the first frame.
//!
//! The file is a looping APNG (`acTL` with `num_plays = 0`), the record in an `aa-lab` text
//! chunk like every PNG aa-lab writes. The first frame is the default image (its `fcTL` before
//! the `IDAT`s); every later frame holds only the bounding box of the pixels that changed from
//! the frame before, unchanged pixels transparent, blended over it (`APNG_BLEND_OP_OVER`).
//!
//! A frame is compressed by encoding it as a PNG of its own with the `png` crate (its adaptive
//! row filters and deflate) and taking that PNG's `IDAT` payload, a zlib stream, as the
//! frame's `fdAT` data, so frames compress independently, on any thread; the sequence numbers
//! are given in file order by [`ApngSequence`].

use std::io::{self, Read, Write};

use super::frame_change::Change;
use super::png::{PNG_SIGNATURE, encode_rgba8, png_chunks};

/// How hard the frames are compressed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Compression {
    /// The `png` crate's fast deflate (fdeflate): several times faster, files somewhat
    /// larger.
    #[default]
    Fast,
    /// zlib's best level (flate2): the smallest files, slowest.
    Best,
}

impl Compression {
    fn png(self) -> ::png::Compression {
        match self {
            Self::Fast => ::png::Compression::Fast,
            Self::Best => ::png::Compression::High,
        }
    }
}

/// A frame after the first, compressed: where it lies and its zlib stream in pieces (the
/// payloads of the `IDAT` chunks of the PNG it was encoded as).
pub struct ApngFrame {
    rect: (u32, u32, u32, u32),
    zlib: Vec<Vec<u8>>,
}

/// Compresses a frame's change (see the module docs).
pub fn encode_change(change: &Change, compression: Compression) -> io::Result<ApngFrame> {
    let (_, _, width, height) = change.rect;
    let png = encoded(&change.pixels, (width, height), compression, None)?;
    let chunks = png_chunks(&png).ok_or_else(|| io::Error::other("malformed PNG"))?;
    let zlib = chunks
        .into_iter()
        .filter(|(kind, _)| kind == b"IDAT")
        .map(|(_, data)| data.to_vec())
        .collect();
    Ok(ApngFrame {
        rect: change.rect,
        zlib,
    })
}

/// The sequence numbers of `fcTL` and `fdAT` chunks, in file order (0 is the first frame's).
pub struct ApngSequence(u32);

impl Default for ApngSequence {
    fn default() -> Self {
        Self(1)
    }
}

impl ApngSequence {
    fn next(&mut self) -> u32 {
        self.0 += 1;
        self.0 - 1
    }

    /// Writes a later frame's `fcTL` and `fdAT` chunks.
    pub fn write_frame(
        &mut self,
        out: &mut impl Write,
        frame: &ApngFrame,
        fps: u16,
    ) -> io::Result<()> {
        let control = frame_control(self.next(), frame.rect, fps, BLEND_OVER);
        write_chunk(out, *b"fcTL", &control)?;
        for piece in &frame.zlib {
            let mut data = Vec::with_capacity(4 + piece.len());
            data.extend_from_slice(&self.next().to_be_bytes());
            data.extend_from_slice(piece);
            write_chunk(out, *b"fdAT", &data)?;
        }
        Ok(())
    }
}

/// Writes the file: the first frame's PNG with `acTL` and its `fcTL` before its `IDAT`s, then
/// `later` (the other frames' chunks) and `IEND`.
pub fn assemble(
    out: &mut impl Write,
    first: &image::RgbaImage,
    frames: u32,
    fps: u16,
    compression: Compression,
    record: Option<&str>,
    later: &mut impl Read,
) -> io::Result<()> {
    let png = encoded(first.as_raw(), first.dimensions(), compression, record)?;
    let chunks = png_chunks(&png).ok_or_else(|| io::Error::other("malformed PNG"))?;
    out.write_all(&PNG_SIGNATURE)?;
    let mut animation_started = false;
    for (kind, data) in chunks {
        if &kind == b"IEND" {
            continue;
        }
        if &kind == b"IDAT" && !animation_started {
            let mut control = Vec::with_capacity(8);
            control.extend_from_slice(&frames.to_be_bytes());
            control.extend_from_slice(&0u32.to_be_bytes());
            write_chunk(out, *b"acTL", &control)?;
            let whole = (0, 0, first.width(), first.height());
            write_chunk(out, *b"fcTL", &frame_control(0, whole, fps, BLEND_SOURCE))?;
            animation_started = true;
        }
        write_chunk(out, kind, data)?;
    }
    io::copy(later, out)?;
    write_chunk(out, *b"IEND", &[])
}

const BLEND_SOURCE: u8 = 0;
const BLEND_OVER: u8 = 1;

/// Writes one PNG chunk: length, type, data, CRC of type and data.
fn write_chunk(out: &mut impl Write, kind: [u8; 4], data: &[u8]) -> io::Result<()> {
    let length = u32::try_from(data.len()).map_err(|_| io::Error::other("chunk too long"))?;
    out.write_all(&length.to_be_bytes())?;
    out.write_all(&kind)?;
    out.write_all(data)?;
    let mut crc = crc32fast::Hasher::new();
    crc.update(&kind);
    crc.update(data);
    out.write_all(&crc.finalize().to_be_bytes())
}

/// An `fcTL` chunk's data: the frame's rectangle, a delay of 1/`fps` s, no disposal.
fn frame_control(
    sequence: u32,
    (x, y, width, height): (u32, u32, u32, u32),
    fps: u16,
    blend: u8,
) -> Vec<u8> {
    let mut data = Vec::with_capacity(26);
    for value in [sequence, width, height, x, y] {
        data.extend_from_slice(&value.to_be_bytes());
    }
    data.extend_from_slice(&1u16.to_be_bytes());
    data.extend_from_slice(&fps.max(1).to_be_bytes());
    data.extend_from_slice(&[0, blend]);
    data
}

/// A PNG of its own for a frame, in memory (its `IDAT` payload becomes the frame's data).
fn encoded(
    pixels: &[u8],
    size: (u32, u32),
    compression: Compression,
    record: Option<&str>,
) -> io::Result<Vec<u8>> {
    let mut bytes = Vec::new();
    encode_rgba8(&mut bytes, pixels, size, Some(compression.png()), record)?;
    Ok(bytes)
}
