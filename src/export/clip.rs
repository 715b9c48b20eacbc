//! Clip animations as `aa-lab clip` and the viewer's clip export write them: every frame is a
//! sheet of labelled, nearest-neighbour zoomed panes (one row for a region, as the magnifier
//! shows them; a grid of whole frames otherwise), each captioned with its temporal figures
//! ([`crate::metrics::stability`]), plus the definitions of those figures for the record.

use super::sheet::{self, Cell, Rect, Row, Sheet, TooLarge};
use crate::metrics::stability::{GHOST_THRESHOLD, TemporalScores};

/// The definitions behind the figures, stated in every record.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Definitions {
    /// Luma the figures use.
    pub luma: &'static str,
    /// `temporal_instability`.
    pub temporal_instability: &'static str,
    /// `ghosting`.
    pub ghosting: &'static str,
    /// Threshold of the moving-pixel mask, luma levels.
    pub ghost_threshold: f32,
    /// Pixels and frames the figures are measured over.
    pub measured_over: String,
}

impl Definitions {
    /// The definitions, with the pixels and frames measured over.
    pub fn over(measured_over: String) -> Self {
        Self {
            luma: "BT.601 on 8-bit sRGB-encoded values: 0.299 R' + 0.587 G' + 0.114 B', 0..255",
            temporal_instability: "mean over pixels and frame pairs of |luma(t) - luma(t-1)| of the technique, divided by the same for the reference",
            ghosting: "mean |luma_technique(t) - luma_reference(t)| over the pixels where |luma_reference(t) - luma_reference(t-1)| > ghost_threshold, over all frame pairs",
            ghost_threshold: GHOST_THRESHOLD,
            measured_over,
        }
    }
}

/// One pane of a clip: its label and the caption under it.
#[derive(Clone, Debug)]
pub struct Pane {
    /// Technique label (or the reference's).
    pub label: String,
    /// Figures (already fitted to the pane with [`fit`]).
    pub caption: String,
}

/// How a clip's frames are laid out.
#[derive(Clone, Debug)]
pub struct Layout {
    /// Title of every frame before its number, e.g. `aa-lab clip: atrium, pan 0.25 px/frame`.
    pub title: String,
    /// Row label in region mode (the scene's name).
    pub scene: String,
    /// The region shown (pixels of the render), `None` for whole frames in a grid.
    pub region: Option<Rect>,
    /// Nearest-neighbour zoom of the panes.
    pub zoom: u32,
    /// Footer of every frame.
    pub footer: String,
    /// The panes, in order.
    pub panes: Vec<Pane>,
}

impl Layout {
    /// Frame `number` (0-based) of `total`: `crops` holds each pane's pixels (the region, or
    /// the whole frame), unzoomed.
    pub fn compose(
        &self,
        number: usize,
        total: usize,
        crops: &[&image::RgbaImage],
    ) -> Result<image::RgbaImage, TooLarge> {
        let cells = crops
            .iter()
            .map(|crop| {
                let whole = Rect {
                    x: 0,
                    y: 0,
                    width: crop.width(),
                    height: crop.height(),
                };
                sheet::crop_zoom(crop, whole, self.zoom)
            })
            .collect::<Result<Vec<_>, _>>()?;
        let title = format!("{}, frame {}/{total}", self.title, number + 1);
        let footer = Some(self.footer.clone());
        let sheet = match self.region {
            Some(rect) => Sheet {
                title,
                columns: self.panes.iter().map(|p| p.label.clone()).collect(),
                rows: vec![Row {
                    label: self.scene.clone(),
                    detail: Some(format!(
                        "{}x{} at {},{}, {}x",
                        rect.width, rect.height, rect.x, rect.y, self.zoom
                    )),
                    cells: cells
                        .into_iter()
                        .zip(&self.panes)
                        .map(|(image, pane)| Cell {
                            image,
                            caption: Some(pane.caption.clone()),
                        })
                        .collect(),
                }],
                footer,
            },
            None => {
                let width = crops.first().map_or(1, |c| c.width()) * self.zoom;
                let mut cells: Vec<Cell> = cells
                    .into_iter()
                    .zip(&self.panes)
                    .map(|(image, pane)| Cell {
                        image,
                        caption: Some(fit(
                            &[
                                format!("{}: {}", pane.label, pane.caption),
                                pane.label.clone(),
                            ],
                            width,
                        )),
                    })
                    .collect();
                let mut rows = Vec::new();
                let columns = columns(self.panes.len(), false);
                while !cells.is_empty() {
                    let rest = cells.split_off(columns.min(cells.len()));
                    rows.push(Row {
                        label: String::new(),
                        detail: None,
                        cells,
                    });
                    cells = rest;
                }
                Sheet {
                    title,
                    columns: Vec::new(),
                    rows,
                    footer,
                }
            }
        };
        // Grid rows may have fewer cells than the first: compose pads them to one size.
        Ok(sheet::compose(&sheet))
    }
}

/// Columns of a clip of `panes` panes: all in one row with a region, else the about square
/// grid of whole frames.
pub fn columns(panes: usize, region: bool) -> usize {
    if region {
        panes.max(1)
    } else {
        (1..=panes.max(1))
            .find(|c| c * c >= panes)
            .unwrap_or(panes.max(1))
    }
}

/// Checks that the frames of `panes` panes of `pane_size` pixels (the region's, or the whole
/// frame's) zoomed `zoom` times stay within the sheet limits.
pub fn check(panes: usize, region: bool, pane_size: (u32, u32), zoom: u32) -> Result<(), TooLarge> {
    let columns = columns(panes, region);
    let pane = Rect {
        x: 0,
        y: 0,
        width: pane_size.0,
        height: pane_size.1,
    };
    sheet::check_layout(columns, &vec![pane; panes.div_ceil(columns)], zoom)
}

/// A figure with `digits` decimals, `n/a` when undefined.
pub fn figure(value: Option<f64>, digits: usize) -> String {
    value.map_or_else(|| "n/a".to_owned(), |v| format!("{v:.digits$}"))
}

/// The caption of a technique's pane: `instability 1.23  ghosting 4.5`.
pub fn caption(scores: &TemporalScores) -> String {
    format!(
        "instability {}  ghosting {}",
        figure(scores.temporal_instability, 2),
        figure(scores.ghosting, 1)
    )
}

/// The short caption of narrow panes: `1.23 / 4.5`.
pub fn short_caption(scores: &TemporalScores) -> String {
    format!(
        "{} / {}",
        figure(scores.temporal_instability, 2),
        figure(scores.ghosting, 1)
    )
}

/// The caption of the reference's pane, its mean change per frame, in `width` pixels.
pub fn reference_caption(mean_change: Option<f64>, width: u32) -> String {
    let change = figure(mean_change, 2);
    fit(
        &[format!("change {change}/frame"), format!("{change}/frame")],
        width,
    )
}

/// The first text that fits in `width` pixels as a sheet caption, else the last one (the
/// figures are in the record either way).
pub fn fit(texts: &[String], width: u32) -> String {
    let sans = crate::text::Typeface::sans();
    texts
        .iter()
        .find(|t| sans.width(t, sheet::CAPTION_SIZE) <= width as f32)
        .or(texts.last())
        .cloned()
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grids_are_about_square_and_regions_one_row() {
        assert_eq!(columns(1, false), 1);
        assert_eq!(columns(4, false), 2);
        assert_eq!(columns(5, false), 3);
        assert_eq!(columns(9, false), 3);
        assert_eq!(columns(5, true), 5);
    }

    #[test]
    fn a_region_lays_every_pane_in_one_zoomed_row() {
        let layout = Layout {
            title: "clip".to_owned(),
            scene: "chart".to_owned(),
            region: Some(Rect {
                x: 0,
                y: 0,
                width: 8,
                height: 4,
            }),
            zoom: 3,
            footer: String::new(),
            panes: vec![
                Pane {
                    label: "A".to_owned(),
                    caption: "a".to_owned(),
                };
                3
            ],
        };
        let crop = image::RgbaImage::from_pixel(8, 4, image::Rgba([200, 10, 10, 255]));
        let frame = layout.compose(0, 2, &[&crop, &crop, &crop]).unwrap();
        assert!(
            frame.width() >= 3 * 8 * 3,
            "three panes of 24 pixels side by side"
        );
        assert!(check(3, true, (8, 4), 3).is_ok());
        assert!(check(3, true, (100_000, 4), 3).is_err());
    }
}
