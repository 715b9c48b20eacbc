//! Fragment-shader invocations per pass, from pipeline-statistics queries: the direct measure
//! of shading work (MSAA shades about once per covered pixel, SSAA and sample-rate shading once
//! per sample).
//!
//! Off by default. When switched on (and the adapter has `PIPELINE_STATISTICS_QUERY`), every
//! render pass the graph records — shared scene renders, a technique's own scene renders and
//! every `render_pass`/`fullscreen_pass` — is bracketed by a query, the results are resolved at
//! the end of the frame and copied out through the recorder's [`ReadbackBelt`] in the frame's
//! own encoder, and `FrameGraph::render` waits for the GPU to read them back, so frames with
//! statistics on should not be the ones that are timed. Compute passes and copies
//! have no fragment work and are not queried. The query set holds a fixed number of queries;
//! a frame with more render passes than that grows the set for the next frame and reports no
//! statistics (render the frame again).

/// Fragment-shader invocations of one render pass.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct PassInvocations {
    /// Pass label, as in timings (`technique/pass` or a scene input's label).
    pub label: String,
    /// Fragment-shader invocations the pass ran.
    pub fragment_invocations: u64,
}

impl PassInvocations {
    /// The technique id of a technique pass, `None` for a shared scene render.
    pub fn technique(&self) -> Option<&str> {
        super::timing::split_pass_label(&self.label).map(|(t, _)| t)
    }
}

/// Pipeline statistics of one frame, in recording order.
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct FrameStatistics {
    /// Every queried pass.
    pub passes: Vec<PassInvocations>,
}

impl FrameStatistics {
    /// Invocations of a technique's own passes.
    pub fn technique_invocations(&self, id: &str) -> u64 {
        self.passes
            .iter()
            .filter(|p| p.technique() == Some(id))
            .map(|p| p.fragment_invocations)
            .sum()
    }

    /// Invocations of the pass with exactly this label (a scene input's render).
    pub fn pass_invocations(&self, label: &str) -> Option<u64> {
        self.passes
            .iter()
            .find(|p| p.label == label)
            .map(|p| p.fragment_invocations)
    }
}

use crate::gpu::readback::{PendingReadback, ReadbackBelt, ReadbackError, Ticket};

/// Queries allocated at first.
const INITIAL_CAPACITY: u32 = 64;
/// Bytes of one query result (one 64-bit counter).
const RESULT_BYTES: u64 = 8;

struct Queries {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    capacity: u32,
}

/// Allocates queries while a frame is recorded and reads them back after it ran.
pub(super) struct StatisticsRecorder {
    enabled: bool,
    queries: Option<Queries>,
    labels: Vec<String>,
    wanted: u32,
    last: Option<FrameStatistics>,
    /// Created with the first query set.
    belt: Option<ReadbackBelt>,
    /// This frame's results on their way back.
    pending: Option<(PendingReadback, Ticket)>,
}

impl StatisticsRecorder {
    pub(super) fn new() -> Self {
        Self {
            enabled: false,
            queries: None,
            labels: Vec::new(),
            wanted: INITIAL_CAPACITY,
            last: None,
            belt: None,
            pending: None,
        }
    }

    pub(super) fn set_enabled(&mut self, enabled: bool) {
        self.enabled = enabled;
        self.last = None;
        if !enabled {
            self.queries = None;
            self.belt = None;
            self.pending = None;
        }
    }

    pub(super) fn last(&self) -> Option<&FrameStatistics> {
        self.last.as_ref()
    }

    /// Starts a frame: makes sure the query set holds `wanted` queries.
    pub(super) fn begin_frame(&mut self, device: &wgpu::Device) {
        self.labels.clear();
        self.pending = None;
        if !self.enabled {
            return;
        }
        self.belt.get_or_insert_with(|| ReadbackBelt::new(device));
        if self
            .queries
            .as_ref()
            .is_some_and(|q| q.capacity >= self.wanted)
        {
            return;
        }
        let capacity = self.wanted;
        let bytes = u64::from(capacity) * RESULT_BYTES;
        self.queries = Some(Queries {
            set: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pipeline statistics"),
                ty: wgpu::QueryType::PipelineStatistics(
                    wgpu::PipelineStatisticsTypes::FRAGMENT_SHADER_INVOCATIONS,
                ),
                count: capacity,
            }),
            resolve: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("pipeline statistics resolve"),
                size: bytes,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            capacity,
        });
    }

    /// A query for the pass `label`, or `None` when statistics are off or the set is full.
    pub(super) fn allocate(&mut self, label: &str) -> Option<(&wgpu::QuerySet, u32)> {
        if !self.enabled {
            return None;
        }
        let index = self.labels.len() as u32;
        self.labels.push(label.to_owned());
        let queries = self.queries.as_ref()?;
        (index < queries.capacity).then_some((&queries.set, index))
    }

    /// Records the resolve of this frame's queries and their copy to the CPU; call it last on
    /// the frame's encoder, before submitting it.
    pub(super) fn resolve(&mut self, encoder: &mut wgpu::CommandEncoder) -> Result<(), String> {
        self.pending = None;
        let (Some(queries), Some(belt)) = (&self.queries, &mut self.belt) else {
            return Ok(());
        };
        let used = (self.labels.len() as u32).min(queries.capacity);
        if !self.enabled || used == 0 || self.labels.len() as u32 > queries.capacity {
            return Ok(());
        }
        encoder.resolve_query_set(&queries.set, 0..used, &queries.resolve, 0);
        let ticket = belt
            .copy_buffer(encoder, &queries.resolve, 0, u64::from(used) * RESULT_BYTES)
            .map_err(|e| e.to_string())?;
        self.pending = Some((belt.finish(encoder), ticket));
        Ok(())
    }

    /// After the frame's submission: waits for the results and keeps them, or, when the frame
    /// needed more queries than the set had, grows the set for the next frame and keeps none.
    pub(super) fn finish_frame(&mut self) -> Result<(), String> {
        self.last = None;
        if !self.enabled || self.labels.is_empty() {
            return Ok(());
        }
        let needed = self.labels.len() as u32;
        if self.queries.as_ref().is_none_or(|q| q.capacity < needed) {
            self.wanted = needed.next_power_of_two().max(INITIAL_CAPACITY);
            return Ok(());
        }
        let Some((pending, ticket)) = self.pending.take() else {
            return Ok(());
        };
        let read = || -> Result<Vec<u64>, ReadbackError> {
            let bytes = pending.wait()?.bytes(ticket)?;
            Ok(bytemuck::pod_collect_to_vec(&bytes))
        };
        let counts = read().map_err(|e| e.to_string())?;
        self.last = Some(FrameStatistics {
            passes: self
                .labels
                .iter()
                .zip(counts)
                .map(|(label, fragment_invocations)| PassInvocations {
                    label: label.clone(),
                    fragment_invocations,
                })
                .collect(),
        });
        Ok(())
    }
}
