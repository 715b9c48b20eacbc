//! What the readback belt's parts share: alignment and size constants, errors, the region of
//! a texture to copy, the ticket that redeems a copy, and where each copy lies in which
//! staging buffer.

use std::sync::mpsc;
use std::time::Duration;

/// Alignment of every copy's offset in the staging buffer.
pub const COPY_OFFSET_ALIGNMENT: u64 = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT as u64;
/// Smallest staging buffer the belt allocates.
pub(super) const MIN_STAGING_BYTES: u64 = 64 * 1024;
/// Free staging buffers the pool keeps at most.
pub(super) const MAX_FREE_BUFFERS: usize = 4;
/// How long [`PendingReadback::wait`] waits for the map callback once the device is idle (the
/// callback may run on another thread polling the same device).
pub(super) const ANSWER_GRACE: Duration = Duration::from_secs(5);

/// Errors of a readback.
#[derive(Debug, thiserror::Error)]
pub enum ReadbackError {
    /// The texture's format has no fixed texel size (compressed, depth-stencil), or is not the
    /// format asked for.
    #[error("cannot read back a texture of format {0:?} this way")]
    UnsupportedFormat(wgpu::TextureFormat),
    /// The texture or buffer was not created with `COPY_SRC` usage.
    #[error("the {0} to read back was not created with COPY_SRC usage")]
    NotCopySource(&'static str),
    /// Multisampled textures cannot be copied (resolve them first).
    #[error("cannot read back a multisampled texture ({0} samples); resolve it first")]
    Multisampled(u32),
    /// The region is empty or not inside the texture.
    #[error("the region {region:?} is empty or not inside the {width}x{height} texture")]
    Region {
        /// The region asked for.
        region: Region,
        /// Texture width.
        width: u32,
        /// Texture height.
        height: u32,
    },
    /// A buffer range that is empty, unaligned or past the buffer's end.
    #[error(
        "cannot read bytes {offset}..+{size} of a {buffer_size}-byte buffer (offset and size \
         must be non-zero multiples of {})",
        wgpu::COPY_BUFFER_ALIGNMENT
    )]
    BufferRange {
        /// Offset asked for.
        offset: u64,
        /// Size asked for.
        size: u64,
        /// The buffer's size.
        buffer_size: u64,
    },
    /// Mapping the staging buffer failed (usually a lost device).
    #[error("mapping the readback buffer failed (device lost?): {0}")]
    Map(#[from] wgpu::BufferAsyncError),
    /// The device was lost or timed out while waiting.
    #[error("waiting for the GPU failed: {0}")]
    Poll(#[from] wgpu::PollError),
    /// The mapped range could not be accessed.
    #[error("reading the mapped readback buffer failed: {0}")]
    MapRange(#[from] wgpu::MapRangeError),
    /// The map was never answered: the encoder holding it was not submitted, or was dropped.
    #[error("the GPU never answered the readback (was the encoder submitted?)")]
    NoAnswer,
    /// The ticket belongs to another frame.
    #[error("the ticket belongs to readback frame {ticket}, not to frame {frame}")]
    ForeignTicket {
        /// The ticket's frame.
        ticket: u64,
        /// The frame asked.
        frame: u64,
    },
    /// [`PendingReadback::try_take`] was called again after it returned the frame.
    #[error("the readback frame was already taken")]
    AlreadyTaken,
}

/// A rectangle of texels.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Region {
    /// Left edge.
    pub x: u32,
    /// Top edge.
    pub y: u32,
    /// Width (at least 1).
    pub width: u32,
    /// Height (at least 1).
    pub height: u32,
}

impl Region {
    /// The whole of a texture.
    pub fn whole(texture: &wgpu::Texture) -> Self {
        Self {
            x: 0,
            y: 0,
            width: texture.width(),
            height: texture.height(),
        }
    }

    /// The part of `self` inside a `size` image, `None` when nothing is left.
    pub fn clipped(self, size: (u32, u32)) -> Option<Self> {
        let x1 = self.x.saturating_add(self.width).min(size.0);
        let y1 = self.y.saturating_add(self.height).min(size.1);
        (x1 > self.x && y1 > self.y).then_some(Self {
            width: x1 - self.x,
            height: y1 - self.y,
            ..self
        })
    }
}

/// Names one copy of one readback frame; redeem it on that frame's [`ReadbackFrame`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Ticket {
    pub(super) frame: u64,
    pub(super) index: usize,
}

/// What a copy holds, to unpack it.
#[derive(Clone, Copy, Debug)]
pub(super) enum Layout {
    Texture {
        format: wgpu::TextureFormat,
        width: u32,
        height: u32,
        row_bytes: u32,
        padded_row_bytes: u32,
    },
    Buffer {
        size: u64,
    },
}

impl Layout {
    /// Bytes the copy takes in the staging buffer.
    pub(super) fn staged_bytes(&self) -> u64 {
        match *self {
            Self::Texture {
                height,
                padded_row_bytes,
                ..
            } => u64::from(padded_row_bytes) * u64::from(height),
            Self::Buffer { size } => size,
        }
    }
}

/// One recorded copy: where it lies in which staging buffer.
#[derive(Clone, Copy, Debug)]
pub(super) struct Record {
    pub(super) chunk: usize,
    pub(super) offset: u64,
    pub(super) layout: Layout,
}

/// A staging buffer being filled, or mapped.
#[derive(Debug)]
pub(super) struct Chunk {
    pub(super) buffer: wgpu::Buffer,
    pub(super) used: u64,
}

pub(super) type MapAnswer = mpsc::Receiver<Result<(), wgpu::BufferAsyncError>>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clipped_keeps_the_part_inside() {
        let region = Region {
            x: 10,
            y: 5,
            width: 20,
            height: 20,
        };
        assert_eq!(
            region.clipped((25, 100)),
            Some(Region {
                width: 15,
                ..region
            })
        );
        assert_eq!(region.clipped((10, 100)), None);
        assert_eq!(region.clipped((100, 5)), None);
        assert_eq!(region.clipped((100, 100)), Some(region));
        let huge = Region {
            x: u32::MAX - 1,
            y: 0,
            width: 10,
            height: 1,
        };
        assert_eq!(huge.clipped((u32::MAX, 1)).map(|r| r.width), Some(1));
    }

    #[test]
    fn staged_sizes_keep_rows_aligned() {
        let layout = Layout::Texture {
            format: wgpu::TextureFormat::Rgba8Unorm,
            width: 65,
            height: 3,
            row_bytes: 260,
            padded_row_bytes: 512,
        };
        assert_eq!(layout.staged_bytes(), 1536);
        assert_eq!(COPY_OFFSET_ALIGNMENT % wgpu::MAP_ALIGNMENT, 0);
        assert_eq!(COPY_OFFSET_ALIGNMENT % wgpu::COPY_BUFFER_ALIGNMENT, 0);
    }
}
