//! `aa-lab compare REFERENCE TEST`: scores a test image against a reference with SSIM, PSNR,
//! MAE and FLIP (see `metrics`), as text or JSON, and optionally writes a heatmap of one
//! metric's per-pixel map (two OpenEXR images go to [`super::compare_hdr`] instead, for
//! HDR-FLIP). `--edge-gain NOAA.png` adds the edge gain over No AA's image (`metrics::edges`).
//! `--gpu` also runs the compute-shader path and prints its numbers
//! next to the CPU reference's. Two sequences (folders or globs of numbered frames) are scored
//! frame by frame and over time by [`super::compare_sequences`].

use std::path::{Path, PathBuf};

use anyhow::{Context, bail};

use super::heatmap_files::write_metric_heatmap;
use crate::export::png::{read_image_limited, read_record};
use crate::files::Overwrite;
use crate::gpu::Gpu;
use crate::metrics::edges::edge_gain;
use crate::metrics::gpu::{GpuMetrics, upload_image};
use crate::metrics::{Comparison, Metric, MetricsError, compare_with_maps};

/// Arguments of `aa-lab compare`.
#[derive(Debug, clap::Args)]
pub struct CompareArgs {
    /// The reference image (e.g. a 64-sample SSAA render), or a sequence: a folder or a glob
    /// (quoted: 'frames/ref_*.png') of numbered PNG, JPEG or OpenEXR frames.
    pub reference: PathBuf,
    /// The image to score, or a sequence of as many frames of the reference's size.
    pub test: PathBuf,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
    /// Write a heatmap (with legend) of one metric's per-pixel map to this PNG.
    #[arg(long, value_name = "OUT.png")]
    pub heatmap: Option<PathBuf>,
    /// The metric the heatmap shows: ssim (as 1 - SSIM), flip or mae.
    #[arg(long, default_value = "flip", value_parser = parse_metric)]
    pub metric: Metric,
    /// Also the edge gain of the test image over this No AA image of the same frame: the
    /// share of No AA's error on the reference's edges (its strong luma gradients) that the
    /// test image removes; 1 all of it, 0 none, negative when it adds error.
    #[arg(long, value_name = "NOAA.png")]
    pub edge_gain: Option<PathBuf>,
    /// Also compute SSIM, MAE and PSNR with the GPU compute path.
    #[arg(long)]
    pub gpu: bool,
    /// Replace an existing heatmap file (without it, aa-lab never replaces a file; the
    /// compared images are never replaced).
    #[arg(long)]
    pub force: bool,
    /// Sequences only: also score the test sequence with ColorVideoVDP against the reference,
    /// in JOD (10: no visible difference), played at --fps on --jod-display. Holds every
    /// frame of both in memory.
    #[arg(long)]
    pub jod: bool,
    /// The display model and viewing distance of --jod.
    #[command(flatten)]
    pub jod_view: super::clip_record::JodDisplayArgs,
    /// The frame rate the sequences play at, for --jod.
    #[arg(long, default_value_t = 30.0, value_name = "FPS", requires = "jod")]
    pub fps: f32,
    /// With --jod: also write ColorVideoVDP's per-pixel distortion map (1 - JOD/10, averaged
    /// over the frames) as a heatmap with legend to this PNG.
    #[arg(long, value_name = "OUT.png", requires = "jod")]
    pub jod_heatmap: Option<PathBuf>,
    /// Sequences of OpenEXR frames only: show their linear light through this tonemapper
    /// (reinhard, aces, agx or neutral) before scoring, instead of clamping it to the
    /// display's white (auto, none).
    #[arg(long, value_name = "NAME", default_value = "auto", value_parser = super::parse::parse_tonemap)]
    pub tonemap: crate::graph::hdr::TonemapChoice,
    /// Exposure in stops (EV) before --tonemap.
    #[arg(long, value_name = "EV", default_value_t = 0.0, allow_hyphen_values = true, value_parser = super::parse::parse_exposure)]
    pub exposure: f32,
}

/// Most pixels an image compared may have: 8K UHD (7680x4320) fits. The error maps take
/// about 50 bytes a pixel, so this bounds compare to under 2 GB.
pub const MAX_COMPARE_PIXELS: u64 = 1 << 25;

fn parse_metric(text: &str) -> Result<Metric, String> {
    Metric::from_name(text).ok_or_else(|| {
        let names: Vec<&str> = Metric::ALL.iter().map(|m| m.name()).collect();
        format!(
            "`{text}` is not a metric with a map; choose one of {}",
            names.join(", ")
        )
    })
}

/// The GPU path's numbers, when asked for.
#[derive(serde::Serialize)]
struct GpuScores {
    ssim: f64,
    psnr: f64,
    mae: f64,
    adapter: String,
}

#[derive(serde::Serialize)]
struct CompareOutput<'a> {
    reference: &'a Path,
    test: &'a Path,
    width: u32,
    height: u32,
    #[serde(flatten)]
    scores: Comparison,
    #[serde(skip_serializing_if = "Option::is_none")]
    gpu: Option<GpuScores>,
    /// Edge gain over `--edge-gain`'s No AA image (`null` when No AA has no edge error).
    #[serde(skip_serializing_if = "Option::is_none")]
    edge_gain: Option<Option<f64>>,
}

fn gpu_scores(reference: &image::RgbaImage, test: &image::RgbaImage) -> anyhow::Result<GpuScores> {
    let gpu = Gpu::headless()?;
    let a = upload_image(&gpu, reference, "compare reference")?;
    let b = upload_image(&gpu, test, "compare test")?;
    let scores = GpuMetrics::new(&gpu).compare(&gpu, &a, &b)?;
    Ok(GpuScores {
        ssim: scores.ssim,
        psnr: scores.psnr(),
        mae: scores.mae,
        adapter: gpu.caps.adapter_name.clone(),
    })
}

/// The overwrite policy of `--heatmap` with `inputs` (the compared files) never written,
/// checked against the heatmap's path before any work is done.
pub(super) fn heatmap_policy<'p>(
    args: &CompareArgs,
    inputs: impl IntoIterator<Item = &'p Path>,
) -> anyhow::Result<Overwrite> {
    let policy = inputs
        .into_iter()
        .fold(Overwrite::new(args.force), Overwrite::with_input);
    for path in args.heatmap.iter().chain(&args.jod_heatmap) {
        policy.check(path)?;
    }
    Ok(policy)
}

/// Runs `aa-lab compare` on two images (the caller checked that neither is a sequence).
pub fn run(args: &CompareArgs) -> anyhow::Result<()> {
    let inputs = [args.reference.as_path(), args.test.as_path()];
    let policy = heatmap_policy(args, inputs.into_iter().chain(args.edge_gain.as_deref()))?;
    let read = |path: &Path| read_image_limited(path, MAX_COMPARE_PIXELS, "compare");
    let reference = read(&args.reference)?;
    let test = read(&args.test)?;
    let (comparison, maps) = match compare_with_maps(&reference, &test) {
        Ok(result) => result,
        Err(MetricsError::SizeMismatch {
            reference: r,
            test: t,
        }) => bail!(
            "cannot compare: {} is {}x{} but {} is {}x{}; both images must have the same size",
            args.reference.display(),
            r.0,
            r.1,
            args.test.display(),
            t.0,
            t.1
        ),
        Err(err) => {
            return Err(err).with_context(|| {
                format!(
                    "cannot compare {} with {}",
                    args.reference.display(),
                    args.test.display()
                )
            });
        }
    };
    let gpu = args
        .gpu
        .then(|| gpu_scores(&reference, &test))
        .transpose()?;
    let edge_gain = args
        .edge_gain
        .as_deref()
        .map(|path| {
            let no_aa = read(path)?;
            edge_gain(&reference, &no_aa, &test).map_err(|err| match err {
                MetricsError::SizeMismatch { test: t, .. } => anyhow::anyhow!(
                    "--edge-gain: {} is {}x{} but the reference is {}x{}",
                    path.display(),
                    t.0,
                    t.1,
                    reference.width(),
                    reference.height()
                ),
                err => err.into(),
            })
        })
        .transpose()?;
    if let Some(path) = &args.heatmap {
        let map = maps.error_map(args.metric);
        let record = |p: &Path| {
            read_record(p)
                .ok()
                .flatten()
                .and_then(|text| serde_json::from_str::<serde_json::Value>(&text).ok())
        };
        let compare = serde_json::json!({
            "reference": args.reference,
            "test": args.test,
            "metric": args.metric,
            "scores": comparison,
            "reference_record": record(&args.reference),
            "test_record": record(&args.test),
        });
        write_metric_heatmap(path, args.metric, &map, compare, &policy)?;
    }
    let output = CompareOutput {
        reference: &args.reference,
        test: &args.test,
        width: reference.width(),
        height: reference.height(),
        scores: comparison,
        gpu,
        edge_gain,
    };
    if args.json {
        println!("{}", serde_json::to_string_pretty(&output)?);
        return Ok(());
    }
    println!(
        "{} vs reference {} ({}x{})",
        args.test.display(),
        args.reference.display(),
        output.width,
        output.height
    );
    let gpu = output.gpu.as_ref();
    let with_gpu = |cpu: String, value: Option<String>| match value {
        Some(v) => format!("{cpu:<12} (GPU {v})"),
        None => cpu,
    };
    println!(
        "SSIM  {}  luma, 11x11 Gaussian window, 1 = identical",
        with_gpu(
            format!("{:.5}", comparison.ssim),
            gpu.map(|g| format!("{:.5}", g.ssim))
        )
    );
    println!(
        "PSNR  {}  R'G'B'",
        with_gpu(
            format!("{:.3} dB", comparison.psnr),
            gpu.map(|g| format!("{:.3} dB", g.psnr))
        )
    );
    println!(
        "MAE   {}  R'G'B', 0..255",
        with_gpu(
            format!("{:.4}", comparison.mae),
            gpu.map(|g| format!("{:.4}", g.mae))
        )
    );
    println!("FLIP  {:.5}  mean, 0 = indistinguishable", comparison.flip);
    match output.edge_gain {
        Some(Some(gain)) => {
            println!("edge gain {gain:.4}  share of No AA's error on the reference's edges removed")
        }
        Some(None) => println!("edge gain undefined: No AA has no error on the reference's edges"),
        None => {}
    }
    if let Some(g) = gpu {
        println!("GPU path on {}", g.adapter);
    }
    Ok(())
}
