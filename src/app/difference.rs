//! The magnifier's difference mode: per-pixel error maps of the lens region against the
//! reference, coloured with the magma map shared with `aa-lab compare --heatmap`
//! ([`crate::export::heatmap::magma`]).
//!
//! A map is computed by the metrics library ([`crate::metrics`]) on the lens plus
//! [`MARGIN`] pixels around it, then cut to the lens: SSIM's 11x11 window and FLIP's filters
//! (at most 10 pixels wide on each side at 67 pixels per degree) see the same neighbours as on
//! the whole frame, so the lens shows the values a full-frame map would have (tested). FLIP on
//! a large lens takes tens of milliseconds per pane, so the maps are computed on a background
//! [`Worker`]; each result remembers the lens it belongs to, and the panes place it there
//! (while the lens is dragged, the newest map is drawn where it was computed, never shifted
//! onto other pixels).

use std::sync::Arc;

use super::lens::{MARGIN, Source, crop};
use super::worker::{Reporter, Worker};
use crate::export::heatmap::magma;
use crate::gpu::readback::Region;
use crate::metrics::{MetricsError, Plane, flip, pixel, ssim};

/// The error metric of the magnifier's difference mode.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum DiffMetric {
    /// Mean absolute difference of the sRGB-encoded channels.
    #[default]
    AbsoluteError,
    /// The SSIM map (shown as dissimilarity, 1 - SSIM).
    Ssim,
    /// NVIDIA's FLIP error map.
    Flip,
    /// Per pixel temporal instability over the shown clip (see `metrics::stability`).
    Instability,
    /// ColorVideoVDP's per-pixel distortion over the shown clip or sequences (1 - JOD/10,
    /// mean over the frames; see `jod.rs`).
    JodDistortion,
}

impl DiffMetric {
    /// Every metric comparing two images, in menu order.
    pub const ALL: [Self; 3] = [Self::AbsoluteError, Self::Ssim, Self::Flip];

    /// Every metric of the menu: the comparisons, then those over the clip or sequences.
    pub const MENU: [Self; 5] = [
        Self::AbsoluteError,
        Self::Ssim,
        Self::Flip,
        Self::Instability,
        Self::JodDistortion,
    ];

    /// Menu label.
    pub fn label(self) -> &'static str {
        match self {
            Self::AbsoluteError => "Absolute error",
            Self::Ssim => "SSIM map",
            Self::Flip => "FLIP",
            Self::Instability => "Temporal instability",
            Self::JodDistortion => "JOD distortion",
        }
    }

    /// What the heatmap shows.
    pub fn help(self) -> String {
        use crate::metrics::{flip, ssim};
        let margin = MARGIN;
        match self {
            Self::AbsoluteError => format!(
                "Per pixel: mean over R', G', B' of |technique - reference| in sRGB-encoded 8-bit \
                 values. Black is 0, the brightest colour {} or more.",
                ABSOLUTE_ERROR_FULL_SCALE
            ),
            Self::Ssim => format!(
                "Per pixel: 1 - SSIM of BT.601 luma against the reference (Gaussian window \
                 {w}x{w}, sigma {s}). Computed on the lens plus {margin} pixels around it, so \
                 windows at the lens border see their real neighbours. Black is identical, the \
                 brightest colour 1 - SSIM = 1 or more.",
                w = ssim::WINDOW,
                s = ssim::SIGMA,
            ),
            Self::Flip => format!(
                "Per pixel: NVIDIA's FLIP (LDR) error against the reference for an observer at \
                 {ppd:.0} pixels per degree. Computed on the lens plus {margin} pixels around \
                 it, so FLIP's filters at the lens border see their real neighbours. Black is \
                 indistinguishable, the brightest colour 1.",
                ppd = flip::PIXELS_PER_DEGREE,
            ),
            Self::Instability => format!(
                "Per pixel, over the shown clip (recorded with the reference): the mean \
                 frame-to-frame change of luma of the technique, divided by the reference's mean \
                 change over the whole frame. Black is still, the brightest colour {} times the \
                 reference's mean change or more: where a technique crawls and shimmers.",
                INSTABILITY_FULL_SCALE
            ),
            Self::JodDistortion => "Per pixel, over the shown clip (recorded with the reference) \
                 or the open sequences: ColorVideoVDP's distortion, 1 - JOD/10, averaged over \
                 the frames, on the display and viewing distance of the metrics panel. Black is \
                 no visible difference, the brightest colour 1 (JOD 0). Choosing it scores \
                 again with the map (seconds per technique)."
                .to_owned(),
        }
    }
}

/// Absolute error (0..255) drawn with the brightest colour of the heatmap.
pub const ABSOLUTE_ERROR_FULL_SCALE: f32 = 64.0;

/// The temporal instability shown brightest (times the reference's mean change).
pub const INSTABILITY_FULL_SCALE: f32 = 8.0;

impl DiffMetric {
    /// The per-pixel map of the metric (SSIM itself, not 1 - SSIM).
    pub fn map(
        self,
        reference: &image::RgbaImage,
        test: &image::RgbaImage,
    ) -> Result<Plane, MetricsError> {
        match self {
            Self::AbsoluteError => pixel::error_maps(reference, test).map(|m| m.abs_error),
            Self::Ssim => ssim::ssim(reference, test).map(|s| s.map),
            Self::Flip => flip::flip_map(reference, test),
            Self::Instability => Err(MetricsError::NotTemporal),
            Self::JodDistortion => Err(MetricsError::Jod(
                "the distortion map is scored over a clip or sequences, not two images".to_owned(),
            )),
        }
    }

    /// Where a map value sits on the colour scale, 0 (no error) to 1 (brightest).
    pub fn heat(self, value: f32) -> f32 {
        match self {
            Self::AbsoluteError => value / ABSOLUTE_ERROR_FULL_SCALE,
            Self::Ssim => 1.0 - value,
            Self::Flip => value,
            Self::Instability => value / INSTABILITY_FULL_SCALE,
            Self::JodDistortion => value,
        }
    }

    /// The values at the ends of the colour scale, for the legend.
    pub fn scale_ends(self) -> (&'static str, String) {
        match self {
            Self::AbsoluteError => ("0", format!("{ABSOLUTE_ERROR_FULL_SCALE:.0}")),
            Self::Ssim => ("SSIM 1", "0".to_owned()),
            Self::Flip => ("0", "1".to_owned()),
            Self::Instability => ("still", format!("{INSTABILITY_FULL_SCALE:.0}x ref")),
            Self::JodDistortion => ("JOD 10", "JOD 0".to_owned()),
        }
    }

    /// A mean of the map, as the caption under a pane shows it.
    pub fn mean_text(self, mean: f64) -> String {
        match self {
            Self::AbsoluteError => format!("lens MAE {mean:.2}"),
            Self::Ssim => format!("lens SSIM {mean:.4}"),
            Self::Flip => format!("lens FLIP {mean:.4}"),
            Self::Instability => format!("lens instability {mean:.2}"),
            Self::JodDistortion => format!("lens distortion {mean:.3}"),
        }
    }
}

/// The colour of a heat value (0..1).
pub fn heat_color(t: f32) -> egui::Color32 {
    let [r, g, b] = magma().color(t);
    egui::Color32::from_rgb(r, g, b)
}

/// The lens plus [`MARGIN`] pixels around it, inside a `size` frame.
pub fn with_margin(lens: Region, size: (u32, u32)) -> Option<Region> {
    Region {
        x: lens.x.saturating_sub(MARGIN),
        y: lens.y.saturating_sub(MARGIN),
        width: lens.width + 2 * MARGIN,
        height: lens.height + 2 * MARGIN,
    }
    .clipped(size)
}

/// The error heatmap of one pane's lens.
#[derive(Clone, Debug)]
pub struct LensHeatmap {
    /// The lens the map covers.
    pub lens: Region,
    /// One colour per lens pixel, row-major.
    pub colors: egui::ColorImage,
    /// Mean of the metric's map over the lens (SSIM itself for the SSIM map).
    pub mean: f64,
}

impl LensHeatmap {
    /// The colours as an opaque RGBA image (for sheets).
    pub fn to_rgba(&self) -> image::RgbaImage {
        image::RgbaImage::from_fn(self.lens.width, self.lens.height, |x, y| {
            let c = self.colors.pixels[(y * self.lens.width + x) as usize];
            image::Rgba([c.r(), c.g(), c.b(), 255])
        })
    }
}

/// The map of `test` against `reference` (whole frames of equal size) in `lens`, computed on
/// the lens plus margin, and coloured.
pub fn lens_heatmap(
    metric: DiffMetric,
    reference: &image::RgbaImage,
    test: &image::RgbaImage,
    lens: Region,
) -> Result<LensHeatmap, MetricsError> {
    if reference.dimensions() != test.dimensions() {
        return Err(MetricsError::SizeMismatch {
            reference: reference.dimensions(),
            test: test.dimensions(),
        });
    }
    let lens = lens
        .clipped(test.dimensions())
        .ok_or(MetricsError::TooSmall {
            width: 0,
            height: 0,
        })?;
    let area = with_margin(lens, test.dimensions()).ok_or(MetricsError::TooSmall {
        width: 0,
        height: 0,
    })?;
    let map = metric.map(&crop(reference, area), &crop(test, area))?;
    Ok(colored(
        metric,
        &map,
        (lens.x - area.x, lens.y - area.y),
        lens,
    ))
}

/// The heatmap of `lens` from a whole-frame `map` of `metric` (a clip's instability map).
pub fn map_heatmap(
    metric: DiffMetric,
    map: &Plane,
    lens: Region,
) -> Result<LensHeatmap, MetricsError> {
    let lens = lens.clipped(map.size()).ok_or(MetricsError::TooSmall {
        width: 0,
        height: 0,
    })?;
    Ok(colored(metric, map, (lens.x, lens.y), lens))
}

/// The lens's colours and mean from `map`, whose pixel `offset` is the lens's first.
fn colored(metric: DiffMetric, map: &Plane, offset: (u32, u32), lens: Region) -> LensHeatmap {
    let mut pixels = Vec::with_capacity((lens.width * lens.height) as usize);
    let mut sum = 0.0;
    for y in 0..lens.height {
        for x in 0..lens.width {
            let value = map.at(x + offset.0, y + offset.1);
            sum += f64::from(value);
            pixels.push(heat_color(metric.heat(value)));
        }
    }
    LensHeatmap {
        lens,
        colors: egui::ColorImage::new([lens.width as usize, lens.height as usize], pixels),
        mean: sum / f64::from(lens.width * lens.height),
    }
}

/// What a pane's heatmap is made from.
pub enum HeatInput {
    /// The pane's image, compared with the reference.
    Image(Arc<image::RgbaImage>),
    /// A whole-frame map already measured (the clip's instability, the JOD distortion).
    Map(Arc<Plane>),
    /// No map: why.
    Missing(String),
}

/// Heatmaps to compute: the panes' images against the reference in one lens.
pub struct HeatJob {
    /// What the heatmaps will be for.
    pub key: HeatKey,
    /// The reference frame.
    pub reference: Arc<image::RgbaImage>,
    /// The panes' frames.
    pub tests: Vec<(Source, HeatInput)>,
}

/// Identifies one set of heatmaps: same lens, same images, same metric.
#[derive(Clone, Debug, PartialEq)]
pub struct HeatKey {
    /// The lens.
    pub lens: Region,
    /// Serials of the reference and the panes' images.
    pub images: Vec<u64>,
    /// The panes, in the order of `images` after the reference.
    pub sources: Vec<Source>,
    /// The view the images show.
    pub view: u64,
    /// The metric.
    pub metric: DiffMetric,
    /// With the JOD distortion, the generation of the maps published (see
    /// `context::JodMaps`): a map that arrives is drawn.
    pub maps: u64,
}

/// One pane's heatmap, or why there is none.
pub struct HeatResult {
    /// What it was computed for.
    pub key: HeatKey,
    /// The pane.
    pub source: Source,
    /// The heatmap.
    pub heatmap: Result<LensHeatmap, String>,
}

/// Starts the worker computing heatmaps.
pub fn spawn_heat_worker(ctx: &egui::Context) -> std::io::Result<Worker<HeatJob, HeatResult>> {
    Worker::spawn(
        "aa-lab lens heatmaps",
        ctx,
        |job: HeatJob, reporter: &Reporter<HeatResult>| {
            for (source, input) in &job.tests {
                let heatmap = match input {
                    HeatInput::Image(test) => {
                        lens_heatmap(job.key.metric, &job.reference, test, job.key.lens)
                    }
                    HeatInput::Map(map) => map_heatmap(job.key.metric, map, job.key.lens),
                    HeatInput::Missing(reason) => {
                        reporter.send(HeatResult {
                            key: job.key.clone(),
                            source: *source,
                            heatmap: Err(reason.clone()),
                        });
                        continue;
                    }
                }
                .map_err(|e| e.to_string());
                reporter.send(HeatResult {
                    key: job.key.clone(),
                    source: *source,
                    heatmap,
                });
            }
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pair() -> (image::RgbaImage, image::RgbaImage) {
        let reference = image::RgbaImage::from_fn(96, 64, |x, y| {
            let v = ((x * 7 + y * 13) % 256) as u8;
            image::Rgba([v, 255 - v, (x * 3) as u8, 255])
        });
        let test = image::RgbaImage::from_fn(96, 64, |x, y| {
            let p = reference.get_pixel(x, y).0;
            let step = if (x + y / 3) % 5 == 0 { 60 } else { 0 };
            image::Rgba([
                p[0].saturating_add(step),
                p[1],
                p[2].saturating_sub(step),
                255,
            ])
        });
        (reference, test)
    }

    /// With the margin, the lens shows exactly what the map of the whole frame has there, for
    /// every metric, whether the lens is inside the frame or at its corner.
    #[test]
    fn lens_maps_equal_whole_frame_maps() {
        let (reference, test) = pair();
        for metric in DiffMetric::ALL {
            let whole = metric.map(&reference, &test).unwrap();
            for lens in [
                Region {
                    x: 30,
                    y: 20,
                    width: 24,
                    height: 18,
                },
                Region {
                    x: 0,
                    y: 50,
                    width: 20,
                    height: 14,
                },
            ] {
                let heat = lens_heatmap(metric, &reference, &test, lens).unwrap();
                let mut sum = 0.0;
                for y in 0..lens.height {
                    for x in 0..lens.width {
                        let value = whole.at(lens.x + x, lens.y + y);
                        sum += f64::from(value);
                        assert_eq!(
                            heat.colors.pixels[(y * lens.width + x) as usize],
                            heat_color(metric.heat(value)),
                            "{metric:?} at ({x}, {y}) of {lens:?}"
                        );
                    }
                }
                let mean = sum / f64::from(lens.width * lens.height);
                assert!((heat.mean - mean).abs() < 1e-5, "{metric:?}: {}", heat.mean);
            }
        }
    }

    #[test]
    fn instability_heatmaps_colour_the_clip_map_and_refuse_still_pairs() {
        let map = Plane::from_fn(40, 30, |x, y| (x + y) as f32 * 0.25);
        let lens = Region {
            x: 5,
            y: 7,
            width: 10,
            height: 6,
        };
        let heat = map_heatmap(DiffMetric::Instability, &map, lens).unwrap();
        let mut sum = 0.0;
        for y in 0..lens.height {
            for x in 0..lens.width {
                let value = map.at(lens.x + x, lens.y + y);
                sum += f64::from(value);
                assert_eq!(
                    heat.colors.pixels[(y * lens.width + x) as usize],
                    heat_color(value / INSTABILITY_FULL_SCALE)
                );
            }
        }
        assert!((heat.mean - sum / 60.0).abs() < 1e-9);
        let (reference, test) = pair();
        assert!(matches!(
            DiffMetric::Instability.map(&reference, &test),
            Err(MetricsError::NotTemporal)
        ));
    }

    #[test]
    fn identical_images_are_black_and_scales_orient() {
        let (reference, _) = pair();
        let lens = Region {
            x: 10,
            y: 10,
            width: 8,
            height: 8,
        };
        for metric in DiffMetric::ALL {
            let heat = lens_heatmap(metric, &reference, &reference, lens).unwrap();
            let black = heat_color(0.0);
            assert!(heat.colors.pixels.iter().all(|c| *c == black), "{metric:?}");
            assert_eq!(
                heat.to_rgba().get_pixel(3, 3).0,
                [black.r(), black.g(), black.b(), 255]
            );
        }
        assert_eq!(DiffMetric::AbsoluteError.heat(64.0), 1.0);
        assert_eq!(DiffMetric::Ssim.heat(1.0), 0.0);
        assert_eq!(heat_color(f32::NAN), heat_color(0.0));
        assert!(
            lens_heatmap(
                DiffMetric::Flip,
                &reference,
                &image::RgbaImage::new(4, 4),
                lens
            )
            .is_err()
        );
    }
}
