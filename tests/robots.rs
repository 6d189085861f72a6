//! Robots other than Henrytwo, on the same robust ELF: told their geometry
//! over the protocol before each run, they drive the thesis' tests as
//! Henrytwo does, before any calibration (the bar: a 2 m line within
//! 1 % of its length, spin turns within 10 degrees of 90).
//!
//! `compact48` has other wheels, gears and encoder resolution on Henrytwo's
//! board; each must end its legs by its own distance per count.

mod support;

use hil::bench::BenchOptions;
use hil::experiment::{run_test, Test, TestOptions, TestRun};
use hil::firmware_params::Tell;
use plant_model::RobotConfig;

const LEG_MM: f64 = 2000.0;

fn run(robot: &RobotConfig, test: Test, tell: Tell) -> TestRun {
    let opts = TestOptions {
        leg_mm: LEG_MM,
        bench: BenchOptions::default(),
        limit_s: Some(200.0),
        tell,
        ..Default::default()
    };
    run_test(support::firmware("robust"), robot, test, &opts).expect("the bench runs the test")
}

/// A 2 m line ends within 1 % of 2 m, straight, by the firmware's own
/// odometry of this robot's counts.
fn drives_a_line(robot: &RobotConfig) {
    let r = run(robot, Test::Line, Tell::Robot);
    assert!(r.completed, "{:?}", r.finding);
    assert_eq!(r.legs.len(), 1, "{:#?}", r.legs);
    let leg = &r.legs[0];
    assert!(
        (leg.plant_distance_mm - LEG_MM).abs() < 0.01 * LEG_MM,
        "line of {:.1} mm",
        leg.plant_distance_mm
    );
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
}

/// A CW square: four legs of 2 m within 1 %, four turns within 10 degrees
/// of 90.
fn drives_a_square(robot: &RobotConfig) {
    let r = run(robot, Test::UmbmarkCw, Tell::Robot);
    assert!(r.completed, "{:?}", r.finding);
    assert_eq!((r.legs.len(), r.turns.len()), (4, 4), "{r:#?}");
    for leg in &r.legs {
        assert!(
            (leg.plant_distance_mm - LEG_MM).abs() < 0.01 * LEG_MM,
            "leg of {:.1} mm",
            leg.plant_distance_mm
        );
    }
    for t in &r.turns {
        assert!(
            (t.plant_angle_deg.abs() - 90.0).abs() < 10.0,
            "turn of {:.1} deg",
            t.plant_angle_deg
        );
    }
}

#[test]
fn compact48_drives_a_line() {
    drives_a_line(&support::robot("compact48"));
}

#[test]
fn compact48_drives_a_square() {
    drives_a_square(&support::robot("compact48"));
}

/// Told nothing, the firmware drives Henrytwo's distance per count on
/// compact48's wheels: the leg is off by their ratio (0.2513 / 0.1669 mm),
/// and the run says why.
#[test]
fn a_firmware_kept_on_its_own_geometry_is_warned_about() {
    let robot = support::robot("compact48");
    let r = run(&robot, Test::Line, Tell::Keep);
    let leg = &r.legs[0];
    let ratio = (std::f64::consts::PI * 48.0 / 600.0) / (std::f64::consts::PI * 32.0 / 602.22);
    assert!(
        (leg.plant_distance_mm / LEG_MM - ratio).abs() < 0.02,
        "{:.1} mm",
        leg.plant_distance_mm
    );
    assert_eq!(r.warnings.len(), 1, "{:?}", r.warnings);
    assert!(
        r.warnings[0].contains("mm per count") && r.warnings[0].contains("keep"),
        "{}",
        r.warnings[0]
    );
}
