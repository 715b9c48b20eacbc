//! CPU profile of the viewer's UI frame, built with the cargo feature `profile` (off by
//! default: without it the `profiling` scopes in the code compile to nothing).
//!
//! With the feature, the `profiling` crate records into puffin: aa-lab's own scopes (the UI
//! frame's phases) and those of eframe and egui-wgpu (painting, texture updates, surface
//! acquisition). [`UiProfile`] collects puffin's frames and sums the time of every scope, by
//! thread and scope name, so the viewer can log and the viewer benchmark can print where a UI
//! frame's time goes, without a profiler UI (puffin_egui does not support egui 0.37).

use std::collections::HashMap;
use std::sync::{Arc, mpsc};

use puffin::{FrameData, Reader, ScopeCollection};

/// Scope nesting reported (1: top-level scopes, 2: their children too).
const DEPTH: usize = 3;

/// Sums of puffin scopes over the frames seen since it started.
pub struct UiProfile {
    frames: mpsc::Receiver<Arc<FrameData>>,
    scopes: ScopeCollection,
    /// (thread, scope path) -> (total ns, calls).
    totals: HashMap<(String, String), (u64, u64)>,
    frame_count: u64,
}

impl UiProfile {
    /// Turns puffin on and starts collecting its frames.
    pub fn start() -> Self {
        puffin::set_scopes_on(true);
        let (sender, frames) = mpsc::channel();
        let mut profiler = puffin::GlobalProfiler::lock();
        profiler.add_sink(Box::new(move |frame| {
            let _ = sender.send(frame);
        }));
        // Scopes seen before this sink was added are named in the next frame.
        profiler.emit_scope_snapshot();
        Self {
            frames,
            scopes: ScopeCollection::default(),
            totals: HashMap::new(),
            frame_count: 0,
        }
    }

    /// Ends puffin's current frame (call once per UI frame, at its start).
    pub fn new_frame() {
        puffin::GlobalProfiler::lock().new_frame();
    }

    /// Adds the frames puffin finished since the last call.
    pub fn collect(&mut self) {
        while let Ok(frame) = self.frames.try_recv() {
            for details in &frame.scope_delta {
                self.scopes.insert(Arc::clone(details));
            }
            let Some(unpacked) = frame.unpacked().ok() else {
                continue;
            };
            self.frame_count += 1;
            for (thread, stream) in &unpacked.thread_streams {
                self.add_scopes(&thread.name, &stream.stream, (0, u64::MAX), "", 1);
            }
        }
    }

    fn add_scopes(
        &mut self,
        thread: &str,
        stream: &puffin::Stream,
        (begin, end): (u64, u64),
        parent: &str,
        depth: usize,
    ) {
        let Ok(reader) = Reader::with_offset(stream, begin) else {
            return;
        };
        for scope in reader {
            let Ok(scope) = scope else { return };
            let name = self
                .scopes
                .fetch_by_id(&scope.id)
                .map_or_else(|| "?".to_owned(), |d| d.name().to_string());
            let path = if parent.is_empty() {
                name
            } else {
                format!("{parent} > {name}")
            };
            let total = self
                .totals
                .entry((thread.to_owned(), path.clone()))
                .or_default();
            total.0 += scope.record.duration_ns.max(0) as u64;
            total.1 += 1;
            if depth < DEPTH && scope.child_begin_position < scope.child_end_position {
                let children = (scope.child_begin_position, scope.child_end_position);
                self.add_scopes(thread, stream, children, &path, depth + 1);
            }
            // The reader would go on past the parent's children.
            if scope.next_sibling_position >= end {
                return;
            }
        }
    }

    /// The `top` costliest scopes as lines: milliseconds per UI frame, calls, thread, path.
    pub fn report(&self, top: usize) -> String {
        let frames = self.frame_count.max(1) as f64;
        let mut rows: Vec<_> = self.totals.iter().collect();
        rows.sort_by_key(|row| std::cmp::Reverse(row.1.0));
        let mut out = format!(
            "UI frame profile over {} frames (ms per frame):\n",
            self.frame_count
        );
        for ((thread, path), (ns, calls)) in rows.into_iter().take(top) {
            out += &format!(
                "{:>9.2} ms  {:>7} calls  [{thread}] {path}\n",
                *ns as f64 / 1e6 / frames,
                calls
            );
        }
        out
    }
}
