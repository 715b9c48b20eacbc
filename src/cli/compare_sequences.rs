//! `aa-lab compare REFERENCE TEST` on two image sequences (folders or globs of numbered frames,
//! [`crate::sequence`]): every frame pair scored with the same SSIM, PSNR, MAE and FLIP as two
//! images, and the whole sequence with the temporal figures of a recorded clip
//! ([`crate::metrics::stability`]: the test's change, instability and ghosting against the
//! reference sequence). Printed as a table, or with `--json` as one record of the per-frame
//! figures and the summary; `--heatmap` writes the metric's map averaged over the frames;
//! `--jod` adds ColorVideoVDP's JOD of the whole test sequence ([`crate::metrics::jod`]).
//!
//! The frames are read one pair at a time (each sequence's cache is capped at two frames), so
//! memory does not grow with the sequence's length; only `--jod` holds them all (the model
//! needs the whole sequences), within a stated cap.

use std::path::Path;

use anyhow::Context;

use super::compare::{CompareArgs, MAX_COMPARE_PIXELS, heatmap_policy};
use super::heatmap_files::{write_jod_heatmap, write_metric_heatmap};
use crate::export::clip::{Definitions, figure};
use crate::files::Overwrite;
use crate::metrics::jod::{self, JodSetting};
use crate::metrics::series::{FrameSeries, SeriesSummary};
use crate::metrics::stability::{ClipMetrics, TemporalScores};
use crate::metrics::{Comparison, Plane};
use crate::scene::renderer::Tonemap;
use crate::sequence::{Sequence, check_same_shape};

/// One frame pair's figures.
#[derive(serde::Serialize)]
struct FrameScores<'a> {
    /// 0-based position in the sequences.
    index: usize,
    reference_file: &'a Path,
    test_file: &'a Path,
    #[serde(flatten)]
    scores: Comparison,
}

/// The sequence's figures: the image metrics over all frames and the temporal ones.
#[derive(serde::Serialize)]
struct SequenceSummary {
    /// Means over the frames, PSNR from the mean squared error over all frames, the worst
    /// frame by FLIP.
    #[serde(flatten)]
    images: SeriesSummary,
    /// The reference sequence's mean luma change per frame pair.
    reference_mean_change: Option<f64>,
    #[serde(flatten)]
    temporal: TemporalScores,
    /// Share of pixels the ghosting measure counted as moving.
    moving_fraction: f64,
    /// ColorVideoVDP's JOD of the test sequence against the reference, with `--jod`.
    #[serde(skip_serializing_if = "Option::is_none")]
    jod: Option<Jod>,
}

/// A JOD and what it was computed for.
#[derive(serde::Serialize)]
struct Jod {
    jod: f64,
    #[serde(flatten)]
    setting: JodSetting,
}

/// The JOD of `test` against `reference` (both whole, in memory).
fn jod(
    args: &CompareArgs,
    reference: &Sequence,
    test: &Sequence,
    policy: &Overwrite,
) -> anyhow::Result<Jod> {
    jod::check_memory(reference.size(), reference.len())?;
    let scorer = args.jod_view.scorer(args.jod_heatmap.is_some())?;
    let all = |sequence: &Sequence| -> anyhow::Result<Vec<_>> {
        (0..sequence.len())
            .map(|i| Ok(sequence.frame(i)?))
            .collect()
    };
    eprintln!("scoring with ColorVideoVDP…");
    let (test_frames, reference_frames) = (all(test)?, all(reference)?);
    let value = match &args.jod_heatmap {
        Some(path) => {
            let (value, map) = scorer.score_with_map(&test_frames, &reference_frames, args.fps)?;
            let record = serde_json::json!({
                "reference": args.reference,
                "test": args.test,
                "jod": value,
                "setting": scorer.setting(args.fps),
                "map": "ColorVideoVDP's per-pixel distortion (1 - JOD/10), mean over the frames",
            });
            write_jod_heatmap(path, &map, record, policy)?;
            value
        }
        None => scorer.score(&test_frames, &reference_frames, args.fps)?,
    };
    Ok(Jod {
        jod: value,
        setting: scorer.setting(args.fps),
    })
}

#[derive(serde::Serialize)]
struct SequenceOutput<'a> {
    reference: &'a Path,
    test: &'a Path,
    width: u32,
    height: u32,
    frames: usize,
    summary: SequenceSummary,
    definitions: Definitions,
    per_frame: Vec<FrameScores<'a>>,
}

/// Decoded frames each sequence keeps while compared: the pair being scored.
const CACHE_FRAMES: usize = 2;

fn open(path: &Path, tonemap: Option<Tonemap>) -> anyhow::Result<Sequence> {
    let sequence = Sequence::open(path)?.with_tonemap(tonemap);
    let (width, height) = sequence.size();
    anyhow::ensure!(
        u64::from(width) * u64::from(height) <= MAX_COMPARE_PIXELS,
        "cannot compare {}: its {width}x{height} frames have more than the {MAX_COMPARE_PIXELS} pixels compare takes",
        path.display()
    );
    let frame_bytes = width as usize * height as usize * 4;
    Ok(sequence.with_cache_bytes(CACHE_FRAMES * frame_bytes))
}

/// Runs `aa-lab compare` on two sequences (the caller checked that both are sequences).
pub fn run(args: &CompareArgs) -> anyhow::Result<()> {
    anyhow::ensure!(
        !args.gpu,
        "--gpu scores two images; sequences are scored on the CPU (leave out --gpu)"
    );
    // Captures are not known to be HDR: only a named tonemapper applies (see `--tonemap`).
    let tonemap = args.tonemap.resolve(false, args.exposure);
    let reference = open(&args.reference, tonemap)?;
    let test = open(&args.test, tonemap)?;
    check_same_shape(&reference, &test)?;
    // Every frame is an input: the heatmap is never written over one, even with --force.
    let policy = heatmap_policy(args, reference.paths().chain(test.paths()))?;
    let (width, height) = reference.size();
    let mut per_frame = Vec::with_capacity(reference.len());
    let mut temporal = ClipMetrics::new(1);
    let mut series = FrameSeries::new();
    let mut map_sum: Option<Plane> = None;
    for index in 0..reference.len() {
        let reference_frame = reference.frame(index)?;
        let test_frame = test.frame(index)?;
        let (reference_file, test_file) = (
            reference.path(index).unwrap_or(&args.reference),
            test.path(index).unwrap_or(&args.test),
        );
        let context = || {
            format!(
                "cannot compare {} with {}",
                reference_file.display(),
                test_file.display()
            )
        };
        let maps = series
            .push(&reference_frame, &test_frame)
            .with_context(context)?;
        temporal
            .push(&reference_frame, &[&test_frame])
            .with_context(context)?;
        if args.heatmap.is_some() {
            let map = maps.error_map(args.metric);
            map_sum = Some(match map_sum {
                Some(mut sum) => {
                    sum.data
                        .iter_mut()
                        .zip(&map.data)
                        .for_each(|(s, v)| *s += v);
                    sum
                }
                None => map,
            });
        }
        per_frame.push(FrameScores {
            index,
            reference_file,
            test_file,
            scores: series.per_frame()[index],
        });
    }
    let mut summary = summarise(&series, &temporal);
    if args.jod {
        summary.jod = Some(jod(args, &reference, &test, &policy)?);
    }
    if let (Some(path), Some(mut map)) = (&args.heatmap, map_sum) {
        let frames = per_frame.len() as f32;
        map.data.iter_mut().for_each(|v| *v /= frames);
        let record = serde_json::json!({
            "reference": args.reference,
            "test": args.test,
            "metric": args.metric,
            "frames": per_frame.len(),
            "map": "mean over the frames of the per-pixel map",
            "scores": summary.images.scores,
        });
        write_metric_heatmap(path, args.metric, &map, record, &policy)?;
    }
    let output = SequenceOutput {
        reference: &args.reference,
        test: &args.test,
        width,
        height,
        frames: per_frame.len(),
        summary,
        definitions: Definitions::over(format!(
            "{} frames of {width}x{height}, every pixel",
            per_frame.len()
        )),
        per_frame,
    };
    if args.json {
        println!("{}", serde_json::to_string_pretty(&output)?);
    } else {
        print_table(&output);
    }
    Ok(())
}

fn summarise(series: &FrameSeries, temporal: &ClipMetrics) -> SequenceSummary {
    SequenceSummary {
        images: series.summary(),
        reference_mean_change: temporal.reference().mean_change(),
        temporal: temporal
            .scores()
            .first()
            .copied()
            .unwrap_or(TemporalScores {
                mean_change: None,
                temporal_instability: None,
                ghosting: None,
            }),
        moving_fraction: temporal.moving_fraction(),
        jod: None,
    }
}

fn print_table(output: &SequenceOutput) {
    println!(
        "{} vs reference {} ({} frames of {}x{})",
        output.test.display(),
        output.reference.display(),
        output.frames,
        output.width,
        output.height
    );
    println!(
        "{:>6}  {:>8}  {:>10}  {:>8}  {:>8}  test file",
        "frame", "SSIM", "PSNR dB", "MAE", "FLIP"
    );
    for frame in &output.per_frame {
        let s = &frame.scores;
        println!(
            "{:>6}  {:>8.5}  {:>10.3}  {:>8.4}  {:>8.5}  {}",
            frame.index,
            s.ssim,
            s.psnr,
            s.mae,
            s.flip,
            frame.test_file.display()
        );
    }
    let summary = &output.summary;
    let s = &summary.images.scores;
    println!(
        "{:>6}  {:>8.5}  {:>10.3}  {:>8.4}  {:>8.5}  (PSNR from the mean squared error of all frames)",
        "mean", s.ssim, s.psnr, s.mae, s.flip
    );
    println!(
        "worst frame {} (FLIP {:.5})",
        summary.images.worst_frame, summary.images.worst_flip
    );
    let t = &summary.temporal;
    println!(
        "change per frame: test {} / reference {} luma levels; temporal instability {} (1 = as steady as the reference)",
        figure(t.mean_change, 3),
        figure(summary.reference_mean_change, 3),
        figure(t.temporal_instability, 3)
    );
    println!(
        "ghosting {} luma levels on the {:.2}% of pixels that moved",
        figure(t.ghosting, 3),
        summary.moving_fraction * 100.0
    );
    if let Some(jod) = &summary.jod {
        println!(
            "ColorVideoVDP: {:.2} JOD ({} at {} fps; 10 = no visible difference)",
            jod.jod, jod.setting.display, jod.setting.fps
        );
    }
}
