//! The kinematic model: exact against calib's forward model, and each effect with the
//! signature its documentation claims.

use approx::assert_abs_diff_eq;
use calib::forward::{Robot, SystematicErrors};
use calib::Direction;
use gap::effects::{
    COAST, DISTANCE_SCALE, FLOOR_NOISE, TOE, TURN_SLIP, WHEELBASE_RATIO, WHEEL_DIAMETER_RATIO,
};
use gap::{
    EffectParams, Experiment, Firmware, KinematicModel, Model, ModelError, Reference, RunEndpoint,
    StraightLegs, TestKind, ALL_EFFECTS,
};

fn reference() -> Reference {
    Reference {
        wheelbase_mm: 125.0,
        mm_per_count: 0.1669339526,
    }
}

fn exp(test: TestKind, straight: StraightLegs) -> Experiment {
    let r = reference();
    Experiment {
        test,
        firmware: Firmware {
            straight_legs: straight,
            ..Firmware::nominal(&r, 2000.0)
        },
        reference: r,
        runs: 1,
        seed: 7,
    }
}

fn one(p: &EffectParams, e: &Experiment) -> RunEndpoint {
    KinematicModel.predict(p, e).unwrap()[0]
}

/// With unit correction factors and equal wheel rates the model is calib's exact forward
/// model, for squares both ways and the line, under both straight-leg conventions.
#[test]
fn matches_calib_forward() {
    for (ed, eb, es) in [(1.0, 1.0, 1.0), (1.01, 0.97, 1.0), (0.995, 1.04, 0.98)] {
        let robot = Robot {
            wheelbase_nominal_cm: 12.5,
            errors: SystematicErrors { ed, eb, es },
        };
        let p = EffectParams::new()
            .with(WHEEL_DIAMETER_RATIO, ed)
            .with(WHEELBASE_RATIO, eb)
            .with(DISTANCE_SCALE, es);
        for straight in [
            StraightLegs::SpeedSetpoints,
            StraightLegs::CorrectedOdometry,
        ] {
            for (kind, dir) in [
                (TestKind::UmbmarkCw, Direction::Cw),
                (TestKind::UmbmarkCcw, Direction::Ccw),
            ] {
                let want = robot.square_endpoint(200.0, dir);
                let got = one(&p, &exp(kind, straight));
                assert_abs_diff_eq!(got.x_cm, want.x_cm, epsilon = 1e-9);
                assert_abs_diff_eq!(got.y_cm, want.y_cm, epsilon = 1e-9);
            }
            let want = robot.line_endpoint(200.0);
            let got = one(&p, &exp(TestKind::Line, straight));
            assert_abs_diff_eq!(got.x_cm, want.x_cm, epsilon = 1e-9);
            assert_abs_diff_eq!(got.y_cm, want.y_cm, epsilon = 1e-9);
        }
    }
}

/// A robot without effects closes every polygon and ends the line where commanded.
#[test]
fn nominal_robot_is_exact() {
    for kind in TestKind::ALL {
        let e = one(
            &EffectParams::new(),
            &exp(kind, StraightLegs::SpeedSetpoints),
        );
        assert_abs_diff_eq!(e.x_cm, 0.0, epsilon = 1e-9);
        assert_abs_diff_eq!(e.y_cm, 0.0, epsilon = 1e-9);
        assert_abs_diff_eq!(e.theta_rad, 0.0, epsilon = 1e-12);
    }
}

/// Toe shifts a line sideways by L·sin φ without turning it, and a closed polygon with exact
/// turns cancels it.
#[test]
fn toe_crabs_and_cancels_on_polygons() {
    let p = EffectParams::new().with(TOE, 1.0);
    let line = one(&p, &exp(TestKind::Line, StraightLegs::SpeedSetpoints));
    assert_abs_diff_eq!(line.y_cm, 200.0 * 1f64.to_radians().sin(), epsilon = 1e-9);
    assert_abs_diff_eq!(line.theta_rad, 0.0, epsilon = 1e-12);
    for kind in [
        TestKind::UmbmarkCw,
        TestKind::UmbmarkCcw,
        TestKind::TriangleCcw,
    ] {
        let e = one(&p, &exp(kind, StraightLegs::SpeedSetpoints));
        assert_abs_diff_eq!(e.x_cm.hypot(e.y_cm), 0.0, epsilon = 1e-9);
    }
}

/// Coast adds the same angle to every turn whatever its size; the wheelbase ratio scales the
/// turn: on a square they match at one size, on the triangle they differ.
#[test]
fn coast_is_constant_per_turn_wheelbase_is_proportional() {
    let c = EffectParams::new().with(COAST, 2.0);
    let sq = one(&c, &exp(TestKind::UmbmarkCcw, StraightLegs::SpeedSetpoints));
    let tri = one(
        &c,
        &exp(TestKind::TriangleCcw, StraightLegs::SpeedSetpoints),
    );
    assert_abs_diff_eq!(sq.theta_rad.to_degrees(), 8.0, epsilon = 1e-9);
    assert_abs_diff_eq!(tri.theta_rad.to_degrees(), 6.0, epsilon = 1e-9);
    // Eb giving 92° per 90° corner gives 122.67° per 120° corner.
    let b = EffectParams::new().with(WHEELBASE_RATIO, 90.0 / 92.0);
    let sq_b = one(&b, &exp(TestKind::UmbmarkCcw, StraightLegs::SpeedSetpoints));
    let tri_b = one(
        &b,
        &exp(TestKind::TriangleCcw, StraightLegs::SpeedSetpoints),
    );
    assert_abs_diff_eq!(sq_b.theta_rad.to_degrees(), 8.0, epsilon = 1e-9);
    assert_abs_diff_eq!(
        tri_b.theta_rad.to_degrees(),
        3.0 * 120.0 * (92.0 / 90.0 - 1.0),
        epsilon = 1e-9
    );
}

/// Turn slip s and wheelbase ratio 1/(1 − s) give the same end point when both wheels spin at
/// the same rate: spins alone cannot tell them apart.
#[test]
fn turn_slip_aliases_wheelbase_on_spins() {
    let s = EffectParams::new().with(TURN_SLIP, 0.03);
    let b = EffectParams::new().with(WHEELBASE_RATIO, 1.0 / 0.97);
    for kind in TestKind::ALL {
        let e = exp(kind, StraightLegs::SpeedSetpoints);
        let (a, c) = (one(&s, &e), one(&b, &e));
        assert_abs_diff_eq!(a.x_cm, c.x_cm, epsilon = 1e-9);
        assert_abs_diff_eq!(a.y_cm, c.y_cm, epsilon = 1e-9);
    }
}

/// Unequal set-points curve a leg of a robot with equal wheels by the count-rate ratio, and a
/// diameter ratio equal to that ratio straightens it again.
#[test]
fn setpoints_set_the_count_ratio_of_a_leg() {
    let mut e = exp(TestKind::Line, StraightLegs::SpeedSetpoints);
    e.firmware.setpoint_left = Some(15.0);
    e.firmware.setpoint_right = Some(14.47);
    let bent = one(&EffectParams::new(), &e);
    assert!(bent.theta_rad < -0.4, "curves right: {}", bent.theta_rad);
    let straight = one(
        &EffectParams::new().with(WHEEL_DIAMETER_RATIO, 15.0 / 14.47),
        &e,
    );
    assert_abs_diff_eq!(straight.theta_rad, 0.0, epsilon = 1e-12);
    assert_abs_diff_eq!(straight.y_cm, 0.0, epsilon = 1e-9);
}

/// Floor noise is reproducible from the seed, zero-mean, and its spread grows in proportion
/// to σ (the same random numbers for every σ).
#[test]
fn floor_noise_is_seeded_and_proportional() {
    let mut e = exp(TestKind::UmbmarkCw, StraightLegs::SpeedSetpoints);
    e.runs = 400;
    let p1 = EffectParams::new().with(FLOOR_NOISE, 0.5);
    let p2 = EffectParams::new().with(FLOOR_NOISE, 1.0);
    let a = KinematicModel.predict(&p1, &e).unwrap();
    let again = KinematicModel.predict(&p1, &e).unwrap();
    assert_eq!(a, again);
    let b = KinematicModel.predict(&p2, &e).unwrap();
    let sd = |v: &[RunEndpoint]| {
        let m = v.iter().map(|r| r.y_cm).sum::<f64>() / v.len() as f64;
        (v.iter().map(|r| (r.y_cm - m).powi(2)).sum::<f64>() / (v.len() - 1) as f64).sqrt()
    };
    let ratio = sd(&b) / sd(&a);
    assert!((ratio - 2.0).abs() < 0.02, "spread ratio {ratio}");
    let mean = a.iter().map(|r| r.y_cm).sum::<f64>() / a.len() as f64;
    assert!(mean.abs() < 3.0 * sd(&a) / 20.0, "mean {mean}");
}

/// Unknown names and out-of-bounds values are refused with errors that say which.
#[test]
fn parameters_are_checked() {
    let e = exp(TestKind::Line, StraightLegs::SpeedSetpoints);
    let err = KinematicModel
        .predict(&EffectParams::new().with("wheel_size", 1.0), &e)
        .unwrap_err();
    assert!(matches!(err, ModelError::UnknownParameter { ref name, .. } if name == "wheel_size"));
    let err = KinematicModel
        .predict(&EffectParams::new().with(TOE, 45.0), &e)
        .unwrap_err();
    assert!(matches!(err, ModelError::OutOfBounds { .. }), "{err}");
}

/// Every library effect is either a parameter of the kinematic model or listed as
/// unsupported with a reason.
#[test]
fn every_library_effect_is_accounted_for() {
    let params: Vec<String> = KinematicModel
        .parameters()
        .into_iter()
        .map(|p| p.name)
        .collect();
    let unsupported = KinematicModel.unsupported();
    for e in ALL_EFFECTS {
        let p = params.iter().any(|n| n == e);
        let u = unsupported
            .iter()
            .any(|u| u.name == e && !u.reason.is_empty());
        assert!(p ^ u, "{e}: parameter {p}, unsupported {u}");
    }
    assert_eq!(params.len(), 7);
}
