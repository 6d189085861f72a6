//! Exact forward model of a differential-drive robot with systematic odometry errors, for
//! generating synthetic end errors with known Ed, Eb and Es.
//!
//! The robot executes a program of straight legs and spins in place, each commanded as
//! encoder counts computed with the *nominal* wheel diameter and wheelbase, and stops each
//! segment when the counts are reached (both wheels at a constant ratio, as under the
//! thesis' speed controller). The actual motion follows from the actual wheels:
//!
//! * D_R = D·2Ed/(Ed + 1), D_L = D·2/(Ed + 1) with D = D_nominal/Es the actual mean
//!   diameter (Ed = D_R/D_L, Es = L_calc/L_actual);
//! * actual wheelbase b·Eb.
//!
//! A segment with commanded wheel travels (s_R, s_L) moves the wheels by s·D_wheel/D_nominal
//! and is integrated exactly as an arc: heading change Δθ = (d_R − d_L)/b_actual, centre
//! travel (d_R + d_L)/2. No small-angle approximation is made anywhere.

use crate::types::{Direction, Endpoint};

/// The systematic errors of a robot (1.0 each for a perfect one).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SystematicErrors {
    /// Ed = D_R/D_L.
    pub ed: f64,
    /// Eb = b_actual/b_nominal.
    pub eb: f64,
    /// Es = L_calc/L_actual (odometry distance over true distance).
    pub es: f64,
}

impl Default for SystematicErrors {
    fn default() -> Self {
        Self {
            ed: 1.0,
            eb: 1.0,
            es: 1.0,
        }
    }
}

/// A pose in the start frame ([`crate::Frame::Default`]): cm, cm, rad.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Pose {
    /// x, cm.
    pub x_cm: f64,
    /// y, cm.
    pub y_cm: f64,
    /// Heading, rad, counter-clockwise from +x.
    pub theta_rad: f64,
}

/// One commanded motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Segment {
    /// Drive straight ahead by this many cm (as the odometry counts them).
    Straight(f64),
    /// Spin in place by this angle, rad (positive = left / counter-clockwise).
    Turn(f64),
}

/// A robot with a nominal wheelbase and its systematic errors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Robot {
    /// The wheelbase the odometry believes in, cm.
    pub wheelbase_nominal_cm: f64,
    /// Its systematic errors.
    pub errors: SystematicErrors,
}

impl Robot {
    /// Actual travel of (right, left) wheel for commanded (right, left) travel.
    fn wheel_travel(&self, s_r: f64, s_l: f64) -> (f64, f64) {
        let SystematicErrors { ed, es, .. } = self.errors;
        // Actual diameters relative to the nominal one.
        let mean = 1.0 / es;
        let k_r = mean * 2.0 * ed / (ed + 1.0);
        let k_l = mean * 2.0 / (ed + 1.0);
        (s_r * k_r, s_l * k_l)
    }

    /// Execute one segment from `pose`.
    pub fn step(&self, pose: Pose, segment: Segment) -> Pose {
        let b = self.wheelbase_nominal_cm;
        let (s_r, s_l) = match segment {
            Segment::Straight(d) => (d, d),
            Segment::Turn(a) => (a * b / 2.0, -a * b / 2.0),
        };
        let (d_r, d_l) = self.wheel_travel(s_r, s_l);
        let b_actual = b * self.errors.eb;
        let dtheta = (d_r - d_l) / b_actual;
        let ds = (d_r + d_l) / 2.0;
        let (x, y, t) = (pose.x_cm, pose.y_cm, pose.theta_rad);
        let (dx, dy) = if dtheta.abs() < 1e-12 {
            (ds * t.cos(), ds * t.sin())
        } else {
            let r = ds / dtheta;
            (
                r * ((t + dtheta).sin() - t.sin()),
                r * (t.cos() - (t + dtheta).cos()),
            )
        };
        Pose {
            x_cm: x + dx,
            y_cm: y + dy,
            theta_rad: t + dtheta,
        }
    }

    /// Execute a program from the origin, heading +x.
    pub fn drive(&self, program: &[Segment]) -> Pose {
        program
            .iter()
            .fold(Pose::default(), |p, s| self.step(p, *s))
    }

    /// End error of one UMBmark square of side `side_cm` (4 legs, 4 turns of 90°).
    pub fn square_endpoint(&self, side_cm: f64, direction: Direction) -> Endpoint {
        let turn = match direction {
            Direction::Ccw => std::f64::consts::FRAC_PI_2,
            Direction::Cw => -std::f64::consts::FRAC_PI_2,
        };
        let program: Vec<Segment> = (0..4)
            .flat_map(|_| [Segment::Straight(side_cm), Segment::Turn(turn)])
            .collect();
        let p = self.drive(&program);
        Endpoint::new(p.x_cm, p.y_cm)
    }

    /// End error of one straight line of `length_cm`: end minus the commanded end (L, 0).
    pub fn line_endpoint(&self, length_cm: f64) -> Endpoint {
        let p = self.drive(&[Segment::Straight(length_cm)]);
        Endpoint::new(p.x_cm - length_cm, p.y_cm)
    }
}
