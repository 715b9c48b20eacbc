//! The record `aa-lab clip` writes beside the animation (`<out>.json`, and the animation's
//! `aa-lab` text chunk): the clip's recipe (the render's, and every captured sequence's folder,
//! offset and frames) and every pane's figures against the reference (temporal figures; with
//! sequences, each frame's SSIM, PSNR, MAE and FLIP and their summary; JOD with `--jod`), and
//! the same figures as a table on standard output. The captions and the JOD scoring of the
//! panes are here too, as they turn a recorded clip into its figures.

use std::path::{Path, PathBuf};

use anyhow::Context;

use super::clip_sequences::{ClipSequences, SequenceRecord};
use super::heatmap_files::write_jod_heatmap;
use crate::aa::user::file_name_part;
use crate::export::clip::{self, Definitions, figure};
use crate::export::clip_writer::ClipFormat;
use crate::export::sheet::Rect;
use crate::files::Overwrite;
use crate::metrics::Comparison;
use crate::metrics::jod::{self, JodDisplay, JodScorer, JodSetting};
use crate::metrics::series::{FrameSeries, SeriesSummary};
use crate::metrics::stability::{ClipMetrics, TemporalScores};
use crate::scene::motion::Motion;
use crate::spec::{RenderSpec, TechniqueSpec};

/// Version of the record `aa-lab clip` writes.
pub const SCHEMA: &str = "aa-lab clip 2";

/// A pane's image figures against the reference, frame by frame and over the clip.
#[derive(Clone, Debug, serde::Serialize)]
pub struct PaneQuality {
    /// Means over the frames (PSNR from the mean squared error), the worst frame by FLIP.
    #[serde(flatten)]
    pub summary: SeriesSummary,
    /// Each clip frame's figures.
    pub per_frame: Vec<Comparison>,
}

/// One pane's figures in the record.
#[derive(Clone, Debug, serde::Serialize)]
pub struct ClipTechnique {
    /// Registry id, or the sequence's label.
    pub id: String,
    /// Label with its defining settings.
    pub label: String,
    /// Temporal figures over the clip (full frame).
    #[serde(flatten)]
    pub scores: TemporalScores,
    /// The same over the `--region` pixels only (what the animation shows), with a region.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub region: Option<TemporalScores>,
    /// SSIM, PSNR, MAE and FLIP of the whole frames against the reference's, in a clip with
    /// sequences.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub quality: Option<PaneQuality>,
    /// ColorVideoVDP's JOD of the whole frames against the reference's, with `--jod`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jod: Option<f64>,
}

/// What the figures are measured against: the rendered reference or a captured sequence.
#[derive(Clone, Debug, serde::Serialize)]
#[serde(untagged)]
pub enum ClipReference {
    /// The 64-sample render.
    Rendered(TechniqueSpec),
    /// `--reference-sequence`.
    Captured(SequenceRecord),
}

/// What `<out>.json` (and the animation's `aa-lab` text chunk) holds.
#[derive(Clone, Debug, serde::Serialize)]
pub struct ClipRecord {
    /// [`SCHEMA`].
    pub schema: &'static str,
    /// Scene, size, camera rig, every technique setting, adapter and build; `frame` is the
    /// first frame of the clip (= warmup). Absent when nothing is rendered.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub spec: Option<RenderSpec>,
    /// The reference the figures are measured against.
    pub reference: ClipReference,
    /// Camera motion, when anything is rendered.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub motion: Option<Motion>,
    /// Speed of pan and dolly, pixels per frame.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub speed_px: Option<f32>,
    /// Frames rendered before the clip.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub warmup: Option<u32>,
    /// Frames of the clip.
    pub frames: u32,
    /// Playback rate.
    pub fps: u16,
    /// Region shown (pixels of the frames), `None` for whole frames.
    pub region: Option<Rect>,
    /// Zoom of the panes.
    pub zoom: u32,
    /// Format of the clip: apng, gif, mp4 or webm.
    pub format: ClipFormat,
    /// How the figures are computed.
    pub definitions: Definitions,
    /// Share of pixels of the frame pairs where the reference moved (the ghosting mask).
    pub moving_fraction: f64,
    /// The reference's mean absolute luma change per pixel and frame.
    pub reference_mean_change: Option<f64>,
    /// The same over the region, with one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub region_reference_mean_change: Option<f64>,
    /// The display model, version and rate of the `jod` figures, with `--jod`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jod: Option<JodSetting>,
    /// The `--sequence` panes: folder or glob, offset and the frames the clip shows.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub sequences: Vec<SequenceRecord>,
    /// Per pane but the reference's, in pane order.
    pub techniques: Vec<ClipTechnique>,
}

/// The rendered side of the recipe.
pub(super) struct RenderedPart {
    /// The render record of the techniques.
    pub spec: RenderSpec,
    /// The rendered reference, unless it is captured.
    pub reference: Option<TechniqueSpec>,
    /// Camera motion, speed and warm-up.
    pub motion: Motion,
    pub speed_px: f32,
    pub warmup: u32,
}

/// The panes of a clip: ids and labels in pane order (the reference's last) and the captured
/// ones.
pub(super) struct ClipPanes<'a> {
    pub ids: &'a [String],
    pub labels: &'a [String],
    pub captured: &'a ClipSequences,
}

/// The clip's length, rate and layout.
pub(super) struct ClipShape {
    pub frames: u32,
    pub fps: u16,
    pub region: Option<Rect>,
    pub zoom: u32,
    pub format: ClipFormat,
}

/// What a recorded clip measured.
pub(super) struct ClipFigures<'a> {
    pub metrics: &'a ClipMetrics,
    pub region_metrics: Option<&'a ClipMetrics>,
    /// Each pane's image figures (empty without sequences).
    pub series: &'a [FrameSeries],
    pub jods: Option<&'a [f64]>,
    pub jod: Option<JodSetting>,
}

/// The record of a clip.
pub(super) fn clip_record(
    rendered: Option<RenderedPart>,
    panes: &ClipPanes,
    shape: ClipShape,
    figures: &ClipFigures,
) -> anyhow::Result<ClipRecord> {
    let frames = shape.frames as usize;
    let captured = panes.captured;
    let reference = match (&captured.reference, rendered.as_ref()) {
        (Some(sequence), _) => ClipReference::Captured(sequence.record(frames)),
        (
            None,
            Some(RenderedPart {
                reference: Some(spec),
                ..
            }),
        ) => ClipReference::Rendered(spec.clone()),
        (None, _) => anyhow::bail!("the clip has no reference"),
    };
    let mut over = String::from("every pixel of the whole frame");
    if let Some(r) = &rendered {
        over += &format!(", frames {w}..{w}+{frames} of the render", w = r.warmup);
    }
    if !captured.is_empty() {
        over += ", frames offset..offset+frames of each sequence (`sequences`, `reference`); `quality`: each frame's SSIM, PSNR, MAE and FLIP against the reference's frame";
    }
    over += "; `region` figures and the captions: the --region pixels only";
    let scores = figures.metrics.scores();
    let region_scores = figures.region_metrics.map(ClipMetrics::scores);
    let techniques = panes
        .ids
        .iter()
        .zip(panes.labels)
        .zip(&scores)
        .enumerate()
        .map(|(i, ((id, label), scores))| ClipTechnique {
            id: id.clone(),
            label: label.clone(),
            scores: *scores,
            region: region_scores.as_ref().and_then(|r| r.get(i).copied()),
            quality: figures.series.get(i).map(|series| PaneQuality {
                summary: series.summary(),
                per_frame: series.per_frame().to_vec(),
            }),
            jod: figures.jods.and_then(|j| j.get(i).copied()),
        })
        .collect();
    Ok(ClipRecord {
        schema: SCHEMA,
        reference,
        motion: rendered.as_ref().map(|r| r.motion),
        speed_px: rendered.as_ref().map(|r| r.speed_px),
        warmup: rendered.as_ref().map(|r| r.warmup),
        spec: rendered.map(|r| r.spec),
        frames: shape.frames,
        fps: shape.fps,
        region: shape.region,
        zoom: shape.zoom,
        format: shape.format,
        definitions: Definitions::over(over),
        moving_fraction: figures.metrics.moving_fraction(),
        reference_mean_change: figures.metrics.reference().mean_change(),
        region_reference_mean_change: figures
            .region_metrics
            .and_then(|m| m.reference().mean_change()),
        jod: figures.jod.clone(),
        sequences: captured.panes.iter().map(|p| p.record(frames)).collect(),
        techniques,
    })
}

/// The display flags of `--jod`, shared by `clip`, `bench` and `compare`.
#[derive(Clone, Debug, clap::Args)]
pub struct JodDisplayArgs {
    /// The display model --jod scores for: one of ColorVideoVDP's standard displays (e.g.
    /// standard_fhd, standard_4k, standard_phone, standard_hmd).
    #[arg(long, default_value = jod::DEFAULT_DISPLAY, value_name = "NAME", requires = "jod")]
    pub jod_display: String,
    /// The viewing distance --jod scores for, as pixels per degree of visual angle replacing
    /// the display model's (ColorVideoVDP keeps a display's geometry as pixels per degree:
    /// twice as far is about twice as many; standard_fhd has about 38). Recorded with the
    /// figures either way.
    #[arg(long, value_name = "PPD", requires = "jod", value_parser = parse_pixels_per_degree)]
    pub jod_ppd: Option<f64>,
}

impl JodDisplayArgs {
    /// The display the flags name.
    pub fn display(&self) -> JodDisplay {
        JodDisplay {
            name: self.jod_display.clone(),
            pixels_per_degree: self.jod_ppd,
        }
    }

    /// A scorer for the display, giving the distortion map when `mapped`.
    pub fn scorer(&self, mapped: bool) -> anyhow::Result<JodScorer> {
        Ok(JodScorer::for_display(&self.display(), mapped)?)
    }
}

fn parse_pixels_per_degree(text: &str) -> Result<f64, String> {
    let value: f64 = text
        .parse()
        .map_err(|_| format!("`{text}` is not a number of pixels per degree"))?;
    jod::check_pixels_per_degree(value).map_err(|e| e.to_string())
}

/// The heatmap files of `clip --jod-heatmap DIR`: `DIR/<technique>-jod.png` for every pane
/// but the reference (the last of `ids`), checked against `policy` before anything renders.
pub(super) fn jod_heatmap_paths(
    dir: &Path,
    ids: &[String],
    policy: &Overwrite,
) -> anyhow::Result<Vec<PathBuf>> {
    let techniques = &ids[..ids.len().saturating_sub(1)];
    let paths: Vec<PathBuf> = techniques
        .iter()
        .map(|id| dir.join(format!("{}-jod.png", file_name_part(id))))
        .collect();
    for (i, path) in paths.iter().enumerate() {
        if let Some(other) = paths[..i].iter().position(|o| o == path) {
            anyhow::bail!(
                "--jod-heatmap: the panes {} and {} would both write {}; label the sequence otherwise",
                techniques[other],
                techniques[i],
                path.display()
            );
        }
        policy.check(path)?;
    }
    std::fs::create_dir_all(dir)
        .with_context(|| format!("cannot create directory {}", dir.display()))?;
    Ok(paths)
}

/// Each pane's JOD over the clip's whole frames (`frames[t][pane]`) against the reference's
/// (the last pane), played at the clip's rate; with `heatmaps` (one path per technique, see
/// [`jod_heatmap_paths`]) each technique's distortion map is written there too (the scorer
/// must give maps).
pub(super) fn jod_figures(
    scorer: &JodScorer,
    frames: &[Vec<image::RgbaImage>],
    labels: &[String],
    fps: u16,
    heatmaps: Option<(&[PathBuf], &Overwrite)>,
) -> anyhow::Result<Vec<f64>> {
    let techniques = labels.len().saturating_sub(1);
    let reference: Vec<&image::RgbaImage> = frames.iter().filter_map(|f| f.last()).collect();
    let fps = f32::from(fps);
    (0..techniques)
        .map(|i| {
            eprintln!(
                "scoring {} with ColorVideoVDP ({}/{techniques})…",
                labels[i],
                i + 1
            );
            let test: Vec<&image::RgbaImage> = frames.iter().filter_map(|f| f.get(i)).collect();
            let context = || format!("the JOD of {}", labels[i]);
            let Some((paths, policy)) = heatmaps else {
                return scorer.score(&test, &reference, fps).with_context(context);
            };
            let (jod, map) = scorer
                .score_with_map(&test, &reference, fps)
                .with_context(context)?;
            let record = serde_json::json!({
                "technique": labels[i],
                "frames": test.len(),
                "jod": jod,
                "setting": scorer.setting(fps),
                "map": "ColorVideoVDP's per-pixel distortion (1 - JOD/10), mean over the clip's frames",
            });
            write_jod_heatmap(&paths[i], &map, record, policy)?;
            Ok(jod)
        })
        .collect()
}

/// Captions every pane of `layout` with its figures, fitted to `width` pixels: the panes'
/// `scores`, then the reference's mean change.
pub(super) fn show_figures(
    layout: &mut clip::Layout,
    scores: &[TemporalScores],
    reference_change: Option<f64>,
    width: u32,
) {
    for (pane, scores) in layout.panes.iter_mut().zip(scores) {
        pane.caption = clip::fit(&[clip::caption(scores), clip::short_caption(scores)], width);
    }
    if let Some(reference_pane) = layout.panes.last_mut() {
        reference_pane.caption = clip::reference_caption(reference_change, width);
    }
}

/// The figures as a table on stdout.
pub(super) fn print_table(record: &ClipRecord) {
    let regional = record.region.is_some();
    let judged = record.techniques.iter().any(|t| t.quality.is_some());
    let jod_head = record
        .jod
        .as_ref()
        .map_or_else(String::new, |j| format!("  | JOD ({})", j.display));
    println!(
        "{:<24} {:>12} {:>12} {:>10}{}{}{jod_head}",
        "technique",
        "instability",
        "mean change",
        "ghosting",
        if regional {
            "  | region: instability  ghosting"
        } else {
            ""
        },
        if judged {
            "  |     SSIM   PSNR dB     FLIP  worst"
        } else {
            ""
        }
    );
    for t in &record.techniques {
        let region = t.region.map_or_else(String::new, |r| {
            format!(
                "  | {:>19} {:>9}",
                figure(r.temporal_instability, 3),
                figure(r.ghosting, 2)
            )
        });
        let quality = t.quality.as_ref().map_or_else(String::new, |q| {
            let s = &q.summary.scores;
            format!(
                "  | {:>8.5} {:>9.3} {:>8.5} {:>6}",
                s.ssim, s.psnr, s.flip, q.summary.worst_frame
            )
        });
        let jod = t
            .jod
            .map_or_else(String::new, |j| format!("  | {:>6}", figure(Some(j), 2)));
        println!(
            "{:<24} {:>12} {:>12} {:>10}{region}{quality}{jod}",
            t.label,
            figure(t.scores.temporal_instability, 3),
            figure(t.scores.mean_change, 3),
            figure(t.scores.ghosting, 2)
        );
    }
    println!(
        "{:<24} {:>12} {:>12} {:>10}",
        "reference",
        "1",
        figure(record.reference_mean_change, 3),
        "0"
    );
    if judged {
        println!(
            "(SSIM, FLIP: means over the clip's frames; PSNR from the mean squared error of all frames; worst: the frame with the largest FLIP)"
        );
    }
}
