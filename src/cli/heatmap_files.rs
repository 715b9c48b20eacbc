//! The heatmap files `compare` and `clip` write: a metric's or ColorVideoVDP's per-pixel map as
//! a PNG with a legend, and a sidecar record of what was compared and the scores.

use std::path::Path;

use crate::export::heatmap::{HeatmapStyle, write_heatmap};
use crate::files::{self, Overwrite};
use crate::metrics::Metric;

/// The heatmap's colour range: SSIM and FLIP span their full 0..1 scale so heatmaps compare
/// across images; absolute error spans 0 to the largest error (at least 1).
fn heatmap_range(metric: Metric, map: &crate::metrics::Plane) -> (f32, f32) {
    match metric {
        Metric::Ssim | Metric::Flip => (0.0, 1.0),
        Metric::Mae => (0.0, map.range().1.max(1.0).ceil()),
    }
}

/// Writes the heatmap of `metric`'s `map` to `path` with a sidecar record holding `compare`
/// (what was compared and the scores) and the build.
pub(super) fn write_metric_heatmap(
    path: &Path,
    metric: Metric,
    map: &crate::metrics::Plane,
    compare: serde_json::Value,
    policy: &Overwrite,
) -> anyhow::Result<()> {
    let style = HeatmapStyle {
        legend: metric.legend(),
        range: heatmap_range(metric, map),
    };
    write_compare_heatmap(path, map, &style, compare, policy)
}

/// Writes a heatmap of `map` in `style` to `path` with a sidecar record holding `compare`
/// (what was compared and the scores) and the build.
pub(super) fn write_compare_heatmap(
    path: &Path,
    map: &crate::metrics::Plane,
    style: &HeatmapStyle,
    compare: serde_json::Value,
    policy: &Overwrite,
) -> anyhow::Result<()> {
    let sidecar = serde_json::json!({
        "compare": compare,
        "build": crate::spec::build_id(),
    });
    let replaced = write_heatmap(
        path,
        map,
        style,
        Some(&serde_json::to_string_pretty(&sidecar)?),
        policy,
    )?;
    eprintln!("{}", files::wrote_line(path, replaced));
    Ok(())
}

/// Writes ColorVideoVDP's per-pixel distortion `map` (1 - JOD/10, see
/// [`crate::metrics::jod::JodScorer::score_with_map`]) as a heatmap to `path` with a sidecar
/// record holding `compare` (`compare --jod-heatmap`, `clip --jod-heatmap`).
pub(super) fn write_jod_heatmap(
    path: &Path,
    map: &crate::metrics::Plane,
    compare: serde_json::Value,
    policy: &Overwrite,
) -> anyhow::Result<()> {
    let style = HeatmapStyle {
        legend: "ColorVideoVDP distortion (1 - JOD/10)",
        range: (0.0, 1.0),
    };
    write_compare_heatmap(path, map, &style, compare, policy)
}
