//! The plot functions write a real SVG and a real PNG (of the stated size, with text drawn
//! from the embedded font) for the thesis data, including the triangle experiment whose
//! y values are missing; the end-error plots' axes carry numbered ticks at the same cm per
//! pixel on x and y, and their vectors, legend and frame note are checked in the SVG's
//! elements. The trajectory plot has its own tests (`trajectories.rs`).

use std::path::PathBuf;

use calib::{
    plot_triangle, plot_umbmark, triangle_correction, umbmark_correction, Endpoint, Frame,
    TriangleParams, UmbmarkParams, UmbmarkRuns,
};

mod common;
use common::svg::*;
use common::{thesis_triangle, thesis_umbmark};

/// UMBmark experiment 1: both files exist; the SVG carries the axis labels, the legend and
/// the numbers; the PNG is 1150 × 820 and not blank (text and markers make it compress to
/// well over a white page's few kB).
#[test]
fn umbmark_plot_files() {
    let runs = thesis_umbmark(1);
    let r = umbmark_correction(
        &runs,
        &UmbmarkParams {
            frame: Frame::ThesisGui,
            ..UmbmarkParams::default()
        },
    );
    let (svg, png) = (out("umbmark_1.svg"), out("umbmark_1.png"));
    plot_umbmark(&r, &runs, &svg, &png).unwrap();
    let s = std::fs::read_to_string(&svg).unwrap();
    for needle in [
        "<svg",
        "x (cm)",
        "y (cm)",
        "CW runs (5)",
        "CCW centroid, vector",
        "origin: start = target",
        "E_max,syst = 45.04 cm",
    ] {
        assert!(s.contains(needle), "SVG lacks {needle:?}");
    }
    let p = std::fs::read(&png).unwrap();
    assert_eq!(png_size(&p), (1150, 820));
    assert!(p.len() > 50_000, "PNG is {} bytes", p.len());
}

/// Triangle experiment 2 (no triangle y): the plot is drawn, with the mean x as a dashed
/// line and the missing values said in the panel.
#[test]
fn triangle_plot_with_missing_y() {
    let e = thesis_triangle(2);
    let r = triangle_correction(&e.line, &e.triangle, &TriangleParams::default());
    let (svg, png) = (out("triangle_2.svg"), out("triangle_2.png"));
    plot_triangle(&r, &e.line, &e.triangle, &svg, &png).unwrap();
    let s = std::fs::read_to_string(&svg).unwrap();
    assert!(s.contains("triangle mean x = -2.12 cm (y unknown)"));
    assert!(s.contains("5 triangle runs lack y"));
    assert_eq!(png_size(&std::fs::read(&png).unwrap()), (1150, 820));
}

/// A path that cannot be written is a Plot error naming it.
#[test]
fn unwritable_path_is_an_error() {
    let e = thesis_triangle(1);
    let r = triangle_correction(&e.line, &e.triangle, &TriangleParams::default());
    let bad = PathBuf::from("/nonexistent-dir/plot.svg");
    let err = plot_triangle(&r, &e.line, &e.triangle, &bad, out("ok.png")).unwrap_err();
    assert!(err.to_string().contains("nonexistent-dir"), "{err}");
}

/// The end-error scatter has numbered ticks on both axes, at one scale.
#[test]
fn umbmark_plot_axes_are_numbered_at_one_scale() {
    let runs = thesis_umbmark(1);
    let r = umbmark_correction(&runs, &UmbmarkParams::default());
    let (svg, png) = (out("umbmark_1_axes.svg"), out("umbmark_1_axes.png"));
    plot_umbmark(&r, &runs, &svg, &png).unwrap();
    let s = std::fs::read_to_string(&svg).unwrap();
    let ((px, nx), (py, ny)) = scale_from_ticks(&s);
    assert!(nx >= 3 && ny >= 3, "{nx} x ticks, {ny} y ticks");
    assert!((px - py).abs() < 0.01 * px, "{px} px/cm on x, {py} on y");
}

/// The x axis of an end-error plot says which frame its points are in: "x (cm)" and
/// then "[frame: thesis GUI, as recorded]" for Frame::ThesisGui, "[frame: x along the
/// first leg, y to the left]" for Frame::Default.
#[test]
fn end_error_x_axis_names_the_frame() {
    let runs = thesis_umbmark(1);
    for (frame, note) in [
        (Frame::ThesisGui, "[frame: thesis GUI, as recorded]"),
        (
            Frame::Default,
            "[frame: x along the first leg, y to the left]",
        ),
    ] {
        let r = umbmark_correction(
            &runs,
            &UmbmarkParams {
                frame,
                ..UmbmarkParams::default()
            },
        );
        let name = format!("umbmark_1_{frame:?}");
        let (svg, png) = (out(&format!("{name}.svg")), out(&format!("{name}.png")));
        plot_umbmark(&r, &runs, &svg, &png).unwrap();
        let s = std::fs::read_to_string(&svg).unwrap();
        let want = format!("x (cm)   {note}");
        assert!(
            texts(&s).iter().any(|t| t.content == want),
            "no x axis label {want:?}"
        );
    }
}

/// Left edge of the side panel, pixels: the figure's 1150 less the panel's 330.
const PANEL_X: f64 = 820.0;

/// The side panel lists the legend top to bottom, one entry a line of 22 px: the
/// heading "UMBmark" at y 24, then from y 24 + 32 = 56 the origin, the CW runs, the CW
/// centroid and its numbers, the same for CCW (down to 56 + 6 × 22 = 188), and the
/// numbers after them from 188 + 22 + 12 = 222, "mode: correct" first. The legend's
/// labels are 44 px into the panel, the heading and numbers 14.
#[test]
fn umbmark_legend_is_listed_down_the_side_panel() {
    let runs = thesis_umbmark(1);
    let r = umbmark_correction(&runs, &UmbmarkParams::default());
    let (svg, png) = (out("umbmark_1_legend.svg"), out("umbmark_1_legend.png"));
    plot_umbmark(&r, &runs, &svg, &png).unwrap();
    let t = texts(&std::fs::read_to_string(&svg).unwrap());
    let at = |x: f64| -> Vec<(f64, &str)> {
        t.iter()
            .filter(|t| t.x == PANEL_X + x)
            .map(|t| (t.y, t.content.as_str()))
            .collect()
    };
    let legend = at(44.0);
    let labels: Vec<&str> = legend.iter().map(|l| l.1).collect();
    assert_eq!(
        labels[..],
        [
            "origin: start = target",
            "CW runs (5)",
            "CW centroid, vector",
            &format!(
                "({:.2}, {:.2}), r = {:.2} cm",
                r.centroid_cw.x_cm, r.centroid_cw.y_cm, r.r_cg_cw_cm
            ),
            "CCW runs (5)",
            "CCW centroid, vector",
            &format!(
                "({:.2}, {:.2}), r = {:.2} cm",
                r.centroid_ccw.x_cm, r.centroid_ccw.y_cm, r.r_cg_ccw_cm
            ),
        ]
    );
    let ys: Vec<f64> = legend.iter().map(|l| l.0).collect();
    assert_eq!(ys, [56.0, 78.0, 100.0, 122.0, 144.0, 166.0, 188.0]);
    let panel = at(14.0);
    assert_eq!(panel[0], (24.0, "UMBmark"));
    assert_eq!(panel[1], (222.0, "mode: correct"));
}

/// A centroid's vector as drawn, in pixels: the centroid's dot, the shaft's two ends and
/// the arrow head's three corners (tip first), for the group drawn in `colour`; None
/// when the plot has no vector in that colour.
struct Vector {
    origin: (f64, f64),
    dot: (f64, f64),
    shaft: Vec<(f64, f64)>,
    head: Vec<(f64, f64)>,
}

fn vector(svg: &str, colour: &str) -> Option<Vector> {
    let circles = tags(svg, "circle");
    let circle = |r: &str, fill: &str| {
        let t = circles
            .iter()
            .find(|t| {
                attr(t, "r").as_deref() == Some(r) && attr(t, "fill").as_deref() == Some(fill)
            })
            .unwrap();
        (num(t, "cx"), num(t, "cy"))
    };
    let shafts: Vec<_> = tags(svg, "polyline")
        .into_iter()
        .filter(|t| attr(t, "stroke").as_deref() == Some(colour))
        .filter(|t| attr(t, "stroke-width").as_deref() == Some("3"))
        .map(points)
        .collect();
    let heads: Vec<_> = tags(svg, "polygon")
        .into_iter()
        .filter(|t| attr(t, "fill").as_deref() == Some(colour))
        .map(points)
        .collect();
    assert_eq!(
        shafts.len(),
        heads.len(),
        "shafts {shafts:?}, heads {heads:?}"
    );
    assert!(heads.len() <= 1, "{} vectors in {colour}", heads.len());
    Some(Vector {
        // The origin: the plot's only ring of 7 px; a centroid: a filled dot of 8 px.
        origin: circle("7", "none"),
        dot: circle("8", colour),
        shaft: shafts.into_iter().next()?,
        head: heads.into_iter().next()?,
    })
}

impl Vector {
    /// The geometry the plot means, within a pixel or two of rounding: the shaft from
    /// the origin to the middle of the head's base; the head's tip on the line from the
    /// origin to the dot, 9 px short of the dot's centre (1 px outside its 8 px radius);
    /// the head 16 px long or half the vector when that is shorter, its base across the
    /// vector and 2 × 0.45 of its length wide.
    fn check(&self, what: &str) {
        let (o, c) = (self.origin, self.dot);
        let r = dist(o, c);
        let (ux, uy) = ((c.0 - o.0) / r, (c.1 - o.1) / r);
        let [tip, b1, b2] = self.head[..] else {
            panic!("{what}: head {:?}", self.head)
        };
        let base = ((b1.0 + b2.0) / 2.0, (b1.1 + b2.1) / 2.0);
        let off_line = |p: (f64, f64)| ((p.0 - o.0) * uy - (p.1 - o.1) * ux).abs();
        let near = |a: f64, b: f64, tol: f64| (a - b).abs() <= tol;
        assert!(
            near(dist(tip, c), 9.0, 1.5) && off_line(tip) <= 1.5,
            "{what}: tip {tip:?}, dot {c:?}, origin {o:?}"
        );
        let head = 16f64.min(r / 2.0);
        assert!(
            near(dist(tip, base), head, 1.5) && off_line(base) <= 1.5,
            "{what}: head from {tip:?} to {base:?}, want {head} px along the vector"
        );
        let across = ((b2.0 - b1.0) * ux + (b2.1 - b1.1) * uy).abs();
        assert!(
            near(dist(b1, b2), 0.9 * head, 2.0) && across <= 1.5,
            "{what}: head's base {b1:?} {b2:?}, want {} px across the vector",
            0.9 * head
        );
        assert_eq!(self.shaft.len(), 2, "{what}: shaft {:?}", self.shaft);
        assert!(
            dist(self.shaft[0], o) <= 1.0 && dist(self.shaft[1], base) <= 1.5,
            "{what}: shaft {:?}, origin {o:?}, head's base {base:?}",
            self.shaft
        );
    }
}

/// UMBmark experiment 1's centroids are far from the origin (CW (-28.54, 34.84), CCW
/// (-21.28, 7.34) cm: some 640 and 320 px at about 0.07 cm per pixel); each gets a
/// vector from the origin with a full 16 px head whose tip stops 9 px short of its dot.
#[test]
fn umbmark_vectors_point_from_the_origin_to_the_centroids() {
    let runs = thesis_umbmark(1);
    let r = umbmark_correction(&runs, &UmbmarkParams::default());
    let (svg, png) = (out("umbmark_1_vectors.svg"), out("umbmark_1_vectors.png"));
    plot_umbmark(&r, &runs, &svg, &png).unwrap();
    let s = std::fs::read_to_string(&svg).unwrap();
    for (what, colour) in [("CW", "#C81E1E"), ("CCW", "#000000")] {
        let v = vector(&s, colour).unwrap_or_else(|| panic!("no {what} vector"));
        assert!(
            dist(v.origin, v.dot) > 300.0,
            "{what} centroid near the origin"
        );
        v.check(what);
    }
}

/// Centroids near the origin: runs 20 cm either side of CW (1.2, 0.9) and of CCW
/// (0.2, 0.1) cm fill about 50 cm in 700 px, some 0.07 cm per pixel. The CW vector,
/// 1.5 cm or about 21 px, has a head of half that, about 10 px, not 16 (which would
/// reach behind the origin); the CCW centroid, about 3 px from the origin, is inside the
/// 9 px its dot covers and gets no vector at all.
#[test]
fn short_vectors_have_half_length_heads_and_hidden_ones_none() {
    let around = |cx: f64, cy: f64| -> Vec<Endpoint> {
        [(20.0, 0.0), (-20.0, 0.0), (0.0, 20.0), (0.0, -20.0)]
            .map(|(dx, dy)| Endpoint::new(cx + dx, cy + dy))
            .to_vec()
    };
    let runs = UmbmarkRuns::new(around(1.2, 0.9), around(0.2, 0.1)).unwrap();
    let r = umbmark_correction(&runs, &UmbmarkParams::default());
    let (svg, png) = (out("umbmark_short.svg"), out("umbmark_short.png"));
    plot_umbmark(&r, &runs, &svg, &png).unwrap();
    let s = std::fs::read_to_string(&svg).unwrap();
    let cw = vector(&s, "#C81E1E").expect("a CW vector");
    let len = dist(cw.origin, cw.dot);
    assert!((15.0..30.0).contains(&len), "CW vector {len} px");
    cw.check("CW");
    let ccw = vector(&s, "#000000");
    assert!(ccw.is_none(), "a vector to a centroid under its dot");
}
