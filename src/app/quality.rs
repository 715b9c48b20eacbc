//! Live quality figures: SSIM, PSNR and MAE, and FLIP, of every enabled technique against the
//! progressive reference, for the metrics panel and the magnifier's captions.
//!
//! **What is measured.** The published images (the very bytes on screen): a technique's
//! output and the reference of the same view. SSIM, PSNR and MAE run in the metrics library's
//! compute shaders ([`GpuMetrics`]) on a device of their own on the engine's adapter, so that
//! they neither wait for nor delay the frames on the engine's queue (on the CPU path of the
//! library if that device cannot be created). FLIP runs on the CPU ([`flip::flip_map`]); it
//! takes most of a second per technique at 1280x720 on a small machine, so it has its own
//! worker and a slower pace.
//!
//! **When.** Both run on background [`Worker`]s, one job at a time, from the newest images:
//! at once when a technique has no valid figures yet or the reference has just converged;
//! otherwise (the reference gained samples, a temporal technique's image moved on) after a
//! pause at least as long as the last measurement took, so measuring never takes more than
//! about half of the machine. FLIP on a reference that is still accumulating waits until the
//! camera has been still for a moment, and always runs once the reference has converged.
//!
//! **Stale figures.** Every measurement remembers the stamps of the images it compared. It
//! is shown only while the view it was measured at is still the view being rendered and the
//! technique's settings are unchanged; otherwise the panel says that the figures are stale
//! (the camera moved, the settings changed) or being measured, never an old number.
//!
//! The figures ([`QualityTracker`]) are a feature of the workspace: the metrics panel, the
//! magnifier's captions, export sheets and the test API read them through it;
//! [`QualityTracker::update`] runs once per UI frame, before the panels, on what the context
//! shows.

use std::collections::BTreeMap;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use super::context::{Context, Level};
use super::engine::ImageStamp;
use super::render_thread::open_device;
use super::worker::{Reporter, Worker};
use crate::aa::ssaa::Progress;
use crate::gpu::Gpu;
use crate::metrics::gpu::{GpuMetrics, upload_image};
use crate::metrics::{flip, pixel, ssim};

/// Least pause between two SSIM/PSNR/MAE measurements that only refresh valid figures.
const PIXEL_PAUSE: Duration = Duration::from_millis(250);
/// Least pause between two FLIP measurements that only refresh valid figures.
const FLIP_PAUSE: Duration = Duration::from_secs(2);
/// How long the reference must have accumulated before FLIP runs on an unfinished one.
const FLIP_DELAY: Duration = Duration::from_millis(1500);

/// SSIM, PSNR and MAE of one image against the reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelFigures {
    /// Mean SSIM of luma, 1 = identical.
    pub ssim: f64,
    /// PSNR in dB (infinite for identical images).
    pub psnr: f64,
    /// Mean absolute error, 0..255.
    pub mae: f64,
}

/// One measurement of one technique's image.
#[derive(Clone, Debug)]
pub struct Measured<T> {
    /// The figures, or why there are none.
    pub value: Result<T, String>,
    /// The technique image it measured.
    pub stamp: ImageStamp,
    /// Serial of the reference image it measured against.
    pub reference_serial: u64,
    /// How far that reference had accumulated.
    pub reference: Progress,
    /// How long the measurement took, milliseconds.
    pub ms: f64,
    /// Where it ran ("GPU" or "CPU").
    pub on: &'static str,
}

/// The current quality figures of one technique (see [`QualityTracker::figures`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Figures {
    /// SSIM, PSNR and MAE.
    pub pixels: PixelFigures,
    /// Reference samples per pixel those rest on.
    pub reference_samples: u32,
    /// Mean FLIP error and the reference samples it rests on, once measured for this view.
    pub flip: Option<(f64, u32)>,
}

/// A measurement to make: technique images against one reference.
struct Job {
    view: u64,
    reference: Arc<image::RgbaImage>,
    reference_serial: u64,
    progress: Progress,
    tests: Vec<(&'static str, ImageStamp, Arc<image::RgbaImage>)>,
}

impl Job {
    /// Measures each technique in turn with `measure`, reporting each; stops early when the
    /// view changes (the figures would be stale anyway).
    fn run<T>(
        &self,
        current_view: &AtomicU64,
        reporter: &Reporter<(&'static str, Measured<T>)>,
        mut measure: impl FnMut(&image::RgbaImage) -> (Result<T, String>, &'static str),
    ) {
        for (id, stamp, test) in &self.tests {
            if current_view.load(Ordering::Relaxed) != self.view {
                return;
            }
            let start = Instant::now();
            let (value, on) = if test.dimensions() == self.reference.dimensions() {
                measure(test)
            } else {
                (
                    Err("the image and the reference differ in size".to_owned()),
                    "",
                )
            };
            reporter.send((
                id,
                Measured {
                    value,
                    stamp: *stamp,
                    reference_serial: self.reference_serial,
                    reference: self.progress,
                    ms: start.elapsed().as_secs_f64() * 1e3,
                    on,
                },
            ));
        }
    }
}

type QualityWorker<T> = Worker<Job, (&'static str, Measured<T>)>;

/// SSIM, PSNR and MAE with the CPU reference implementations.
fn pixel_figures_cpu(
    reference: &image::RgbaImage,
    test: &image::RgbaImage,
) -> Result<PixelFigures, String> {
    let ssim = ssim::ssim(reference, test).map_err(|e| e.to_string())?;
    let errors = pixel::error_maps(reference, test)
        .map_err(|e| e.to_string())?
        .pool(None);
    Ok(PixelFigures {
        ssim: ssim.mean,
        psnr: errors.psnr(),
        mae: errors.mae,
    })
}

/// SSIM, PSNR and MAE in compute shaders.
fn pixel_figures_gpu(
    gpu: &Gpu,
    metrics: &mut GpuMetrics,
    reference: &wgpu::Texture,
    test: &image::RgbaImage,
) -> Result<PixelFigures, String> {
    let test = upload_image(gpu, test, "quality test image").map_err(|e| e.to_string())?;
    let scores = metrics
        .compare(gpu, reference, &test)
        .map_err(|e| e.to_string())?;
    Ok(PixelFigures {
        ssim: scores.ssim,
        psnr: scores.psnr(),
        mae: scores.mae,
    })
}

/// The worker measuring SSIM, PSNR and MAE; it opens its device on the first job.
fn spawn_pixel_worker(
    ctx: &egui::Context,
    adapter: wgpu::Adapter,
    current_view: Arc<AtomicU64>,
) -> std::io::Result<QualityWorker<PixelFigures>> {
    let mut device: Option<Option<(Gpu, GpuMetrics)>> = None;
    Worker::spawn("aa-lab quality figures", ctx, move |job: Job, reporter| {
        let opened = device.get_or_insert_with(|| match open_device(&adapter) {
            Ok(gpu) => {
                let metrics = GpuMetrics::new(&gpu);
                Some((gpu, metrics))
            }
            Err(err) => {
                log::warn!("quality figures on the CPU: {err}");
                None
            }
        });
        let uploaded = match opened {
            Some((gpu, metrics)) => match upload_image(gpu, &job.reference, "quality reference") {
                Ok(reference) => Some((gpu, metrics, reference)),
                Err(err) => {
                    log::warn!("quality figures on the CPU: {err}");
                    None
                }
            },
            None => None,
        };
        match uploaded {
            Some((gpu, metrics, reference)) => job.run(&current_view, reporter, |test| {
                (pixel_figures_gpu(gpu, metrics, &reference, test), "GPU")
            }),
            None => job.run(&current_view, reporter, |test| {
                (pixel_figures_cpu(&job.reference, test), "CPU")
            }),
        }
    })
}

/// The worker measuring FLIP.
fn spawn_flip_worker(
    ctx: &egui::Context,
    current_view: Arc<AtomicU64>,
) -> std::io::Result<QualityWorker<f64>> {
    Worker::spawn("aa-lab FLIP", ctx, move |job: Job, reporter| {
        job.run(&current_view, reporter, |test| {
            let mean = flip::flip_map(&job.reference, test)
                .map(|map| map.mean(None).unwrap_or(0.0))
                .map_err(|e| e.to_string());
            (mean, "CPU")
        });
    })
}

/// How much a technique needs measuring.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Need {
    /// Its figures describe exactly these images.
    Nothing,
    /// Its figures are valid but the images moved on (more reference samples, a new frame of a
    /// temporal technique): measure when the worker has rested.
    Refresh,
    /// Measure as soon as the worker is free.
    Urgent,
}

/// Whether a measurement of `stored` is still valid for a technique image stamped `test`.
fn valid_for<T>(stored: &Measured<T>, view: u64, revision: u64) -> bool {
    stored.stamp.view == view && stored.stamp.revision == revision
}

/// What a technique with `stored` figures needs, given its image and the reference; `eager`
/// says whether missing figures are urgent even before the reference has converged.
fn need<T>(
    stored: Option<&Measured<T>>,
    test: ImageStamp,
    reference_serial: u64,
    progress: Progress,
    eager: bool,
) -> Need {
    match stored {
        Some(m) if m.stamp.serial == test.serial && m.reference_serial == reference_serial => {
            Need::Nothing
        }
        Some(m)
            if valid_for(m, test.view, test.revision)
                && (!progress.complete() || m.reference.samples >= progress.total) =>
        {
            Need::Refresh
        }
        _ if eager || progress.complete() => Need::Urgent,
        _ => Need::Refresh,
    }
}

/// The measurements of the techniques, the workers making them and their pacing.
#[derive(Default)]
pub struct QualityTracker {
    pixels: BTreeMap<&'static str, Measured<PixelFigures>>,
    flip: BTreeMap<&'static str, Measured<f64>>,
    pixel_worker: Option<QualityWorker<PixelFigures>>,
    flip_worker: Option<QualityWorker<f64>>,
    /// The engine's current view, shared with the workers (they stop stale jobs).
    current_view: Arc<AtomicU64>,
    /// The view of the reference last seen, and when it was first seen.
    reference_view: Option<(u64, Instant)>,
    /// A measurement is due but waits for a worker to rest.
    deferred: bool,
    /// The workers could not be started.
    failed: bool,
}

impl QualityTracker {
    /// Forgets every figure (new scene).
    pub fn clear(&mut self) {
        self.pixels.clear();
        self.flip.clear();
    }

    /// A measurement is running or waiting for its turn (the UI keeps polling).
    pub fn waiting(&self) -> bool {
        self.deferred
            || self.pixel_worker.as_ref().is_some_and(Worker::busy)
            || self.flip_worker.as_ref().is_some_and(Worker::busy)
    }

    /// The SSIM, PSNR and MAE measurement of a technique (or image) if it is valid for what
    /// is on screen now: `key` is the view and settings revision it must have been made at
    /// (`Context::measure_key`).
    pub fn current_pixels(
        &self,
        id: &str,
        key: Option<(u64, u64)>,
    ) -> Option<&Measured<PixelFigures>> {
        current(self.pixels.get(id), key)
    }

    /// The FLIP measurement of a technique (or image) if it is valid for what is on screen
    /// now (`key` as for [`QualityTracker::current_pixels`]).
    pub fn current_flip(&self, id: &str, key: Option<(u64, u64)>) -> Option<&Measured<f64>> {
        current(self.flip.get(id), key)
    }

    /// Takes the workers' results.
    fn collect(&mut self) {
        if let Some(worker) = &mut self.pixel_worker {
            self.pixels.extend(worker.poll());
        }
        if let Some(worker) = &mut self.flip_worker {
            self.flip.extend(worker.poll());
        }
    }

    fn start_workers(
        &mut self,
        ctx: &egui::Context,
        adapter: &wgpu::Adapter,
    ) -> Result<(), String> {
        if self.pixel_worker.is_none() {
            let view = Arc::clone(&self.current_view);
            self.pixel_worker =
                Some(spawn_pixel_worker(ctx, adapter.clone(), view).map_err(|e| e.to_string())?);
        }
        if self.flip_worker.is_none() {
            let view = Arc::clone(&self.current_view);
            self.flip_worker = Some(spawn_flip_worker(ctx, view).map_err(|e| e.to_string())?);
        }
        Ok(())
    }
}

/// `stored` if it was measured at `key` (view, settings revision).
fn current<T>(stored: Option<&Measured<T>>, key: Option<(u64, u64)>) -> Option<&Measured<T>> {
    let (view, revision) = key?;
    stored.filter(|m| valid_for(m, view, revision))
}

/// Hands a job for the techniques that need it to `worker`, respecting its pace; returns
/// whether a measurement is due but was deferred.
#[allow(clippy::too_many_arguments)]
fn schedule<T: Send + 'static>(
    worker: Option<&mut QualityWorker<T>>,
    stored: &BTreeMap<&'static str, Measured<T>>,
    tests: &[(&'static str, ImageStamp, Arc<image::RgbaImage>)],
    reference: (&Arc<image::RgbaImage>, u64, Progress),
    view: u64,
    eager: bool,
    pause: Duration,
    may_refresh: bool,
) -> bool {
    let Some(worker) = worker else { return false };
    let (reference, reference_serial, progress) = reference;
    let mut most = Need::Nothing;
    let mut due = Vec::new();
    for (id, stamp, image) in tests {
        let need = need(stored.get(id), *stamp, reference_serial, progress, eager);
        if need != Need::Nothing {
            most = most.max(need);
            due.push((*id, *stamp, Arc::clone(image)));
        }
    }
    let go = match most {
        Need::Nothing => return false,
        Need::Urgent => !worker.busy(),
        Need::Refresh => may_refresh && worker.rested(pause),
    };
    if go {
        worker.submit(Job {
            view,
            reference: Arc::clone(reference),
            reference_serial,
            progress,
            tests: due,
        });
        false
    } else {
        true
    }
}

impl QualityTracker {
    /// Takes finished measurements and starts the next ones (see the module docs).
    pub(super) fn update(&mut self, cx: &mut Context, ctx: &egui::Context) {
        profiling::function_scope!();
        self.collect();
        self.deferred = false;
        // The engine's view, or the open image set's.
        let Some(view) = cx.current_view() else {
            return;
        };
        self.current_view.store(view, Ordering::Relaxed);
        if !cx.settings.quality || self.failed {
            return;
        }
        // A playing clip or sequence set changes frames faster than figures can follow: they
        // are measured for the frame it pauses on.
        let clip_playing = |e: &super::engine::Engine| {
            e.clip().is_some_and(|c| c.player.playing) && e.clip_shown()
        };
        if cx.images.sequences_playing()
            || (!cx.images.is_open() && cx.engine.as_ref().is_some_and(clip_playing))
        {
            return;
        }
        let Some((reference, progress)) = cx.reference_for() else {
            return;
        };
        if reference.stamp.view != view {
            return;
        }
        let tests = cx.measured_images(view);
        if tests.is_empty() {
            return;
        }
        let Some(reference_pixels) = &reference.pixels else {
            return;
        };
        let reference = (
            Arc::clone(reference_pixels),
            reference.stamp.serial,
            progress,
        );
        let now = Instant::now();
        let since = match self.reference_view {
            Some((seen, at)) if seen == view => at,
            _ => {
                self.reference_view = Some((view, now));
                now
            }
        };
        let adapter = cx.gpu.adapter.clone();
        if let Err(err) = self.start_workers(ctx, &adapter) {
            self.failed = true;
            cx.notify(
                Level::Error,
                format!("quality figures are off: no thread to measure them ({err})"),
            );
            return;
        }
        let q = &mut *self;
        let reference = (&reference.0, reference.1, reference.2);
        let pixels_deferred = schedule(
            q.pixel_worker.as_mut(),
            &q.pixels,
            &tests,
            reference,
            view,
            true,
            PIXEL_PAUSE,
            true,
        );
        let flip_deferred = schedule(
            q.flip_worker.as_mut(),
            &q.flip,
            &tests,
            reference,
            view,
            false,
            FLIP_PAUSE,
            now.duration_since(since) >= FLIP_DELAY,
        );
        q.deferred = pixels_deferred || flip_deferred;
    }

    /// The quality figures of a technique that describe what is on screen now (`None` while
    /// they are stale or being measured).
    pub(super) fn figures(&self, cx: &Context, id: &str) -> Option<Figures> {
        let key = cx.measure_key(id);
        let pixels = self.current_pixels(id, key)?;
        let flip = self
            .current_flip(id, key)
            .and_then(|m| m.value.as_ref().ok().map(|v| (*v, m.reference.samples)));
        Some(Figures {
            pixels: *pixels.value.as_ref().ok()?,
            reference_samples: pixels.reference.samples,
            flip,
        })
    }

    /// A short line of current figures for a technique (magnifier captions, sheets): SSIM,
    /// PSNR and, once measured, FLIP.
    pub(super) fn figures_text(&self, cx: &Context, id: &str) -> Option<String> {
        let f = self.figures(cx, id)?;
        let mut text = format!("SSIM {:.4} · {}", f.pixels.ssim, psnr_text(f.pixels.psnr));
        if let Some((flip, _)) = f.flip {
            text.push_str(&format!(" · FLIP {flip:.4}"));
        }
        Some(text)
    }
}

/// PSNR with its unit ("∞ dB" for identical images).
pub fn psnr_text(psnr: f64) -> String {
    if psnr.is_finite() {
        format!("{psnr:.2} dB")
    } else {
        "∞ dB".to_owned()
    }
}

/// What the SSIM figure measures, for its tooltip.
pub fn ssim_help(samples: u32) -> String {
    format!(
        "SSIM of BT.601 luma (Y' = 0.299 R' + 0.587 G' + 0.114 B' of the sRGB-encoded values) \
         against the {samples}-spp reference: Gaussian window {w}x{w}, sigma {s}, K1 {k1}, \
         K2 {k2}, averaged over the pixels at least {r} pixels from the frame's edges. \
         1 = identical.",
        w = ssim::WINDOW,
        s = ssim::SIGMA,
        k1 = ssim::K1,
        k2 = ssim::K2,
        r = ssim::RADIUS,
    )
}

/// What the PSNR figure measures.
pub fn psnr_help(samples: u32) -> String {
    format!(
        "PSNR = 10 log10(255² / MSE) in dB, the mean squared error taken over R', G' and B' \
         (sRGB-encoded 8-bit values) against the {samples}-spp reference. Higher is closer; \
         ∞ = identical."
    )
}

/// What the MAE figure measures.
pub fn mae_help(samples: u32) -> String {
    format!(
        "Mean absolute error over R', G' and B' in sRGB-encoded 8-bit values (0..255) against \
         the {samples}-spp reference. 0 = identical."
    )
}

/// What the FLIP figure measures.
pub fn flip_help(samples: u32) -> String {
    format!(
        "Mean of NVIDIA's FLIP (LDR) per-pixel error against the {samples}-spp reference, for \
         an observer at {ppd:.0} pixels per degree: 0 = indistinguishable, 1 = maximal. Sees \
         colour, and weighs edges and points the way the eye's contrast sensitivity does. \
         Computed on the CPU, less often than the others.",
        ppd = flip::PIXELS_PER_DEGREE,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stamp(view: u64, revision: u64, serial: u64) -> ImageStamp {
        ImageStamp {
            view,
            revision,
            serial,
        }
    }

    fn measured(stamp: ImageStamp, reference_serial: u64, samples: u32) -> Measured<f64> {
        Measured {
            value: Ok(0.5),
            stamp,
            reference_serial,
            reference: Progress { samples, total: 64 },
            ms: 1.0,
            on: "CPU",
        }
    }

    #[test]
    fn needs_follow_stamps_and_reference_progress() {
        let partial = Progress {
            samples: 8,
            total: 64,
        };
        let complete = Progress {
            samples: 64,
            total: 64,
        };
        let image = stamp(3, 1, 10);
        // Nothing measured yet: urgent when eager or when the reference is complete.
        assert_eq!(need::<f64>(None, image, 20, partial, true), Need::Urgent);
        assert_eq!(need::<f64>(None, image, 20, partial, false), Need::Refresh);
        assert_eq!(need::<f64>(None, image, 20, complete, false), Need::Urgent);
        // Exactly these images: nothing to do.
        let done = measured(image, 20, 8);
        assert_eq!(need(Some(&done), image, 20, partial, true), Need::Nothing);
        // More reference samples: refresh at the worker's pace, until it converges.
        assert_eq!(need(Some(&done), image, 21, partial, true), Need::Refresh);
        assert_eq!(need(Some(&done), image, 21, complete, false), Need::Urgent);
        // A new frame of a temporal technique in the same view: refresh.
        let converged = measured(image, 21, 64);
        assert_eq!(
            need(Some(&converged), stamp(3, 1, 11), 21, complete, true),
            Need::Refresh
        );
        // Another view or other settings: the old figures are invalid.
        assert_eq!(
            need(Some(&done), stamp(4, 1, 12), 22, partial, true),
            Need::Urgent
        );
        assert_eq!(
            need(Some(&done), stamp(3, 2, 12), 22, partial, false),
            Need::Refresh
        );
        assert!(!valid_for(&done, 3, 2));
        assert!(valid_for(&done, 3, 1));
    }

    #[test]
    fn cpu_figures_agree_with_the_library() {
        let reference = image::RgbaImage::from_fn(40, 30, |x, y| {
            image::Rgba([(x * 6) as u8, (y * 8) as u8, 90, 255])
        });
        let mut test = reference.clone();
        test.put_pixel(20, 15, image::Rgba([255, 255, 255, 255]));
        let figures = pixel_figures_cpu(&reference, &test).unwrap();
        let library = crate::metrics::compare(&reference, &test).unwrap();
        assert_eq!(figures.ssim, library.ssim);
        assert_eq!(figures.psnr, library.psnr);
        assert_eq!(figures.mae, library.mae);
        assert!(pixel_figures_cpu(&reference, &image::RgbaImage::new(40, 29)).is_err());
        assert_eq!(psnr_text(f64::INFINITY), "∞ dB");
        assert!(ssim_help(64).contains("64-spp") && ssim_help(64).contains("11x11"));
    }
}
