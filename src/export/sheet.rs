//! Comparison sheets: a grid of zoomed crops, one column per technique and one row per image
//! region, with column headers, row labels and optional per-cell captions (metrics). Crops are
//! enlarged with nearest-neighbour sampling so every source pixel stays a crisp square: a sheet
//! shows exactly the pixels each technique produced.
//!
//! Sizes are bounded: a zoomed crop is at most [`MAX_SHEET_SIDE`] pixels a side, and
//! [`check_layout`] refuses a sheet wider or taller than that (or of more than
//! [`MAX_SHEET_PIXELS`] pixels) before anything is rendered.

use crate::text::Typeface;

/// A rectangle of an image in pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Rect {
    /// Left.
    pub x: u32,
    /// Top.
    pub y: u32,
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
}

impl Rect {
    /// The rectangle moved and shrunk to lie inside an image of `size` (at least 1x1).
    pub fn clamped(self, size: (u32, u32)) -> Self {
        let x = self.x.min(size.0.saturating_sub(1));
        let y = self.y.min(size.1.saturating_sub(1));
        Self {
            x,
            y,
            width: self.width.clamp(1, size.0 - x),
            height: self.height.clamp(1, size.1 - y),
        }
    }
}

/// Longest side of a sheet and of any zoomed crop, in pixels.
pub const MAX_SHEET_SIDE: u64 = 16384;
/// Most pixels of a sheet (256 MiB of RGBA).
pub const MAX_SHEET_PIXELS: u64 = 1 << 26;

/// A sheet or crop that would not fit in reasonable memory.
#[derive(Debug, thiserror::Error)]
#[error(
    "{what} would be {width}x{height} pixels; sheets are limited to {MAX_SHEET_SIDE} pixels a \
     side and {MAX_SHEET_PIXELS} pixels in all (lower --zoom or the region size, or use fewer \
     techniques)"
)]
pub struct TooLarge {
    /// What was measured (`the sheet`, `a zoomed crop`).
    pub what: &'static str,
    /// Width it would have.
    pub width: u64,
    /// Height it would have.
    pub height: u64,
}

fn check_side(what: &'static str, width: u64, height: u64) -> Result<(), TooLarge> {
    if width > MAX_SHEET_SIDE || height > MAX_SHEET_SIDE || width * height > MAX_SHEET_PIXELS {
        Err(TooLarge {
            what,
            width,
            height,
        })
    } else {
        Ok(())
    }
}

/// The size of a sheet of `columns` cells per row, one row per crop in `regions`, each
/// zoomed `zoom` times, without its labels: refused when over the limits (see the module docs).
pub fn check_layout(columns: usize, regions: &[Rect], zoom: u32) -> Result<(), TooLarge> {
    let zoom = u64::from(zoom.max(1));
    let cell_width = regions
        .iter()
        .map(|r| u64::from(r.width))
        .max()
        .unwrap_or(1)
        * zoom;
    let columns = columns.max(1) as u64;
    let width = u64::from(MARGIN * 2) + columns * (cell_width + u64::from(GAP));
    let height: u64 = regions
        .iter()
        .map(|r| u64::from(r.height) * zoom + u64::from(GAP))
        .sum::<u64>()
        + u64::from(MARGIN);
    check_side("the sheet", width, height)
}

/// `rect` of `image` enlarged `zoom` times with nearest-neighbour sampling; refused when the
/// result is over the limits (see the module docs).
pub fn crop_zoom(
    image: &image::RgbaImage,
    rect: Rect,
    zoom: u32,
) -> Result<image::RgbaImage, TooLarge> {
    let rect = rect.clamped(image.dimensions());
    let zoom = zoom.max(1);
    let width = u64::from(rect.width) * u64::from(zoom);
    let height = u64::from(rect.height) * u64::from(zoom);
    check_side("a zoomed crop", width, height)?;
    // Both fit in u32: they are at most MAX_SHEET_SIDE.
    Ok(image::RgbaImage::from_fn(
        width as u32,
        height as u32,
        |x, y| *image.get_pixel(rect.x + x / zoom, rect.y + y / zoom),
    ))
}

/// One cell: an already zoomed crop and an optional caption under it.
pub struct Cell {
    /// The pixels.
    pub image: image::RgbaImage,
    /// Caption (e.g. `SSIM 0.962`).
    pub caption: Option<String>,
}

/// A row: its label and one cell per column.
pub struct Row {
    /// Label on the left (e.g. `diagonals`).
    pub label: String,
    /// Second label line (e.g. the scene and region).
    pub detail: Option<String>,
    /// Cells, one per column.
    pub cells: Vec<Cell>,
}

/// A whole sheet.
pub struct Sheet {
    /// Title line at the top.
    pub title: String,
    /// Column headers (technique names).
    pub columns: Vec<String>,
    /// Rows.
    pub rows: Vec<Row>,
    /// Footer line (scene, frame, adapter...).
    pub footer: Option<String>,
}

const BACKGROUND: [u8; 3] = [24, 25, 30];
/// The background colour as an opaque RGBA8 pixel (what pads a video's odd sides).
pub const BACKGROUND_RGBA: [u8; 4] = [BACKGROUND[0], BACKGROUND[1], BACKGROUND[2], 255];
const FRAME: [u8; 3] = [70, 72, 80];
const TEXT: [u8; 3] = [232, 232, 236];
const DIM_TEXT: [u8; 3] = [150, 152, 160];
const MARGIN: u32 = 16;
const GAP: u32 = 8;
const TITLE: f32 = 22.0;
const HEADER: f32 = 17.0;
const SMALL: f32 = 14.0;
/// Text size of cell captions, pixels.
pub const CAPTION_SIZE: f32 = SMALL;

fn fill(image: &mut image::RgbaImage, x: u32, y: u32, w: u32, h: u32, color: [u8; 3]) {
    for py in y..(y + h).min(image.height()) {
        for px in x..(x + w).min(image.width()) {
            image.put_pixel(px, py, image::Rgba([color[0], color[1], color[2], 255]));
        }
    }
}

/// Lays the sheet out and draws it.
pub fn compose(sheet: &Sheet) -> image::RgbaImage {
    let sans = Typeface::sans();
    let columns = sheet
        .columns
        .len()
        .max(sheet.rows.iter().map(|r| r.cells.len()).max().unwrap_or(0)) as u32;
    let cell_width = sheet
        .rows
        .iter()
        .flat_map(|r| &r.cells)
        .map(|c| c.image.width())
        .max()
        .unwrap_or(1);
    let has_captions = sheet
        .rows
        .iter()
        .flat_map(|r| &r.cells)
        .any(|c| c.caption.is_some());
    let caption_height = if has_captions { SMALL as u32 + 6 } else { 0 };
    let label_width = sheet
        .rows
        .iter()
        .flat_map(|r| {
            std::iter::once(sans.width(&r.label, HEADER))
                .chain(r.detail.iter().map(|d| sans.width(d, SMALL)))
        })
        .fold(0.0f32, f32::max)
        .ceil() as u32
        + GAP * 2;
    let title_height = TITLE as u32 + GAP * 2;
    let header_height = HEADER as u32 + GAP;
    let row_heights: Vec<u32> = sheet
        .rows
        .iter()
        .map(|r| r.cells.iter().map(|c| c.image.height()).max().unwrap_or(1) + caption_height)
        .collect();
    let footer_height = if sheet.footer.is_some() {
        SMALL as u32 + GAP * 2
    } else {
        GAP
    };
    let width = MARGIN * 2 + label_width + columns * (cell_width + GAP);
    let height = MARGIN
        + title_height
        + header_height
        + row_heights.iter().map(|h| h + GAP).sum::<u32>()
        + footer_height;
    let mut out = image::RgbaImage::from_pixel(
        width,
        height,
        image::Rgba([BACKGROUND[0], BACKGROUND[1], BACKGROUND[2], 255]),
    );

    sans.draw(
        &mut out,
        MARGIN as f32,
        MARGIN as f32,
        TITLE,
        TEXT,
        &sheet.title,
    );
    let mut y = MARGIN + title_height;
    for (i, name) in sheet.columns.iter().enumerate() {
        let x = MARGIN + label_width + i as u32 * (cell_width + GAP);
        let text_x = x as f32 + (cell_width as f32 - sans.width(name, HEADER)).max(0.0) / 2.0;
        sans.draw(&mut out, text_x, y as f32, HEADER, TEXT, name);
    }
    y += header_height;
    for (row, row_height) in sheet.rows.iter().zip(&row_heights) {
        sans.draw(
            &mut out,
            MARGIN as f32,
            (y + GAP) as f32,
            HEADER,
            TEXT,
            &row.label,
        );
        if let Some(detail) = &row.detail {
            sans.draw(
                &mut out,
                MARGIN as f32,
                (y + GAP) as f32 + HEADER + 4.0,
                SMALL,
                DIM_TEXT,
                detail,
            );
        }
        for (i, cell) in row.cells.iter().enumerate() {
            let x = MARGIN + label_width + i as u32 * (cell_width + GAP);
            fill(
                &mut out,
                x.saturating_sub(1),
                y.saturating_sub(1),
                cell.image.width() + 2,
                cell.image.height() + 2,
                FRAME,
            );
            image::imageops::replace(&mut out, &cell.image, i64::from(x), i64::from(y));
            if let Some(caption) = &cell.caption {
                let text_x = x as f32
                    + (cell.image.width() as f32 - sans.width(caption, SMALL)).max(0.0) / 2.0;
                sans.draw(
                    &mut out,
                    text_x,
                    (y + cell.image.height() + 3) as f32,
                    SMALL,
                    DIM_TEXT,
                    caption,
                );
            }
        }
        y += row_height + GAP;
    }
    if let Some(footer) = &sheet.footer {
        sans.draw(
            &mut out,
            MARGIN as f32,
            (y + GAP / 2) as f32,
            SMALL,
            DIM_TEXT,
            footer,
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crop_zoom_keeps_pixels_square_and_clamps() {
        let image = image::RgbaImage::from_fn(4, 4, |x, y| {
            image::Rgba([(x * 60) as u8, (y * 60) as u8, 0, 255])
        });
        let z = crop_zoom(
            &image,
            Rect {
                x: 1,
                y: 2,
                width: 2,
                height: 2,
            },
            3,
        )
        .unwrap();
        assert_eq!(z.dimensions(), (6, 6));
        assert_eq!(z.get_pixel(0, 0), image.get_pixel(1, 2));
        assert_eq!(z.get_pixel(2, 2), image.get_pixel(1, 2));
        assert_eq!(z.get_pixel(3, 5), image.get_pixel(2, 3));
        let clamped = crop_zoom(
            &image,
            Rect {
                x: 3,
                y: 3,
                width: 10,
                height: 10,
            },
            1,
        )
        .unwrap();
        assert_eq!(clamped.dimensions(), (1, 1));
    }

    /// `--zoom 100000` asked for 122 TB and `--zoom 2147483648` wrapped (issue 10, items 4
    /// and 6): both are refused with the limit.
    #[test]
    fn oversized_zooms_are_refused_with_the_limit() {
        let image = image::RgbaImage::new(64, 48);
        let region = Rect {
            x: 0,
            y: 0,
            width: 64,
            height: 48,
        };
        for zoom in [1000, 100_000, 2_147_483_648] {
            let err = crop_zoom(&image, region, zoom).unwrap_err();
            assert!(err.to_string().contains("16384"), "{err}");
            assert!(check_layout(12, &[region], zoom).is_err());
        }
        assert!(check_layout(12, &[region; 5], 5).is_ok());
        assert!(check_layout(400, &[region; 5], 5).is_err());
    }

    #[test]
    fn sheet_places_every_cell() {
        let cell = |v: u8| Cell {
            image: image::RgbaImage::from_pixel(40, 30, image::Rgba([v, v, v, 255])),
            caption: Some("x".into()),
        };
        let sheet = Sheet {
            title: "test".into(),
            columns: vec!["a".into(), "b".into()],
            rows: vec![Row {
                label: "row".into(),
                detail: None,
                cells: vec![cell(200), cell(100)],
            }],
            footer: Some("footer".into()),
        };
        let out = compose(&sheet);
        let count = |v: u8| {
            out.pixels()
                .filter(|p| p[0] == v && p[1] == v && p[2] == v)
                .count()
        };
        assert_eq!(count(200), 40 * 30);
        assert_eq!(count(100), 40 * 30);
    }
}
