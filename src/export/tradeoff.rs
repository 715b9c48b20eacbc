//! Quality-against-cost charts: one labelled point per technique (a technique at a render
//! scale, in a scale sweep), the Pareto front drawn through the points that nothing cheaper
//! matches, and [`pareto_front`], which the reports also use to list that front. Points come in
//! groups (one colour each, named in the legend: in a scale sweep, one group per technique
//! with its points at every scale) and are drawn as circles at the output resolution and
//! triangles when rendered below it and upscaled, so native and upscaled techniques share one
//! front at the same output size. Quality may be higher-is-better (SSIM) or lower-is-better
//! (FLIP). Drawn with plotters into a buffer and written atomically like every chart
//! ([`super::charts`]).

use std::path::Path;

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::charts::{
    ChartError, SANS, draw_axes, drawing_error, register_fonts, save_chart, series_color,
    titled_canvas,
};
use crate::files::Overwrite;

/// One labelled point of a [`TradeoffChart`].
#[derive(Clone, Debug)]
pub struct TradeoffPoint {
    /// Label drawn beside the point.
    pub name: String,
    /// Cost (x).
    pub cost: f64,
    /// Quality (y).
    pub quality: f64,
    /// Index into [`TradeoffChart::groups`] (its colour); 0 when the chart has no groups.
    pub group: usize,
    /// Rendered below the output resolution and upscaled (a triangle, not a circle).
    pub upscaled: bool,
}

/// Cost against quality, one point per technique, the Pareto front drawn.
#[derive(Clone, Debug)]
pub struct TradeoffChart<'a> {
    /// Title above the chart.
    pub title: &'a str,
    /// Description of the x axis (cost).
    pub x_label: &'a str,
    /// Description of the y axis (quality).
    pub y_label: &'a str,
    /// The points.
    pub points: &'a [TradeoffPoint],
    /// Whether lower quality values are better (FLIP) rather than higher (SSIM).
    pub lower_is_better: bool,
    /// Legend names of the point groups; empty for one unnamed group.
    pub groups: &'a [String],
}

/// Indices of the Pareto-optimal points, cheapest first: the points that no other point
/// matches or beats in quality (higher is better) at the same or lower cost. Non-finite
/// points are ignored.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..points.len())
        .filter(|&i| points[i].0.is_finite() && points[i].1.is_finite())
        .collect();
    // Cheapest first; at equal cost the better first, so it shadows the others.
    order.sort_by(|&a, &b| {
        points[a]
            .0
            .total_cmp(&points[b].0)
            .then(points[b].1.total_cmp(&points[a].1))
    });
    let mut front = Vec::new();
    let mut best = f64::NEG_INFINITY;
    for i in order {
        if points[i].1 > best {
            best = points[i].1;
            front.push(i);
        }
    }
    front
}

/// The indices of [`pareto_front`] of `points`, cheapest first, where lower quality values
/// are better when `lower_is_better` (FLIP) and higher ones otherwise (SSIM).
pub fn quality_front(points: &[TradeoffPoint], lower_is_better: bool) -> Vec<usize> {
    let sign = if lower_is_better { -1.0 } else { 1.0 };
    let coords: Vec<(f64, f64)> = points.iter().map(|p| (p.cost, sign * p.quality)).collect();
    pareto_front(&coords)
}

/// Draws a [`TradeoffChart`] to a PNG file (atomically, under `policy`): every point labelled,
/// the Pareto front as a step line (each front point holds until a dearer one beats it), its
/// points filled, and a legend of the groups and markers. Returns whether an existing file
/// was replaced.
pub fn draw_tradeoff(
    path: &Path,
    chart: &TradeoffChart<'_>,
    policy: &Overwrite,
) -> Result<bool, ChartError> {
    register_fonts().map_err(|e| ChartError::draw(path, e))?;
    let finite: Vec<&TradeoffPoint> = chart
        .points
        .iter()
        .filter(|p| p.cost.is_finite() && p.quality.is_finite())
        .collect();
    if finite.is_empty() {
        return Err(ChartError::Empty(path.to_owned()));
    }
    let (x_lo, x_hi) = finite.iter().fold((f64::MAX, f64::MIN), |(a, b), p| {
        (a.min(p.cost), b.max(p.cost))
    });
    let (y_lo, y_hi) = finite.iter().fold((f64::MAX, f64::MIN), |(a, b), p| {
        (a.min(p.quality), b.max(p.quality))
    });
    let x_pad = ((x_hi - x_lo) * 0.08).max(x_hi.abs() * 0.05).max(1e-9);
    // Room on the right for the labels of the dearest points.
    let x_range = (x_lo - x_pad).max(0.0)..(x_hi + 3.0 * x_pad);
    let y_pad = ((y_hi - y_lo) * 0.1).max(1e-4);
    let y_range = (y_lo - y_pad)..(y_hi + y_pad);
    let size = (960, 640);
    let mut pixels = vec![255u8; size.0 as usize * size.1 as usize * 3];
    {
        let (root, _, body) = titled_canvas(&mut pixels, size, chart.title, 48, path)?;
        let err = drawing_error(path);
        let mut ctx = ChartBuilder::on(&body)
            .margin(16)
            .margin_top(4)
            .x_label_area_size(48)
            .y_label_area_size(72)
            .build_cartesian_2d(x_range.clone(), y_range)
            .map_err(&err)?;
        draw_axes(&mut ctx, chart.x_label, chart.y_label, path)?;
        let front = quality_front(chart.points, chart.lower_is_better);
        let coords: Vec<(f64, f64)> = chart.points.iter().map(|p| (p.cost, p.quality)).collect();
        let mut steps = Vec::new();
        for (k, &i) in front.iter().enumerate() {
            if k > 0 {
                steps.push((coords[i].0, coords[front[k - 1]].1));
            }
            steps.push(coords[i]);
        }
        if let Some(&last) = front.last() {
            steps.push((x_range.end, coords[last].1));
        }
        let line_color = RGBColor(60, 60, 60);
        ctx.draw_series(LineSeries::new(steps, line_color.stroke_width(2)))
            .map_err(&err)?
            .label("Pareto front: the best quality for the cost")
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 18, y)], line_color.stroke_width(2))
            });
        for (g, name) in chart.groups.iter().enumerate() {
            let color = series_color(g);
            ctx.draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                .map_err(&err)?
                .label(name.clone())
                .legend(move |(x, y)| {
                    Rectangle::new([(x, y - 6), (x + 14, y + 6)], color.filled())
                });
        }
        if chart.points.iter().any(|p| p.upscaled) {
            let grey = RGBColor(90, 90, 90);
            ctx.draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                .map_err(&err)?
                .label("circle: output resolution; triangle: upscaled")
                .legend(move |(x, y)| TriangleMarker::new((x + 7, y), 7, grey.filled()));
        }
        for (i, p) in chart.points.iter().enumerate() {
            if !(p.cost.is_finite() && p.quality.is_finite()) {
                continue;
            }
            // Filled on the front, an outline elsewhere; a triangle when upscaled (drawn from
            // pixel offsets: plotters' own triangle marker is always filled).
            let on_front = front.contains(&i);
            let color = series_color(p.group);
            let style = if on_front {
                color.filled()
            } else {
                color.stroke_width(2)
            };
            let at = (p.cost, p.quality);
            let corners = vec![(0, -8), (7, 5), (-7, 5), (0, -8)];
            match (p.upscaled, on_front) {
                (false, _) => ctx.draw_series(std::iter::once(Circle::new(at, 6, style))),
                (true, true) => ctx.draw_series(std::iter::once(
                    EmptyElement::at(at) + Polygon::new(corners, style),
                )),
                (true, false) => ctx.draw_series(std::iter::once(
                    EmptyElement::at(at) + PathElement::new(corners, style),
                )),
            }
            .map_err(&err)?;
            let at = ctx.backend_coord(&(p.cost, p.quality));
            let text =
                TextStyle::from((SANS, 15).into_font()).pos(Pos::new(HPos::Left, VPos::Center));
            root.draw(&Text::new(p.name.clone(), (at.0 + 9, at.1), text))
                .map_err(&err)?;
        }
        ctx.configure_series_labels()
            .position(if chart.lower_is_better {
                SeriesLabelPosition::UpperRight
            } else {
                SeriesLabelPosition::LowerRight
            })
            .label_font((SANS, 15))
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(200, 200, 200))
            .draw()
            .map_err(&err)?;
        root.present().map_err(&err)?;
    }
    save_chart(path, pixels, size, policy)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pareto_front_keeps_what_nothing_cheaper_beats() {
        let points = [
            (1.0, 0.80),
            (1.2, 0.78),
            (3.0, 0.85),
            (2.0, 0.90),
            (f64::NAN, 0.99),
            (2.0, 0.85),
            (0.5, 0.80),
        ];
        // (0.5, .80) shadows (1.0, .80): same quality, dearer.
        assert_eq!(pareto_front(&points), vec![6, 3]);
        assert!(pareto_front(&[]).is_empty());
        assert_eq!(pareto_front(&[(1.0, 0.5)]), vec![0]);
    }

    fn point(name: &str, cost: f64, quality: f64, group: usize, upscaled: bool) -> TradeoffPoint {
        TradeoffPoint {
            name: name.into(),
            cost,
            quality,
            group,
            upscaled,
        }
    }

    #[test]
    fn a_lower_is_better_front_keeps_the_smallest_errors() {
        let points = [
            point("native", 3.0, 0.05, 0, false),
            point("67%", 1.5, 0.07, 0, true),
            point("50%", 1.0, 0.09, 0, true),
            point("67% other", 2.0, 0.08, 1, true),
        ];
        assert_eq!(quality_front(&points, true), vec![2, 1, 0]);
        assert_eq!(quality_front(&points, false), vec![2]);
    }

    #[test]
    fn tradeoff_charts_draw_groups_and_markers_and_respect_the_policy() {
        let dir = tempfile::tempdir().unwrap();
        let points = vec![
            point("No AA", 1.0, 0.80, 0, false),
            point("50%", 0.6, 0.74, 0, true),
            point("MSAA 4x", 3.0, 0.85, 1, false),
        ];
        let groups = ["No AA".to_owned(), "MSAA 4x".to_owned()];
        let path = dir.path().join("tradeoff.png");
        for lower_is_better in [false, true] {
            let chart = TradeoffChart {
                title: "Quality against cost",
                x_label: "ms",
                y_label: "SSIM",
                points: &points,
                lower_is_better,
                groups: &groups,
            };
            draw_tradeoff(&path, &chart, &Overwrite::new(true)).unwrap();
            assert_eq!(image::open(&path).unwrap().width(), 960);
            assert!(
                draw_tradeoff(&path, &chart, &Overwrite::new(false)).is_err(),
                "an existing chart is replaced only with --force"
            );
        }
        let empty = TradeoffChart {
            title: "",
            x_label: "",
            y_label: "",
            points: &[],
            lower_is_better: false,
            groups: &[],
        };
        assert!(matches!(
            draw_tradeoff(&dir.path().join("empty.png"), &empty, &Overwrite::new(true)),
            Err(ChartError::Empty(_))
        ));
    }
}
