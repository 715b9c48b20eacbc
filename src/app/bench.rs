//! The viewer's bench: `aa-lab bench`'s measurement ([`crate::bench::BenchRunner`]) of the
//! compared techniques, with their current settings, on the loaded scene at the viewport's
//! render size, seen from the viewer's camera; its report (`report.json`, `report.md`, charts,
//! the run's sidecars) goes to a folder of its own in the export folder, and its figures show
//! in the metrics panel.
//!
//! The bench runs on a thread with a device of its own, so the window stays responsive. The
//! thread keeps the normal CPU priority, unlike the viewer's other background threads
//! ([`super::worker::lower_priority`]): in the idle class a bench would not advance at all
//! while other programs keep the cores busy. While it runs the live view renders nothing new (the app asks
//! [`BenchFeature::running`] before it submits a frame), so the engine's frames do not share
//! the GPU with the frames being timed. Progress and a Cancel button show in the panel; a
//! cancelled bench writes nothing.
//!
//! The feature owns its state and draws its own section; what it needs of the rest of the
//! viewer comes in a [`BenchRequest`], and what it has to say goes back as notices.

use std::path::PathBuf;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, mpsc};
use std::time::Instant;

use super::context::Level;
use super::style::{self, number};
use crate::bench::{
    BenchError, BenchOptions, BenchProgress, BenchRunner, DEFAULT_FLICKER_FRAMES,
    DEFAULT_QUALITY_FRAME, DEFAULT_WARMUP, RunPlan, reference_spec, write_report,
};
use crate::export::report::{self, BenchReport};
use crate::files::Overwrite;
use crate::gpu::Gpu;
use crate::graph::overlay::OverlayOrder;
use crate::scene::CameraRig;
use crate::scene::procedural::SceneOptions;
use crate::spec::{self, TechniqueSpec};

/// Timed frames a viewer bench offers by default (the command line's default is 60).
const DEFAULT_FRAMES: u32 = 30;
/// Most timed frames the viewer offers.
const MAX_FRAMES: u32 = 600;

/// What a bench measures, from the rest of the viewer.
pub(super) struct BenchRequest {
    /// The scene as loaded (built-in name or model path).
    pub scene: String,
    /// The camera the timing track starts from (the viewer's).
    pub rig: CameraRig,
    /// The render size.
    pub size: (u32, u32),
    /// The compared techniques, with their settings.
    pub techniques: Vec<TechniqueSpec>,
    /// The export folder (the report goes to a new folder inside it).
    pub export_dir: PathBuf,
    /// The UI overlay of the viewer's settings.
    pub overlay: Option<OverlayOrder>,
    /// Whether the viewer's scene renders have specular antialiasing.
    pub specular_aa: bool,
    /// The viewer's tonemap choice and exposure.
    pub tonemap: crate::graph::hdr::TonemapChoice,
    /// Exposure of HDR renders in stops.
    pub exposure: f32,
}

/// One technique's row of the panel's table.
struct Row {
    name: String,
    total_ms: f64,
    ssim: Option<f64>,
    flip: Option<f64>,
    flicker: Option<f64>,
}

/// A finished bench: where its report went and the figures the panel shows.
struct Finished {
    folder: PathBuf,
    adapter: String,
    rows: Vec<Row>,
}

/// How a bench ended, as its thread says.
enum Message {
    /// The report is written.
    Finished(Finished),
    /// Cancel was pressed; nothing was written.
    Cancelled,
    /// The bench failed.
    Failed(String),
}

/// What the bench thread shares with the UI: steps done, the phase, the Cancel button, and
/// the UI's context to wake it at a new phase.
struct SharedProgress {
    steps: AtomicU64,
    phase: Mutex<String>,
    cancel: AtomicBool,
    ctx: egui::Context,
}

impl BenchProgress for SharedProgress {
    fn phase(&self, _run: &RunPlan, phase: &str) {
        if let Ok(mut shown) = self.phase.lock() {
            phase.clone_into(&mut shown);
        }
        super::repaint::request_one_frame(&self.ctx);
    }

    fn advance(&self, steps: u64) {
        self.steps.fetch_add(steps, Ordering::Relaxed);
    }

    fn cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }
}

/// What the bench thread is given.
struct Job {
    request: BenchRequest,
    options: BenchOptions,
    progress: Arc<SharedProgress>,
}

/// A running bench, as the UI follows it.
struct Running {
    progress: Arc<SharedProgress>,
    total_steps: u64,
    started: Instant,
    outcome: mpsc::Receiver<Message>,
}

/// The bench section of the metrics panel: its settings, the running bench and the last
/// result (see the module docs).
pub(super) struct BenchFeature {
    frames: u32,
    running: Option<Running>,
    last: Option<Finished>,
}

impl Default for BenchFeature {
    fn default() -> Self {
        Self {
            frames: DEFAULT_FRAMES,
            running: None,
            last: None,
        }
    }
}

impl BenchFeature {
    /// Whether a bench runs (the live view waits meanwhile).
    pub(super) fn running(&self) -> bool {
        self.running.is_some()
    }

    /// Picks up a finished bench; returns what to tell the user.
    pub(super) fn poll(&mut self) -> Option<(Level, String)> {
        let outcome = match self.running.as_ref()?.outcome.try_recv() {
            Ok(message) => message,
            Err(mpsc::TryRecvError::Empty) => return None,
            Err(mpsc::TryRecvError::Disconnected) => {
                Message::Failed("the bench thread ended without a result".to_owned())
            }
        };
        self.running = None;
        Some(match outcome {
            Message::Finished(finished) => {
                let text = format!("Bench report written to {}", finished.folder.display());
                self.last = Some(finished);
                (Level::Info, text)
            }
            Message::Cancelled => (Level::Info, "Bench cancelled; nothing written.".to_owned()),
            Message::Failed(err) => (Level::Error, format!("Bench: {err}")),
        })
    }

    /// Draws the section: the frames to time, Run or the progress with Cancel, and the last
    /// result. `request` builds what to measure when Run is pressed (or says why it cannot).
    pub(super) fn ui(
        &mut self,
        ui: &mut egui::Ui,
        request: impl FnOnce() -> Result<BenchRequest, String>,
    ) -> Option<(Level, String)> {
        style::section(ui, "Bench");
        let mut notice = None;
        if let Some(running) = &self.running {
            let done = running.progress.steps.load(Ordering::Relaxed);
            let fraction = done as f32 / running.total_steps.max(1) as f32;
            let phase = running
                .progress
                .phase
                .lock()
                .map(|p| p.clone())
                .unwrap_or_default();
            let text = format!("{phase} ({:.0} s)", running.started.elapsed().as_secs_f64());
            let cancelling = running.progress.cancel.load(Ordering::Relaxed);
            // The bar and Cancel on one row, so Cancel stays in view under the figures.
            ui.horizontal(|ui| {
                let bar_width = (ui.available_width() - 70.0).max(80.0);
                ui.add(
                    egui::ProgressBar::new(fraction.min(1.0))
                        .desired_width(bar_width)
                        .text(text),
                );
                let cancel = egui::Id::unique("bench: cancel");
                if style::keyed(ui, cancel, |ui| {
                    ui.add_enabled(!cancelling, egui::Button::new("Cancel"))
                })
                .on_hover_text(
                    "Stop the bench after the frame it is rendering; nothing is written.",
                )
                .clicked()
                {
                    running.progress.cancel.store(true, Ordering::Relaxed);
                }
            });
            ui.ctx()
                .request_repaint_after(std::time::Duration::from_millis(250));
        } else {
            ui.horizontal(|ui| {
                ui.add(
                    egui::DragValue::new(&mut self.frames)
                        .range(1..=MAX_FRAMES)
                        .suffix(" frames"),
                )
                .on_hover_text(format!("Timed frames (after {DEFAULT_WARMUP} warm-up frames), as `aa-lab bench --frames`."));
                // Keyed: the figures above it change with every frame.
                if style::keyed(ui, egui::Id::unique("bench: run"), |ui| ui.button("Run bench"))
                    .on_hover_text(format!("Measure the compared techniques as `aa-lab bench` does: GPU time per pass over the timed frames along a slow camera track from this view, memory, quality of frame {DEFAULT_QUALITY_FRAME} against the 64-sample reference, flicker. The live view pauses meanwhile; the report goes to a new folder in the export folder."))
                    .clicked()
                {
                    notice = match request() {
                        Ok(request) => self.start(ui.ctx(), request).err(),
                        Err(reason) => Some(reason),
                    }
                    .map(|reason| (Level::Warning, reason));
                }
            });
        }
        if let Some(last) = &self.last {
            last.ui(ui);
        }
        notice
    }

    /// Starts a bench of `request` on a thread of its own.
    fn start(&mut self, ctx: &egui::Context, request: BenchRequest) -> Result<(), String> {
        let options = BenchOptions {
            warmup: DEFAULT_WARMUP,
            frames: self.frames,
            flicker_frames: DEFAULT_FLICKER_FRAMES,
            quality_frame: DEFAULT_QUALITY_FRAME,
            quality: true,
            seed: SceneOptions::default().seed,
            specular_aa: request.specular_aa,
            tonemap: request.tonemap,
            exposure: request.exposure,
            images: None,
            overlay: request.overlay,
        };
        let progress = Arc::new(SharedProgress {
            steps: AtomicU64::new(0),
            phase: Mutex::new(String::new()),
            cancel: AtomicBool::new(false),
            ctx: ctx.clone(),
        });
        let (send, outcome) = mpsc::channel();
        let running = Running {
            progress: Arc::clone(&progress),
            total_steps: options.steps_per_run(),
            started: Instant::now(),
            outcome,
        };
        let job = Job {
            request,
            options,
            progress,
        };
        let ctx = ctx.clone();
        std::thread::Builder::new()
            .name("bench".to_owned())
            .spawn(move || {
                let _ = send.send(run_job(&job));
                super::repaint::request_one_frame(&ctx);
            })
            .map_err(|err| format!("cannot start the bench thread: {err}"))?;
        self.running = Some(running);
        Ok(())
    }
}

impl Finished {
    /// The figures of the last bench, and where its report is.
    fn ui(&self, ui: &mut egui::Ui) {
        let ssim_tip = format!(
            "Structural similarity of frame {DEFAULT_QUALITY_FRAME} to the 64-sample reference (1 = identical)."
        );
        let flip_tip = format!(
            "NVIDIA FLIP error of frame {DEFAULT_QUALITY_FRAME} against the reference (0 = identical)."
        );
        style::figures_table(
            ui,
            "bench table",
            &[
                ("technique", None),
                (
                    "GPU ms",
                    Some(
                        "Median GPU time per frame: the technique's passes and the scene render it reads.",
                    ),
                ),
                ("SSIM", Some(ssim_tip.as_str())),
                ("FLIP", Some(flip_tip.as_str())),
                (
                    "flicker",
                    Some(
                        "Frame-to-frame change over the reference's on the last timed frames (1 = as steady as the reference).",
                    ),
                ),
            ],
            |ui| {
                let figure = |v: Option<f64>, digits: usize| {
                    v.map_or_else(|| "n/a".to_owned(), |v| format!("{v:.digits$}"))
                };
                for row in &self.rows {
                    ui.label(&row.name);
                    number(
                        ui,
                        format!("{:.3}", row.total_ms),
                        "median over the timed frames",
                    );
                    number(ui, figure(row.ssim, 4), "against the reference");
                    number(ui, figure(row.flip, 4), "against the reference");
                    number(ui, figure(row.flicker, 2), "over the reference's change");
                    ui.end_row();
                }
            },
        );
        ui.weak(format!("on {}; report in", self.adapter));
        ui.add(
            egui::Label::new(egui::RichText::new(self.folder.display().to_string()).monospace())
                .selectable(true),
        );
    }
}

/// The bench thread's work: runs the bench, writes its report and says how it ended.
fn run_job(job: &Job) -> Message {
    match bench(job) {
        Ok(finished) => Message::Finished(finished),
        Err(ViewerBenchError::Bench(BenchError::Cancelled)) => Message::Cancelled,
        Err(err) => Message::Failed(err.to_string()),
    }
}

/// Errors of a viewer bench.
#[derive(Debug, thiserror::Error)]
enum ViewerBenchError {
    #[error(transparent)]
    Gpu(#[from] crate::gpu::GpuError),
    #[error("{0} has no timestamp queries, so GPU time per pass cannot be measured")]
    NoTimestamps(String),
    #[error(transparent)]
    Technique(#[from] crate::aa::TechniqueError),
    #[error(transparent)]
    Scene(#[from] crate::scene::source::SceneError),
    #[error(transparent)]
    Bench(#[from] BenchError),
    #[error(transparent)]
    Export(#[from] crate::export::ExportError),
    #[error(transparent)]
    Chart(#[from] crate::export::charts::ChartError),
    #[error("cannot create {0}: {1}")]
    Folder(PathBuf, std::io::Error),
}

/// Measures the job's one run on a device of the worker's own, then writes the report into
/// a new folder `bench-<scene>-<W>x<H>[-N]` of the export folder.
fn bench(job: &Job) -> Result<Finished, ViewerBenchError> {
    let started = Instant::now();
    let started_unix = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let request = &job.request;
    let gpu = Gpu::headless()?;
    if !gpu.caps.timestamps {
        return Err(ViewerBenchError::NoTimestamps(
            gpu.caps.adapter_name.clone(),
        ));
    }
    let run = RunPlan {
        scene: request.scene.clone(),
        density: 1.0,
        size: request.size,
    };
    job.progress.phase(&run, "loading the scene");
    let mut scene = crate::scene::source::load(&request.scene, &SceneOptions::default())?;
    scene.camera = request.rig;
    let runner = BenchRunner {
        gpu: &gpu,
        options: job.options.clone(),
        techniques: request.techniques.clone(),
        reference: reference_spec(&gpu)?,
        progress: job.progress.as_ref(),
    };
    let (mut spec, mut reference) = runner.specs(&run);
    spec.rig = Some(request.rig);
    reference.rig = Some(request.rig);
    let report = runner.run(&run, &scene, spec, reference)?;

    let stem = crate::files::free_stem(
        &request.export_dir,
        &format!("bench-{}-{}x{}", report.scene, run.size.0, run.size.1),
        &[String::new()],
    );
    let folder = request.export_dir.join(stem);
    std::fs::create_dir_all(&folder)
        .map_err(|err| ViewerBenchError::Folder(folder.clone(), err))?;
    let policy = Overwrite::new(false);
    report.write_sidecars(&folder, &policy)?;
    let rows = report
        .techniques
        .iter()
        .map(|t| Row {
            name: t.name.clone(),
            total_ms: t.total_ms.median,
            ssim: t.quality.map(|q| q.ssim),
            flip: t.quality.map(|q| q.flip),
            flicker: t.flicker_ratio,
        })
        .collect();
    let ids = request.techniques.iter().map(|t| t.id.clone()).collect();
    let bench_report = BenchReport {
        schema: report::SCHEMA,
        build: spec::build_id(),
        adapter: gpu.caps.clone(),
        command: format!(
            "aa-lab viewer: bench of the compared techniques ({} timed frames; each run's settings and camera are in its .spec.json)",
            job.options.frames
        ),
        started_unix,
        wall_seconds: started.elapsed().as_secs_f64(),
        settings: runner.settings(ids, None),
        runs: vec![report],
    };
    write_report(&bench_report, &folder, &policy)?;
    Ok(Finished {
        folder,
        adapter: format!("{} ({})", gpu.caps.adapter_name, gpu.caps.backend),
        rows,
    })
}
