//! Edge gain: the share of No AA's error on the reference's edges that a technique removes.
//!
//! SSIM and FLIP pool over the whole image, where texture detail that a post-process technique
//! blurs can outweigh the edges it fixes. Edge gain looks at edges alone:
//!
//! - **edge pixels** are those where the reference has a strong gradient: the Sobel gradient
//!   of its BT.601 luma (of the sRGB-encoded values, 0..1, the border replicated), divided by
//!   4 so that a step of height `h` between two pixels reads `h` on both, has a magnitude of at
//!   least [`EDGE_GRADIENT`];
//! - on them, an image's **edge error** is the sum of its absolute errors against the
//!   reference (mean over R'G'B', as [`super::pixel`] defines them);
//! - **edge gain** = 1 - edge error(technique) / edge error(No AA): 1 when the technique
//!   removes all of No AA's error there, 0 when it removes none, negative when it adds error;
//!   undefined when No AA has no error on the edges (or the reference has no edges).
//!
//! It is the measure issue 31 names for comparing post-process techniques' edge work with
//! their peers' (pmndrs `postprocessing`, Bevy), computed the same way for every image pair.

use super::MetricsError;
use super::map::{Mask, Plane};
use super::pixel;

/// Smallest normalised Sobel magnitude of the reference's luma (0..1) that makes an edge pixel.
pub const EDGE_GRADIENT: f32 = 0.2;

/// The reference's edge pixels (see the module docs).
pub fn edge_mask(reference: &image::RgbaImage) -> Mask {
    let luma = Plane::luma(reference);
    let (w, h) = luma.size();
    let at = |x: i64, y: i64| {
        let cx = x.clamp(0, i64::from(w) - 1) as u32;
        let cy = y.clamp(0, i64::from(h) - 1) as u32;
        luma.at(cx, cy) / 255.0
    };
    Mask::from_fn(w, h, |x, y| {
        let (x, y) = (i64::from(x), i64::from(y));
        let gx = (at(x + 1, y - 1) + 2.0 * at(x + 1, y) + at(x + 1, y + 1))
            - (at(x - 1, y - 1) + 2.0 * at(x - 1, y) + at(x - 1, y + 1));
        let gy = (at(x - 1, y + 1) + 2.0 * at(x, y + 1) + at(x + 1, y + 1))
            - (at(x - 1, y - 1) + 2.0 * at(x, y - 1) + at(x + 1, y - 1));
        (gx * gx + gy * gy).sqrt() / 4.0 >= EDGE_GRADIENT
    })
}

/// Edge gain of `test` over `no_aa`, both scored against `reference` (see the module docs);
/// `None` where No AA has no error on the reference's edges.
pub fn edge_gain(
    reference: &image::RgbaImage,
    no_aa: &image::RgbaImage,
    test: &image::RgbaImage,
) -> Result<Option<f64>, MetricsError> {
    let edges = edge_mask(reference);
    let edge_error = |image: &image::RgbaImage| -> Result<Option<f64>, MetricsError> {
        Ok(pixel::error_maps(reference, image)?
            .abs_error
            .mean(Some(&edges)))
    };
    let (base, technique) = (edge_error(no_aa)?, edge_error(test)?);
    Ok(match (base, technique) {
        (Some(base), Some(technique)) if base > 0.0 => Some(1.0 - technique / base),
        _ => None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A vertical edge at x = 8 of a 16x8 image: black left, white right; pixel 8 holds
    /// `edge` (the antialiased column's value).
    fn edge_image(edge: u8) -> image::RgbaImage {
        image::RgbaImage::from_fn(16, 8, |x, _| {
            let v = match x {
                0..8 => 0,
                8 => edge,
                _ => 255,
            };
            image::Rgba([v, v, v, 255])
        })
    }

    #[test]
    fn edge_pixels_are_the_strong_steps_of_the_reference() {
        let mask = edge_mask(&edge_image(128));
        let columns: Vec<u32> = (0..16).filter(|&x| mask.selected[x as usize]).collect();
        assert_eq!(columns, vec![7, 8, 9]);
        // A faint step (0.1 of the range) is no edge; a flat image has none.
        let faint = image::RgbaImage::from_fn(16, 8, |x, _| {
            let v = if x < 8 { 100 } else { 125 };
            image::Rgba([v, v, v, 255])
        });
        assert!(edge_mask(&faint).selected.iter().all(|s| !s));
    }

    #[test]
    fn edge_gain_is_the_share_of_no_aa_edge_error_removed() {
        let reference = edge_image(128);
        let no_aa = edge_image(255);
        let gain = |test: &image::RgbaImage| edge_gain(&reference, &no_aa, test).unwrap();
        assert_eq!(gain(&reference), Some(1.0));
        assert_eq!(gain(&no_aa), Some(0.0));
        let halfway = gain(&edge_image(192)).unwrap();
        assert!((halfway - 0.5).abs() < 0.01, "{halfway}");
        assert!(gain(&edge_image(0)).unwrap() < 0.0);
        // Error off the edges does not count.
        let mut off_edge = reference.clone();
        off_edge.put_pixel(1, 1, image::Rgba([255, 255, 255, 255]));
        assert_eq!(gain(&off_edge), Some(1.0));
        // No AA without edge error: undefined.
        assert_eq!(edge_gain(&reference, &reference, &no_aa).unwrap(), None);
        assert!(edge_gain(&reference, &no_aa, &image::RgbaImage::new(4, 4)).is_err());
    }
}
