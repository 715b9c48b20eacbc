//! Text on images without a system font: labels for comparison sheets, heatmap legends,
//! charts and the UI overlay of the frame graph use the Ubuntu Light and Hack faces that egui
//! embeds (`epaint_default_fonts`), rasterised with `ab_glyph`: blended onto RGBA8 images
//! ([`Typeface::draw`]) or handed over as coverage ([`Typeface::coverage`]).

use ab_glyph::{Font, FontRef, PxScale, ScaleFont};

/// A typeface ready to draw.
pub struct Typeface {
    font: FontRef<'static>,
}

impl Typeface {
    /// The proportional face (Ubuntu Light).
    pub fn sans() -> Self {
        Self::from_bytes(epaint_default_fonts::UBUNTU_LIGHT)
    }

    /// The monospace face (Hack), for numbers that should line up.
    pub fn mono() -> Self {
        Self::from_bytes(epaint_default_fonts::HACK_REGULAR)
    }

    fn from_bytes(bytes: &'static [u8]) -> Self {
        // The embedded fonts are valid TrueType files compiled into egui; failure here would be
        // a broken dependency, not user input.
        Self {
            font: FontRef::try_from_slice(bytes).expect("egui's embedded font parses"),
        }
    }

    /// Width in pixels of `text` at `size` pixels.
    pub fn width(&self, text: &str, size: f32) -> f32 {
        let scaled = self.font.as_scaled(PxScale::from(size));
        let mut width = 0.0;
        let mut previous = None;
        for c in text.chars() {
            let id = scaled.glyph_id(c);
            if let Some(p) = previous {
                width += scaled.kern(p, id);
            }
            width += scaled.h_advance(id);
            previous = Some(id);
        }
        width
    }

    /// Draws `text` with its top-left corner at (`x`, `y`), `size` pixels high, blending `color`
    /// (sRGB-encoded RGB) over the image by glyph coverage. Returns the drawn width.
    pub fn draw(
        &self,
        image: &mut image::RgbaImage,
        x: f32,
        y: f32,
        size: f32,
        color: [u8; 3],
        text: &str,
    ) -> f32 {
        self.coverage(x, y, size, text, |px, py, coverage| {
            let (Ok(px), Ok(py)) = (u32::try_from(px), u32::try_from(py)) else {
                return;
            };
            let Some(pixel) = image.get_pixel_mut_checked(px, py) else {
                return;
            };
            for (channel, target) in pixel.0.iter_mut().zip(color) {
                *channel = (f32::from(*channel) * (1.0 - coverage) + f32::from(target) * coverage)
                    .round() as u8;
            }
        })
    }

    /// Rasterises `text` with its top-left corner at (`x`, `y`), `size` pixels high, calling
    /// `plot(x, y, coverage)` for every pixel a glyph covers (positions may fall outside any
    /// image). Returns the width.
    pub fn coverage(
        &self,
        x: f32,
        y: f32,
        size: f32,
        text: &str,
        mut plot: impl FnMut(i64, i64, f32),
    ) -> f32 {
        let scaled = self.font.as_scaled(PxScale::from(size));
        let baseline = y + scaled.ascent();
        let mut caret = x;
        let mut previous = None;
        for c in text.chars() {
            let id = scaled.glyph_id(c);
            if let Some(p) = previous {
                caret += scaled.kern(p, id);
            }
            let glyph =
                id.with_scale_and_position(PxScale::from(size), ab_glyph::point(caret, baseline));
            caret += scaled.h_advance(id);
            previous = Some(id);
            let Some(outline) = self.font.outline_glyph(glyph) else {
                continue;
            };
            let bounds = outline.px_bounds();
            outline.draw(|gx, gy, coverage| {
                plot(
                    bounds.min.x as i64 + i64::from(gx),
                    bounds.min.y as i64 + i64::from(gy),
                    coverage,
                );
            });
        }
        caret - x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_is_drawn_inside_its_measured_width() {
        let face = Typeface::sans();
        let mut image = image::RgbaImage::from_pixel(200, 40, image::Rgba([0, 0, 0, 255]));
        let width = face.draw(&mut image, 10.0, 5.0, 20.0, [255, 255, 255], "MSAA 4x");
        assert!((width - face.width("MSAA 4x", 20.0)).abs() < 0.5);
        let lit: Vec<u32> = image
            .enumerate_pixels()
            .filter(|(_, _, p)| p[0] > 128)
            .map(|(x, _, _)| x)
            .collect();
        assert!(!lit.is_empty());
        assert!(
            lit.iter()
                .all(|&x| x >= 9 && f32::from(x as u16) <= 11.0 + width)
        );
    }
}
