//! The staging buffers between frames: the free list the belt records into, and the buffers
//! of abandoned readbacks waiting for their map to be answered before they can be reused.

use std::sync::{Mutex, PoisonError, mpsc};

use super::types::{MAX_FREE_BUFFERS, MapAnswer};

/// Staging buffers between frames.
#[derive(Debug, Default)]
pub(super) struct Pool {
    /// Unmapped buffers ready for recording.
    pub(super) free: Vec<wgpu::Buffer>,
    /// Buffers of abandoned readbacks whose map has not been answered yet.
    pub(super) returning: Vec<(wgpu::Buffer, MapAnswer)>,
    /// Buffers smaller than this are dropped instead of kept (the belt has grown).
    pub(super) min_size: u64,
}

impl Pool {
    pub(super) fn give_back(&mut self, buffer: wgpu::Buffer) {
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
    pub(super) fn sweep(&mut self) {
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

pub(super) fn lock(pool: &Mutex<Pool>) -> std::sync::MutexGuard<'_, Pool> {
    // The pool holds no invariant a panicking holder could break half-way.
    pool.lock().unwrap_or_else(PoisonError::into_inner)
}
