//! The Triangular Path analysis (Mode::Correct): it inverts the documented first-order model
//! exactly, gives unit factors for zero errors, copes with missing triangle y values, and
//! treats the two directions and the line correction as derived. (Verifying the first-order
//! model itself against exact geometry is left to an independent simulation.)

use approx::assert_relative_eq;
use calib::{
    triangle_correction, Direction, EdVariant, Endpoint, LineRuns, PartialEndpoint, TriangleParams,
    TriangleRuns, HENRYTWO_WHEELBASE_MM,
};
use proptest::prelude::*;

const L: f64 = 200.0;

/// The first-order end errors documented in `calib::triangle`, for turn error `delta`
/// and leg curvature `beta_t` (rad).
fn model_endpoint(delta: f64, beta_t: f64, direction: Direction) -> Endpoint {
    let s3 = 3f64.sqrt();
    match direction {
        Direction::Ccw => {
            Endpoint::new(s3 / 2.0 * L * (beta_t - delta), -1.5 * L * (beta_t - delta))
        }
        Direction::Cw => Endpoint::new(
            -s3 / 2.0 * L * (beta_t + delta),
            -1.5 * L * (beta_t + delta),
        ),
    }
}

fn line_for(beta: f64) -> LineRuns {
    LineRuns::new(vec![Endpoint::new(0.0, L * beta / 2.0); 5]).unwrap()
}

proptest! {
    /// The analysis inverts the documented model: δ from x and from y both equal the
    /// injected turn error, Eb = 120/(120 − δ°), for either direction and whether or not the
    /// line's correction was applied before the triangle.
    #[test]
    fn inverts_the_documented_model(
        delta in -0.05..0.05f64,
        beta in -0.03..0.03f64,
        ccw in any::<bool>(),
        applied in any::<bool>(),
    ) {
        let direction = if ccw { Direction::Ccw } else { Direction::Cw };
        let beta_t = if applied { 0.0 } else { beta };
        let tri = TriangleRuns::complete(vec![model_endpoint(delta, beta_t, direction); 5]).unwrap();
        let p = TriangleParams { direction, line_correction_applied: applied, ..TriangleParams::default() };
        let r = triangle_correction(&line_for(beta), &tri, &p);
        assert_relative_eq!(r.alpha_x_rad, delta, epsilon = 1e-12);
        assert_relative_eq!(r.alpha_y_rad.unwrap(), delta, epsilon = 1e-12);
        assert_relative_eq!(r.beta_rad, beta, epsilon = 1e-12);
        assert_relative_eq!(r.eb, 120.0 / (120.0 - delta.to_degrees()), max_relative = 1e-12);
        assert_relative_eq!(r.wheelbase_mm, r.eb * HENRYTWO_WHEELBASE_MM, max_relative = 1e-12);
        prop_assert!(r.agreement.unwrap().consistent);
    }

    /// cR/cL = Ed and (cL + cR)/2 = 1 for the line's correction too.
    #[test]
    fn line_factors_keep_the_mean_diameter(y in -5.0..5.0f64) {
        let line = LineRuns::new(vec![Endpoint::new(1.0, y); 5]).unwrap();
        let tri = TriangleRuns::complete(vec![Endpoint::new(0.0, 0.0); 5]).unwrap();
        let r = triangle_correction(&line, &tri, &TriangleParams::default());
        assert_relative_eq!(r.cr / r.cl, r.ed, max_relative = 1e-12);
        assert_relative_eq!((r.cl + r.cr) / 2.0, 1.0, max_relative = 1e-12);
    }
}

/// Zero end errors give Ed = Eb = 1, cL = cR = 1 and the nominal wheelbase.
#[test]
fn zero_errors_give_unit_factors() {
    let line = LineRuns::new(vec![Endpoint::new(0.0, 0.0); 5]).unwrap();
    let tri = TriangleRuns::complete(vec![Endpoint::new(0.0, 0.0); 5]).unwrap();
    let r = triangle_correction(&line, &tri, &TriangleParams::default());
    assert_eq!((r.ed, r.eb, r.cl, r.cr), (1.0, 1.0, 1.0, 1.0));
    assert_eq!(r.radius_cm, None);
    assert_eq!(r.wheelbase_mm, HENRYTWO_WHEELBASE_MM);
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
}

/// A line that curves left (+y) means the right wheel is the larger: Ed = D_R/D_L > 1, and
/// the correction scales the right wheel's distance per count up (cR > 1 > cL).
#[test]
fn left_curving_line_means_larger_right_wheel() {
    let line = LineRuns::new(vec![Endpoint::new(0.0, 2.0); 5]).unwrap();
    let tri = TriangleRuns::complete(vec![Endpoint::new(0.0, 0.0); 5]).unwrap();
    let r = triangle_correction(&line, &tri, &TriangleParams::default());
    assert!(r.ed > 1.0 && r.cr > 1.0 && r.cl < 1.0, "{r:?}");
    assert!(r.radius_cm.unwrap() > 0.0);
}

/// Triangle runs without y: the turn error and Eb still come from x, while the y-based
/// estimate, the agreement check and the triangle's end error are reported as unknown,
/// with a warning.
#[test]
fn missing_triangle_y_is_reported_not_invented() {
    let line = LineRuns::new(vec![Endpoint::new(3.0, 1.6); 5]).unwrap();
    let tri = TriangleRuns::new(vec![PartialEndpoint::new(-2.0, None); 5]).unwrap();
    let r = triangle_correction(&line, &tri, &TriangleParams::default());
    assert_eq!(r.alpha_y_deg, None);
    assert_eq!(r.agreement, None);
    assert_eq!(r.triangle_r_cm, None);
    assert_eq!(r.triangle_centroid.y_cm, None);
    assert_relative_eq!(
        r.alpha_x_rad,
        2.0 * 2.0 / (3f64.sqrt() * L),
        max_relative = 1e-12
    );
    assert!(r.warnings.iter().any(|w| w.contains("y is missing")));
}

/// y values given for some triangle runs only: the centroid's y is unknown (a mean over
/// part of the runs would not be comparable with x).
#[test]
fn partly_missing_y_counts_as_missing() {
    let line = LineRuns::new(vec![Endpoint::new(0.0, 0.0); 5]).unwrap();
    let mut runs = vec![PartialEndpoint::new(-2.0, Some(1.0)); 4];
    runs.push(PartialEndpoint::new(-2.0, None));
    let tri = TriangleRuns::new(runs).unwrap();
    assert!(!tri.has_all_y());
    let r = triangle_correction(&line, &tri, &TriangleParams::default());
    assert_eq!(r.triangle_centroid.y_cm, None);
}

/// The OptiOdom variant puts Eb·b into the line's Ed; Borenstein's the nominal b.
#[test]
fn ed_variant_is_recorded_and_used() {
    let line = LineRuns::new(vec![Endpoint::new(0.0, 1.6); 5]).unwrap();
    let tri = TriangleRuns::complete(vec![Endpoint::new(-5.6, 12.16); 5]).unwrap();
    let b = triangle_correction(&line, &tri, &TriangleParams::default());
    let o = triangle_correction(
        &line,
        &tri,
        &TriangleParams {
            ed_variant: EdVariant::OptiOdom,
            ..TriangleParams::default()
        },
    );
    assert_eq!(o.ed_variant, EdVariant::OptiOdom);
    let r = b.radius_cm.unwrap();
    let h = o.wheelbase_mm / 20.0;
    assert_relative_eq!(o.ed, (r + h) / (r - h), max_relative = 1e-12);
    assert!(o.ed > b.ed);
}

/// x and y telling opposite turn errors (as when one axis is mirrored) are flagged, and a
/// mirrored axis or the other direction is named.
#[test]
fn mirrored_triangle_is_flagged() {
    let good = model_endpoint(0.04, 0.0, Direction::Ccw);
    let mirrored = Endpoint::new(-good.x_cm, good.y_cm);
    let line = LineRuns::new(vec![Endpoint::new(0.0, 0.0); 5]).unwrap();
    let tri = TriangleRuns::complete(vec![mirrored; 5]).unwrap();
    let r = triangle_correction(&line, &tri, &TriangleParams::default());
    let a = r.agreement.unwrap();
    assert!(!a.consistent);
    assert!(a.explained_by.iter().any(|s| s == "x mirrored"));
    assert!(a.explained_by.iter().any(|s| s.contains("clockwise")));
}
