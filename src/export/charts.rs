//! PNG charts for reports, drawn with plotters on its bitmap backend. Text uses a font embedded
//! in the binary (Ubuntu Light from `epaint_default_fonts`, registered with plotters' `ab_glyph`
//! renderer on first use as its default `sans-serif` family), so charts render identically on
//! machines without fontconfig or any system font.
//!
//! Three chart kinds cover the reports: horizontal bar charts ([`BarChart`]: one row per
//! technique, bars grouped or stacked by series, each labelled with its value), line charts
//! ([`LineChart`]: scaling curves, one line per technique, optional log-scale y axis) and
//! trade-off charts (cost against quality with the Pareto front, in [`super::tradeoff`],
//! which draws on the helpers here).

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use plotters::coord::ranged1d::ValueFormatter;
use plotters::prelude::*;
use plotters::style::FontStyle;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::png::{ExportError, write_png};
use crate::files::Overwrite;

/// Family name the sans-serif UI font is registered under (plotters' default family).
pub const SANS: &str = "sans-serif";

/// Errors of drawing charts and heatmaps.
#[derive(Debug, thiserror::Error)]
pub enum ChartError {
    /// Plotters failed (the file could not be written, or a font failed to load).
    #[error("cannot draw {path}: {reason}")]
    Draw {
        /// The output path.
        path: PathBuf,
        /// Plotters' message.
        reason: String,
    },
    /// Writing the PNG failed.
    #[error(transparent)]
    Export(#[from] ExportError),
    /// A chart has nothing to show.
    #[error("cannot draw {0}: the chart has no data")]
    Empty(PathBuf),
}

impl ChartError {
    pub(crate) fn draw(path: &Path, reason: impl std::fmt::Display) -> Self {
        Self::Draw {
            path: path.to_owned(),
            reason: reason.to_string(),
        }
    }
}

/// Registers the embedded fonts with plotters (idempotent); `Err` names the font that failed.
pub fn register_fonts() -> Result<(), String> {
    static REGISTERED: OnceLock<Result<(), String>> = OnceLock::new();
    REGISTERED
        .get_or_init(|| {
            plotters::style::register_font(
                SANS,
                FontStyle::Normal,
                epaint_default_fonts::UBUNTU_LIGHT,
            )
            .map_err(|_| "the embedded Ubuntu Light font is not a valid font".to_owned())
        })
        .clone()
}

/// Colour-blind-safe series colours (Okabe and Ito), in series order.
pub const PALETTE: [RGBColor; 8] = [
    RGBColor(0, 114, 178),
    RGBColor(230, 159, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(86, 180, 233),
    RGBColor(213, 94, 0),
    RGBColor(240, 228, 66),
    RGBColor(0, 0, 0),
];

/// The colour of series `i`.
pub fn series_color(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// How the series of a [`BarChart`] share a row.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BarLayout {
    /// Side by side (one thin bar per series).
    Grouped,
    /// End to end (the row's total is the sum).
    Stacked,
}

/// One series of bars: a value per category (`NaN` where it has none).
#[derive(Clone, Debug)]
pub struct BarSeries {
    /// Legend name.
    pub name: String,
    /// One value per category.
    pub values: Vec<f64>,
}

/// A horizontal bar chart.
#[derive(Clone, Debug)]
pub struct BarChart<'a> {
    /// Title above the chart.
    pub title: &'a str,
    /// Description of the value axis.
    pub value_label: &'a str,
    /// Row names, top to bottom.
    pub categories: &'a [String],
    /// The series.
    pub series: &'a [BarSeries],
    /// Grouped or stacked.
    pub layout: BarLayout,
    /// Value axis range; `None` runs from 0 to a little past the largest bar.
    pub range: Option<(f64, f64)>,
    /// Decimals of the value labels.
    pub decimals: usize,
}

pub(super) fn drawing_error<E: std::error::Error + Send + Sync>(
    path: &Path,
) -> impl Fn(plotters::drawing::DrawingAreaErrorKind<E>) -> ChartError + '_ {
    move |e| ChartError::draw(path, e)
}

/// Draws the axes, grid and axis titles every x-y chart shares (numbers without trailing zeros).
pub(super) fn draw_axes<'a, X, Y>(
    ctx: &mut ChartContext<'a, BitMapBackend<'a>, Cartesian2d<X, Y>>,
    x_label: &str,
    y_label: &str,
    path: &Path,
) -> Result<(), ChartError>
where
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let number = |v: &f64| format_number(*v);
    ctx.configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .x_label_formatter(&number)
        .y_label_formatter(&number)
        .axis_desc_style((SANS, 17))
        .label_style((SANS, 15))
        .light_line_style(RGBColor(238, 238, 238))
        .draw()
        .map_err(drawing_error(path))
}

/// Axis numbers without trailing zeros (`2000`, `0.25`).
pub fn format_number(value: f64) -> String {
    let text = format!("{value:.3}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    if text == "-0" {
        "0".to_owned()
    } else {
        text.to_owned()
    }
}

/// Draws a row of legend entries (colour box and name per series) at height `y` of `area`.
fn draw_legend<'n, DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    names: impl Iterator<Item = &'n str>,
    y: i32,
) -> Result<(), plotters::drawing::DrawingAreaErrorKind<DB::ErrorType>> {
    let mut x = 20;
    for (i, name) in names.enumerate() {
        area.draw(&Rectangle::new(
            [(x, y - 7), (x + 16, y + 7)],
            series_color(i).filled(),
        ))?;
        let style = TextStyle::from((SANS, 16).into_font()).pos(Pos::new(HPos::Left, VPos::Center));
        area.draw(&Text::new(name.to_owned(), (x + 22, y), style))?;
        x += 22 + 9 * name.chars().count() as i32 + 28;
    }
    Ok(())
}

/// A chart's drawing area over an RGB buffer.
pub(super) type Canvas<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;

/// A white canvas of `size` over `pixels` with `title` in a header `header` pixels high:
/// (the whole canvas, the header, the body below it).
pub(super) fn titled_canvas<'a>(
    pixels: &'a mut [u8],
    size: (u32, u32),
    title: &str,
    header: u32,
    path: &Path,
) -> Result<(Canvas<'a>, Canvas<'a>, Canvas<'a>), ChartError> {
    let root = BitMapBackend::with_buffer(pixels, size).into_drawing_area();
    let err = drawing_error(path);
    root.fill(&WHITE).map_err(&err)?;
    let (top, body) = root.split_vertically(header);
    top.draw(&Text::new(
        title.to_owned(),
        (16, 12),
        (SANS, 24).into_font(),
    ))
    .map_err(&err)?;
    Ok((root, top, body))
}

/// Writes a chart drawn into an RGB buffer as PNG, atomically under `policy`.
pub(super) fn save_chart(
    path: &Path,
    pixels: Vec<u8>,
    size: (u32, u32),
    policy: &Overwrite,
) -> Result<bool, ChartError> {
    let image = image::RgbImage::from_raw(size.0, size.1, pixels)
        .ok_or_else(|| ChartError::draw(path, "the chart buffer has the wrong size"))?;
    let image = image::DynamicImage::ImageRgb8(image).to_rgba8();
    Ok(write_png(path, &image, None, policy)?)
}

/// Draws a [`BarChart`] to a PNG file (atomically, under `policy`); returns whether an
/// existing file was replaced.
pub fn draw_bars(
    path: &Path,
    chart: &BarChart<'_>,
    policy: &Overwrite,
) -> Result<bool, ChartError> {
    register_fonts().map_err(|e| ChartError::draw(path, e))?;
    let rows = chart.categories.len();
    if rows == 0 || chart.series.is_empty() {
        return Err(ChartError::Empty(path.to_owned()));
    }
    let row_total = |row: usize| -> f64 {
        let values = chart
            .series
            .iter()
            .map(|s| s.values.get(row).copied().unwrap_or(f64::NAN));
        match chart.layout {
            BarLayout::Stacked => values.filter(|v| v.is_finite()).sum(),
            BarLayout::Grouped => values.filter(|v| v.is_finite()).fold(0.0, f64::max),
        }
    };
    let largest = (0..rows).map(row_total).fold(0.0, f64::max);
    let (lo, hi) = chart
        .range
        .unwrap_or((0.0, if largest > 0.0 { largest * 1.18 } else { 1.0 }));
    let bar_rows = match chart.layout {
        BarLayout::Grouped => chart.series.len(),
        BarLayout::Stacked => 1,
    };
    let legend = chart.series.len() > 1;
    let header: u32 = if legend { 76 } else { 48 };
    let height = (header + 70 + (rows * (18 + 16 * bar_rows)) as u32).clamp(240, 1400);
    let size = (960, height);
    let mut pixels = vec![255u8; size.0 as usize * size.1 as usize * 3];
    {
        let (root, top, body) = titled_canvas(&mut pixels, size, chart.title, header, path)?;
        let err = drawing_error(path);
        if legend {
            draw_legend(&top, chart.series.iter().map(|s| s.name.as_str()), 48).map_err(&err)?;
        }
        let label_width = chart
            .categories
            .iter()
            .map(|c| c.chars().count())
            .max()
            .unwrap_or(4) as u32
            * 9
            + 20;
        let mut ctx = ChartBuilder::on(&body)
            .margin(16)
            .margin_top(4)
            .x_label_area_size(44)
            .y_label_area_size(label_width.clamp(80, 320))
            .build_cartesian_2d(lo..hi, 0.0..rows as f64)
            .map_err(&err)?;
        let number = |v: &f64| format_number(*v);
        ctx.configure_mesh()
            .disable_y_mesh()
            .y_labels(0)
            .x_label_formatter(&number)
            .x_desc(chart.value_label)
            .axis_desc_style((SANS, 17))
            .label_style((SANS, 15))
            .light_line_style(RGBColor(238, 238, 238))
            .draw()
            .map_err(&err)?;
        let slot = 0.78 / bar_rows as f64;
        for (s, series) in chart.series.iter().enumerate() {
            let color = series_color(s);
            let mut bars = Vec::new();
            let mut labels = Vec::new();
            for row in 0..rows {
                let value = series.values.get(row).copied().unwrap_or(f64::NAN);
                if !value.is_finite() {
                    continue;
                }
                // Row 0 at the top.
                let top = (rows - row) as f64 - 0.11;
                let (start, end, y0) = match chart.layout {
                    BarLayout::Grouped => (lo, value, top - s as f64 * slot),
                    BarLayout::Stacked => {
                        let before: f64 = chart.series[..s]
                            .iter()
                            .filter_map(|o| o.values.get(row).copied().filter(|v| v.is_finite()))
                            .sum();
                        (lo + before, lo + before + value, top)
                    }
                };
                bars.push(Rectangle::new(
                    [(start, y0), (end.max(start), y0 - slot)],
                    color.filled(),
                ));
                let last_of_row = chart.series[s + 1..]
                    .iter()
                    .all(|o| !o.values.get(row).is_some_and(|v| v.is_finite()));
                if chart.layout == BarLayout::Grouped || last_of_row {
                    let shown = if chart.layout == BarLayout::Stacked {
                        row_total(row)
                    } else {
                        value
                    };
                    labels.push((end.max(start), y0 - slot * 0.5, shown));
                }
            }
            ctx.draw_series(bars).map_err(&err)?;
            for (x, y, value) in labels {
                let at = ctx.backend_coord(&(x.min(hi), y));
                let style =
                    TextStyle::from((SANS, 14).into_font()).pos(Pos::new(HPos::Left, VPos::Center));
                root.draw(&Text::new(
                    format!("{value:.*}", chart.decimals),
                    (at.0 + 5, at.1),
                    style,
                ))
                .map_err(&err)?;
            }
        }
        for (row, name) in chart.categories.iter().enumerate() {
            let at = ctx.backend_coord(&(lo, (rows - row) as f64 - 0.5));
            let style =
                TextStyle::from((SANS, 16).into_font()).pos(Pos::new(HPos::Right, VPos::Center));
            root.draw(&Text::new(name.clone(), (at.0 - 8, at.1), style))
                .map_err(&err)?;
        }
        root.present().map_err(&err)?;
    }
    save_chart(path, pixels, size, policy)
}

/// One line of a [`LineChart`].
#[derive(Clone, Debug)]
pub struct Line {
    /// Legend name.
    pub name: String,
    /// (x, y) points in x order.
    pub points: Vec<(f64, f64)>,
}

/// A line chart (scaling curves).
#[derive(Clone, Debug)]
pub struct LineChart<'a> {
    /// Title above the chart.
    pub title: &'a str,
    /// Description of the x axis.
    pub x_label: &'a str,
    /// Description of the y axis.
    pub y_label: &'a str,
    /// The lines.
    pub lines: &'a [Line],
    /// Logarithmic y axis (costs that span orders of magnitude).
    pub log_y: bool,
}

/// Draws a [`LineChart`] to a PNG file (atomically, under `policy`); returns whether an
/// existing file was replaced.
pub fn draw_lines(
    path: &Path,
    chart: &LineChart<'_>,
    policy: &Overwrite,
) -> Result<bool, ChartError> {
    register_fonts().map_err(|e| ChartError::draw(path, e))?;
    let points = || {
        chart
            .lines
            .iter()
            .flat_map(|l| l.points.iter())
            .filter(|p| p.0.is_finite() && p.1.is_finite())
    };
    if points().next().is_none() {
        return Err(ChartError::Empty(path.to_owned()));
    }
    let (x_lo, x_hi) = points().fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.0), b.max(p.0)));
    let (y_lo, y_hi) = points().fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.1), b.max(p.1)));
    let x_pad = ((x_hi - x_lo) * 0.05).max(1e-9);
    let size = (960, 640);
    let mut pixels = vec![255u8; size.0 as usize * size.1 as usize * 3];
    {
        let (root, top, body) = titled_canvas(&mut pixels, size, chart.title, 76, path)?;
        let err = drawing_error(path);
        draw_legend(&top, chart.lines.iter().map(|l| l.name.as_str()), 48).map_err(&err)?;
        let mut builder = ChartBuilder::on(&body);
        builder
            .margin(16)
            .margin_top(4)
            .x_label_area_size(48)
            .y_label_area_size(72);
        let x_range = (x_lo - x_pad)..(x_hi + x_pad);
        macro_rules! finish {
            ($ctx:expr) => {{
                let mut ctx = $ctx;
                draw_axes(&mut ctx, chart.x_label, chart.y_label, path)?;
                for (i, line) in chart.lines.iter().enumerate() {
                    let color = series_color(i);
                    let pts: Vec<(f64, f64)> = line
                        .points
                        .iter()
                        .copied()
                        .filter(|p| {
                            p.0.is_finite() && p.1.is_finite() && (!chart.log_y || p.1 > 0.0)
                        })
                        .collect();
                    ctx.draw_series(LineSeries::new(pts.clone(), color.stroke_width(3)))
                        .map_err(&err)?;
                    ctx.draw_series(pts.into_iter().map(|p| Circle::new(p, 4, color.filled())))
                        .map_err(&err)?;
                }
            }};
        }
        if chart.log_y {
            let lo = points()
                .map(|p| p.1)
                .filter(|&v| v > 0.0)
                .fold(f64::MAX, f64::min);
            if lo == f64::MAX {
                return Err(ChartError::Empty(path.to_owned()));
            }
            finish!(
                builder
                    .build_cartesian_2d(x_range, ((lo * 0.7)..(y_hi * 1.4)).log_scale())
                    .map_err(&err)?
            );
        } else {
            let pad = ((y_hi - y_lo.min(0.0)) * 0.08).max(1e-9);
            finish!(
                builder
                    .build_cartesian_2d(x_range, y_lo.min(0.0)..(y_hi + pad))
                    .map_err(&err)?
            );
        }
        root.present().map_err(&err)?;
    }
    save_chart(path, pixels, size, policy)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn charts_draw_with_embedded_fonts() {
        let dir = tempfile::tempdir().unwrap();
        let categories = vec!["No AA".to_owned(), "MSAA 4x".to_owned()];
        let series = vec![
            BarSeries {
                name: "scene input".into(),
                values: vec![1.0, 3.5],
            },
            BarSeries {
                name: "own passes".into(),
                values: vec![0.1, f64::NAN],
            },
        ];
        for layout in [BarLayout::Stacked, BarLayout::Grouped] {
            let path = dir.path().join("bars.png");
            draw_bars(
                &path,
                &BarChart {
                    title: "GPU time",
                    value_label: "ms",
                    categories: &categories,
                    series: &series,
                    layout,
                    range: None,
                    decimals: 2,
                },
                &Overwrite::new(true),
            )
            .unwrap();
            let image = image::open(&path).unwrap().to_rgb8();
            assert_eq!(image.width(), 960);
        }
        let path = dir.path().join("lines.png");
        let lines = vec![Line {
            name: "MSAA 4x".into(),
            points: vec![(0.9, 3.0), (2.1, 7.5), (8.3, 30.0)],
        }];
        for log_y in [false, true] {
            draw_lines(
                &path,
                &LineChart {
                    title: "Scaling",
                    x_label: "megapixels",
                    y_label: "ms",
                    lines: &lines,
                    log_y,
                },
                &Overwrite::new(true),
            )
            .unwrap();
        }
        assert!(matches!(
            draw_lines(
                &path,
                &LineChart {
                    title: "",
                    x_label: "",
                    y_label: "",
                    lines: &[],
                    log_y: false
                },
                &Overwrite::new(true),
            ),
            Err(ChartError::Empty(_))
        ));
    }
}
