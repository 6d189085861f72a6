//! Reading the plots the tests write: where they go, a PNG's size, and an SVG's elements as
//! plotters writes them.

use std::path::PathBuf;

pub fn out(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name)
}

/// Width and height from a PNG's IHDR chunk, after checking the signature.
pub fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "PNG signature");
    assert_eq!(&bytes[12..16], b"IHDR");
    let be = |i: usize| u32::from_be_bytes(bytes[i..i + 4].try_into().unwrap());
    (be(16), be(20))
}

/// A `<text>` element of an SVG written by plotters: where, anchored how, saying what.
pub struct Text {
    pub x: f64,
    pub y: f64,
    pub anchor: String,
    pub content: String,
}

/// The value of attribute `name` in `tag` (the text after the element's name).
pub fn attr(tag: &str, name: &str) -> Option<String> {
    let tag = format!(" {tag}");
    let at = tag.find(&format!(" {name}=\""))? + name.len() + 3;
    Some(tag[at..].split('"').next()?.to_string())
}

pub fn texts(svg: &str) -> Vec<Text> {
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
pub fn scale_from_ticks(svg: &str) -> ((f64, usize), (f64, usize)) {
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
pub fn tags<'a>(svg: &'a str, name: &str) -> Vec<&'a str> {
    svg.split(&format!("<{name} "))
        .skip(1)
        .map(|t| t.split_once("/>").unwrap().0)
        .collect()
}

/// The `points` of a `<polyline>` or `<polygon>`, in pixels.
pub fn points(tag: &str) -> Vec<(f64, f64)> {
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
pub fn num(tag: &str, name: &str) -> f64 {
    attr(tag, name).unwrap().parse().unwrap()
}

/// The `<polyline>`s stroked in `colour`, each as its points.
pub fn polylines(svg: &str, colour: &str) -> Vec<Vec<(f64, f64)>> {
    tags(svg, "polyline")
        .into_iter()
        .filter(|t| attr(t, "stroke").as_deref() == Some(colour))
        .map(points)
        .collect()
}

/// Every point of the `<polyline>`s stroked in `colour`.
pub fn polyline_points(svg: &str, colour: &str) -> Vec<(f64, f64)> {
    polylines(svg, colour).concat()
}

pub fn dist(a: (f64, f64), b: (f64, f64)) -> f64 {
    (a.0 - b.0).hypot(a.1 - b.1)
}

pub fn bbox(pts: &[(f64, f64)]) -> (f64, f64) {
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in pts {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    (x1 - x0, y1 - y0)
}
