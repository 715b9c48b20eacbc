//! The record `aa-lab clip` writes beside the animation (`<out>.json`, and the animation's
//! `aa-lab` text chunk): the clip's recipe and every technique's temporal figures (and JOD with
//! `--jod`), and the same figures as a table on standard output.

use crate::export::clip::Definitions;
use crate::export::clip_writer::ClipFormat;
use crate::export::sheet::Rect;
use crate::metrics::stability::TemporalScores;
use crate::scene::motion::Motion;
use crate::spec::{RenderSpec, TechniqueSpec};

/// One technique's figures in the record.
#[derive(Clone, Debug, serde::Serialize)]
pub struct ClipTechnique {
    /// Registry id.
    pub id: String,
    /// Label with its defining settings.
    pub label: String,
    /// Temporal figures over the clip (full frame).
    #[serde(flatten)]
    pub scores: TemporalScores,
    /// The same over the `--region` pixels only (what the animation shows), with a region.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub region: Option<TemporalScores>,
    /// ColorVideoVDP's JOD of the whole frames against the reference's, with `--jod`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jod: Option<f64>,
}

/// How the JOD figures were computed.
#[derive(Clone, Debug, serde::Serialize)]
pub struct JodSetting {
    /// The display model, by its ColorVideoVDP name.
    pub display: String,
    /// The model's calibration version.
    pub model: &'static str,
}

/// What `<out>.json` (and the animation's `aa-lab` text chunk) holds.
#[derive(Clone, Debug, serde::Serialize)]
pub struct ClipRecord {
    /// [`SCHEMA`].
    pub schema: &'static str,
    /// Scene, size, camera rig, every technique setting, adapter and build; `frame` is the
    /// first frame of the clip (= warmup).
    pub spec: RenderSpec,
    /// The reference the figures divide by.
    pub reference: TechniqueSpec,
    /// Camera motion.
    pub motion: Motion,
    /// Speed of pan and dolly, pixels per frame.
    pub speed_px: f32,
    /// Frames rendered before the clip.
    pub warmup: u32,
    /// Frames of the clip.
    pub frames: u32,
    /// Playback rate.
    pub fps: u16,
    /// Region shown (pixels of the render), `None` for whole frames.
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
    /// The display model and version of the `jod` figures, with `--jod`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jod: Option<JodSetting>,
    /// Per technique, in pane order.
    pub techniques: Vec<ClipTechnique>,
}

/// Every technique's figures for the record, in pane order.
pub(super) fn technique_figures(
    ids: &[String],
    labels: &[String],
    scores: &[TemporalScores],
    region_scores: Option<&[TemporalScores]>,
    jods: Option<&[f64]>,
) -> Vec<ClipTechnique> {
    ids.iter()
        .zip(labels)
        .zip(scores)
        .enumerate()
        .map(|(i, ((id, label), scores))| ClipTechnique {
            id: id.clone(),
            label: label.clone(),
            scores: *scores,
            region: region_scores.and_then(|r| r.get(i).copied()),
            jod: jods.and_then(|j| j.get(i).copied()),
        })
        .collect()
}

/// The figures as a table on stdout.
pub(super) fn print_table(record: &ClipRecord) {
    let figure = |v: Option<f64>, digits: usize| {
        v.map_or_else(|| "n/a".to_owned(), |v| format!("{v:.digits$}"))
    };
    let regional = record.region.is_some();
    let jod_head = record
        .jod
        .as_ref()
        .map_or_else(String::new, |j| format!("  | JOD ({})", j.display));
    println!(
        "{:<24} {:>12} {:>12} {:>10}{}{jod_head}",
        "technique",
        "instability",
        "mean change",
        "ghosting",
        if regional {
            "  | region: instability  ghosting"
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
        let jod = t
            .jod
            .map_or_else(String::new, |j| format!("  | {:>6}", figure(Some(j), 2)));
        println!(
            "{:<24} {:>12} {:>12} {:>10}{region}{jod}",
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
}
