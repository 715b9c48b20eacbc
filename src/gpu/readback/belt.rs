//! [`ReadbackBelt`]: records a frame's copies into one reused staging buffer and asks for it
//! to be mapped when the frame's commands have run (steps 1 and 2 of the module docs).

use std::sync::{Arc, Mutex, mpsc};

use super::frame::{MapState, PendingChunk, PendingReadback};
use super::pool::{Pool, lock};
use super::types::{
    COPY_OFFSET_ALIGNMENT, Chunk, Layout, MIN_STAGING_BYTES, ReadbackError, Record, Region, Ticket,
};

/// Records a frame's GPU-to-CPU copies into one reused staging buffer (see the module docs).
#[derive(Debug)]
pub struct ReadbackBelt {
    pub(super) device: wgpu::Device,
    pub(super) pool: Arc<Mutex<Pool>>,
    pub(super) chunks: Vec<Chunk>,
    pub(super) records: Vec<Record>,
    pub(super) frame: u64,
    /// Size of the first staging buffer of a frame: the largest frame so far.
    pub(super) capacity: u64,
    pub(super) buffers_created: u64,
}

impl ReadbackBelt {
    /// An empty belt; staging buffers are created on the first copy.
    pub fn new(device: &wgpu::Device) -> Self {
        Self {
            device: device.clone(),
            pool: Arc::default(),
            chunks: Vec::new(),
            records: Vec::new(),
            frame: 0,
            capacity: 0,
            buffers_created: 0,
        }
    }

    /// Staging buffers created so far (a steady stream of equal frames creates none after the
    /// first frames).
    pub fn buffers_created(&self) -> u64 {
        self.buffers_created
    }

    /// Bytes of the staging buffer a frame starts with (the largest frame so far).
    pub fn capacity(&self) -> u64 {
        self.capacity
    }

    /// Copies recorded in the current frame.
    pub fn pending_copies(&self) -> usize {
        self.records.len()
    }

    /// Records a copy of `region` of mip level 0, layer 0 of `texture` (`COPY_SRC` usage, one
    /// sample, a format with 1x1 texel blocks) into `encoder`.
    pub fn copy_texture(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        texture: &wgpu::Texture,
        region: Region,
    ) -> Result<Ticket, ReadbackError> {
        let format = texture.format();
        let texel_bytes = match (format.block_dimensions(), format.block_copy_size(None)) {
            ((1, 1), Some(bytes)) => bytes,
            _ => return Err(ReadbackError::UnsupportedFormat(format)),
        };
        if !texture.usage().contains(wgpu::TextureUsages::COPY_SRC) {
            return Err(ReadbackError::NotCopySource("texture"));
        }
        if texture.sample_count() != 1 {
            return Err(ReadbackError::Multisampled(texture.sample_count()));
        }
        let inside = |start: u32, length: u32, limit: u32| {
            length > 0 && start.checked_add(length).is_some_and(|end| end <= limit)
        };
        if !(inside(region.x, region.width, texture.width())
            && inside(region.y, region.height, texture.height()))
        {
            return Err(ReadbackError::Region {
                region,
                width: texture.width(),
                height: texture.height(),
            });
        }
        let row_bytes = region.width * texel_bytes;
        let padded_row_bytes = row_bytes.next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        let layout = Layout::Texture {
            format,
            width: region.width,
            height: region.height,
            row_bytes,
            padded_row_bytes,
        };
        let (chunk, offset) = self.allocate(layout.staged_bytes());
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture,
                mip_level: 0,
                origin: wgpu::Origin3d {
                    x: region.x,
                    y: region.y,
                    z: 0,
                },
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &self.chunks[chunk].buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset,
                    bytes_per_row: Some(padded_row_bytes),
                    rows_per_image: Some(region.height),
                },
            },
            wgpu::Extent3d {
                width: region.width,
                height: region.height,
                depth_or_array_layers: 1,
            },
        );
        Ok(self.push(chunk, offset, layout))
    }

    /// Records a copy of `size` bytes of `buffer` (`COPY_SRC` usage) from `offset` into
    /// `encoder`; both must be multiples of `COPY_BUFFER_ALIGNMENT` (4), `size` non-zero.
    pub fn copy_buffer(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        buffer: &wgpu::Buffer,
        offset: u64,
        size: u64,
    ) -> Result<Ticket, ReadbackError> {
        if !buffer.usage().contains(wgpu::BufferUsages::COPY_SRC) {
            return Err(ReadbackError::NotCopySource("buffer"));
        }
        let aligned = offset.is_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT)
            && size.is_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT)
            && size > 0;
        if !aligned
            || offset
                .checked_add(size)
                .is_none_or(|end| end > buffer.size())
        {
            return Err(ReadbackError::BufferRange {
                offset,
                size,
                buffer_size: buffer.size(),
            });
        }
        let layout = Layout::Buffer { size };
        let (chunk, staged) = self.allocate(size);
        encoder.copy_buffer_to_buffer(buffer, offset, &self.chunks[chunk].buffer, staged, size);
        Ok(self.push(chunk, staged, layout))
    }

    /// Ends the frame: asks wgpu to map its staging buffer once `encoder` (the encoder every
    /// copy of the frame went into) has been submitted and has run. Call it last on the
    /// encoder, then submit the encoder. The next copy starts a new frame.
    pub fn finish(&mut self, encoder: &mut wgpu::CommandEncoder) -> PendingReadback {
        let frame = self.frame;
        self.frame += 1;
        let chunks = std::mem::take(&mut self.chunks);
        let records = std::mem::take(&mut self.records);
        let total: u64 = chunks
            .iter()
            .map(|c| c.used.next_multiple_of(COPY_OFFSET_ALIGNMENT))
            .sum();
        if total > self.capacity {
            self.capacity = total;
            lock(&self.pool).min_size = total;
        }
        let chunks = chunks
            .into_iter()
            .map(|chunk| {
                let (sender, answer) = mpsc::channel();
                encoder.map_buffer_on_submit(
                    &chunk.buffer,
                    wgpu::MapMode::Read,
                    0..chunk.used,
                    move |result| {
                        // The receiver is gone only when the readback was dropped.
                        let _ = sender.send(result);
                    },
                );
                PendingChunk {
                    chunk,
                    state: MapState::Waiting(answer),
                }
            })
            .collect();
        PendingReadback {
            device: self.device.clone(),
            frame,
            chunks,
            records,
            pool: Arc::clone(&self.pool),
            taken: false,
        }
    }

    /// Room for `bytes` in this frame's staging buffer: (chunk index, offset).
    pub(super) fn allocate(&mut self, bytes: u64) -> (usize, u64) {
        if let Some(last) = self.chunks.last_mut() {
            let offset = last.used.next_multiple_of(COPY_OFFSET_ALIGNMENT);
            if offset + bytes <= last.buffer.size() {
                last.used = offset + bytes;
                return (self.chunks.len() - 1, offset);
            }
        }
        let wanted = match self.chunks.last() {
            None => bytes.max(self.capacity),
            Some(last) => bytes.max(last.buffer.size()),
        };
        let buffer = self.take_buffer(wanted);
        self.chunks.push(Chunk {
            buffer,
            used: bytes,
        });
        (self.chunks.len() - 1, 0)
    }

    /// The smallest pooled buffer of at least `wanted` bytes, or a new one.
    pub(super) fn take_buffer(&mut self, wanted: u64) -> wgpu::Buffer {
        {
            let mut pool = lock(&self.pool);
            pool.sweep();
            let best = (0..pool.free.len())
                .filter(|&i| pool.free[i].size() >= wanted)
                .min_by_key(|&i| pool.free[i].size());
            if let Some(i) = best {
                return pool.free.swap_remove(i);
            }
        }
        self.buffers_created += 1;
        self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback belt staging"),
            size: wanted
                .max(MIN_STAGING_BYTES)
                .next_multiple_of(COPY_OFFSET_ALIGNMENT),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        })
    }

    pub(super) fn push(&mut self, chunk: usize, offset: u64, layout: Layout) -> Ticket {
        self.records.push(Record {
            chunk,
            offset,
            layout,
        });
        Ticket {
            frame: self.frame,
            index: self.records.len() - 1,
        }
    }
}
