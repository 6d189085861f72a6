//! Properties of the UMBmark analysis (Mode::Correct), on synthetic end errors from the exact
//! wheel-level forward model and on arbitrary data: it recovers injected Ed and Eb to second
//! order, treats the two directions and the frames symmetrically, and its correction factors
//! keep the mean wheel diameter.

use approx::assert_relative_eq;
use calib::forward::{Robot, SystematicErrors};
use calib::{
    umbmark_correction, Direction, EdVariant, Endpoint, Frame, ScaleError, UmbmarkParams,
    UmbmarkRuns,
};
use proptest::prelude::*;

/// Five CW and five CCW runs of a robot with the given errors, from the exact forward
/// model (all alike: the model has no random error).
fn simulated(errors: SystematicErrors, side_cm: f64, wheelbase_cm: f64) -> UmbmarkRuns {
    let robot = Robot {
        wheelbase_nominal_cm: wheelbase_cm,
        errors,
    };
    UmbmarkRuns::new(
        vec![robot.square_endpoint(side_cm, Direction::Cw); 5],
        vec![robot.square_endpoint(side_cm, Direction::Ccw); 5],
    )
    .unwrap()
}

fn params(side_cm: f64, wheelbase_cm: f64) -> UmbmarkParams {
    UmbmarkParams {
        side_cm,
        wheelbase_mm: wheelbase_cm * 10.0,
        ..UmbmarkParams::default()
    }
}

/// The true α (rad) and β (rad) of the injected errors, for error bounds.
fn true_angles(e: SystematicErrors, side_cm: f64, wheelbase_cm: f64) -> (f64, f64) {
    let alpha = (90.0 * (1.0 - 1.0 / e.eb)).to_radians();
    let beta = side_cm * 2.0 * (e.ed - 1.0) / ((e.ed + 1.0) * wheelbase_cm * e.eb);
    (alpha, beta)
}

fn endpoint() -> impl Strategy<Value = Endpoint> {
    (-60.0..60.0f64, -60.0..60.0f64).prop_map(|(x, y)| Endpoint::new(x, y))
}

fn runs() -> impl Strategy<Value = UmbmarkRuns> {
    (
        prop::collection::vec(endpoint(), 1..8),
        prop::collection::vec(endpoint(), 1..8),
    )
        .prop_map(|(cw, ccw)| UmbmarkRuns::new(cw, ccw).unwrap())
}

proptest! {
    /// Injected Ed and Eb come back from exact-geometry squares, with errors of second order
    /// in the angles (the method is first order): |ΔEb| ≤ 1.5(α² + β²) and the relative
    /// error of Ed − 1 at most 5(|α| + |β|), for both Ed variants.
    #[test]
    fn recovers_injected_ed_and_eb(
        eb in 0.97..1.03f64,
        ed in 0.997..1.003f64,
        wheelbase_cm in 10.0..50.0f64,
        side_cm in prop::sample::select(vec![200.0, 400.0]),
        optiodom in any::<bool>(),
    ) {
        let e = SystematicErrors { ed, eb, es: 1.0 };
        let runs = simulated(e, side_cm, wheelbase_cm);
        let p = UmbmarkParams {
            ed_variant: if optiodom { EdVariant::OptiOdom } else { EdVariant::Borenstein },
            ..params(side_cm, wheelbase_cm)
        };
        let r = umbmark_correction(&runs, &p);
        let (a, b) = true_angles(e, side_cm, wheelbase_cm);
        prop_assert!((r.eb - eb).abs() <= 1.5 * (a * a + b * b) + 1e-12,
            "Eb {} vs injected {}", r.eb, eb);
        prop_assert!((r.ed - ed).abs() <= 5.0 * (a.abs() + b.abs()) * (ed - 1.0).abs() + 1e-12,
            "Ed {} vs injected {}", r.ed, ed);
        prop_assert!((r.wheelbase_mm - eb * wheelbase_cm * 10.0).abs()
            <= 1.5 * (a * a + b * b) * wheelbase_cm * 10.0 + 1e-9);
    }

    /// On model data (errors up to ~1.7° per turn and per leg) the x- and y-based estimates
    /// agree within the default 1° tolerance and no frame problem is reported.
    #[test]
    fn x_and_y_estimates_agree_on_model_data(
        eb in 0.98..1.02f64,
        ed in 0.9985..1.0015f64,
    ) {
        let runs = simulated(SystematicErrors { ed, eb, es: 1.0 }, 200.0, 12.5);
        let r = umbmark_correction(&runs, &params(200.0, 12.5));
        prop_assert!(r.agreement.consistent, "{:?}", r.agreement);
        prop_assert!(r.agreement.explained_by.is_empty());
        prop_assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    }

    /// Exchanging the CW and CCW labels flips β (and so inverts Ed and swaps cL and cR)
    /// while α and Eb stay the same.
    #[test]
    fn swapping_directions_flips_beta(runs in runs()) {
        let p = UmbmarkParams::default();
        let r = umbmark_correction(&runs, &p);
        let s = umbmark_correction(&runs.swapped(), &p);
        assert_relative_eq!(s.beta_rad, -r.beta_rad, epsilon = 1e-12);
        assert_relative_eq!(s.alpha_rad, r.alpha_rad, epsilon = 1e-12);
        assert_relative_eq!(s.eb, r.eb, epsilon = 1e-12);
        assert_relative_eq!(s.ed, 1.0 / r.ed, max_relative = 1e-9);
        assert_relative_eq!(s.cl, r.cr, max_relative = 1e-9);
        assert_relative_eq!(s.cr, r.cl, max_relative = 1e-9);
        assert_relative_eq!(s.e_max_cm, r.e_max_cm, epsilon = 1e-12);
    }

    /// The correction factors keep the mean diameter and realise the ratio:
    /// cR/cL = Ed and (cL + cR)/2 = 1, whatever the data.
    #[test]
    fn correction_factors_keep_the_mean_diameter(runs in runs()) {
        let r = umbmark_correction(&runs, &UmbmarkParams::default());
        assert_relative_eq!(r.cr / r.cl, r.ed, max_relative = 1e-12);
        assert_relative_eq!((r.cl + r.cr) / 2.0, 1.0, max_relative = 1e-12);
    }

    /// Declaring Frame::ThesisGui is the same as mirroring x and declaring the default frame:
    /// every estimate is equal; only the reported centroids stay as recorded.
    #[test]
    fn thesis_frame_is_mirrored_x(runs in runs()) {
        let mirror = |v: &[Endpoint]| v.iter().map(|p| Endpoint::new(-p.x_cm, p.y_cm)).collect();
        let mirrored = UmbmarkRuns::new(mirror(runs.cw()), mirror(runs.ccw())).unwrap();
        let a = umbmark_correction(&runs, &UmbmarkParams { frame: Frame::ThesisGui, ..UmbmarkParams::default() });
        let b = umbmark_correction(&mirrored, &UmbmarkParams::default());
        for (x, y) in [
            (a.alpha_x_rad, b.alpha_x_rad), (a.alpha_y_rad, b.alpha_y_rad),
            (a.beta_x_rad, b.beta_x_rad), (a.beta_y_rad, b.beta_y_rad),
            (a.ed, b.ed), (a.eb, b.eb), (a.r_cg_cw_cm, b.r_cg_cw_cm),
        ] {
            assert_relative_eq!(x, y, epsilon = 1e-12);
        }
        assert_eq!(a.centroid_cw.x_cm, -b.centroid_cw.x_cm);
    }

    /// The OptiOdom variant is Borenstein's formula with Eb·b in place of b, on the same R.
    #[test]
    fn optiodom_uses_the_corrected_wheelbase(runs in runs()) {
        let base = UmbmarkParams::default();
        let b = umbmark_correction(&runs, &base);
        let o = umbmark_correction(&runs, &UmbmarkParams { ed_variant: EdVariant::OptiOdom, ..base.clone() });
        prop_assert_eq!(b.ed_variant, EdVariant::Borenstein);
        prop_assert_eq!(o.ed_variant, EdVariant::OptiOdom);
        if let Some(r) = b.radius_cm {
            let h = o.wheelbase_mm / 20.0;
            prop_assume!((r.abs() - h).abs() > 1e-3);
            assert_relative_eq!(o.ed, (r + h) / (r - h), max_relative = 1e-9);
        }
    }
}

/// A perfect robot (and, equally, perfect measurements) gives Ed = Eb = 1, cL = cR = 1 and
/// the nominal wheelbase, with nothing to warn about.
#[test]
fn zero_errors_give_unit_factors() {
    let perfect = simulated(SystematicErrors::default(), 200.0, 12.5);
    let zeros = UmbmarkRuns::new(
        vec![Endpoint::new(0.0, 0.0); 5],
        vec![Endpoint::new(0.0, 0.0); 5],
    )
    .unwrap();
    for runs in [perfect, zeros] {
        let r = umbmark_correction(&runs, &params(200.0, 12.5));
        assert_relative_eq!(r.ed, 1.0, epsilon = 1e-9);
        assert_relative_eq!(r.eb, 1.0, epsilon = 1e-9);
        assert_relative_eq!(r.cl, 1.0, epsilon = 1e-9);
        assert_relative_eq!(r.cr, 1.0, epsilon = 1e-9);
        assert_relative_eq!(r.wheelbase_mm, 125.0, epsilon = 1e-6);
        assert!(r.agreement.consistent);
    }
}

/// Exactly zero end errors give exactly 1 and an infinite radius reported as `None`
/// (no NaN from (∞ + b/2)/(∞ − b/2)).
#[test]
fn straight_legs_have_no_radius() {
    let zeros =
        UmbmarkRuns::new(vec![Endpoint::new(0.0, 0.0)], vec![Endpoint::new(0.0, 0.0)]).unwrap();
    let r = umbmark_correction(&zeros, &UmbmarkParams::default());
    assert_eq!(r.radius_cm, None);
    assert_eq!(r.ed, 1.0);
    assert_eq!(r.eb, 1.0);
}

/// A scale error, measured on a straight line and given as `scale`, is removed before the
/// wheelbase is estimated: a robot whose only fault is its mean wheel diameter gets Eb ≈ 1,
/// while ignoring Es would blame the wheelbase for it.
#[test]
fn scale_error_is_applied_first() {
    let e = SystematicErrors {
        ed: 1.0,
        eb: 1.0,
        es: 1.02,
    };
    let robot = Robot {
        wheelbase_nominal_cm: 12.5,
        errors: e,
    };
    let line = robot.line_endpoint(300.0);
    let scale = ScaleError {
        commanded_cm: 300.0,
        measured_cm: 300.0 + line.x_cm,
    };
    assert_relative_eq!(scale.es(), 1.02, max_relative = 1e-12);
    let runs = simulated(e, 200.0, 12.5);
    let with = umbmark_correction(
        &runs,
        &UmbmarkParams {
            scale: Some(scale),
            ..params(200.0, 12.5)
        },
    );
    let without = umbmark_correction(&runs, &params(200.0, 12.5));
    assert_relative_eq!(with.eb, 1.0, epsilon = 1e-3);
    assert_eq!(with.es, Some(scale.es()));
    assert_relative_eq!(with.side_actual_cm, 200.0 / 1.02, max_relative = 1e-12);
    assert!(
        (without.eb - 1.0).abs() > 0.015,
        "Eb without Es: {}",
        without.eb
    );
}

/// Data mirrored in x but declared in the default frame make the x- and y-based estimates
/// disagree, and the warning names a mirrored axis as an explanation.
#[test]
fn mirrored_data_are_flagged() {
    let runs = simulated(
        SystematicErrors {
            ed: 1.001,
            eb: 1.02,
            es: 1.0,
        },
        200.0,
        12.5,
    );
    let mirror = |v: &[Endpoint]| v.iter().map(|p| Endpoint::new(-p.x_cm, p.y_cm)).collect();
    let mirrored = UmbmarkRuns::new(mirror(runs.cw()), mirror(runs.ccw())).unwrap();
    let r = umbmark_correction(&mirrored, &params(200.0, 12.5));
    assert!(!r.agreement.consistent);
    assert!(r.agreement.explained_by.iter().any(|s| s == "x mirrored"));
    assert!(r.warnings.iter().any(|w| w.contains("x mirrored")));
    // Declaring the frame that was used resolves it.
    let ok = umbmark_correction(
        &mirrored,
        &UmbmarkParams {
            frame: Frame::ThesisGui,
            ..params(200.0, 12.5)
        },
    );
    assert!(ok.agreement.consistent);
}

/// Fewer or more than five runs per direction still compute, with a warning.
#[test]
fn unusual_run_counts_warn() {
    let runs = UmbmarkRuns::new(
        vec![Endpoint::new(1.0, 1.0); 3],
        vec![Endpoint::new(1.0, -1.0); 5],
    )
    .unwrap();
    let r = umbmark_correction(&runs, &UmbmarkParams::default());
    assert_eq!(r.runs_cw, 3);
    assert!(r.warnings.iter().any(|w| w.contains("3 cw runs")));
}

/// Runs must be non-empty and finite: the constructor refuses anything else.
#[test]
fn invalid_runs_are_refused() {
    assert!(UmbmarkRuns::new(vec![], vec![Endpoint::new(0.0, 0.0)]).is_err());
    assert!(UmbmarkRuns::new(
        vec![Endpoint::new(f64::NAN, 0.0)],
        vec![Endpoint::new(0.0, 0.0)]
    )
    .is_err());
}

/// Ed is meaningless, and said to be, when the legs bend tighter than half the wheelbase
/// (13 cm here): on 10 cm legs a β of 0.5 rad is a radius of about 20 cm (no warning), one
/// of 2 rad about 5.9 cm (the warning).
#[test]
fn a_leg_radius_below_half_the_wheelbase_is_reported() {
    let warned = |x_cm: f64| {
        let runs = calib::UmbmarkRuns::new(
            vec![calib::Endpoint::new(-x_cm, 0.0)],
            vec![calib::Endpoint::new(x_cm, 0.0)],
        )
        .unwrap();
        let r = calib::umbmark_correction(
            &runs,
            &calib::UmbmarkParams {
                side_cm: 10.0,
                wheelbase_mm: 130.0,
                ..calib::UmbmarkParams::default()
            },
        );
        let radius = r.radius_cm.unwrap().abs();
        let says = r
            .warnings
            .iter()
            .any(|w| w.contains("radius of curvature is below half the wheelbase"));
        (radius, says)
    };
    let (radius, says) = warned(10.0);
    assert!((radius - 20.0).abs() < 0.5 && !says, "{radius} {says}");
    let (radius, says) = warned(40.0);
    assert!((radius - 5.94).abs() < 0.01 && says, "{radius} {says}");
}
