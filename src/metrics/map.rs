//! Per-pixel planes and masks: the common currency of the metrics. A [`Plane`] holds one `f32`
//! per pixel (BT.601 luma of an image, an SSIM map, a FLIP error map, an absolute-error map),
//! row-major from the top-left; a [`Mask`] selects the pixels a score is pooled over (the
//! chart's test elements, for instance). Pooling is done in `f64` so that means over millions
//! of pixels do not drift.

use super::MetricsError;

/// BT.601 luma weights (R', G', B'), applied to sRGB-encoded values.
pub const BT601: [f32; 3] = [0.299, 0.587, 0.114];

/// One `f32` per pixel, row-major from the top-left.
#[derive(Clone, Debug, PartialEq)]
pub struct Plane {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` values.
    pub data: Vec<f32>,
}

impl Plane {
    /// A plane filled with `value`.
    pub fn filled(width: u32, height: u32, value: f32) -> Self {
        Self {
            width,
            height,
            data: vec![value; width as usize * height as usize],
        }
    }

    /// A plane computed pixel by pixel.
    pub fn from_fn(width: u32, height: u32, mut f: impl FnMut(u32, u32) -> f32) -> Self {
        let mut data = Vec::with_capacity(width as usize * height as usize);
        for y in 0..height {
            for x in 0..width {
                data.push(f(x, y));
            }
        }
        Self {
            width,
            height,
            data,
        }
    }

    /// BT.601 luma (`0.299 R' + 0.587 G' + 0.114 B'`) of the sRGB-encoded values, 0..255.
    pub fn luma(image: &image::RgbaImage) -> Self {
        Self {
            width: image.width(),
            height: image.height(),
            data: image.pixels().map(|p| luma_of(p.0)).collect(),
        }
    }

    /// The value at a pixel.
    pub fn at(&self, x: u32, y: u32) -> f32 {
        self.data[y as usize * self.width as usize + x as usize]
    }

    /// Width and height.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// Mean over the pixels `mask` selects (every pixel when `None`), `None` when it selects
    /// nothing.
    pub fn mean(&self, mask: Option<&Mask>) -> Option<f64> {
        let (sum, count) = match mask {
            None => (
                self.data.iter().map(|&v| f64::from(v)).sum::<f64>(),
                self.data.len(),
            ),
            Some(mask) => self
                .data
                .iter()
                .zip(&mask.selected)
                .filter(|(_, selected)| **selected)
                .fold((0.0, 0), |(s, n), (&v, _)| (s + f64::from(v), n + 1)),
        };
        (count > 0).then(|| sum / count as f64)
    }

    /// Smallest and largest value (`(0, 0)` for an empty plane).
    pub fn range(&self) -> (f32, f32) {
        if self.data.is_empty() {
            return (0.0, 0.0);
        }
        self.data
            .iter()
            .fold((f32::MAX, f32::MIN), |(lo, hi), &v| (lo.min(v), hi.max(v)))
    }
}

/// BT.601 luma of one sRGB-encoded RGBA8 pixel, 0..255.
pub fn luma_of(pixel: [u8; 4]) -> f32 {
    BT601[0] * f32::from(pixel[0]) + BT601[1] * f32::from(pixel[1]) + BT601[2] * f32::from(pixel[2])
}

/// A selection of pixels.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Mask {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` flags, row-major.
    pub selected: Vec<bool>,
}

impl Mask {
    /// Selects the pixels for which `f(x, y)` is true.
    pub fn from_fn(width: u32, height: u32, mut f: impl FnMut(u32, u32) -> bool) -> Self {
        let mut selected = Vec::with_capacity(width as usize * height as usize);
        for y in 0..height {
            for x in 0..width {
                selected.push(f(x, y));
            }
        }
        Self {
            width,
            height,
            selected,
        }
    }

    /// Pixels at least `border` pixels away from every image edge.
    pub fn interior(width: u32, height: u32, border: u32) -> Self {
        Self::from_fn(width, height, |x, y| {
            x >= border && y >= border && x + border < width && y + border < height
        })
    }

    /// Pixels selected by both masks (same size assumed; extra pixels are dropped).
    pub fn and(&self, other: &Mask) -> Mask {
        Mask {
            width: self.width,
            height: self.height,
            selected: self
                .selected
                .iter()
                .zip(&other.selected)
                .map(|(a, b)| *a && *b)
                .collect(),
        }
    }

    /// Number of selected pixels.
    pub fn count(&self) -> usize {
        self.selected.iter().filter(|s| **s).count()
    }

    /// Checks that the mask fits an image of `size`.
    pub fn check_size(&self, size: (u32, u32)) -> Result<(), MetricsError> {
        if (self.width, self.height) == size {
            Ok(())
        } else {
            Err(MetricsError::SizeMismatch {
                reference: size,
                test: (self.width, self.height),
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn luma_weights_sum_to_one() {
        assert!((BT601.iter().sum::<f32>() - 1.0).abs() < 1e-6);
        assert!((luma_of([255, 255, 255, 0]) - 255.0).abs() < 1e-3);
        assert_eq!(luma_of([0, 0, 0, 255]), 0.0);
        assert!((luma_of([0, 255, 0, 255]) - 0.587 * 255.0).abs() < 1e-3);
    }

    #[test]
    fn masked_mean_and_interior() {
        let plane = Plane::from_fn(4, 3, |x, y| (x + 10 * y) as f32);
        assert_eq!(
            plane.mean(None),
            Some(plane.data.iter().sum::<f32>() as f64 / 12.0)
        );
        let inner = Mask::interior(4, 3, 1);
        assert_eq!(inner.count(), 2);
        assert_eq!(plane.mean(Some(&inner)), Some(11.5));
        let none = Mask::from_fn(4, 3, |_, _| false);
        assert_eq!(plane.mean(Some(&none)), None);
        assert_eq!(inner.and(&none).count(), 0);
        assert_eq!(plane.range(), (0.0, 23.0));
    }
}
