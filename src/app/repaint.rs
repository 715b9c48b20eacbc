//! Waking the UI from any thread with exactly one more frame ([`request_one_frame`]): what
//! every background job (the render thread, the workers, the loaders, the file dialogs) calls
//! when it has something to show. This file imports nothing of the viewer.

/// Asks egui for exactly one more UI frame, from any thread. `request_repaint` asks for two
/// (egui runs a second pass to let things settle), and on a software rasteriser every painted
/// frame costs CPU that the engine would use; a request with a delay, however short, gets one.
/// (Track caller: egui's repaint causes name the code that asked.)
#[track_caller]
pub(crate) fn request_one_frame(ctx: &egui::Context) {
    ctx.request_repaint_after(std::time::Duration::from_millis(1));
}
