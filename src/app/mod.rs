//! The viewer: an eframe/egui desktop application hosting the same frame graph as the headless
//! command line, so that what the window shows are exactly the pixels each technique produced.
//!
//! How it fits together:
//! - [`AaLabApp`] (app.rs) is the `eframe::App`: a thin shell around the workspace and the
//!   panels. Each UI frame it picks up what finished in the background, handles shortcuts,
//!   hands the engine the next frame to render when it is free, then calls each panel's `ui`.
//!   Its public methods are the test API (tests/ui.rs, benches/viewer.rs).
//! - The context (context/) is what every feature shares: the settings, the engine, the scene
//!   and camera, the open image set (of still images, or of image sequences whose images are
//!   the playhead's frames: sequence_set.rs), the blind session (whose numbering every label follows),
//!   the lens size, the notices, the file dialog and the render size, with the commands and
//!   queries on them (scene loading, dialogs, techniques, comparison, bookmarks, the lookups of
//!   what the panes show, the image set, clips, the blind session).
//! - The features own their state and take the context as an argument: the magnifier's
//!   heatmaps (magnifier.rs), the quality figures (quality.rs), exports (export.rs), the bench
//!   (bench.rs), the clip bar (clip_bar.rs), ColorVideoVDP's JOD and distortion maps of clips
//!   and sequences (jod.rs). No feature imports another; what one asks of
//!   another is a `context::Command` that the workspace (workspace.rs, the context and the
//!   features together) carries out after the panels.
//! - The panels are the shell above them: they take the workspace and never each other; what
//!   one needs of another the app passes in (the pixel under the pointer, the help overlay's
//!   flag). The viewport tiles (viewport.rs) and the magnifier panel are structs owning what
//!   only they keep between frames; the others own nothing and are functions: the menu bar,
//!   toolbar and status bar (panels.rs), the techniques panel (techniques_panel.rs), the
//!   metrics panel (metrics_panel.rs), the image set's panels (image_panel.rs), the clip bar
//!   and the blind comparison's panel (blind/), which numbers and shuffles the panes and
//!   records answers.
//! - The engine never runs on the UI thread: the render thread (render_thread/) owns the
//!   render device, the frame graph and every technique, and does all slow engine work
//!   (pipeline creation, scene uploads, target resizes, rendering, readback through the one
//!   readback belt of `gpu/`, uploads for display). engine/ is the UI's side (and owns the recorded
//!   clip and its player): it
//!   decides what to render (schedule.rs, plain data), mirrors the techniques' settings and
//!   publishes finished frames, which blit.rs draws (one texel load per screen pixel: egui's
//!   own image path costs several times more on a software rasteriser). A toggle, a layout
//!   change or a settings edit shows in the next UI frame; the new images replace the
//!   previous ones when they arrive.
//! - Scene loading, file dialogs, PNG encoding, the quality figures (quality.rs) and the
//!   magnifier's heatmaps (difference.rs) run on worker threads (worker.rs) as well.
//!   Those threads, and the devices the render thread and the quality worker open, run at the
//!   lowest CPU priority; on a software adapter the window's own rasteriser threads get a CPU
//!   each (rasterizer_threads.rs), so that the window's paint never shares a core with itself.
//! - Settings and layout persist through eframe's storage (settings.rs); keyboard shortcuts and
//!   the help overlay share one table (shortcuts.rs).

// `app.rs` holds the `eframe::App`, as the module layout of the design names it.
#[allow(clippy::module_inception)]
mod app;
mod bench;
mod blind;
mod blit;
mod camera;
mod clip_bar;
mod context;
mod difference;
mod engine;
mod event_filter;
mod export;
mod image_panel;
mod image_set;
mod jod;
mod jod_panel;
mod key_events;
mod lens;
mod magnifier;
mod metrics_panel;
mod notice;
mod panels;
mod quality;
mod rasterizer_threads;
mod reference;
mod render_thread;
mod repaint;
mod scale_form;
mod scene_loader;
mod schedule;
mod sequence_set;
mod settings;
mod shortcuts;
mod stats;
mod style;
mod techniques_panel;
mod viewport;
mod worker;
mod workspace;

use std::cell::RefCell;
use std::rc::Rc;
use std::sync::Arc;

pub use app::{AaLabApp, LaunchOptions};
pub use blind::pane_order;
pub use camera::CameraController;
pub use difference::DiffMetric;
pub use engine::DisplayPath;
pub use engine::{ClipPath, ClipSettings};
use key_events::HeldKeys;
pub use quality::{Figures, PixelFigures};
pub use rasterizer_threads::spread_window_rasterizer_threads;
use settings::APP_ID;
pub use settings::{Layout, Resolution, Settings};
pub use worker::lower_priority;

/// Errors of opening the viewer.
#[derive(Debug, thiserror::Error)]
pub enum ViewerError {
    /// There is no display server to open a window on.
    #[error(
        "no display to open the viewer on (neither DISPLAY nor WAYLAND_DISPLAY is set); \
         render headless instead, e.g. `aa-lab render --scene atrium --technique all --out out/` \
         (see `aa-lab render --help`)"
    )]
    NoDisplay,
    /// eframe could not create the window or the GPU device.
    #[error("the viewer window could not be opened: {0}; `aa-lab render` works without a window")]
    Window(String),
}

/// The wgpu setup the viewer asks eframe (and the UI tests ask egui_kittest) for: Vulkan,
/// Metal or DX12 unless `WGPU_BACKEND` says otherwise (Mesa's GL reads multisampled textures
/// as zeros), and the device features the frame graph uses (timestamps, adapter-specific
/// format features), which egui-wgpu alone would not request.
pub fn wgpu_setup() -> egui_wgpu::WgpuSetup {
    let mut setup = egui_wgpu::WgpuSetupCreateNew::without_display_handle();
    setup.instance_descriptor.backends =
        wgpu::Backends::from_env().unwrap_or(wgpu::Backends::PRIMARY);
    setup.power_preference = wgpu::PowerPreference::HighPerformance;
    setup.device_descriptor = Arc::new(crate::gpu::device_descriptor);
    egui_wgpu::WgpuSetup::CreateNew(setup)
}

/// eframe options: wgpu renderer with [`wgpu_setup`], no dithering (pixel-exact images), no
/// multisampling of egui itself, files may be dropped on the window.
pub fn native_options() -> eframe::NativeOptions {
    eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title("aa-lab")
            .with_app_id(APP_ID)
            .with_inner_size([1600.0, 1000.0])
            .with_min_inner_size([800.0, 500.0])
            .with_drag_and_drop(true),
        renderer: eframe::Renderer::Wgpu,
        wgpu_options: egui_wgpu::WgpuConfiguration {
            wgpu_setup: wgpu_setup(),
            ..Default::default()
        },
        multisampling: blit::EGUI_MULTISAMPLING,
        dithering: false,
        persist_window: true,
        ..Default::default()
    }
}

/// Whether a display server is reachable (always true outside Linux and the BSDs).
pub fn display_available() -> bool {
    if cfg!(all(unix, not(target_os = "macos"))) {
        let set = |name: &str| std::env::var_os(name).is_some_and(|v| !v.is_empty());
        set("DISPLAY") || set("WAYLAND_DISPLAY")
    } else {
        true
    }
}

/// Opens the viewer and returns when its window is closed.
pub fn run(options: LaunchOptions) -> Result<(), ViewerError> {
    if !display_available() {
        return Err(ViewerError::NoDisplay);
    }
    let window_error = |e: &dyn std::fmt::Display| ViewerError::Window(e.to_string());
    let event_loop = winit::event_loop::EventLoop::<eframe::UserEvent>::with_user_event()
        .build()
        .map_err(|e| window_error(&e))?;
    let held_keys = HeldKeys::default();
    // eframe reports an app that could not be created only in its log when it runs on an
    // event loop of ours: the creator keeps the outcome.
    let created: Rc<RefCell<Option<Result<(), String>>>> = Rc::default();
    let outcome = Rc::clone(&created);
    let launch = LaunchOptions {
        window_clears: true,
        held_keys: held_keys.clone(),
        ..options
    };
    let eframe = eframe::create_native(
        APP_ID,
        native_options(),
        Box::new(move |cc| {
            let app = AaLabApp::new(cc, launch);
            *outcome.borrow_mut() = Some(app.as_ref().map(|_| ()).map_err(|e| e.to_string()));
            app.map(|app| Box::new(app) as Box<dyn eframe::App>)
                .map_err(|e| e.into())
        }),
        &event_loop,
    );
    let mut filtered = event_filter::ShortcutReleaseFilter::new(eframe, held_keys);
    event_loop
        .run_app(&mut filtered)
        .map_err(|e| window_error(&e))?;
    match created.take() {
        Some(Ok(())) => Ok(()),
        Some(Err(e)) => Err(ViewerError::Window(e)),
        None => Err(ViewerError::Window(
            "eframe could not open it (its log above says why)".to_owned(),
        )),
    }
}
