//! A frame's readback after it was recorded: [`PendingReadback`] waits for or polls the map,
//! [`ReadbackFrame`] hands out each ticket's bytes or image, and dropping either gives the
//! staging buffer back to the pool (steps 3 and 4 of the module docs).

use std::ops::Range;
use std::sync::{Arc, Mutex, mpsc};
use std::time::{Duration, Instant};

use super::pool::{Pool, lock};
use super::types::{ANSWER_GRACE, Chunk, Layout, MapAnswer, ReadbackError, Record, Ticket};

#[derive(Debug)]
pub(super) enum MapState {
    Waiting(MapAnswer),
    Mapped,
    Failed,
}

#[derive(Debug)]
pub(super) struct PendingChunk {
    pub(super) chunk: Chunk,
    pub(super) state: MapState,
}

/// A frame's readback in flight: wait for it, or poll it (see the module docs). Dropping it
/// abandons the readback; its staging buffer goes back to the pool once the GPU is done.
#[derive(Debug)]
pub struct PendingReadback {
    pub(super) device: wgpu::Device,
    pub(super) frame: u64,
    pub(super) chunks: Vec<PendingChunk>,
    pub(super) records: Vec<Record>,
    pub(super) pool: Arc<Mutex<Pool>>,
    pub(super) taken: bool,
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

    pub(super) fn waiting(&self) -> bool {
        self.chunks
            .iter()
            .any(|c| matches!(c.state, MapState::Waiting(_)))
    }

    /// Reads the answers that arrived; the frame once every chunk is mapped.
    pub(super) fn collect(&mut self) -> Result<Option<ReadbackFrame>, ReadbackError> {
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
    pub(super) frame: u64,
    pub(super) chunks: Vec<Chunk>,
    pub(super) records: Vec<Record>,
    pub(super) pool: Arc<Mutex<Pool>>,
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

    pub(super) fn record(&self, ticket: Ticket) -> Result<&Record, ReadbackError> {
        self.records
            .get(ticket.index)
            .filter(|_| ticket.frame == self.frame)
            .ok_or(ReadbackError::ForeignTicket {
                ticket: ticket.frame,
                frame: self.frame,
            })
    }

    pub(super) fn staged(&self, record: &Record) -> (&wgpu::Buffer, Range<u64>) {
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
