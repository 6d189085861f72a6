//! The plot functions write a real SVG and a real PNG (of the stated size, with text drawn
//! from the embedded font) for the thesis data, including the triangle experiment whose
//! y values are missing.

use std::path::PathBuf;

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
