//! What an animation stores for every frame after the first: the pixels that changed from the
//! frame before, in their bounding box, the unchanged ones transparent. The APNG and GIF
//! encoders both start from it.

/// The pixels of a frame that changed from the one before: their bounding box (x, y, width,
/// height) and its RGBA8 pixels, unchanged ones transparent black.
pub struct Change {
    /// The bounding box.
    pub rect: (u32, u32, u32, u32),
    /// Its pixels, row by row.
    pub pixels: Vec<u8>,
}

impl Change {
    /// The change from `before` to `now` (images of one size); a transparent 1x1 pixel at the
    /// origin when nothing changed.
    pub fn between(before: &image::RgbaImage, now: &image::RgbaImage) -> Self {
        let rect = changed_box(before, now);
        let (x, y, width, height) = rect;
        let row = now.width() as usize * 4;
        let mut pixels = Vec::with_capacity(width as usize * height as usize * 4);
        for py in y..y + height {
            let start = py as usize * row + x as usize * 4;
            let end = start + width as usize * 4;
            let (old, new) = (&before.as_raw()[start..end], &now.as_raw()[start..end]);
            for (o, n) in old.chunks_exact(4).zip(new.chunks_exact(4)) {
                pixels.extend_from_slice(if o == n { &[0, 0, 0, 0] } else { n });
            }
        }
        Self { rect, pixels }
    }
}

/// The smallest rectangle (x, y, width, height) holding every pixel that differs between two
/// images of one size; a 1x1 rectangle at the origin when none does.
fn changed_box(a: &image::RgbaImage, b: &image::RgbaImage) -> (u32, u32, u32, u32) {
    let row = (a.width() as usize * 4).max(1);
    let rows = a
        .as_raw()
        .chunks_exact(row)
        .zip(b.as_raw().chunks_exact(row));
    let (mut x0, mut y0, mut x1, mut y1) = (usize::MAX, usize::MAX, 0, 0);
    for (y, (ra, rb)) in rows.enumerate() {
        if ra == rb {
            continue;
        }
        let pixels = || ra.chunks_exact(4).zip(rb.chunks_exact(4));
        let first = pixels().position(|(p, q)| p != q).unwrap_or(0);
        let last = pixels().rposition(|(p, q)| p != q).unwrap_or(first);
        x0 = x0.min(first);
        x1 = x1.max(last);
        y0 = y0.min(y);
        y1 = y;
    }
    if x0 == usize::MAX {
        (0, 0, 1, 1)
    } else {
        let side = |v: usize| u32::try_from(v).unwrap_or(u32::MAX);
        (side(x0), side(y0), side(x1 - x0 + 1), side(y1 - y0 + 1))
    }
}
