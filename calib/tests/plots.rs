//! The plot functions write a real SVG and a real PNG (of the stated size, with text drawn
//! from the embedded font) for the thesis data, including the triangle experiment whose
//! y values are missing; their axes carry numbered ticks at the same cm per pixel on x and
//! y, and the trajectory plot shows the ideal square, square, and one end marker per run.
//! The end-error plots' vectors, legend and frame note, and the trajectory plot's dashes
//! and end-marker colours, are checked in the SVG's elements and their pixels.

use std::path::PathBuf;

use calib::plot::{ideal_path, plot_trajectories, IdealPath, Path2d};
use calib::{
    plot_triangle, plot_umbmark, triangle_correction, umbmark_correction, Endpoint, Frame,
    TriangleParams, UmbmarkParams, UmbmarkRuns,
};

mod common;
use common::{thesis_triangle, thesis_umbmark};

fn out(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name)
}

/// Width and height from a PNG's IHDR chunk, after checking the signature.
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "PNG signature");
    assert_eq!(&bytes[12..16], b"IHDR");
    let be = |i: usize| u32::from_be_bytes(bytes[i..i + 4].try_into().unwrap());
    (be(16), be(20))
}

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

/// A `<text>` element of an SVG written by plotters: where, anchored how, saying what.
struct Text {
    x: f64,
    y: f64,
    anchor: String,
    content: String,
}

/// The value of attribute `name` in `tag` (the text after the element's name).
fn attr(tag: &str, name: &str) -> Option<String> {
    let tag = format!(" {tag}");
    let at = tag.find(&format!(" {name}=\""))? + name.len() + 3;
    Some(tag[at..].split('"').next()?.to_string())
}

fn texts(svg: &str) -> Vec<Text> {
    svg.split("<text ")
        .skip(1)
        .map(|t| {
            let (tag, rest) = t.split_once('>').unwrap();
            Text {
                x: attr(tag, "x").unwrap().parse().unwrap(),
                y: attr(tag, "y").unwrap().parse().unwrap(),
                anchor: attr(tag, "text-anchor").unwrap_or_default(),
                content: rest.split("</text>").next().unwrap().trim().to_string(),
            }
        })
        .collect()
}

/// Pixels per axis unit from an axis' numbered ticks (first to last), and how many
/// there are: x ticks are centred under the plot, y ticks right-aligned beside it.
fn scale_from_ticks(svg: &str) -> ((f64, usize), (f64, usize)) {
    let ticks = |anchor: &str| -> Vec<(f64, f64)> {
        texts(svg)
            .into_iter()
            .filter(|t| t.anchor == anchor)
            .filter_map(|t| {
                Some((
                    t.content.parse::<f64>().ok()?,
                    if anchor == "end" { t.y } else { t.x },
                ))
            })
            .collect()
    };
    let per = |v: Vec<(f64, f64)>, sign: f64| {
        assert!(v.len() >= 3, "only {} numbered ticks", v.len());
        let (a, b) = (v[0], v[v.len() - 1]);
        (sign * (b.1 - a.1) / (b.0 - a.0), v.len())
    };
    // SVG y grows downwards.
    (per(ticks("middle"), 1.0), per(ticks("end"), -1.0))
}

/// The attributes of every `<name .../>` element of an SVG, in drawing order.
fn tags<'a>(svg: &'a str, name: &str) -> Vec<&'a str> {
    svg.split(&format!("<{name} "))
        .skip(1)
        .map(|t| t.split_once("/>").unwrap().0)
        .collect()
}

/// The `points` of a `<polyline>` or `<polygon>`, in pixels.
fn points(tag: &str) -> Vec<(f64, f64)> {
    attr(tag, "points")
        .unwrap()
        .split_whitespace()
        .map(|p| {
            let (x, y) = p.split_once(',').unwrap();
            (x.parse().unwrap(), y.parse().unwrap())
        })
        .collect()
}

/// Attribute `name` of `tag` as a number.
fn num(tag: &str, name: &str) -> f64 {
    attr(tag, name).unwrap().parse().unwrap()
}

/// The `<polyline>`s stroked in `colour`, each as its points.
fn polylines(svg: &str, colour: &str) -> Vec<Vec<(f64, f64)>> {
    tags(svg, "polyline")
        .into_iter()
        .filter(|t| attr(t, "stroke").as_deref() == Some(colour))
        .map(points)
        .collect()
}

/// Every point of the `<polyline>`s stroked in `colour`.
fn polyline_points(svg: &str, colour: &str) -> Vec<(f64, f64)> {
    polylines(svg, colour).concat()
}

fn dist(a: (f64, f64), b: (f64, f64)) -> f64 {
    (a.0 - b.0).hypot(a.1 - b.1)
}

fn bbox(pts: &[(f64, f64)]) -> (f64, f64) {
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in pts {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    (x1 - x0, y1 - y0)
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

/// A UMBmark's paths: two CW runs and one CCW run, a little off their squares.
fn runs() -> [Vec<(f64, f64)>; 3] {
    let off = |turn: f64, sx: f64, sy: f64, dy: f64| -> Vec<(f64, f64)> {
        ideal_path(4, turn, 200.0)
            .into_iter()
            .map(|(x, y)| (x * sx, y * sy + dy))
            .collect()
    };
    [
        off(-90.0, 1.01, 0.98, 3.0),
        off(-90.0, 0.99, 1.02, -2.0),
        off(90.0, 1.02, 0.97, 4.0),
    ]
}

/// The trajectory plot of [`runs`] (groups 0, 0 and 1) over their ideal squares, as
/// `name`.svg and `name`.png: the SVG's text and the PNG's path.
fn square_runs_plot(name: &str) -> (String, PathBuf) {
    let [a, b, c] = runs();
    let paths = [
        Path2d {
            label: "clockwise",
            points: &a,
            group: 0,
        },
        Path2d {
            label: "clockwise",
            points: &b,
            group: 0,
        },
        Path2d {
            label: "counter-clockwise",
            points: &c,
            group: 1,
        },
    ];
    let ideal = [
        IdealPath {
            label: "ideal squares, L = 200 cm".into(),
            points: ideal_path(4, -90.0, 200.0),
        },
        IdealPath {
            label: "ideal squares, L = 200 cm".into(),
            points: ideal_path(4, 90.0, 200.0),
        },
    ];
    let (svg, png) = (out(&format!("{name}.svg")), out(&format!("{name}.png")));
    plot_trajectories(
        "UMBmark trajectories, L = 200 cm",
        &ideal,
        &paths,
        &svg,
        &png,
    )
    .unwrap();
    (std::fs::read_to_string(&svg).unwrap(), png)
}

/// Whether a pixel is inside the plot's legend (its framed box).
fn in_legend(svg: &str) -> impl Fn(&(f64, f64)) -> bool {
    let legend = tags(svg, "rect")
        .into_iter()
        .find(|t| attr(t, "fill").as_deref() == Some("none"))
        .map(|t| ["x", "y", "width", "height"].map(|a| num(t, a)))
        .unwrap();
    move |&(x, y)| {
        x >= legend[0] && x <= legend[0] + legend[2] && y >= legend[1] && y <= legend[1] + legend[3]
    }
}

/// `trajectories.svg`: the ideal squares drawn dashed and square on the page (as many
/// pixels per cm as the ticks say, on x and on y), one end marker per run at its path's
/// last point, the title as given.
#[test]
fn trajectories_show_the_ideal_square_and_the_end_points() {
    let (s, png) = square_runs_plot("trajectories");
    let paths = runs();
    for needle in [
        "UMBmark trajectories, L = 200 cm",
        "x (cm)",
        "y (cm)",
        "ideal squares, L = 200 cm",
        "end points",
    ] {
        assert!(s.contains(needle), "SVG lacks {needle:?}");
    }
    let ((px, _), (py, _)) = scale_from_ticks(&s);
    assert!((px - py).abs() < 0.01 * px, "{px} px/cm on x, {py} on y");
    // The two squares, CW below the x axis and CCW above it: 200 cm by 400 cm.
    // (The legend's sample of the dashes, inside its framed box, aside.)
    let in_legend = in_legend(&s);
    let dashes: Vec<_> = polyline_points(&s, "#5A5A5A")
        .into_iter()
        .filter(|p| !in_legend(p))
        .collect();
    let (w, h) = bbox(&dashes);
    assert!(
        (w - 200.0 * px).abs() <= 1.5,
        "ideal squares {w} px wide, {px} px/cm"
    );
    assert!(
        (h - 400.0 * py).abs() <= 1.5,
        "ideal squares {h} px high, {py} px/cm"
    );
    // Runs' end markers: as many as runs, filled circles of the end radius, at the
    // paths' last points (the legend's marker is smaller).
    let ends: Vec<(f64, f64)> = s
        .split("<circle ")
        .skip(1)
        .filter(|t| attr(t, "r").as_deref() == Some("5"))
        .map(|t| {
            (
                attr(t, "cx").unwrap().parse().unwrap(),
                attr(t, "cy").unwrap().parse().unwrap(),
            )
        })
        .collect();
    assert_eq!(ends.len(), paths.len(), "{ends:?}");
    let (ox, oy) = {
        // The origin's pixel, from the ticks labelled 0.
        let t = texts(&s);
        let zero = |anchor: &str| {
            t.iter()
                .find(|t| t.anchor == anchor && t.content.parse::<f64>() == Ok(0.0))
                .unwrap()
        };
        (zero("middle").x, zero("end").y)
    };
    for (p, e) in paths.iter().zip(&ends) {
        let (x, y) = p[p.len() - 1];
        let want = (ox + x * px, oy - y * py);
        assert!(
            (e.0 - want.0).abs() <= 1.5 && (e.1 - want.1).abs() <= 1.5,
            "end {e:?}, path ends at {want:?}"
        );
    }
    assert!(std::fs::read(&png).unwrap().len() > 20_000);
}

/// The ideal squares' dashes are 12 px long with 8 px gaps on the page, whatever the
/// scale (here about 0.71 cm per pixel, so 8.5 cm dashes): away from the legend, every
/// dash is at most 12 px (give or take a pixel's rounding at each end), all but the last
/// of each of the 8 legs and its corner piece (a quarter dash, 3 px) are 12 px, and a
/// full dash starts 20 px after the one before it on the same leg.
#[test]
fn ideal_path_dashes_are_twelve_px_with_eight_px_gaps() {
    let (s, _) = square_runs_plot("trajectories_dashes");
    let in_legend = in_legend(&s);
    let dashes: Vec<Vec<(f64, f64)>> = polylines(&s, "#5A5A5A")
        .into_iter()
        .filter(|d| !d.iter().any(&in_legend))
        .collect();
    let len = |d: &Vec<(f64, f64)>| {
        assert_eq!(d.len(), 2, "a dash is one segment: {d:?}");
        dist(d[0], d[1])
    };
    let full = |d: &Vec<(f64, f64)>| (len(d) - 12.0).abs() <= 1.5;
    for d in &dashes {
        assert!(len(d) <= 13.5, "dash {d:?} is {} px", len(d));
    }
    let n_full = dashes.iter().filter(|d| full(d)).count();
    assert!(
        n_full + 2 * 8 >= dashes.len() && n_full > 50,
        "{n_full} of {} dashes are 12 px",
        dashes.len()
    );
    // Consecutive full dashes running the same way are on one leg: 12 + 8 px apart.
    let mut pitches = 0;
    for w in dashes.windows(2) {
        let (a, b) = (&w[0], &w[1]);
        let dir = |d: &Vec<(f64, f64)>| ((d[1].0 - d[0].0).signum(), (d[1].1 - d[0].1).signum());
        if full(a) && full(b) && dir(a) == dir(b) {
            let gap = dist(a[0], b[0]);
            assert!((gap - 20.0).abs() <= 1.5, "dashes {a:?} and {b:?}");
            pitches += 1;
        }
    }
    assert!(pitches > 40, "only {pitches} pairs of dashes on one leg");
}

/// Each run's end marker is filled in its run's colour: the two clockwise runs (group 0)
/// red, #C81E1E, and the counter-clockwise one (group 1) blue, #1E50C8, the colours of
/// their lines (drawn in the runs' order, as the markers are).
#[test]
fn end_markers_take_the_colour_of_their_run() {
    let (s, _) = square_runs_plot("trajectories_colours");
    let in_legend = in_legend(&s);
    let lines: Vec<String> = tags(&s, "polyline")
        .into_iter()
        .filter(|t| attr(t, "stroke-width").as_deref() == Some("2"))
        .filter(|t| attr(t, "stroke").as_deref() != Some("#5A5A5A"))
        .filter(|t| !points(t).iter().any(&in_legend))
        .map(|t| attr(t, "stroke").unwrap())
        .collect();
    assert_eq!(lines, ["#C81E1E", "#C81E1E", "#1E50C8"]);
    let ends: Vec<String> = tags(&s, "circle")
        .into_iter()
        .filter(|t| attr(t, "r").as_deref() == Some("5"))
        .map(|t| attr(t, "fill").unwrap())
        .collect();
    assert_eq!(ends, lines);
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

/// The trajectory plot's legend marks sit in its framed box, each beside its label as
/// plotters lays an entry out: the box (911, 50, 218 × 107 here) holds a 10 px margin,
/// a 30 px area for the mark and the label, so an entry's mark is drawn from x = 911 +
/// 10 = 921 and its label starts at 921 + 30 = 951, and the mark's y is the middle of
/// its label's line, 6 px below the label's top (labels at y 60, 79, 98, 116, 135, marks
/// at 66, 85, 104, 122, 141). From that origin (x0, y): the ideal squares' sample is a
/// dash from x0 to x0 + 8, each group's line runs from x0 to x0 + 20, the end points' dot
/// (radius 4, grey #787878) is centred at x0 + 10, and the start's cross (size 5) too:
/// its two strokes, the last black 2 px `<line>`s drawn, are the diagonals of the square
/// from (x0 + 5, y - 5) to (x0 + 15, y + 5), centred at (931, 141), 10 px right of the
/// entry's origin and 20 px left of "start".
#[test]
fn trajectory_legend_marks_sit_beside_their_labels() {
    let (s, _) = square_runs_plot("trajectories_legend");
    let in_legend = in_legend(&s);
    let frame = tags(&s, "rect")
        .into_iter()
        .find(|t| attr(t, "fill").as_deref() == Some("none"))
        .map(|t| (num(t, "x"), num(t, "y")))
        .unwrap();
    let x0 = frame.0 + 10.0;
    let label = |what: &str| {
        let t = texts(&s);
        let t = t.iter().find(|t| t.content == what).unwrap();
        assert_eq!(t.anchor, "start", "{what:?}");
        assert!(in_legend(&(t.x, t.y)), "{what:?} at ({}, {})", t.x, t.y);
        assert_eq!(t.x, x0 + 30.0, "{what:?} starts at x {}", t.x);
        (t.x, t.y)
    };
    // The mark's row y, which must be the middle of its label's line.
    let beside = |what: &str, y: f64| {
        let (_, ty) = label(what);
        assert!(
            (y - (ty + 6.0)).abs() <= 1.0,
            "{what:?}'s mark at y {y}, its label's top at {ty}"
        );
    };
    let legend_line = |colour: &str| {
        let l: Vec<_> = polylines(&s, colour)
            .into_iter()
            .filter(|l| l.iter().all(&in_legend))
            .collect();
        assert_eq!(l.len(), 1, "{colour} legend lines: {l:?}");
        l[0].clone()
    };
    for (what, colour, length) in [
        ("ideal squares, L = 200 cm", "#5A5A5A", 8.0),
        ("clockwise", "#C81E1E", 20.0),
        ("counter-clockwise", "#1E50C8", 20.0),
    ] {
        let l = legend_line(colour);
        let y = l[0].1;
        assert_eq!(l, [(x0, y), (x0 + length, y)], "{what:?}'s legend line");
        beside(what, y);
    }
    let dots: Vec<_> = tags(&s, "circle")
        .into_iter()
        .filter(|t| attr(t, "r").as_deref() == Some("4"))
        .map(|t| (num(t, "cx"), num(t, "cy"), attr(t, "fill").unwrap()))
        .collect();
    assert_eq!(dots.len(), 1, "{dots:?}");
    let (cx, cy, fill) = &dots[0];
    assert!(in_legend(&(*cx, *cy)), "end points' dot at ({cx}, {cy})");
    assert_eq!(
        (*cx, fill.as_str()),
        (x0 + 10.0, "#787878"),
        "end points' dot"
    );
    beside("end points", *cy);
    let strokes: Vec<[f64; 4]> = tags(&s, "line")
        .into_iter()
        .filter(|t| attr(t, "stroke").as_deref() == Some("#000000"))
        .filter(|t| attr(t, "stroke-width").as_deref() == Some("2"))
        .map(|t| ["x1", "y1", "x2", "y2"].map(|a| num(t, a)))
        .collect();
    assert_eq!(strokes.len(), 4, "two crosses' strokes: {strokes:?}");
    let cross = &strokes[2..];
    let (mx, my) = (
        (cross[0][0] + cross[0][2]) / 2.0,
        (cross[0][1] + cross[0][3]) / 2.0,
    );
    for c in cross {
        for p in [(c[0], c[1]), (c[2], c[3])] {
            assert!(in_legend(&p), "start's cross {cross:?} leaves the legend");
        }
    }
    assert_eq!(mx, x0 + 10.0, "start's cross {cross:?}, entry at x {x0}");
    let y = my;
    assert_eq!(
        cross,
        [
            [x0 + 5.0, y - 5.0, x0 + 15.0, y + 5.0],
            [x0 + 5.0, y + 5.0, x0 + 15.0, y - 5.0]
        ],
        "start's cross"
    );
    assert!(
        x0 + 15.0 < label("start").0,
        "start's cross reaches its label"
    );
    beside("start", y);
}
