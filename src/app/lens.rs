//! The magnifier's lens as the features share it: where it is in the frame ([`lens_region`]),
//! what a pane shows ([`Source`]), cutting the lens out of an image ([`crop`]) and the margin
//! read around it for windowed metrics ([`MARGIN`]). The magnifier draws it, the difference
//! heatmaps, export sheets and blind answers read it; this file imports nothing of the viewer.

use crate::gpu::readback::Region;

/// Pixels read around the lens, so that windowed metrics see context: more than SSIM's window
/// radius (5) and FLIP's widest filter radius (10 at 67 pixels per degree).
pub const MARGIN: u32 = 12;

/// The lens rectangle in frame pixels: `side` pixels square around `center` (the frame
/// centre when there is none), moved inside the frame.
pub fn lens_region(center: Option<[f32; 2]>, side: u32, size: (u32, u32)) -> Option<Region> {
    if side == 0 || size.0 == 0 || size.1 == 0 {
        return None;
    }
    let [cx, cy] = center.unwrap_or([size.0 as f32 * 0.5, size.1 as f32 * 0.5]);
    let place = |c: f32, extent: u32| {
        let side = side.min(extent);
        let start = (c - side as f32 * 0.5).round().max(0.0) as u32;
        (start.min(extent - side), side)
    };
    let (x, width) = place(if cx.is_finite() { cx } else { 0.0 }, size.0);
    let (y, height) = place(if cy.is_finite() { cy } else { 0.0 }, size.1);
    Some(Region {
        x,
        y,
        width,
        height,
    })
}

/// Where a pane's pixels come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Source {
    /// A compared technique (slot 0 = A) by id.
    Technique(usize, &'static str),
    /// The reference.
    Reference,
}

/// Pixels of `region` of an image.
pub fn crop(image: &image::RgbaImage, region: Region) -> image::RgbaImage {
    image::imageops::crop_imm(image, region.x, region.y, region.width, region.height).to_image()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lens_stays_inside_the_frame() {
        let mut center = None;
        let r = lens_region(center, 32, (100, 50)).unwrap();
        assert_eq!((r.x, r.y, r.width, r.height), (34, 9, 32, 32));
        center = Some([-50.0, 1000.0]);
        let r = lens_region(center, 32, (100, 50)).unwrap();
        assert_eq!((r.x, r.y), (0, 18));
        let r = lens_region(center, 80, (100, 50)).unwrap();
        assert_eq!((r.width, r.height), (80, 50));
        assert!(lens_region(center, 0, (100, 50)).is_none());
        center = Some([f32::NAN, 3.0]);
        assert!(lens_region(center, 8, (100, 50)).is_some());
    }
}
