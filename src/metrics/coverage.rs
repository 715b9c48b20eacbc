//! Exact ground truth for the `chart` scene: the area of every pixel that the chart's black
//! polygons cover, computed analytically instead of by sampling.
//!
//! The chart is seen head-on by its camera, so chart units map to pixels by one affine map
//! (a scale and a flip of y; [`ChartLayout::chart_point`] is its inverse). Each convex polygon
//! is mapped to pixel space and, for every pixel its bounding box touches, clipped against the
//! pixel square with Sutherland-Hodgman; the clipped polygon's shoelace area is that polygon's
//! coverage of the pixel. The polygons never overlap, so coverages add. All of this runs in
//! `f64`.
//!
//! The chart is unlit black on white, and the renderer averages samples in linear light, so the
//! ideal pixel is linear `1 - coverage`, stored sRGB-encoded like every render. The zone plate
//! is a texture, whose rendered value depends on mip-mapping rather than geometry: the truth
//! image shows its ideal pattern (8 x 8 samples per pixel) for completeness, but
//! [`ChartTruth::mask`] leaves it out: scores against the truth are taken over the test
//! elements' bounding boxes (grown by two pixels), where the truth is exact.

use glam::{DVec2, Vec2};

use super::map::{Mask, Plane};
use crate::scene::procedural::ChartLayout;

/// Pixels added around each test element's bounding box in [`ChartTruth::mask`].
pub const MASK_MARGIN_PX: f64 = 2.0;

/// The ground truth of one chart image size.
#[derive(Clone, Debug)]
pub struct ChartTruth {
    /// Black coverage per pixel, 0..1.
    pub coverage: Plane,
    /// The ideal image: linear `1 - coverage`, sRGB-encoded, opaque.
    pub image: image::RgbaImage,
    /// The pixels where the truth is exact and the chart has something to test.
    pub mask: Mask,
}

/// The affine map from chart units to pixel coordinates of a `size` image.
struct ChartToPixels {
    center_chart: DVec2,
    center_pixels: DVec2,
    pixels_per_unit: f64,
}

impl ChartToPixels {
    fn new(layout: &ChartLayout, size: (u32, u32)) -> Self {
        let height_units = f64::from(layout.max.y - layout.min.y);
        Self {
            center_chart: (layout.min.as_dvec2() + layout.max.as_dvec2()) * 0.5,
            center_pixels: DVec2::new(f64::from(size.0), f64::from(size.1)) * 0.5,
            pixels_per_unit: f64::from(size.1.max(1)) / height_units,
        }
    }

    fn apply(&self, p: Vec2) -> DVec2 {
        let d = (p.as_dvec2() - self.center_chart) * self.pixels_per_unit;
        self.center_pixels + DVec2::new(d.x, -d.y)
    }
}

/// Shoelace area, absolute.
pub fn polygon_area(points: &[DVec2]) -> f64 {
    let n = points.len();
    (0..n)
        .map(|i| points[i].perp_dot(points[(i + 1) % n]))
        .sum::<f64>()
        .abs()
        * 0.5
}

/// Clips a convex polygon to the half-plane where `inside(p)` holds; `cross(a, b)` gives the
/// point where segment a-b meets the boundary.
fn clip_half_plane(
    points: &[DVec2],
    inside: impl Fn(DVec2) -> bool,
    cross: impl Fn(DVec2, DVec2) -> DVec2,
) -> Vec<DVec2> {
    let mut out = Vec::with_capacity(points.len() + 2);
    for (i, &current) in points.iter().enumerate() {
        let previous = points[(i + points.len() - 1) % points.len()];
        match (inside(previous), inside(current)) {
            (true, true) => out.push(current),
            (true, false) => out.push(cross(previous, current)),
            (false, true) => {
                out.push(cross(previous, current));
                out.push(current);
            }
            (false, false) => {}
        }
    }
    out
}

/// Area of a convex polygon inside the axis-aligned box `min..max` (Sutherland-Hodgman).
pub fn clipped_area(points: &[DVec2], min: DVec2, max: DVec2) -> f64 {
    let at_x = |x: f64| {
        move |a: DVec2, b: DVec2| {
            let t = (x - a.x) / (b.x - a.x);
            DVec2::new(x, a.y + t * (b.y - a.y))
        }
    };
    let at_y = |y: f64| {
        move |a: DVec2, b: DVec2| {
            let t = (y - a.y) / (b.y - a.y);
            DVec2::new(a.x + t * (b.x - a.x), y)
        }
    };
    let mut poly = clip_half_plane(points, |p| p.x >= min.x, at_x(min.x));
    poly = clip_half_plane(&poly, |p| p.x <= max.x, at_x(max.x));
    poly = clip_half_plane(&poly, |p| p.y >= min.y, at_y(min.y));
    poly = clip_half_plane(&poly, |p| p.y <= max.y, at_y(max.y));
    if poly.len() < 3 {
        0.0
    } else {
        polygon_area(&poly)
    }
}

/// Adds the exact coverage of one convex polygon (pixel coordinates) to `coverage`.
pub fn accumulate_coverage(coverage: &mut Plane, points: &[DVec2]) {
    let (w, h) = (i64::from(coverage.width), i64::from(coverage.height));
    let lo = points.iter().fold(DVec2::splat(f64::MAX), |a, &p| a.min(p));
    let hi = points.iter().fold(DVec2::splat(f64::MIN), |a, &p| a.max(p));
    let x0 = (lo.x.floor() as i64).max(0);
    let y0 = (lo.y.floor() as i64).max(0);
    let x1 = (hi.x.ceil() as i64).min(w);
    let y1 = (hi.y.ceil() as i64).min(h);
    for y in y0..y1 {
        for x in x0..x1 {
            let min = DVec2::new(x as f64, y as f64);
            let area = clipped_area(points, min, min + DVec2::ONE);
            if area > 0.0 {
                coverage.data[(y * w + x) as usize] += area as f32;
            }
        }
    }
}

/// sRGB encoding of a linear value in 0..1, rounded to 8 bits.
pub fn encode_srgb(linear: f64) -> u8 {
    crate::srgb::encode_byte_f64(linear)
}

/// The exact ground truth of the chart at an image size (see the module docs).
pub fn chart_truth(layout: &ChartLayout, size: (u32, u32)) -> ChartTruth {
    let map = ChartToPixels::new(layout, size);
    let mut coverage = Plane::filled(size.0, size.1, 0.0);
    for polygon in &layout.polygons {
        let points: Vec<DVec2> = polygon.points.iter().map(|&p| map.apply(p)).collect();
        accumulate_coverage(&mut coverage, &points);
    }
    // Pixel rectangles (min inclusive, max exclusive) of the zone plate and the test elements.
    let rect = |min: Vec2, max: Vec2, margin: f64| {
        let a = map.apply(min);
        let b = map.apply(max);
        let lo = a.min(b) - DVec2::splat(margin);
        let hi = a.max(b) + DVec2::splat(margin);
        (lo.floor(), hi.ceil())
    };
    let contains = |(lo, hi): (DVec2, DVec2), x: u32, y: u32| {
        let p = DVec2::new(f64::from(x), f64::from(y));
        p.x >= lo.x && p.y >= lo.y && p.x < hi.x && p.y < hi.y
    };
    let plate = layout.zone_plate;
    let plate_rect = rect(plate.min, plate.max, 0.0);
    let elements: Vec<(DVec2, DVec2)> = layout
        .regions
        .iter()
        .map(|r| rect(r.min, r.max, MASK_MARGIN_PX))
        .collect();
    let mask = Mask::from_fn(size.0, size.1, |x, y| {
        !contains(plate_rect, x, y) && elements.iter().any(|&r| contains(r, x, y))
    });
    let image = image::RgbaImage::from_fn(size.0, size.1, |x, y| {
        let linear = if contains(plate_rect, x, y) {
            zone_plate_average(layout, size, x, y)
        } else {
            1.0 - f64::from(coverage.at(x, y)).clamp(0.0, 1.0)
        };
        let v = encode_srgb(linear);
        image::Rgba([v, v, v, 255])
    });
    ChartTruth {
        coverage,
        image,
        mask,
    }
}

/// The zone plate's ideal linear intensity averaged over a pixel (8 x 8 samples); white where
/// the pixel leaves the plate.
fn zone_plate_average(layout: &ChartLayout, size: (u32, u32), x: u32, y: u32) -> f64 {
    const N: u32 = 8;
    let plate = layout.zone_plate;
    let mut sum = 0.0;
    for j in 0..N {
        for i in 0..N {
            let pixel = Vec2::new(
                x as f32 + (i as f32 + 0.5) / N as f32,
                y as f32 + (j as f32 + 0.5) / N as f32,
            );
            let p = layout.chart_point(size, pixel);
            let inside = p.cmpge(plate.min).all() && p.cmple(plate.max).all();
            sum += if inside {
                f64::from(plate.intensity(p))
            } else {
                1.0
            };
        }
    }
    sum / f64::from(N * N)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::procedural::chart_layout;

    #[test]
    fn clipping_gives_exact_areas() {
        let square = [
            DVec2::new(0.0, 0.0),
            DVec2::new(2.0, 0.0),
            DVec2::new(2.0, 2.0),
            DVec2::new(0.0, 2.0),
        ];
        assert!((clipped_area(&square, DVec2::ZERO, DVec2::ONE) - 1.0).abs() < 1e-12);
        assert!((clipped_area(&square, DVec2::splat(1.5), DVec2::splat(2.5)) - 0.25).abs() < 1e-12);
        let diagonal = [
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(0.0, 1.0),
        ];
        assert!((clipped_area(&diagonal, DVec2::ZERO, DVec2::ONE) - 0.5).abs() < 1e-12);
        assert_eq!(
            clipped_area(&diagonal, DVec2::splat(3.0), DVec2::splat(4.0)),
            0.0
        );
    }

    #[test]
    fn coverage_of_a_polygon_sums_to_its_area() {
        let mut plane = Plane::filled(8, 8, 0.0);
        let tri = [
            DVec2::new(0.3, 0.2),
            DVec2::new(7.1, 1.9),
            DVec2::new(2.6, 6.4),
        ];
        accumulate_coverage(&mut plane, &tri);
        let total: f64 = plane.data.iter().map(|&v| f64::from(v)).sum();
        assert!((total - polygon_area(&tri)).abs() < 1e-4);
        assert!(plane.data.iter().all(|&v| (0.0..=1.0 + 1e-6).contains(&v)));
    }

    #[test]
    fn chart_truth_covers_the_layout_black_area() {
        let layout = chart_layout();
        let size = (640, 360);
        let truth = chart_truth(&layout, size);
        let pixels_per_unit = 360.0 / f64::from(layout.max.y - layout.min.y);
        let expected = f64::from(layout.black_area()) * pixels_per_unit * pixels_per_unit;
        let total: f64 = truth.coverage.data.iter().map(|&v| f64::from(v)).sum();
        assert!(
            (total - expected).abs() < 1e-3 * expected,
            "{total} vs {expected}"
        );
        assert!(truth.coverage.data.iter().all(|&v| v <= 1.0 + 1e-4));
        // The mask keeps the test elements and drops the zone plate and empty margins.
        let selected = truth.mask.count();
        assert!(
            selected > 640 * 360 / 4 && selected < 640 * 360,
            "{selected}"
        );
        assert_eq!(truth.image.get_pixel(0, 0).0, [255, 255, 255, 255]);
    }

    #[test]
    fn srgb_encoding_end_points() {
        assert_eq!(encode_srgb(0.0), 0);
        assert_eq!(encode_srgb(1.0), 255);
        assert_eq!(encode_srgb(0.215_861), 128);
        assert_eq!(encode_srgb(-1.0), 0);
    }
}
