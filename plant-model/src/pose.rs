//! Coordinate frames and the robot's pose.
//!
//! The frame is a type parameter, so a pose in one frame cannot be used as one in another.
//! For now there is one frame, [`World`]; more (a body frame for sensor offsets, a floor frame
//! for a measured start pose) are added when a model needs them.

use std::fmt;
use std::marker::PhantomData;

use nalgebra::{UnitComplex, Vector2};

use crate::units::{Millimetres, Radians};

/// A coordinate frame.
pub trait Frame {
    /// Name used when a pose is printed.
    const NAME: &'static str;
}

/// The floor frame fixed at the robot's start.
///
/// Origin at the midpoint between the wheel contact points at plant time 0; `x` along the
/// initial heading (forward), `y` to the robot's initial left, `theta` the heading measured
/// counter-clockwise from `x` (seen from above), in radians. Lengths in millimetres.
///
/// The start frame of every run: the gap diagnosis' kinematic model (`gap::kinematic`)
/// integrates its poses in it too, so a pose of the workspace is this one type (`calib`, which
/// depends on no physics, keeps its own in cm: `calib::forward::Pose`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum World {}

impl Frame for World {
    const NAME: &'static str = "World";
}

/// Position and heading of the robot's wheel-axle midpoint in frame `F`.
///
/// `theta` is not wrapped: a full counter-clockwise turn adds `2 pi`, so turns can be counted.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose<F: Frame> {
    position_mm: Vector2<f64>,
    theta_rad: f64,
    frame: PhantomData<F>,
}

impl<F: Frame> Pose<F> {
    /// A pose at `(x, y)` with heading `theta`.
    pub fn new(x: Millimetres, y: Millimetres, theta: Radians) -> Self {
        Pose {
            position_mm: Vector2::new(x.0, y.0),
            theta_rad: theta.0,
            frame: PhantomData,
        }
    }

    /// The origin, heading along `x`.
    pub fn origin() -> Self {
        Self::new(Millimetres::ZERO, Millimetres::ZERO, Radians::ZERO)
    }

    /// Position along `x`.
    pub fn x(&self) -> Millimetres {
        Millimetres(self.position_mm.x)
    }

    /// Position along `y`.
    pub fn y(&self) -> Millimetres {
        Millimetres(self.position_mm.y)
    }

    /// Heading, counter-clockwise from `x`, not wrapped.
    pub fn theta(&self) -> Radians {
        Radians(self.theta_rad)
    }

    /// Distance of the position from the frame's origin.
    pub fn distance_from_origin(&self) -> Millimetres {
        Millimetres(self.position_mm.norm())
    }

    /// Distance between this pose's position and `other`'s (same frame).
    pub fn distance_to(&self, other: &Pose<F>) -> Millimetres {
        Millimetres((self.position_mm - other.position_mm).norm())
    }

    /// Heading change from `other` to this pose (this minus `other`), not
    /// wrapped.
    pub fn turned_from(&self, other: &Pose<F>) -> Radians {
        Radians(self.theta_rad - other.theta_rad)
    }

    /// Moves along a circular arc (or a straight line when `dtheta` is 0) that starts at this
    /// pose tangent to its heading, has length `ds` (negative: backwards) and turns the heading
    /// by `dtheta`. The chord of the arc has length `ds * sinc(dtheta / 2)` and points along
    /// the mean heading `theta + dtheta / 2`.
    pub(crate) fn move_along_arc(&mut self, ds: Millimetres, dtheta: Radians) {
        let half = 0.5 * dtheta.0;
        let chord = ds.0 * sinc(half);
        let mean_heading = UnitComplex::new(self.theta_rad + half);
        self.position_mm += mean_heading * Vector2::new(chord, 0.0);
        self.theta_rad += dtheta.0;
    }
}

impl<F: Frame> Pose<F> {
    /// Like [`Pose::move_along_arc`], plus a sideways shift `lateral` (to the left of the mean
    /// heading): a robot that crabs while it rolls.
    pub(crate) fn move_with_crab(
        &mut self,
        ds: Millimetres,
        lateral: Millimetres,
        dtheta: Radians,
    ) {
        let half = 0.5 * dtheta.0;
        let chord = ds.0 * sinc(half);
        let mean_heading = UnitComplex::new(self.theta_rad + half);
        self.position_mm += mean_heading * Vector2::new(chord, lateral.0);
        self.theta_rad += dtheta.0;
    }
}

impl<F: Frame> fmt::Display for Pose<F> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "Pose<{}>(x = {}, y = {}, theta = {})",
            F::NAME,
            self.x(),
            self.y(),
            self.theta()
        )
    }
}

/// `sin(x) / x`, exact to rounding for small `x` too.
fn sinc(x: f64) -> f64 {
    if x.abs() < 1e-4 {
        // Taylor series; the next term x^4/120 is below 1e-18 here.
        1.0 - x * x / 6.0
    } else {
        x.sin() / x
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use std::f64::consts::PI;

    /// A quarter circle of radius 100 mm turning left ends at (100, 100) facing +y.
    #[test]
    fn quarter_arc_ends_where_geometry_says() {
        let mut pose = Pose::<World>::origin();
        pose.move_along_arc(Millimetres(100.0 * PI / 2.0), Radians(PI / 2.0));
        assert_relative_eq!(pose.x().0, 100.0, epsilon = 1e-9);
        assert_relative_eq!(pose.y().0, 100.0, epsilon = 1e-9);
        assert_relative_eq!(pose.theta().0, PI / 2.0);
    }

    /// The small-angle branch of sinc joins the exact one without a visible step.
    #[test]
    fn sinc_is_continuous_at_the_branch() {
        let a = 1e-4 * (1.0 - 1e-12);
        let b = 1e-4 * (1.0 + 1e-12);
        assert_relative_eq!(sinc(a), sinc(b), epsilon = 1e-15);
        assert_eq!(sinc(0.0), 1.0);
    }

    /// The distance and turn between two poses, in their units: (3, 4) is
    /// 5 mm from (0, 0) whichever is asked from, and a heading of 90
    /// degrees turned 90 from the origin's, -90 the other way.
    #[test]
    fn poses_measure_distance_and_turn_between_them() {
        let a = Pose::<World>::new(Millimetres(1.0), Millimetres(1.0), Radians::ZERO);
        let b = Pose::<World>::new(
            Millimetres(4.0),
            Millimetres(5.0),
            Radians::from_degrees(90.0),
        );
        assert_eq!(b.distance_to(&a), Millimetres(5.0));
        assert_eq!(a.distance_to(&b), Millimetres(5.0));
        assert_eq!(Millimetres(3.0).hypot(Millimetres(-4.0)), Millimetres(5.0));
        assert_relative_eq!(b.turned_from(&a).to_degrees(), 90.0, epsilon = 1e-12);
        assert_relative_eq!(a.turned_from(&b).to_degrees(), -90.0, epsilon = 1e-12);
        assert_relative_eq!(Radians(PI).to_degrees(), 180.0);
    }
}
