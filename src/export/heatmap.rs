//! Heatmaps of per-pixel error maps (SSIM, FLIP, absolute error) with a legend: the map is
//! coloured with magma (perceptually uniform, readable in greyscale; the table comes from the
//! FLIP reference implementation through `nv-flip`), one image pixel per map pixel, and a strip
//! below it holds the colour bar, its scale and what the colours mean. Text uses the embedded
//! fonts of [`super::charts`].

use std::path::Path;
use std::sync::OnceLock;

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::charts::{ChartError, SANS, register_fonts};
use super::png::write_png;
use crate::files::Overwrite;
use crate::metrics::Plane;

/// Height of the legend strip below the map, pixels.
pub const LEGEND_HEIGHT: u32 = 78;
/// Narrowest image: smaller maps are centred on a canvas this wide so the legend stays legible.
pub const MIN_WIDTH: u32 = 420;

/// A 256-entry colour map.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Colormap {
    lut: Vec<[u8; 3]>,
}

impl Colormap {
    /// The colour of `t` in 0..1 (clamped; NaN maps to 0).
    pub fn color(&self, t: f32) -> [u8; 3] {
        let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
        let i = (t * (self.lut.len() - 1) as f32).round() as usize;
        self.lut[i]
    }
}

/// The magma colour map.
pub fn magma() -> &'static Colormap {
    static MAGMA: OnceLock<Colormap> = OnceLock::new();
    MAGMA.get_or_init(|| {
        let lut = nv_flip::magma_lut().to_vec();
        Colormap {
            lut: lut.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
        }
    })
}

/// How to draw a map: what it shows and the value range the colour bar spans.
#[derive(Clone, Copy, Debug)]
pub struct HeatmapStyle<'a> {
    /// What the colours mean, e.g. "FLIP error".
    pub legend: &'a str,
    /// Values mapped to the first and last colour (values outside are clamped).
    pub range: (f32, f32),
}

fn tick_text(value: f32) -> String {
    if value.abs() >= 10.0 || value == value.round() {
        format!("{value:.0}")
    } else {
        format!("{value:.2}")
    }
}

/// Renders a map and its legend into an opaque RGBA image.
pub fn render_heatmap(plane: &Plane, style: &HeatmapStyle<'_>) -> Result<image::RgbaImage, String> {
    register_fonts()?;
    let map = magma();
    let width = plane.width.max(MIN_WIDTH);
    let height = plane.height + LEGEND_HEIGHT;
    let mut rgb = vec![255u8; width as usize * height as usize * 3];
    let left = (width - plane.width) / 2;
    let (lo, hi) = style.range;
    let span = if hi > lo { hi - lo } else { 1.0 };
    let mut put = |x: u32, y: u32, c: [u8; 3]| {
        let i = (y as usize * width as usize + x as usize) * 3;
        rgb[i..i + 3].copy_from_slice(&c);
    };
    for y in 0..plane.height {
        for x in 0..plane.width {
            put(left + x, y, map.color((plane.at(x, y) - lo) / span));
        }
    }
    let bar = (20u32, width - 20, plane.height + 34, plane.height + 50);
    for x in bar.0..bar.1 {
        let c = map.color((x - bar.0) as f32 / (bar.1 - bar.0 - 1) as f32);
        for y in bar.2..bar.3 {
            put(x, y, c);
        }
    }
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (width, height)).into_drawing_area();
        let e = |e: plotters::drawing::DrawingAreaErrorKind<_>| e.to_string();
        root.draw(&Text::new(
            style.legend.to_owned(),
            (bar.0 as i32, plane.height as i32 + 8),
            (SANS, 17).into_font(),
        ))
        .map_err(e)?;
        let ticks = 5;
        for i in 0..ticks {
            let t = i as f32 / (ticks - 1) as f32;
            let x = bar.0 as f32 + t * (bar.1 - bar.0 - 1) as f32;
            let anchor = match i {
                0 => HPos::Left,
                i if i == ticks - 1 => HPos::Right,
                _ => HPos::Center,
            };
            let text = TextStyle::from((SANS, 14).into_font()).pos(Pos::new(anchor, VPos::Top));
            root.draw(&Text::new(
                tick_text(lo + t * span),
                (x as i32, bar.3 as i32 + 4),
                text,
            ))
            .map_err(e)?;
            root.draw(&PathElement::new(
                vec![(x as i32, bar.2 as i32 - 3), (x as i32, bar.2 as i32)],
                BLACK,
            ))
            .map_err(e)?;
        }
        root.present().map_err(e)?;
    }
    let rgb = image::RgbImage::from_raw(width, height, rgb)
        .ok_or_else(|| "heatmap buffer has the wrong size".to_owned())?;
    Ok(image::DynamicImage::ImageRgb8(rgb).to_rgba8())
}

/// Writes a map with its legend as PNG, with `record` (JSON saying how it was made) embedded,
/// atomically under `policy`; returns whether an existing file was replaced.
pub fn write_heatmap(
    path: &Path,
    plane: &Plane,
    style: &HeatmapStyle<'_>,
    record: Option<&str>,
    policy: &Overwrite,
) -> Result<bool, ChartError> {
    let image = render_heatmap(plane, style).map_err(|e| ChartError::draw(path, e))?;
    Ok(write_png(path, &image, record, policy)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn magma_runs_dark_to_light() {
        let m = magma();
        let luma = |c: [u8; 3]| u32::from(c[0]) + u32::from(c[1]) + u32::from(c[2]);
        assert!(luma(m.color(0.0)) < 40);
        assert!(luma(m.color(1.0)) > 600);
        assert!(luma(m.color(0.5)) > luma(m.color(0.25)));
        assert_eq!(m.color(f32::NAN), m.color(0.0));
    }

    #[test]
    fn heatmap_has_map_and_legend() {
        let plane = Plane::from_fn(64, 32, |x, _| x as f32 / 63.0);
        let image = render_heatmap(
            &plane,
            &HeatmapStyle {
                legend: "FLIP error",
                range: (0.0, 1.0),
            },
        )
        .unwrap();
        assert_eq!(image.dimensions(), (MIN_WIDTH, 32 + LEGEND_HEIGHT));
        let left = (MIN_WIDTH - 64) / 2;
        let first = image.get_pixel(left, 0).0;
        assert_eq!(&first[..3], &magma().color(0.0));
        let last = image.get_pixel(left + 63, 31).0;
        assert_eq!(&last[..3], &magma().color(1.0));
        // Legend text: dark pixels in the strip above the colour bar.
        let dark = (0..MIN_WIDTH)
            .flat_map(|x| (32..32 + 30).map(move |y| (x, y)))
            .filter(|&(x, y)| image.get_pixel(x, y).0[0] < 100)
            .count();
        assert!(dark > 30, "{dark}");
    }
}
