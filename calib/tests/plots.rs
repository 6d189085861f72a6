//! The plot functions write a real SVG and a real PNG (of the stated size, with text drawn
//! from the embedded font) for the thesis data, including the triangle experiment whose
//! y values are missing; their axes carry numbered ticks at the same cm per pixel on x and
//! y, and the trajectory plot shows the ideal square, square, and one end marker per run.

use std::path::PathBuf;

use calib::plot::{ideal_path, plot_trajectories, IdealPath, Path2d};
use calib::{
    plot_triangle, plot_umbmark, triangle_correction, umbmark_correction, Frame, TriangleParams,
    UmbmarkParams,
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

/// Every point of the `<polyline>`s stroked in `colour`.
fn polyline_points(svg: &str, colour: &str) -> Vec<(f64, f64)> {
    svg.split("<polyline ")
        .skip(1)
        .map(|t| t.split_once("/>").unwrap().0)
        .filter(|t| attr(t, "stroke").as_deref() == Some(colour))
        .flat_map(|t| {
            attr(t, "points")
                .unwrap()
                .split_whitespace()
                .map(|p| {
                    let (x, y) = p.split_once(',').unwrap();
                    (x.parse().unwrap(), y.parse().unwrap())
                })
                .collect::<Vec<_>>()
        })
        .collect()
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

/// `trajectories.svg`: the ideal squares drawn dashed and square on the page (as many
/// pixels per cm as the ticks say, on x and on y), one end marker per run at its path's
/// last point, the title as given.
#[test]
fn trajectories_show_the_ideal_square_and_the_end_points() {
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
    let (svg, png) = (out("trajectories.svg"), out("trajectories.png"));
    plot_trajectories(
        "UMBmark trajectories, L = 200 cm",
        &ideal,
        &paths,
        &svg,
        &png,
    )
    .unwrap();
    let s = std::fs::read_to_string(&svg).unwrap();
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
    let legend = s
        .split("<rect ")
        .skip(1)
        .find(|t| attr(t, "fill").as_deref() == Some("none"))
        .map(|t| ["x", "y", "width", "height"].map(|a| attr(t, a).unwrap().parse::<f64>().unwrap()))
        .unwrap();
    let in_legend = |&(x, y): &(f64, f64)| {
        x >= legend[0] && x <= legend[0] + legend[2] && y >= legend[1] && y <= legend[1] + legend[3]
    };
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
        let (x, y) = p.points[p.points.len() - 1];
        let want = (ox + x * px, oy - y * py);
        assert!(
            (e.0 - want.0).abs() <= 1.5 && (e.1 - want.1).abs() <= 1.5,
            "end {e:?}, path ends at {want:?}"
        );
    }
    assert!(std::fs::read(&png).unwrap().len() > 20_000);
}
