//! The trajectory plot: the ideal square dashed under the runs, one end marker per run in its
//! run's colour, and a legend whose marks sit beside their labels, checked in the SVG's
//! elements and the PNG's pixels.

use std::path::PathBuf;

use calib::plot::{ideal_path, plot_trajectories, IdealPath, Path2d};

mod common;
use common::svg::*;

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
