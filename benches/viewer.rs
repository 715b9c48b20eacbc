//! The viewer benchmark: drives the real [`AaLabApp`] headless (egui_kittest on the wgpu
//! renderer, as the UI tests do) and measures what a user feels, per scene, with four
//! techniques (No AA, FXAA, SMAA 1x, MSAA 4x) rendering at 1280x720 (or `--size`):
//! - **UI frame** (median, p95, worst): the wall time of one UI frame while the camera orbits
//!   and the engine renders continuously: the app's update, its panels, the upload of newly
//!   published images (egui-wgpu's texture updates) and painting the window on eframe's
//!   device until the GPU has finished it ([`WindowPainter`]: a window-sized texture stands in
//!   for the swapchain, and nothing is read back, as in the app). Painting on the GPU is what
//!   waits when the engine shares eframe's queue, so it must be in the figure. Frames run as
//!   eframe runs them: when the app asked for a repaint (its own requests, the render thread's
//!   wake-ups) or input arrives, on the refresh ticks of a 60 Hz display ([`Display`]).
//! - **engine frames per second** (frames whose outputs were published) over the first half of
//!   the run, when nothing but the camera moves, and over the second half, with the key presses;
//! - **input-to-visible latency** of a pure UI change (a layout key every 1.5 s in the second
//!   half: Single, 2x2 grid, Wipe, A/B flip; the render size is fixed, so only the UI changes):
//!   from the key event to the end of the UI frame that shows the new layout;
//! - **idle UI frame**: the same with the camera still and the engine idle.
//! - **UI thread CPU** per UI frame, orbiting and idle: the CPU time the UI thread itself spends
//!   on a frame (update, layout, tessellation, buffer uploads, submit), without the wait for
//!   the GPU; on a software adapter the window's rasteriser threads do the painting besides.
//! - **clip playback**: a 48-frame clip of the four techniques is recorded (camera panning,
//!   no reference) and played at 30 frames per second in the 2x2 grid (all four on screen,
//!   and in the magnifier) for a second, then measured over eight seconds: UI frames per
//!   second, clip frames shown per second (every clip frame the UI showed, counted once per
//!   change), clip frames skipped (a change to another frame than the next) and the UI frame's
//!   time while playing.
//!
//! `cargo bench --bench viewer -- [--seconds S] [--scenes a,b] [--size WxH] [--out file.json]`
//! (`--size 1920x1080` for the GPU target, which is stated at that size); with
//! `--features profile` it also prints where the UI frame's time goes (puffin scopes).
//! The viewer figures in `docs/gpu-figures.md` come from this benchmark.

use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use aa_lab::app::{AaLabApp, ClipPath, ClipSettings, LaunchOptions, Layout, Resolution};
use aa_lab::scene::motion::Motion;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;

/// The render size the targets on this machine are stated for.
const RENDER_SIZE: (u32, u32) = (1280, 720);
/// What the window adds around the viewport: the side panels, the menu, toolbar, magnifier
/// and status bar (a 1900x1000 window for 1280x720).
const PANELS: egui::Vec2 = egui::vec2(620.0, 280.0);
/// The UI's pace (a 60 Hz display).
const UI_PERIOD: Duration = Duration::from_micros(16_667);
/// Longest wait for the first frame.
const TIMEOUT: Duration = Duration::from_secs(600);
/// Layout keys pressed in turn while the camera orbits, with the layout each selects.
const LAYOUT_KEYS: [(egui::Key, Layout); 4] = [
    (egui::Key::G, Layout::Grid),
    (egui::Key::W, Layout::Wipe),
    (egui::Key::F, Layout::Flip),
    (egui::Key::S, Layout::Single),
];

/// Figures of one scene.
#[derive(serde::Serialize)]
struct SceneFigures {
    scene: String,
    /// The adapter eframe's device runs on (the engine's too).
    adapter: String,
    /// The render size of each technique.
    size: (u32, u32),
    seconds: f64,
    ui_frames: usize,
    ui_frames_per_second: f64,
    ui_frame_ms_median: f64,
    ui_frame_ms_p95: f64,
    ui_frame_ms_max: f64,
    /// The part of a UI frame before the paint: the app's update, layout, tessellation.
    ui_update_ms_median: f64,
    ui_update_ms_p95: f64,
    /// CPU time of the UI thread per UI frame (see [`FrameTimes::ui_thread_cpu`]).
    ui_thread_cpu_ms_median: f64,
    ui_thread_cpu_ms_p95: f64,
    engine_frames_per_second: f64,
    engine_frames_per_second_with_input: f64,
    layout_latency_ms_median: f64,
    layout_latency_ms_max: f64,
    layout_changes: usize,
    idle_ui_frame_ms_median: f64,
    idle_ui_frame_ms_p95: f64,
    idle_ui_update_ms_median: f64,
    idle_ui_update_ms_p95: f64,
    idle_ui_thread_cpu_ms_median: f64,
    idle_ui_thread_cpu_ms_p95: f64,
    clip_frames: usize,
    clip_record_seconds: f64,
    playback_ui_frames_per_second: f64,
    playback_clip_frames_per_second: f64,
    playback_skipped_clip_frames: usize,
    playback_ui_frame_ms_median: f64,
    playback_ui_frame_ms_p95: f64,
}

/// Frames of the played clip.
const CLIP_FRAMES: u32 = 48;
/// How long the clip plays.
const PLAYBACK: Duration = Duration::from_secs(8);
/// How long the clip plays in the grid before the measured playback.
const PLAYBACK_WARMUP: Duration = Duration::from_secs(1);

struct Options {
    seconds: f64,
    scenes: Vec<String>,
    size: (u32, u32),
    out: Option<String>,
}

fn options() -> Options {
    let mut options = Options {
        seconds: 30.0,
        scenes: vec!["hairball".to_owned(), "atrium".to_owned()],
        size: RENDER_SIZE,
        out: None,
    };
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--seconds" => {
                options.seconds = args
                    .next()
                    .and_then(|s| s.parse().ok())
                    .expect("--seconds takes a number");
            }
            "--scenes" => {
                options.scenes = args
                    .next()
                    .expect("--scenes takes a list")
                    .split(',')
                    .map(str::to_owned)
                    .collect();
            }
            "--size" => {
                options.size = args
                    .next()
                    .and_then(|s| {
                        let (w, h) = s.split_once('x')?;
                        Some((w.parse().ok()?, h.parse().ok()?))
                    })
                    .expect("--size takes WIDTHxHEIGHT");
            }
            "--out" => options.out = Some(args.next().expect("--out takes a path")),
            // `cargo bench` passes `--bench`; other flags are the test harness's.
            _ => {}
        }
    }
    options
}

fn percentile(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let rank = ((sorted.len() - 1) as f64 * p).round() as usize;
    sorted[rank.min(sorted.len() - 1)]
}

fn sorted(mut values: Vec<f64>) -> Vec<f64> {
    values.sort_by(f64::total_cmp);
    values
}

/// One painted UI frame, in milliseconds.
struct FrameTimes {
    /// Wall time, paint included.
    wall: f64,
    /// The part before the paint: the app's update, layout and tessellation.
    update: f64,
    /// CPU time of the UI thread over the whole frame (update, buffer uploads, submit; not the
    /// wait for the GPU, nor a software rasteriser's own threads).
    ui_thread_cpu: f64,
}

/// Each part of the frames, sorted: wall times, update parts, UI thread CPU.
fn split(timed: Vec<FrameTimes>) -> [Vec<f64>; 3] {
    let part = |f: fn(&FrameTimes) -> f64| sorted(timed.iter().map(f).collect());
    [
        part(|t| t.wall),
        part(|t| t.update),
        part(|t| t.ui_thread_cpu),
    ]
}

/// CPU time the calling thread has used so far, in milliseconds (NaN where the system does
/// not say: `/proc/thread-self/schedstat` is Linux's).
fn thread_cpu_ms() -> f64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|stat| stat.split_whitespace().next()?.parse::<f64>().ok())
        .map_or(f64::NAN, |ns| ns / 1e6)
}

/// One UI frame, painted and timed.
fn step_timed(harness: &mut Harness<'_, AaLabApp>) -> FrameTimes {
    let cpu_start = thread_cpu_ms();
    let start = Instant::now();
    harness.step();
    let update = start.elapsed().as_secs_f64() * 1000.0;
    harness.render().expect("the window paints");
    FrameTimes {
        wall: start.elapsed().as_secs_f64() * 1000.0,
        update,
        ui_thread_cpu: thread_cpu_ms() - cpu_start,
    }
}

/// Paints the UI as eframe does on a window, with a window-sized texture in place of the
/// swapchain: tessellation, egui-wgpu's buffer updates and render pass, one submit, then a wait
/// until the GPU has finished (the frame is on screen). Unlike egui_kittest's own wgpu renderer
/// it reads nothing back: that copy to the CPU, which the app never makes, cost about 8 ms of a
/// UI frame on lavapipe and 20-25 ms on an H100 (mapped readback memory of a virtual machine).
/// Texture uploads and the app's render state come from egui_kittest's renderer on the same
/// device.
struct WindowPainter {
    uploads: egui_kittest::wgpu::WgpuTestRenderer,
    state: egui_wgpu::RenderState,
    window: Option<wgpu::Texture>,
}

impl WindowPainter {
    fn new() -> Self {
        let state = egui_kittest::wgpu::create_render_state(
            aa_lab::app::wgpu_setup(),
            egui_wgpu::RendererOptions::default(),
        );
        Self {
            uploads: egui_kittest::wgpu::WgpuTestRenderer::from_render_state(state.clone()),
            state,
            window: None,
        }
    }

    fn adapter(&self) -> String {
        let info = self.state.adapter.get_info();
        format!("{} ({:?}, {})", info.name, info.backend, info.driver_info)
    }

    /// The window-sized target, recreated when the window's size changes.
    fn window(&mut self, size: [u32; 2]) -> wgpu::TextureView {
        let fits = self
            .window
            .as_ref()
            .is_some_and(|t| [t.width(), t.height()] == size);
        if !fits {
            self.window = Some(self.state.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("benchmark window"),
                size: wgpu::Extent3d {
                    width: size[0],
                    height: size[1],
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: self.state.target_format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
                view_formats: &[],
            }));
        }
        self.window
            .as_ref()
            .expect("the window target exists")
            .create_view(&wgpu::TextureViewDescriptor::default())
    }
}

impl egui_kittest::TestRenderer for WindowPainter {
    fn setup_eframe(&self, cc: &mut eframe::CreationContext<'_>, frame: &mut eframe::Frame) {
        self.uploads.setup_eframe(cc, frame);
    }

    fn handle_delta(&mut self, delta: &mut egui::TexturesDelta) {
        self.uploads.handle_delta(delta);
    }

    /// Paints the frame and waits for the GPU; returns no pixels (an empty image).
    fn render(
        &mut self,
        ctx: &egui::Context,
        output: &egui::FullOutput,
    ) -> Result<image::RgbaImage, String> {
        let pixels_per_point = ctx.pixels_per_point();
        let size = ctx.content_rect().size() * pixels_per_point;
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [size.x.round() as u32, size.y.round() as u32],
            pixels_per_point,
        };
        let view = self.window(screen.size_in_pixels);
        let triangles = ctx.tessellate(output.shapes.clone(), pixels_per_point);
        let (device, queue) = (&self.state.device, &self.state.queue);
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("benchmark window paint"),
        });
        let mut renderer = self.state.renderer.write();
        let callbacks = renderer.update_buffers(device, queue, &mut encoder, &triangles, &screen);
        {
            let mut pass = encoder
                .begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("benchmark window paint"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: &view,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                            store: wgpu::StoreOp::Store,
                        },
                        depth_slice: None,
                    })],
                    ..Default::default()
                })
                .forget_lifetime();
            renderer.render(&mut pass, &triangles, &screen);
        }
        queue.submit(
            callbacks
                .into_iter()
                .chain(std::iter::once(encoder.finish())),
        );
        device
            .poll(wgpu::PollType::Wait {
                submission_index: None,
                timeout: Some(Duration::from_secs(60)),
            })
            .map_err(|err| format!("the paint did not finish: {err}"))?;
        Ok(image::RgbaImage::new(0, 0))
    }
}

/// When the app wants its next frame, as eframe learns it: every repaint request (from the
/// UI thread or the render thread's wake-ups) moves the due time earlier.
struct RepaintClock {
    due: Arc<Mutex<Option<Instant>>>,
}

impl RepaintClock {
    fn install(ctx: &egui::Context) -> Self {
        let due = Arc::new(Mutex::new(Some(Instant::now())));
        let shared = Arc::clone(&due);
        ctx.set_request_repaint_callback(move |info| {
            let at = Instant::now() + info.delay;
            let mut due = shared.lock().expect("repaint clock");
            if due.is_none_or(|d| at < d) {
                *due = Some(at);
            }
        });
        Self { due }
    }

    fn due(&self) -> bool {
        self.due
            .lock()
            .expect("repaint clock")
            .is_some_and(|at| Instant::now() >= at)
    }

    fn clear(&self) {
        *self.due.lock().expect("repaint clock") = None;
    }
}

/// A 60 Hz display's refresh ticks on a fixed grid: eframe presents at most one frame per
/// tick, so a frame asked for between two ticks starts at the next one, and a frame slower
/// than a period misses the ticks it overlaps (as with vsync). Pacing by "a period after the
/// last frame started" instead drifts by the polling delay and ran ~58 frames per second.
struct Display {
    next_tick: Instant,
}

impl Display {
    fn new() -> Self {
        Self {
            next_tick: Instant::now(),
        }
    }

    /// Whether a refresh tick has come since the last frame began.
    fn ready(&self) -> bool {
        Instant::now() >= self.next_tick
    }

    /// Sleeps 1 ms at most (until the next tick if that is sooner), so that a repaint request
    /// or input is still seen at once.
    fn wait(&self) {
        let until_tick = self.next_tick.saturating_duration_since(Instant::now());
        let nap = Duration::from_millis(1);
        std::thread::sleep(if until_tick.is_zero() {
            nap
        } else {
            until_tick.min(nap)
        });
    }

    /// A frame begins now: the next one waits for the first tick after it.
    fn frame_begins(&mut self) {
        let now = Instant::now();
        while self.next_tick <= now {
            self.next_tick += UI_PERIOD;
        }
    }
}

fn measure(scene: &str, seconds: f64, size: (u32, u32)) -> SceneFigures {
    let owned = scene.to_owned();
    let painter = WindowPainter::new();
    let adapter = painter.adapter();
    let mut harness = Harness::builder()
        .with_size(egui::vec2(size.0 as f32, size.1 as f32) + PANELS)
        .renderer(painter)
        .build_eframe(move |cc| {
            AaLabApp::new(
                cc,
                LaunchOptions {
                    scene: Some(owned),
                    fresh_settings: true,
                    ..Default::default()
                },
            )
            .expect("the viewer starts")
        });
    {
        let app = harness.state_mut();
        app.settings_mut().resolution = Resolution::Fixed(size.0, size.1);
        app.camera_mut().playing = false;
        app.camera_mut().auto_rotate = false;
    }
    let start = Instant::now();
    while !harness.state().frame_ready() {
        assert!(start.elapsed() < TIMEOUT, "no first frame of {scene}");
        harness.step();
        std::thread::sleep(Duration::from_millis(10));
    }
    eprintln!(
        "  {scene}: first frame after {:.1} s",
        start.elapsed().as_secs_f64()
    );
    assert_eq!(harness.state().render_size(), size);
    assert_eq!(harness.state().compared().len(), 4, "four techniques");

    // Orbiting: the engine renders continuously.
    #[cfg(feature = "profile")]
    let mut profile = aa_lab::profile::UiProfile::start();
    harness.state_mut().camera_mut().auto_rotate = true;
    harness.state_mut().camera_mut().playing = true;
    let repaint = RepaintClock::install(&harness.ctx);
    let mut frames = Vec::new();
    let mut latencies = Vec::new();
    let engine_start = harness.state().engine_frames();
    let run_start = Instant::now();
    // First half: the camera orbits and nobody touches anything (the engine's throughput);
    // second half: a layout key every 1.5 s (the latency; each key costs a few UI frames).
    let half = Duration::from_secs_f64(seconds / 2.0);
    let mut next_key = run_start + half;
    let mut engine_at_half = None;
    let mut key_index = 0;
    let mut display = Display::new();
    while run_start.elapsed().as_secs_f64() < seconds {
        if engine_at_half.is_none() && run_start.elapsed() >= half {
            engine_at_half = Some(harness.state().engine_frames());
        }
        if Instant::now() >= next_key {
            // Input runs a frame at once.
            let (key, layout) = LAYOUT_KEYS[key_index % LAYOUT_KEYS.len()];
            key_index += 1;
            let pressed = Instant::now();
            harness.key_press(key);
            let mut shown = false;
            while !shown && pressed.elapsed() < Duration::from_secs(30) {
                frames.push(step_timed(&mut harness));
                shown = harness.state().settings().layout == layout;
            }
            latencies.push(pressed.elapsed().as_secs_f64() * 1000.0);
            display.frame_begins();
            next_key = Instant::now() + Duration::from_millis(1500);
        } else if repaint.due() && display.ready() {
            repaint.clear();
            display.frame_begins();
            frames.push(step_timed(&mut harness));
        } else {
            display.wait();
        }
    }
    let elapsed = run_start.elapsed().as_secs_f64();
    let engine_end = harness.state().engine_frames();
    let engine_at_half = engine_at_half.unwrap_or(engine_end);
    #[cfg(feature = "profile")]
    {
        profile.collect();
        eprintln!("{scene}, camera orbiting: {}", profile.report(30));
    }

    // Still: let the engine settle (last orbit frame, the reference), then measure.
    harness.state_mut().camera_mut().auto_rotate = false;
    harness.state_mut().camera_mut().playing = false;
    harness.state_mut().settings_mut().quality = false;
    eprintln!("  {scene}: orbit measured");
    let settle = Instant::now();
    while harness.state().rendering() || !harness.state().frame_ready() {
        assert!(
            settle.elapsed() < TIMEOUT,
            "the engine of {scene} did not settle"
        );
        harness.step();
        std::thread::sleep(Duration::from_millis(10));
    }
    let mut idle = Vec::new();
    let mut display = Display::new();
    while idle.len() < 120 {
        if display.ready() {
            display.frame_begins();
            idle.push(step_timed(&mut harness));
        } else {
            display.wait();
        }
    }

    // A clip: recorded once, then played at 30 frames per second.
    let mut clip = ClipSettings {
        frames: CLIP_FRAMES,
        warmup: 4,
        path: ClipPath::Motion(Motion::Pan),
        reference: false,
        ..ClipSettings::default()
    };
    // The memory cap is the user's to raise; 1920x1080 needs more than the default.
    let needed_mib = clip.bytes(4, size).div_ceil(1 << 20);
    clip.budget_mib = clip.budget_mib.max(needed_mib as u32);
    harness.state_mut().settings_mut().clip = clip;
    eprintln!("  {scene}: idle UI measured");
    let recording = Instant::now();
    harness.get_by_label("Record").click();
    // Input runs frames at once, as in eframe (on a GPU the settled app asks for none).
    while harness.state().clip_progress().is_none() {
        assert!(
            recording.elapsed() < Duration::from_secs(10),
            "the Record click did not start a clip of {scene}"
        );
        harness.step();
        std::thread::sleep(Duration::from_millis(1));
    }
    while harness.state().clip_progress() != Some((CLIP_FRAMES as usize, false)) {
        assert!(
            recording.elapsed() < TIMEOUT,
            "the clip of {scene} was not recorded"
        );
        // Painted when the app asks, as eframe paints while the progress bar moves: each
        // paint's submit also carries the recorded frames' uploads to the display device,
        // which otherwise all wait for the first paint after the recording (~1 s on lavapipe).
        if repaint.due() {
            repaint.clear();
            harness.step();
            harness.render().expect("the window paints");
        } else {
            std::thread::sleep(Duration::from_millis(1));
        }
    }
    let clip_record_seconds = recording.elapsed().as_secs_f64();
    eprintln!("  {scene}: clip recorded in {clip_record_seconds:.1} s");
    harness.state_mut().settings_mut().layout = Layout::Grid;
    // The switch to the grid is a layout change, timed above, not playback.
    let switched = Instant::now();
    while switched.elapsed() < PLAYBACK_WARMUP {
        harness.step();
        harness.render().expect("the window paints");
    }
    #[cfg(feature = "profile")]
    let mut profile = aa_lab::profile::UiProfile::start();
    let mut playback = Vec::new();
    let mut shown_frames = 0usize;
    let mut skipped = 0usize;
    let mut shown = harness.state().shown_clip_frame();
    let start = Instant::now();
    let mut display = Display::new();
    while start.elapsed() < PLAYBACK {
        if repaint.due() && display.ready() {
            repaint.clear();
            display.frame_begins();
            playback.push(step_timed(&mut harness));
            let now_shown = harness.state().shown_clip_frame();
            if now_shown != shown {
                shown_frames += 1;
                if let (Some(before), Some(now)) = (shown, now_shown) {
                    skipped += (now + CLIP_FRAMES as usize - before - 1) % CLIP_FRAMES as usize;
                }
                shown = now_shown;
            }
        } else {
            std::thread::sleep(Duration::from_millis(1));
        }
    }
    let playing = start.elapsed().as_secs_f64();
    #[cfg(feature = "profile")]
    {
        profile.collect();
        eprintln!("{scene}, clip playing: {}", profile.report(30));
    }
    let playback_ui_frames_per_second = playback.len() as f64 / playing;
    let [playback, _, _] = split(playback);

    let [frames, updates, ui_thread_cpu] = split(frames);
    let [idle, idle_updates, idle_ui_thread_cpu] = split(idle);
    let latencies = sorted(latencies);
    SceneFigures {
        scene: scene.to_owned(),
        adapter,
        size,
        seconds: elapsed,
        ui_frames: frames.len(),
        ui_frames_per_second: frames.len() as f64 / elapsed,
        ui_frame_ms_median: percentile(&frames, 0.5),
        ui_frame_ms_p95: percentile(&frames, 0.95),
        ui_frame_ms_max: frames.last().copied().unwrap_or(f64::NAN),
        ui_update_ms_median: percentile(&updates, 0.5),
        ui_update_ms_p95: percentile(&updates, 0.95),
        ui_thread_cpu_ms_median: percentile(&ui_thread_cpu, 0.5),
        ui_thread_cpu_ms_p95: percentile(&ui_thread_cpu, 0.95),
        engine_frames_per_second: (engine_at_half - engine_start) as f64 / half.as_secs_f64(),
        engine_frames_per_second_with_input: (engine_end - engine_at_half) as f64
            / (elapsed - half.as_secs_f64()),
        layout_latency_ms_median: percentile(&latencies, 0.5),
        layout_latency_ms_max: latencies.last().copied().unwrap_or(f64::NAN),
        layout_changes: latencies.len(),
        idle_ui_frame_ms_median: percentile(&idle, 0.5),
        idle_ui_frame_ms_p95: percentile(&idle, 0.95),
        idle_ui_update_ms_median: percentile(&idle_updates, 0.5),
        idle_ui_update_ms_p95: percentile(&idle_updates, 0.95),
        idle_ui_thread_cpu_ms_median: percentile(&idle_ui_thread_cpu, 0.5),
        idle_ui_thread_cpu_ms_p95: percentile(&idle_ui_thread_cpu, 0.95),
        clip_frames: CLIP_FRAMES as usize,
        clip_record_seconds,
        playback_ui_frames_per_second,
        playback_clip_frames_per_second: shown_frames as f64 / playing,
        playback_skipped_clip_frames: skipped,
        playback_ui_frame_ms_median: percentile(&playback, 0.5),
        playback_ui_frame_ms_p95: percentile(&playback, 0.95),
    }
}

fn main() {
    let options = options();
    let mut all = Vec::new();
    for scene in &options.scenes {
        eprintln!(
            "viewer benchmark: {scene} at {}x{}, {} s…",
            options.size.0, options.size.1, options.seconds
        );
        let figures = measure(scene, options.seconds, options.size);
        eprintln!("on {}", figures.adapter);
        println!(
            "{:<10} {:>5.1} UI frames/s, median {:>6.1} ms  p95 {:>6.1} ms  max {:>7.1} ms | engine {:>5.2} frames/s ({:.2} with input) | \
             layout change visible after median {:>6.1} ms, worst {:>6.1} ms ({} changes) | idle UI frame median {:>5.1} ms p95 {:>5.1} ms | update (before the paint) median {:>5.1} ms p95 {:>5.1} ms, idle {:>5.1} ms p95 {:>5.1} ms | UI thread CPU per frame median {:>5.1} ms p95 {:>5.1} ms, idle {:>5.1} ms p95 {:>5.1} ms | clip of {} frames recorded in {:.0} s, plays at {:.1} UI frames/s showing {:.1} clip frames/s ({} skipped), UI frame median {:.1} ms p95 {:.1} ms",
            figures.scene,
            figures.ui_frames_per_second,
            figures.ui_frame_ms_median,
            figures.ui_frame_ms_p95,
            figures.ui_frame_ms_max,
            figures.engine_frames_per_second,
            figures.engine_frames_per_second_with_input,
            figures.layout_latency_ms_median,
            figures.layout_latency_ms_max,
            figures.layout_changes,
            figures.idle_ui_frame_ms_median,
            figures.idle_ui_frame_ms_p95,
            figures.ui_update_ms_median,
            figures.ui_update_ms_p95,
            figures.idle_ui_update_ms_median,
            figures.idle_ui_update_ms_p95,
            figures.ui_thread_cpu_ms_median,
            figures.ui_thread_cpu_ms_p95,
            figures.idle_ui_thread_cpu_ms_median,
            figures.idle_ui_thread_cpu_ms_p95,
            figures.clip_frames,
            figures.clip_record_seconds,
            figures.playback_ui_frames_per_second,
            figures.playback_clip_frames_per_second,
            figures.playback_skipped_clip_frames,
            figures.playback_ui_frame_ms_median,
            figures.playback_ui_frame_ms_p95,
        );
        all.push(figures);
    }
    if let Some(out) = &options.out {
        let json = serde_json::to_string_pretty(&all).expect("figures serialise");
        std::fs::write(out, json + "\n").expect("the figures file is writable");
        eprintln!("wrote {out}");
    }
}
