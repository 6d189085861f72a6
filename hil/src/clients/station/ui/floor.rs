//! Where the emulated robot's runs are on the floor: each in its start
//! frame (x along the first leg, y to the left), as the tape measure and the
//! floor plot both take them.

use serde::Serialize;

use crate::runs::experiment::Test;

/// Where the emulated robot stood when a test started.
#[derive(Debug, Clone, Copy)]
pub(super) struct StartPose {
    /// Numbers the runs since `hil ui` started, so that the page tells two
    /// runs of one test apart.
    pub(super) run: u64,
    pub(super) test: Test,
    pub(super) leg_mm: f64,
    pub(super) x_mm: f64,
    pub(super) y_mm: f64,
    pub(super) theta_rad: f64,
}

/// A point of the floor in a run's start frame (x along the first leg, y
/// to the left), mm.
pub(super) fn in_start_frame(start: &StartPose, x_mm: f64, y_mm: f64) -> (f64, f64) {
    let (dx, dy) = (x_mm - start.x_mm, y_mm - start.y_mm);
    let (s, c) = start.theta_rad.sin_cos();
    (dx * c + dy * s, -dx * s + dy * c)
}

/// The end error of a run in its start frame, minus the ideal end, cm: what
/// the tape measure says.
pub(super) fn end_error(start: &StartPose, x_mm: f64, y_mm: f64) -> [f64; 2] {
    let (x, y) = in_start_frame(start, x_mm, y_mm);
    let (ix, iy) = start.test.ideal_end(start.leg_mm);
    [(x - ix) / 10.0, (y - iy) / 10.0]
}

/// The running test's pose for the floor plot: in its start frame, so that
/// every run starts at the origin whatever the last one left; with the path
/// it was commanded to drive.
#[derive(Debug, Serialize)]
pub(super) struct RunPose {
    id: u64,
    test: Test,
    leg_mm: f64,
    /// The ideal path's corners (cm), from the origin.
    ideal_cm: Vec<(f64, f64)>,
    x_cm: f64,
    y_cm: f64,
    /// Heading relative to the start's, rad.
    theta_rad: f64,
}

pub(super) fn run_pose(start: &StartPose, x_mm: f64, y_mm: f64, theta_rad: f64) -> RunPose {
    let (x, y) = in_start_frame(start, x_mm, y_mm);
    let t = start.test;
    RunPose {
        id: start.run,
        test: t,
        leg_mm: start.leg_mm,
        ideal_cm: calib::plot::ideal_path(t.legs(), t.turn_deg(), start.leg_mm / 10.0),
        x_cm: x / 10.0,
        y_cm: y / 10.0,
        theta_rad: theta_rad - start.theta_rad,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn end_errors_are_in_the_start_frame() {
        // Started at (1000, 500) heading +90 degrees; ended 30 mm further
        // along the heading and 20 mm to its right.
        let start = StartPose {
            run: 0,
            test: Test::UmbmarkCw,
            leg_mm: 2000.0,
            x_mm: 1000.0,
            y_mm: 500.0,
            theta_rad: std::f64::consts::FRAC_PI_2,
        };
        let [x, y] = end_error(&start, 1000.0 + 20.0, 500.0 + 30.0);
        assert!((x - 3.0).abs() < 1e-9 && (y + 2.0).abs() < 1e-9, "{x} {y}");
        let line = StartPose {
            test: Test::Line,
            theta_rad: 0.0,
            ..start
        };
        let [x, _] = end_error(&line, 1000.0 + 1990.0, 500.0);
        assert!((x + 1.0).abs() < 1e-9, "{x}");
    }

    #[test]
    fn a_run_is_drawn_from_the_origin_of_its_start_frame() {
        // A line started at (1000, 500) heading +90 degrees, now 100 mm
        // along it, turned 0.1 rad to the left.
        let start = StartPose {
            run: 7,
            test: Test::Line,
            leg_mm: 300.0,
            x_mm: 1000.0,
            y_mm: 500.0,
            theta_rad: std::f64::consts::FRAC_PI_2,
        };
        let p = run_pose(&start, 1000.0, 600.0, std::f64::consts::FRAC_PI_2 + 0.1);
        assert_eq!(p.id, 7);
        assert!((p.x_cm - 10.0).abs() < 1e-9 && p.y_cm.abs() < 1e-9, "{p:?}");
        assert!((p.theta_rad - 0.1).abs() < 1e-12, "{p:?}");
        assert_eq!(p.ideal_cm, [(0.0, 0.0), (30.0, 0.0)]);
        let here = run_pose(&start, 1000.0, 500.0, 0.0);
        assert_eq!((here.x_cm, here.y_cm), (0.0, 0.0));
        let square = run_pose(
            &StartPose {
                test: Test::UmbmarkCcw,
                ..start
            },
            0.0,
            0.0,
            0.0,
        );
        assert_eq!(square.ideal_cm[2], (30.0, 30.0));
    }
}
