//! The JSON reports of the thesis' experiment 1, in both modes, are pinned by insta
//! snapshots: any change to a formula, a field name or a warning shows up as a diff to
//! review. Floats are rounded to 9 significant digits so that last-bit differences between
//! libm implementations do not matter.

use calib::thesis::{triangle_params_for_experiment, umbmark_params_for_experiment};
use calib::{triangle_correction, umbmark_correction, Frame, TriangleParams, UmbmarkParams};
use serde_json::Value;

mod common;
use common::{thesis_triangle, thesis_umbmark};

fn rounded(v: Value) -> Value {
    match v {
        Value::Number(n) if n.is_f64() => {
            let x = n.as_f64().unwrap();
            let r: f64 = format!("{x:.8e}").parse().unwrap();
            serde_json::json!(r)
        }
        Value::Array(a) => Value::Array(a.into_iter().map(rounded).collect()),
        Value::Object(o) => Value::Object(o.into_iter().map(|(k, v)| (k, rounded(v))).collect()),
        other => other,
    }
}

fn json<T: serde::Serialize>(t: &T) -> Value {
    rounded(serde_json::to_value(t).unwrap())
}

/// UMBmark experiment 1, Mode::Correct, data declared in the thesis GUI's frame, with the
/// wheelbase the robot ran it with (125 mm, not the crate's default).
#[test]
fn umbmark_experiment_1_correct() {
    let r = umbmark_correction(
        &thesis_umbmark(1),
        &UmbmarkParams {
            frame: Frame::ThesisGui,
            wheelbase_mm: umbmark_params_for_experiment(1).unwrap().wheelbase_mm,
            ..UmbmarkParams::default()
        },
    );
    insta::assert_json_snapshot!(json(&r));
}

/// UMBmark experiment 1, Mode::ThesisCompat with the GUI as it was for that experiment.
#[test]
fn umbmark_experiment_1_thesis_compat() {
    let r = umbmark_correction(
        &thesis_umbmark(1),
        &umbmark_params_for_experiment(1).unwrap(),
    );
    insta::assert_json_snapshot!(json(&r));
}

/// Triangular Path experiment 1, Mode::Correct, default frame (where its x and y agree), with
/// the wheelbase the robot ran it with (125 mm, not the crate's default).
#[test]
fn triangle_experiment_1_correct() {
    let e = thesis_triangle(1);
    let params = TriangleParams {
        wheelbase_mm: triangle_params_for_experiment(1).unwrap().wheelbase_mm,
        ..TriangleParams::default()
    };
    let r = triangle_correction(&e.line, &e.triangle, &params);
    insta::assert_json_snapshot!(json(&r));
}

/// Triangular Path experiment 1, Mode::ThesisCompat.
#[test]
fn triangle_experiment_1_thesis_compat() {
    let e = thesis_triangle(1);
    let r = triangle_correction(
        &e.line,
        &e.triangle,
        &triangle_params_for_experiment(1).unwrap(),
    );
    insta::assert_json_snapshot!(json(&r));
}

/// The result's JSON carries the field names other tools rely on.
#[test]
fn json_field_names() {
    let u = serde_json::to_value(umbmark_correction(
        &thesis_umbmark(1),
        &UmbmarkParams::default(),
    ))
    .unwrap();
    for k in [
        "r_cg_cw_cm",
        "r_cg_ccw_cm",
        "e_max_cm",
        "alpha_deg",
        "beta_deg",
        "ed",
        "eb",
        "cl",
        "cr",
        "wheelbase_mm",
        "frame",
        "ed_variant",
        "warnings",
    ] {
        assert!(u.get(k).is_some(), "umbmark: {k}");
    }
    let e = thesis_triangle(1);
    let t = serde_json::to_value(triangle_correction(
        &e.line,
        &e.triangle,
        &TriangleParams::default(),
    ))
    .unwrap();
    for k in [
        "line_centroid",
        "triangle_centroid",
        "alpha_deg",
        "beta_deg",
        "ed",
        "eb",
        "cl",
        "cr",
        "wheelbase_mm",
    ] {
        assert!(t.get(k).is_some(), "triangle: {k}");
    }
}
