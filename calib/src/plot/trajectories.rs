//! The robot's paths on the floor, in the test's frame (start at the origin, x along the
//! first leg, y to the left), over the ideal path they were commanded to drive, each
//! run's end point marked. Both axes in cm at the same scale: a square looks square.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{ranges, register_fonts, OrMessage, FONT, GREY, SIZE};
use crate::types::Endpoint;
use crate::Error;

/// The ideal path's colour, used for nothing else (its dashes can be told apart).
pub(crate) const IDEAL: RGBColor = RGBColor(90, 90, 90);
/// Radius of a run's end marker, pixels.
pub(crate) const END_RADIUS: u32 = 5;

const PALETTE: [RGBColor; 4] = [
    RGBColor(200, 30, 30),
    RGBColor(30, 80, 200),
    RGBColor(20, 140, 60),
    RGBColor(150, 90, 10),
];

/// One path to draw in [`plot_trajectories`]: a label and points in cm.
pub struct Path2d<'a> {
    pub label: &'a str,
    pub points: &'a [(f64, f64)],
    /// Index into a small palette: runs of one direction share a colour.
    pub group: usize,
}

/// A path the runs were commanded to drive (cm), drawn dashed beneath them.
pub struct IdealPath {
    pub label: String,
    pub points: Vec<(f64, f64)>,
}

/// The corners of an ideal run from the origin heading along +x: `legs` straight legs of
/// `leg_cm`, each followed by a turn of `turn_deg` (positive counter-clockwise). A
/// clockwise square is `ideal_path(4, -90.0, side)`, the Triangular Path's triangle
/// `ideal_path(3, 120.0, side)`, a line `ideal_path(1, 0.0, length)`.
pub fn ideal_path(legs: usize, turn_deg: f64, leg_cm: f64) -> Vec<(f64, f64)> {
    let mut points = vec![(0.0, 0.0)];
    let (mut x, mut y, mut heading) = (0.0f64, 0.0f64, 0.0f64);
    for _ in 0..legs {
        x += leg_cm * heading.cos();
        y += leg_cm * heading.sin();
        // Exact corners: a square's are not 1e-14 off its sides.
        points.push((round_off(x, leg_cm), round_off(y, leg_cm)));
        heading += turn_deg.to_radians();
    }
    points
}

/// `v` on a grid of 1e-9 `scale`: without the rounding noise of sin and cos.
fn round_off(v: f64, scale: f64) -> f64 {
    if scale == 0.0 {
        return v;
    }
    (v * 1e9 / scale).round() * scale / 1e9
}

/// Dashes along a polyline, restarting at each corner so that every corner is drawn.
fn dashes(points: &[(f64, f64)], dash: f64, gap: f64) -> Vec<Vec<(f64, f64)>> {
    let mut out = Vec::new();
    for w in points.windows(2) {
        let ((x0, y0), (x1, y1)) = (w[0], w[1]);
        let len = (x1 - x0).hypot(y1 - y0);
        if len <= 0.0 {
            continue;
        }
        let at = |s: f64| (x0 + (x1 - x0) * s / len, y0 + (y1 - y0) * s / len);
        let mut s = 0.0;
        while s < len {
            out.push(vec![at(s), at((s + dash).min(len))]);
            s += dash + gap;
        }
        // The corner itself, when the pattern ended in a gap.
        if s - gap >= len {
            continue;
        }
        out.push(vec![at((len - dash / 4.0).max(0.0)), at(len)]);
    }
    out
}

fn draw_paths<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    title: &str,
    ideal: &[IdealPath],
    paths: &[Path2d],
) -> Result<(), String> {
    root.fill(&WHITE).msg()?;
    let all: Vec<Endpoint> = paths
        .iter()
        .flat_map(|p| p.points.iter())
        .chain(ideal.iter().flat_map(|i| i.points.iter()))
        .map(|&(x, y)| Endpoint::new(x, y))
        .chain([Endpoint::new(0.0, 0.0)])
        .collect();
    let root = root.titled(title, (FONT, 24).into_font()).msg()?;
    let build = |xr: std::ops::Range<f64>, yr: std::ops::Range<f64>| {
        ChartBuilder::on(&root)
            .margin(16)
            .x_label_area_size(50)
            .y_label_area_size(64)
            .build_cartesian_2d(xr, yr)
    };
    // Measure the plotting area first, then choose ranges with equal cm per pixel.
    let px = build(0.0..1.0, 0.0..1.0)
        .msg()?
        .plotting_area()
        .dim_in_pixel();
    let (xr, yr) = ranges(&all, px);
    let cm_per_px = (xr.end - xr.start) / f64::from(px.0.max(1));
    let mut chart = build(xr, yr).msg()?;
    chart
        .configure_mesh()
        .x_desc("x (cm), along the first leg")
        .y_desc("y (cm), to the left")
        .axis_desc_style((FONT, 18))
        .label_style((FONT, 15))
        .light_line_style(RGBColor(244, 244, 244))
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()
        .msg()?;
    for (k, i) in ideal.iter().enumerate() {
        let style = IDEAL.stroke_width(2);
        let series = chart
            .draw_series(
                dashes(&i.points, 12.0 * cm_per_px, 8.0 * cm_per_px)
                    .into_iter()
                    .map(move |d| PathElement::new(d, style)),
            )
            .msg()?;
        // One legend line for all of them when they share a label.
        if ideal[..k].iter().all(|o| o.label != i.label) {
            series
                .label(i.label.as_str())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 8, y)], style));
        }
    }
    let mut labelled = [false; PALETTE.len()];
    for p in paths {
        let g = p.group % PALETTE.len();
        let color = PALETTE[g];
        let series = chart
            .draw_series(LineSeries::new(
                p.points.iter().copied(),
                color.stroke_width(2),
            ))
            .msg()?;
        if !labelled[g] {
            labelled[g] = true;
            series.label(p.label).legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
            });
        }
    }
    // Each run's end point, over every path: where the tape measure would go.
    chart
        .draw_series(paths.iter().filter_map(|p| {
            let color = PALETTE[p.group % PALETTE.len()];
            p.points
                .last()
                .map(|&e| Circle::new(e, END_RADIUS, ShapeStyle::from(color).filled()))
        }))
        .msg()?
        .label("end points")
        .legend(|(x, y)| Circle::new((x + 10, y), 4, GREY.filled()));
    chart
        .draw_series([Cross::new((0.0, 0.0), 8, BLACK.stroke_width(2))])
        .msg()?
        .label("start")
        .legend(|(x, y)| Cross::new((x + 10, y), 5, BLACK.stroke_width(2)));
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font((FONT, 15))
        .draw()
        .msg()?;
    root.present().msg()?;
    Ok(())
}

/// Plot robot paths (cm, start at the origin) over the `ideal` paths they were commanded
/// to drive, to an SVG and a PNG file; the first path of each group names the group in
/// the legend, and each path's last point is marked as its end point.
pub fn plot_trajectories(
    title: &str,
    ideal: &[IdealPath],
    paths: &[Path2d],
    path_svg: impl AsRef<Path>,
    path_png: impl AsRef<Path>,
) -> Result<(), Error> {
    register_fonts();
    let (svg, png) = (path_svg.as_ref(), path_png.as_ref());
    draw_paths(
        SVGBackend::new(svg, SIZE).into_drawing_area(),
        title,
        ideal,
        paths,
    )
    .map_err(|message| Error::Plot {
        path: svg.to_path_buf(),
        message,
    })?;
    draw_paths(
        BitMapBackend::new(png, SIZE).into_drawing_area(),
        title,
        ideal,
        paths,
    )
    .map_err(|message| Error::Plot {
        path: png.to_path_buf(),
        message,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ideal_paths_close_where_the_tests_end() {
        let cw = ideal_path(4, -90.0, 200.0);
        assert_eq!(
            cw,
            [
                (0.0, 0.0),
                (200.0, 0.0),
                (200.0, -200.0),
                (0.0, -200.0),
                (0.0, 0.0)
            ]
        );
        let tri = ideal_path(3, 120.0, 100.0);
        assert_eq!(tri.len(), 4);
        assert!((tri[2].1 - 100.0 * 60f64.to_radians().sin()).abs() < 1e-6);
        assert_eq!(tri[3], (0.0, 0.0));
        assert_eq!(ideal_path(1, 0.0, 50.0), [(0.0, 0.0), (50.0, 0.0)]);
    }

    #[test]
    fn dashes_reach_every_corner() {
        let square = ideal_path(4, 90.0, 10.0);
        let d = dashes(&square, 3.0, 2.0);
        for corner in &square {
            assert!(
                d.iter().flatten().any(|p| p == corner),
                "no dash at {corner:?}"
            );
        }
    }

    /// Dashes of 3 with gaps of 2 along a straight leg, as (start, end) x values.
    fn along_x(len: f64) -> Vec<(f64, f64)> {
        dashes(&[(0.0, 0.0), (len, 0.0)], 3.0, 2.0)
            .into_iter()
            .map(|d| {
                assert!(d.iter().all(|p| p.1 == 0.0), "{d:?} off the leg");
                (d[0].0, d[1].0)
            })
            .collect()
    }

    /// Dash 3, gap 2 (a period of 5): a leg of 10 ends in a gap (dashes 0..3 and 5..8), so
    /// a quarter dash, 9.25..10, marks its corner; a leg of 8 ends with the dash 5..8 on
    /// the corner and one of 6 with 5..6 cut there, and neither gets another piece.
    #[test]
    fn dashes_mark_a_corner_only_when_the_pattern_ends_in_a_gap() {
        assert_eq!(along_x(10.0), [(0.0, 3.0), (5.0, 8.0), (9.25, 10.0)]);
        assert_eq!(along_x(8.0), [(0.0, 3.0), (5.0, 8.0)]);
        assert_eq!(along_x(6.0), [(0.0, 3.0), (5.0, 6.0)]);
    }
}
