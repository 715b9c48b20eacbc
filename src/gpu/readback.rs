//! The one way pixels and buffer contents come back from the GPU: a readback belt, after
//! re_renderer's `GpuReadbackBelt`.
//!
//! This module owns every GPU-to-CPU copy of the crate: technique outputs for the viewer and
//! the CLI, the GPU metrics' totals and SSIM map, and the graph's pipeline-statistics results.
//!
//! # How the belt works
//! 1. While a frame is recorded, [`ReadbackBelt::copy_texture`] and
//!    [`ReadbackBelt::copy_buffer`] record copies into the caller's own command encoder (the
//!    frame's encoder, so a copy sees exactly what the passes before it wrote) and hand back a
//!    [`Ticket`]. Every copy of the frame is packed into one `MAP_READ` staging buffer, each at
//!    an offset aligned to [`COPY_OFFSET_ALIGNMENT`] (256 bytes: a multiple of every texel
//!    block size, of `MAP_ALIGNMENT` and of `COPY_BUFFER_ALIGNMENT`), texture rows padded to
//!    `COPY_BYTES_PER_ROW_ALIGNMENT`.
//! 2. [`ReadbackBelt::finish`], called last on that encoder before it is submitted, asks wgpu
//!    to map the staging buffer when the encoder's commands have run
//!    (`CommandEncoder::map_buffer_on_submit`) and returns a [`PendingReadback`].
//! 3. The caller submits, then either blocks ([`PendingReadback::wait`]: `device.poll(Wait)`)
//!    or polls each UI frame ([`PendingReadback::try_take`]: `Ok(None)` while the GPU works).
//!    Both give a [`ReadbackFrame`] handing out each ticket's bytes ([`ReadbackFrame::bytes`],
//!    row padding removed) or image ([`ReadbackFrame::rgba8`]).
//! 4. Dropping the [`ReadbackFrame`] (or an abandoned [`PendingReadback`]) unmaps the staging
//!    buffer and returns it to the belt's small pool, so the next frame records into it again
//!    while, if needed, another frame's buffer is still mapped.
//!
//! The staging buffer of a frame is sized from the largest frame seen so far. A frame that
//! outgrows it opens a second buffer (mapped separately, that frame only), and the belt then
//! grows: smaller buffers are dropped as they come back, and later frames get one buffer of
//! the new size. [`ReadbackBelt::buffers_created`] counts allocations, so tests can check that
//! a steady stream of frames allocates nothing.
//!
//! # Why one map per frame
//! Every `map_async` is a separate request the device must track and answer, and on Vulkan a
//! separate wait on the submission's fence; a buffer and an encoder per image (what the crate
//! did before) also allocate GPU memory every frame. Packing a frame's copies into one reused
//! buffer costs one allocation in steady state (none), one submission (the frame's own) and
//! one map, whatever the number of images.
//!
//! No call here panics on a GPU result: a failed map, a lost device, a ticket of another frame
//! or a copy wgpu would reject (missing `COPY_SRC`, a region outside the texture, unaligned
//! buffer ranges) are [`ReadbackError`]s.

use std::ops::Range;
use std::sync::{Arc, Mutex, PoisonError, mpsc};
use std::time::{Duration, Instant};

use super::Gpu;

/// Alignment of every copy's offset in the staging buffer.
pub const COPY_OFFSET_ALIGNMENT: u64 = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT as u64;
/// Smallest staging buffer the belt allocates.
const MIN_STAGING_BYTES: u64 = 64 * 1024;
/// Free staging buffers the pool keeps at most.
const MAX_FREE_BUFFERS: usize = 4;
/// How long [`PendingReadback::wait`] waits for the map callback once the device is idle (the
/// callback may run on another thread polling the same device).
const ANSWER_GRACE: Duration = Duration::from_secs(5);

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
    frame: u64,
    index: usize,
}

/// What a copy holds, to unpack it.
#[derive(Clone, Copy, Debug)]
enum Layout {
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
    fn staged_bytes(&self) -> u64 {
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
struct Record {
    chunk: usize,
    offset: u64,
    layout: Layout,
}

/// A staging buffer being filled, or mapped.
#[derive(Debug)]
struct Chunk {
    buffer: wgpu::Buffer,
    used: u64,
}

type MapAnswer = mpsc::Receiver<Result<(), wgpu::BufferAsyncError>>;

/// Staging buffers between frames.
#[derive(Debug, Default)]
struct Pool {
    /// Unmapped buffers ready for recording.
    free: Vec<wgpu::Buffer>,
    /// Buffers of abandoned readbacks whose map has not been answered yet.
    returning: Vec<(wgpu::Buffer, MapAnswer)>,
    /// Buffers smaller than this are dropped instead of kept (the belt has grown).
    min_size: u64,
}

impl Pool {
    fn give_back(&mut self, buffer: wgpu::Buffer) {
        if buffer.size() < self.min_size {
            return;
        }
        self.free.push(buffer);
        if self.free.len() > MAX_FREE_BUFFERS
            && let Some(smallest) = (0..self.free.len()).min_by_key(|&i| self.free[i].size())
        {
            self.free.swap_remove(smallest);
        }
    }

    /// Moves the abandoned buffers whose map was answered to the free list.
    fn sweep(&mut self) {
        let mut i = 0;
        while i < self.returning.len() {
            match self.returning[i].1.try_recv() {
                Err(mpsc::TryRecvError::Empty) => i += 1,
                answer => {
                    let (buffer, _) = self.returning.swap_remove(i);
                    if matches!(answer, Ok(Ok(()))) {
                        buffer.unmap();
                    }
                    self.give_back(buffer);
                }
            }
        }
        let min_size = self.min_size;
        self.free.retain(|b| b.size() >= min_size);
    }
}

fn lock(pool: &Mutex<Pool>) -> std::sync::MutexGuard<'_, Pool> {
    // The pool holds no invariant a panicking holder could break half-way.
    pool.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Records a frame's GPU-to-CPU copies into one reused staging buffer (see the module docs).
#[derive(Debug)]
pub struct ReadbackBelt {
    device: wgpu::Device,
    pool: Arc<Mutex<Pool>>,
    chunks: Vec<Chunk>,
    records: Vec<Record>,
    frame: u64,
    /// Size of the first staging buffer of a frame: the largest frame so far.
    capacity: u64,
    buffers_created: u64,
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
    fn allocate(&mut self, bytes: u64) -> (usize, u64) {
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
    fn take_buffer(&mut self, wanted: u64) -> wgpu::Buffer {
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

    fn push(&mut self, chunk: usize, offset: u64, layout: Layout) -> Ticket {
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

#[derive(Debug)]
enum MapState {
    Waiting(MapAnswer),
    Mapped,
    Failed,
}

#[derive(Debug)]
struct PendingChunk {
    chunk: Chunk,
    state: MapState,
}

/// A frame's readback in flight: wait for it, or poll it (see the module docs). Dropping it
/// abandons the readback; its staging buffer goes back to the pool once the GPU is done.
#[derive(Debug)]
pub struct PendingReadback {
    device: wgpu::Device,
    frame: u64,
    chunks: Vec<PendingChunk>,
    records: Vec<Record>,
    pool: Arc<Mutex<Pool>>,
    taken: bool,
}

impl PendingReadback {
    /// Number of copies in the frame.
    pub fn len(&self) -> usize {
        self.records.len()
    }

    /// Whether the frame has no copies (it is ready at once).
    pub fn is_empty(&self) -> bool {
        self.records.is_empty()
    }

    /// Polls the device without blocking and returns the frame once its staging buffer is
    /// mapped, `Ok(None)` while the GPU is still working. After it returned the frame, further
    /// calls fail with [`ReadbackError::AlreadyTaken`].
    pub fn try_take(&mut self) -> Result<Option<ReadbackFrame>, ReadbackError> {
        if self.taken {
            return Err(ReadbackError::AlreadyTaken);
        }
        if self.waiting() {
            self.device.poll(wgpu::PollType::Poll)?;
        }
        self.collect()
    }

    /// Blocks until the GPU has run the frame's submission and returns the mapped frame.
    pub fn wait(mut self) -> Result<ReadbackFrame, ReadbackError> {
        if self.taken {
            return Err(ReadbackError::AlreadyTaken);
        }
        if self.waiting() {
            self.device.poll(wgpu::PollType::wait_indefinitely())?;
        }
        let deadline = Instant::now() + ANSWER_GRACE;
        loop {
            if let Some(frame) = self.collect()? {
                return Ok(frame);
            }
            // Another thread polling the same device may be running the callback right now.
            let remaining = deadline.saturating_duration_since(Instant::now());
            if remaining.is_zero() {
                return Err(ReadbackError::NoAnswer);
            }
            let Some(pending) = self
                .chunks
                .iter_mut()
                .find(|c| matches!(c.state, MapState::Waiting(_)))
            else {
                return Err(ReadbackError::NoAnswer);
            };
            if let MapState::Waiting(answer) = &pending.state {
                match answer.recv_timeout(remaining.min(Duration::from_millis(50))) {
                    Err(mpsc::RecvTimeoutError::Timeout) => {}
                    Ok(Ok(())) => pending.state = MapState::Mapped,
                    Ok(Err(err)) => {
                        pending.state = MapState::Failed;
                        return Err(ReadbackError::Map(err));
                    }
                    Err(mpsc::RecvTimeoutError::Disconnected) => {
                        pending.state = MapState::Failed;
                        return Err(ReadbackError::NoAnswer);
                    }
                }
            }
            self.device.poll(wgpu::PollType::Poll)?;
        }
    }

    fn waiting(&self) -> bool {
        self.chunks
            .iter()
            .any(|c| matches!(c.state, MapState::Waiting(_)))
    }

    /// Reads the answers that arrived; the frame once every chunk is mapped.
    fn collect(&mut self) -> Result<Option<ReadbackFrame>, ReadbackError> {
        let mut failure = None;
        for pending in &mut self.chunks {
            let MapState::Waiting(answer) = &pending.state else {
                continue;
            };
            match answer.try_recv() {
                Err(mpsc::TryRecvError::Empty) => {}
                Ok(Ok(())) => pending.state = MapState::Mapped,
                Ok(Err(err)) => {
                    pending.state = MapState::Failed;
                    failure = Some(ReadbackError::Map(err));
                }
                Err(mpsc::TryRecvError::Disconnected) => {
                    pending.state = MapState::Failed;
                    failure = Some(ReadbackError::NoAnswer);
                }
            }
        }
        if let Some(err) = failure {
            return Err(err);
        }
        if self
            .chunks
            .iter()
            .any(|c| matches!(c.state, MapState::Failed))
        {
            return Err(ReadbackError::NoAnswer);
        }
        if self.waiting() {
            return Ok(None);
        }
        self.taken = true;
        Ok(Some(ReadbackFrame {
            frame: self.frame,
            chunks: std::mem::take(&mut self.chunks)
                .into_iter()
                .map(|p| p.chunk)
                .collect(),
            records: std::mem::take(&mut self.records),
            pool: Arc::clone(&self.pool),
        }))
    }
}

impl Drop for PendingReadback {
    fn drop(&mut self) {
        if self.chunks.is_empty() {
            return;
        }
        let mut pool = lock(&self.pool);
        for pending in self.chunks.drain(..) {
            let buffer = pending.chunk.buffer;
            match pending.state {
                MapState::Mapped => {
                    buffer.unmap();
                    pool.give_back(buffer);
                }
                MapState::Failed => pool.give_back(buffer),
                MapState::Waiting(answer) => pool.returning.push((buffer, answer)),
            }
        }
    }
}

/// A frame's mapped staging buffer: redeem its tickets, then drop it to hand the buffer back.
#[derive(Debug)]
pub struct ReadbackFrame {
    frame: u64,
    chunks: Vec<Chunk>,
    records: Vec<Record>,
    pool: Arc<Mutex<Pool>>,
}

impl ReadbackFrame {
    /// Number of copies in the frame.
    pub fn len(&self) -> usize {
        self.records.len()
    }

    /// Whether the frame has no copies.
    pub fn is_empty(&self) -> bool {
        self.records.is_empty()
    }

    fn record(&self, ticket: Ticket) -> Result<&Record, ReadbackError> {
        self.records
            .get(ticket.index)
            .filter(|_| ticket.frame == self.frame)
            .ok_or(ReadbackError::ForeignTicket {
                ticket: ticket.frame,
                frame: self.frame,
            })
    }

    fn staged(&self, record: &Record) -> (&wgpu::Buffer, Range<u64>) {
        let start = record.offset;
        (
            &self.chunks[record.chunk].buffer,
            start..start + record.layout.staged_bytes(),
        )
    }

    /// The bytes of a copy: a buffer copy as it was, a texture copy as tightly packed rows
    /// (padding removed).
    pub fn bytes(&self, ticket: Ticket) -> Result<Vec<u8>, ReadbackError> {
        let record = self.record(ticket)?;
        let (buffer, range) = self.staged(record);
        let mapped = buffer.get_mapped_range(range)?;
        Ok(match record.layout {
            Layout::Buffer { .. } => mapped.to_vec(),
            Layout::Texture {
                height,
                row_bytes,
                padded_row_bytes,
                ..
            } => {
                let mut packed = Vec::with_capacity(row_bytes as usize * height as usize);
                for row in mapped.chunks_exact(padded_row_bytes as usize) {
                    packed.extend_from_slice(&row[..row_bytes as usize]);
                }
                packed
            }
        })
    }

    /// The region of an RGBA8 texture (`Rgba8Unorm` or `Rgba8UnormSrgb`: the stored, encoded
    /// bytes) as an image.
    pub fn rgba8(&self, ticket: Ticket) -> Result<image::RgbaImage, ReadbackError> {
        let (width, height) = match self.record(ticket)?.layout {
            Layout::Texture {
                format: wgpu::TextureFormat::Rgba8Unorm | wgpu::TextureFormat::Rgba8UnormSrgb,
                width,
                height,
                ..
            } => (width, height),
            Layout::Texture { format, .. } => {
                return Err(ReadbackError::UnsupportedFormat(format));
            }
            Layout::Buffer { .. } => {
                return Err(ReadbackError::UnsupportedFormat(
                    wgpu::TextureFormat::Rgba8Unorm,
                ));
            }
        };
        let bytes = self.bytes(ticket)?;
        image::RgbaImage::from_raw(width, height, bytes).ok_or(ReadbackError::UnsupportedFormat(
            wgpu::TextureFormat::Rgba8Unorm,
        ))
    }
}

impl Drop for ReadbackFrame {
    fn drop(&mut self) {
        let mut pool = lock(&self.pool);
        for chunk in self.chunks.drain(..) {
            chunk.buffer.unmap();
            pool.give_back(chunk.buffer);
        }
    }
}

/// Records, submits and waits for one readback on its own encoder: `record` adds the copies to
/// `belt` and returns what `read` needs to redeem them.
fn read_now<T, R>(
    gpu: &Gpu,
    belt: &mut ReadbackBelt,
    record: impl FnOnce(&mut ReadbackBelt, &mut wgpu::CommandEncoder) -> Result<T, ReadbackError>,
    read: impl FnOnce(&ReadbackFrame, T) -> Result<R, ReadbackError>,
) -> Result<R, ReadbackError> {
    let mut encoder = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("readback"),
        });
    let recorded = record(belt, &mut encoder);
    let pending = belt.finish(&mut encoder);
    let tickets = recorded?;
    gpu.queue.submit([encoder.finish()]);
    read(&pending.wait()?, tickets)
}

/// Reads mip level 0 of a 2D texture (which needs `COPY_SRC` usage) into tightly packed rows:
/// one encoder, one submission, a blocking wait (on a belt of its own).
pub fn read_texture_bytes(gpu: &Gpu, texture: &wgpu::Texture) -> Result<Vec<u8>, ReadbackError> {
    read_now(
        gpu,
        &mut ReadbackBelt::new(&gpu.device),
        |belt, encoder| belt.copy_texture(encoder, texture, Region::whole(texture)),
        |frame, ticket| frame.bytes(ticket),
    )
}

/// Reads an RGBA8 texture (`Rgba8Unorm` or `Rgba8UnormSrgb`: the stored, encoded bytes) into an
/// image: one encoder, one submission, a blocking wait (on a belt of its own).
pub fn read_texture_rgba8(
    gpu: &Gpu,
    texture: &wgpu::Texture,
) -> Result<image::RgbaImage, ReadbackError> {
    match texture.format() {
        wgpu::TextureFormat::Rgba8Unorm | wgpu::TextureFormat::Rgba8UnormSrgb => {}
        other => return Err(ReadbackError::UnsupportedFormat(other)),
    }
    read_now(
        gpu,
        &mut ReadbackBelt::new(&gpu.device),
        |belt, encoder| belt.copy_texture(encoder, texture, Region::whole(texture)),
        |frame, ticket| frame.rgba8(ticket),
    )
}

/// [`read_texture_bytes`] on a belt the caller keeps, so repeated reads reuse its staging
/// buffer.
pub fn read_texture_bytes_with(
    gpu: &Gpu,
    belt: &mut ReadbackBelt,
    texture: &wgpu::Texture,
) -> Result<Vec<u8>, ReadbackError> {
    read_now(
        gpu,
        belt,
        |belt, encoder| belt.copy_texture(encoder, texture, Region::whole(texture)),
        |frame, ticket| frame.bytes(ticket),
    )
}

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
    fn handles_move_between_threads() {
        // The viewer records on its render thread and polls from the UI thread.
        fn send<T: Send>() {}
        send::<ReadbackBelt>();
        send::<PendingReadback>();
        send::<ReadbackFrame>();
        send::<Ticket>();
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
