//! Plots of the end errors, as the thesis GUI drew them (CW / line runs as red circles,
//! CCW / triangle runs as black crosses, the centroids and the vectors from the origin to
//! them), with labelled axes in cm, equal aspect, the origin marked, a legend, and the
//! computed corrections in a side panel.
//!
//! Text is rendered from DejaVu Sans embedded in the binary (the `dejavu` crate) through
//! plotters' `ab_glyph` feature: no system font is needed, for SVG or PNG.

use std::fmt::Display;
use std::ops::Range;
use std::path::Path;
use std::sync::Once;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::FontStyle;

use crate::triangle::TriangleResult;
use crate::types::{centroid, Endpoint, LineRuns, TriangleRuns, UmbmarkRuns};
use crate::umbmark::UmbmarkResult;
use crate::Error;

const SIZE: (u32, u32) = (1150, 820);
const PANEL_W: u32 = 330;
const FONT: &str = "sans-serif";
const RED_RUNS: RGBColor = RGBColor(200, 30, 30);
const GREY: RGBColor = RGBColor(120, 120, 120);

static FONTS: Once = Once::new();

fn register_fonts() {
    FONTS.call_once(|| {
        // DejaVu Sans is a valid TrueType font; registration cannot fail for it.
        let _ = plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular());
        let _ = plotters::style::register_font(FONT, FontStyle::Bold, dejavu::sans::bold());
    });
}

trait OrMessage<T> {
    fn msg(self) -> Result<T, String>;
}

impl<T, E: Display> OrMessage<T> for Result<T, E> {
    fn msg(self) -> Result<T, String> {
        self.map_err(|e| e.to_string())
    }
}

/// A group of points to draw.
struct Group<'a> {
    label: &'a str,
    points: Vec<Endpoint>,
    color: RGBColor,
    cross: bool,
    centroid: Option<Endpoint>,
}

/// What one figure shows.
struct Figure<'a> {
    title: String,
    frame_note: String,
    groups: Vec<Group<'a>>,
    /// Vertical marker at this x (a centroid whose y is unknown), with its label.
    x_only: Option<(f64, String)>,
    panel: Vec<String>,
}

/// Equal-aspect ranges covering `pts` in a plot of `px` pixels.
fn ranges(pts: &[Endpoint], px: (u32, u32)) -> (Range<f64>, Range<f64>) {
    let (mut x0, mut x1, mut y0, mut y1) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for p in pts {
        x0 = x0.min(p.x_cm);
        x1 = x1.max(p.x_cm);
        y0 = y0.min(p.y_cm);
        y1 = y1.max(p.y_cm);
    }
    let pad = 0.12 * (x1 - x0).max(y1 - y0).max(5.0);
    let (x0, x1, y0, y1) = (x0 - pad, x1 + pad, y0 - pad, y1 + pad);
    let (w, h) = (f64::from(px.0.max(1)), f64::from(px.1.max(1)));
    let cm_per_px = ((x1 - x0) / w).max((y1 - y0) / h);
    let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
    let (hx, hy) = (cm_per_px * w / 2.0, cm_per_px * h / 2.0);
    (cx - hx..cx + hx, cy - hy..cy + hy)
}

/// A legend entry, drawn in the side panel so that it never hides a point.
enum Mark {
    Ring(RGBColor),
    Cross(RGBColor),
    Dot(RGBColor),
    Dashed,
    Blank,
}

fn draw<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, fig: &Figure) -> Result<(), String> {
    root.fill(&WHITE).msg()?;
    let (left, right) = root.split_horizontally(SIZE.0 - PANEL_W);
    let left = left
        .titled(&fig.title, (FONT, 24).into_font().style(FontStyle::Bold))
        .msg()?;

    let mut all: Vec<Endpoint> = Vec::new();
    for g in &fig.groups {
        all.extend(&g.points);
        all.extend(g.centroid);
    }
    if let Some((x, _)) = &fig.x_only {
        all.push(Endpoint::new(*x, 0.0));
    }
    let build = |xr: Range<f64>, yr: Range<f64>| {
        ChartBuilder::on(&left)
            .margin(18)
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
    let mut chart = build(xr.clone(), yr.clone()).msg()?;
    chart
        .configure_mesh()
        .x_desc(format!("x (cm){}", fig.frame_note))
        .y_desc("y (cm)")
        .axis_desc_style((FONT, 18))
        .label_style((FONT, 15))
        .light_line_style(RGBColor(244, 244, 244))
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()
        .msg()?;

    let mut legend: Vec<(Mark, String)> = Vec::new();
    // Axes through the origin, and the origin itself.
    let axis = GREY.stroke_width(1);
    chart
        .draw_series([
            PathElement::new(vec![(xr.start, 0.0), (xr.end, 0.0)], axis),
            PathElement::new(vec![(0.0, yr.start), (0.0, yr.end)], axis),
        ])
        .msg()?;
    chart
        .draw_series([Circle::new((0.0, 0.0), 7, BLACK.stroke_width(2))])
        .msg()?;
    legend.push((Mark::Ring(BLACK), "origin: start = target".into()));

    for g in &fig.groups {
        let color = g.color;
        if g.cross {
            chart
                .draw_series(
                    g.points
                        .iter()
                        .map(|p| Cross::new((p.x_cm, p.y_cm), 6, color.stroke_width(2))),
                )
                .msg()?;
            legend.push((
                Mark::Cross(color),
                format!("{} runs ({})", g.label, g.points.len()),
            ));
        } else {
            chart
                .draw_series(
                    g.points
                        .iter()
                        .map(|p| Circle::new((p.x_cm, p.y_cm), 6, color.stroke_width(2))),
                )
                .msg()?;
            legend.push((
                Mark::Ring(color),
                format!("{} runs ({})", g.label, g.points.len()),
            ));
        }
        if let Some(c) = g.centroid {
            // Vector from the origin to the rim of the centroid's dot, with an arrow head.
            let r = c.norm();
            let rim = 9.0 * cm_per_px;
            if r > rim {
                let (ux, uy) = (c.x_cm / r, c.y_cm / r);
                let tip = (c.x_cm - rim * ux, c.y_cm - rim * uy);
                let head = (16.0 * cm_per_px).min(0.5 * r);
                let base = (tip.0 - head * ux, tip.1 - head * uy);
                let w = 0.45 * head;
                chart
                    .draw_series([PathElement::new(
                        vec![(0.0, 0.0), base],
                        color.stroke_width(3),
                    )])
                    .msg()?;
                chart
                    .draw_series([Polygon::new(
                        vec![
                            tip,
                            (base.0 - w * uy, base.1 + w * ux),
                            (base.0 + w * uy, base.1 - w * ux),
                        ],
                        color.filled(),
                    )])
                    .msg()?;
            }
            chart
                .draw_series([Circle::new((c.x_cm, c.y_cm), 8, color.filled())])
                .msg()?;
            legend.push((Mark::Dot(color), format!("{} centroid, vector", g.label)));
            legend.push((
                Mark::Blank,
                format!("  ({:.2}, {:.2}), r = {:.2} cm", c.x_cm, c.y_cm, r),
            ));
        }
    }
    if let Some((x, label)) = &fig.x_only {
        chart
            .draw_series(DashedLineSeries::new(
                vec![(*x, yr.start), (*x, yr.end)],
                8,
                6,
                BLACK.stroke_width(2),
            ))
            .msg()?;
        legend.push((Mark::Dashed, label.clone()));
    }

    // Side panel: legend, then the numbers (the GUI's "Factor de corrección" box).
    right.fill(&RGBColor(247, 247, 247)).msg()?;
    let text = (FONT, 15).into_font().color(&BLACK);
    let mut y = 24;
    let mut lines = fig.panel.iter();
    if let Some(first) = lines.next() {
        let bold = (FONT, 19).into_font().style(FontStyle::Bold).color(&BLACK);
        right.draw_text(first, &bold, (14, y)).msg()?;
        y += 32;
    }
    for (mark, label) in &legend {
        let c = (26, y + 8);
        match mark {
            Mark::Ring(col) => right.draw(&Circle::new(c, 6, col.stroke_width(2))).msg()?,
            Mark::Cross(col) => right.draw(&Cross::new(c, 6, col.stroke_width(2))).msg()?,
            Mark::Dot(col) => right.draw(&Circle::new(c, 7, col.filled())).msg()?,
            Mark::Dashed => right
                .draw(&PathElement::new(
                    vec![(16, c.1), (36, c.1)],
                    BLACK.stroke_width(2),
                ))
                .msg()?,
            Mark::Blank => {}
        }
        right.draw_text(label, &text, (44, y)).msg()?;
        y += 22;
    }
    y += 12;
    for line in lines {
        right.draw_text(line, &text, (14, y)).msg()?;
        y += if line.is_empty() { 10 } else { 22 };
    }
    root.present().msg()?;
    Ok(())
}

fn render(fig: &Figure, path_svg: &Path, path_png: &Path) -> Result<(), Error> {
    register_fonts();
    draw(SVGBackend::new(path_svg, SIZE).into_drawing_area(), fig).map_err(|message| {
        Error::Plot {
            path: path_svg.to_path_buf(),
            message,
        }
    })?;
    draw(BitMapBackend::new(path_png, SIZE).into_drawing_area(), fig).map_err(|message| {
        Error::Plot {
            path: path_png.to_path_buf(),
            message,
        }
    })
}

fn frame_note(frame: crate::Frame) -> String {
    match frame {
        crate::Frame::Default => "   [frame: x along the first leg, y to the left]".into(),
        crate::Frame::ThesisGui => "   [frame: thesis GUI, as recorded]".into(),
    }
}

fn mode_line(mode: crate::Mode) -> String {
    match mode {
        crate::Mode::Correct => "mode: correct".into(),
        crate::Mode::ThesisCompat => "mode: THESIS COMPAT (GUI bugs)".into(),
    }
}

/// Plot a UMBmark experiment to an SVG and a PNG file.
pub fn plot_umbmark(
    result: &UmbmarkResult,
    runs: &UmbmarkRuns,
    path_svg: impl AsRef<Path>,
    path_png: impl AsRef<Path>,
) -> Result<(), Error> {
    let r = result;
    let mut panel = vec![
        "UMBmark".to_string(),
        mode_line(r.mode),
        format!(
            "L = {:.0} cm, b = {:.1} mm",
            r.side_cm, r.wheelbase_nominal_mm
        ),
        String::new(),
        format!("r_cg CW  = {:.2} cm", r.r_cg_cw_cm),
        format!("r_cg CCW = {:.2} cm", r.r_cg_ccw_cm),
        format!("E_max,syst = {:.2} cm", r.e_max_cm),
        format!("mean r_cg = {:.2} cm", r.error_mean_cm),
        String::new(),
        format!("α = {:.3}°   β = {:.3}°", r.alpha_deg, r.beta_deg),
        format!("α_x {:.2}°, α_y {:.2}°", r.alpha_x_deg, r.alpha_y_deg),
        format!("β_x {:.2}°, β_y {:.2}°", r.beta_x_deg, r.beta_y_deg),
        match r.radius_cm {
            Some(rc) => format!("R = {rc:.1} cm"),
            None => "R = ∞ (straight legs)".into(),
        },
        String::new(),
        format!("Ed = {:.6}   ({:?})", r.ed, r.ed_variant),
        format!("Eb = {:.6}", r.eb),
        format!("cL = {:.6}", r.cl),
        format!("cR = {:.6}", r.cr),
        format!("b actual = {:.1} mm", r.wheelbase_mm),
    ];
    if let Some(es) = r.es {
        panel.push(format!("Es = {es:.6}"));
    }
    if !r.agreement.consistent {
        panel.push(String::new());
        panel.push("⚠ x and y estimates disagree".into());
        if !r.agreement.explained_by.is_empty() {
            panel.push("  (as with a mirrored axis)".into());
        }
    }
    let fig = Figure {
        title: "UMBmark: end-position errors".into(),
        frame_note: frame_note(r.frame),
        groups: vec![
            Group {
                label: "CW",
                points: runs.cw().to_vec(),
                color: RED_RUNS,
                cross: false,
                centroid: Some(r.centroid_cw),
            },
            Group {
                label: "CCW",
                points: runs.ccw().to_vec(),
                color: BLACK,
                cross: true,
                centroid: Some(r.centroid_ccw),
            },
        ],
        x_only: None,
        panel,
    };
    render(&fig, path_svg.as_ref(), path_png.as_ref())
}

/// Plot a Triangular Path experiment to an SVG and a PNG file. Triangle runs without a y
/// value cannot be placed: their mean x is drawn as a dashed vertical line.
pub fn plot_triangle(
    result: &TriangleResult,
    line_runs: &LineRuns,
    triangle_runs: &TriangleRuns,
    path_svg: impl AsRef<Path>,
    path_png: impl AsRef<Path>,
) -> Result<(), Error> {
    let r = result;
    let complete: Vec<Endpoint> = triangle_runs
        .runs()
        .iter()
        .filter_map(|p| p.complete())
        .collect();
    let missing = triangle_runs.runs().len() - complete.len();
    let tri_centroid = r.triangle_centroid.complete();
    let mut panel = vec![
        "Triangular Path".to_string(),
        mode_line(r.mode),
        format!(
            "L = {:.0} cm, b = {:.1} mm, {}",
            r.side_cm,
            r.wheelbase_nominal_mm,
            r.direction.as_str().to_uppercase()
        ),
        String::new(),
        format!("line: β = {:.3}°", r.beta_deg),
        match r.radius_cm {
            Some(rc) => format!("R = {rc:.1} cm"),
            None => "R = ∞ (straight line)".into(),
        },
        format!("Ed = {:.6}   ({:?})", r.ed, r.ed_variant),
        format!("cL = {:.6}", r.cl),
        format!("cR = {:.6}", r.cr),
        String::new(),
        format!("triangle: turn error {:.3}°", r.alpha_deg),
        match r.alpha_y_deg {
            Some(ay) => format!("δ_x {:.2}°, δ_y {:.2}°", r.alpha_x_deg, ay),
            None => format!("δ_x {:.2}° (no y)", r.alpha_x_deg),
        },
        format!("Eb = {:.6}", r.eb),
        format!("b actual = {:.1} mm", r.wheelbase_mm),
        match r.triangle_r_cm {
            Some(e) => format!("triangle error r = {e:.2} cm"),
            None => "triangle error r: unknown".into(),
        },
    ];
    if let Some(es) = r.es {
        panel.push(format!("Es = {es:.6}"));
    }
    if missing > 0 {
        panel.push(String::new());
        panel.push(format!("{missing} triangle runs lack y:"));
        panel.push("  not drawn (dashed line: their mean x)".into());
    }
    if r.agreement.as_ref().is_some_and(|a| !a.consistent) {
        panel.push(String::new());
        panel.push("⚠ x and y estimates disagree".into());
    }
    let fig = Figure {
        title: "Triangular Path: end-position errors".into(),
        frame_note: frame_note(r.frame),
        groups: vec![
            Group {
                label: "line",
                points: line_runs.runs().to_vec(),
                color: RED_RUNS,
                cross: false,
                centroid: Some(centroid(line_runs.runs())),
            },
            Group {
                label: if missing > 0 {
                    "triangle (y known)"
                } else {
                    "triangle"
                },
                points: complete,
                color: BLACK,
                cross: true,
                centroid: tri_centroid,
            },
        ],
        x_only: tri_centroid.is_none().then(|| {
            (
                r.triangle_centroid.x_cm,
                format!(
                    "triangle mean x = {:.2} cm (y unknown)",
                    r.triangle_centroid.x_cm
                ),
            )
        }),
        panel,
    };
    render(&fig, path_svg.as_ref(), path_png.as_ref())
}

mod trajectories;

pub use trajectories::{ideal_path, plot_trajectories, IdealPath, Path2d};

#[cfg(test)]
mod tests {
    use super::*;

    /// `ranges` for `pts` in `px` pixels, checked against what it is for: every point
    /// (and the origin) inside with a margin of 12 % of the larger data span (at least
    /// 5 cm) on every side, exactly that margin on the axis that fills its pixels, the
    /// data centred on both axes, and one cm per pixel on x and y.
    fn check_ranges(pts: &[(f64, f64)], px: (u32, u32)) -> (Range<f64>, Range<f64>) {
        let e: Vec<Endpoint> = pts.iter().map(|&(x, y)| Endpoint::new(x, y)).collect();
        let (xr, yr) = ranges(&e, px);
        let lo_hi = |f: fn(&(f64, f64)) -> f64| {
            pts.iter()
                .map(f)
                .fold((0.0f64, 0.0f64), |(lo, hi), v| (lo.min(v), hi.max(v)))
        };
        let ((x0, x1), (y0, y1)) = (lo_hi(|p| p.0), lo_hi(|p| p.1));
        let pad = 0.12 * (x1 - x0).max(y1 - y0).max(5.0);
        let tol = 1e-9 * (1.0 + pad);
        for (r, lo, hi, axis) in [(&xr, x0, x1, "x"), (&yr, y0, y1, "y")] {
            assert!(
                r.start <= lo - pad + tol && r.end >= hi + pad - tol,
                "{axis} range {r:?} leaves less than {pad} cm around {lo}..{hi}"
            );
            assert!(
                ((r.start + r.end) / 2.0 - (lo + hi) / 2.0).abs() < tol,
                "{axis} range {r:?} not centred on {lo}..{hi}"
            );
        }
        let (w, h) = (f64::from(px.0), f64::from(px.1));
        let (sx, sy) = ((xr.end - xr.start) / w, (yr.end - yr.start) / h);
        assert!((sx - sy).abs() < 1e-12 * sx, "{sx} cm/px on x, {sy} on y");
        // The binding axis: no wider than the data and its margins need.
        let spare_x = (xr.end - xr.start) - (x1 - x0 + 2.0 * pad);
        let spare_y = (yr.end - yr.start) - (y1 - y0 + 2.0 * pad);
        assert!(
            spare_x.min(spare_y).abs() < tol,
            "{spare_x} cm spare on x, {spare_y} on y: neither axis is tight"
        );
        (xr, yr)
    }

    fn close(r: &Range<f64>, want: Range<f64>) -> bool {
        (r.start - want.start).abs() < 1e-9 && (r.end - want.end).abs() < 1e-9
    }

    /// Wide data, x binding: points (100, 10) and (40, -5) with the origin span x 0..100,
    /// y -5..10; the margin is 0.12 × 100 = 12 cm, so x is -12..112 (124 cm over 500 px,
    /// 0.248 cm/px) and y, 400 px at 0.248 cm/px = 99.2 cm centred on 2.5, is
    /// -47.1..52.1.
    #[test]
    fn ranges_hold_wide_data_with_a_twelve_percent_margin_at_one_scale() {
        let (xr, yr) = check_ranges(&[(100.0, 10.0), (40.0, -5.0)], (500, 400));
        assert!(close(&xr, -12.0..112.0), "{xr:?}");
        assert!(close(&yr, -47.1..52.1), "{yr:?}");
    }

    /// Tall data, y binding: points (-30, -80) and (5, 20) span x -30..5, y -80..20; the
    /// margin is 12 cm, so y is -92..32 (124 cm over 400 px, 0.31 cm/px) and x, 600 px
    /// at 0.31 cm/px = 186 cm centred on -12.5, is -105.5..80.5.
    #[test]
    fn ranges_hold_tall_data_with_a_twelve_percent_margin_at_one_scale() {
        let (xr, yr) = check_ranges(&[(-30.0, -80.0), (5.0, 20.0)], (600, 400));
        assert!(close(&xr, -105.5..80.5), "{xr:?}");
        assert!(close(&yr, -92.0..32.0), "{yr:?}");
    }

    /// Data within 5 cm of the origin still get 0.12 × 5 = 0.6 cm of margin: the point
    /// (1, 2) in 100 × 100 px gives y -0.6..2.6 and x, centred on 0.5, -1.1..2.1.
    #[test]
    fn ranges_of_small_data_keep_a_margin_of_twelve_percent_of_five_cm() {
        let (xr, yr) = check_ranges(&[(1.0, 2.0)], (100, 100));
        assert!(close(&xr, -1.1..2.1), "{xr:?}");
        assert!(close(&yr, -0.6..2.6), "{yr:?}");
    }
}
