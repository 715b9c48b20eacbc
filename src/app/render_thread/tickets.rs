//! The readback copies of one frame ([`Tickets`]): every output that rendered, the debug
//! views asked for and the reference go through the thread's one readback belt, mapped once;
//! then the images are uploaded for display and the frame's result is built.

use super::*;

/// The readback copies of one frame.
pub(super) struct Tickets {
    outputs: Vec<(usize, Ticket)>,
    debug: Vec<(usize, &'static str, &'static str, Ticket)>,
    reference: Option<Ticket>,
}

impl Tickets {
    /// Records a copy of every output that rendered, the debug views the plan asks for and
    /// the reference.
    pub(super) fn record(
        belt: &mut ReadbackBelt,
        encoder: &mut wgpu::CommandEncoder,
        slots: &[crate::graph::Slot],
        plan: &FramePlan,
        slot_of: &[Option<usize>],
        reference_slot: usize,
    ) -> Result<Self, ReadbackError> {
        let mut copy =
            |texture: &wgpu::Texture| belt.copy_texture(encoder, texture, Region::whole(texture));
        let mut tickets = Self {
            outputs: Vec::new(),
            debug: Vec::new(),
            reference: None,
        };
        let slot = |index: usize| Some(&slots[slot_of.get(index).copied().flatten()?]);
        for &index in &plan.read {
            if let Some(texture) = slot(index).and_then(|s| s.output()) {
                tickets.outputs.push((index, copy(texture)?));
            }
        }
        for &index in &plan.debug {
            if let Some(slot) = slot(index) {
                for view in slot.technique.debug_views() {
                    if view.texture.usage().contains(wgpu::TextureUsages::COPY_SRC) {
                        tickets.debug.push((
                            index,
                            view.name,
                            view.description,
                            copy(view.texture)?,
                        ));
                    }
                }
            }
        }
        if plan.reference.is_some()
            && let Some(texture) = slots[reference_slot].output()
        {
            tickets.reference = Some(copy(texture)?);
        }
        Ok(tickets)
    }

    /// Waits for the copies, uploads the images for display and builds the frame's result
    /// (without the graph's figures). `textures` are outputs shown from their own texture;
    /// other read-back outputs are uploaded when `shown_as_is` (the read-back display), and
    /// only their pixels kept otherwise (the native display reading a still frame's pixels).
    pub(super) fn take(
        self,
        pending: PendingReadback,
        uploader: &Uploader,
        reference_progress: Progress,
        textures: Vec<(usize, wgpu::Texture)>,
        shown_as_is: bool,
    ) -> Result<FrameResult, RenderError> {
        let read = pending.wait()?;
        let image = |ticket: Ticket| -> Result<RenderedImage, RenderError> {
            let pixels = read.rgba8(ticket)?;
            let texture = uploader.upload(&pixels);
            Ok(RenderedImage { pixels, texture })
        };
        let mut outputs: Vec<(usize, FrameOutput)> = textures
            .into_iter()
            .map(|(index, texture)| {
                let output = FrameOutput {
                    display: Some(uploader.wrap(texture)),
                    pixels: None,
                };
                (index, output)
            })
            .collect();
        for &(index, ticket) in &self.outputs {
            let pixels = read.rgba8(ticket)?;
            match outputs.iter_mut().find(|(i, _)| *i == index) {
                // The output texture itself is shown: the pixels are for the CPU only.
                Some((_, output)) => output.pixels = Some(pixels),
                None => {
                    let display = shown_as_is.then(|| uploader.upload(&pixels));
                    outputs.push((
                        index,
                        FrameOutput {
                            display,
                            pixels: Some(pixels),
                        },
                    ));
                }
            }
        }
        let result = FrameResult {
            outputs,
            debug: collect(&self.debug, |&(index, name, description, ticket)| {
                Ok((index, name, description, image(ticket)?))
            })?,
            reference: self
                .reference
                .map(|ticket| Ok::<_, RenderError>((reference_progress, image(ticket)?)))
                .transpose()?,
            memory: None,
            scene_renders: 0,
            timings: None,
        };
        uploader.flush();
        Ok(result)
    }
}

/// Maps every item, stopping at the first error.
fn collect<T, U>(
    items: &[T],
    map: impl FnMut(&T) -> Result<U, RenderError>,
) -> Result<Vec<U>, RenderError> {
    items.iter().map(map).collect()
}
