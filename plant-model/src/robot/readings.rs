//! What the bench and the tests read off the plant: encoder levels and counts, wheel speeds
//! and angles, the distance rolled, the pose.

use super::pose_steps::integrate;
use super::Robot;
use crate::encoder::{self, Encoder};
use crate::pose::{Pose, World};
use crate::side::Side;
use crate::units::{Millimetres, RadPerSec, Radians, Seconds, ThesisRpm};

impl Robot {
    /// Encoder levels `(A, B)` of `side` now, with the encoder effects.
    pub fn encoder_levels(&self, side: Side) -> (bool, bool) {
        self.dynamics.wheels.get(side).levels(self.dynamics.now)
    }

    /// Encoder levels `(A, B)` of `side` at `t`, without advancing the robot: exact for
    /// `t` from now up to the next change of the inputs or of the plant's own dynamics
    /// ([`Robot::next_internal_change`]), over which the wheels' closed forms hold. For a
    /// reader that samples a channel between the robot's events.
    pub fn encoder_levels_at(&self, side: Side, t: Seconds) -> (bool, bool) {
        debug_assert!(t >= self.dynamics.now, "encoder_levels_at looks ahead only");
        debug_assert!(
            self.dynamics.next_internal_change().is_none_or(|c| t <= c),
            "encoder_levels_at beyond the next internal change"
        );
        self.dynamics.wheels.get(side).levels(t)
    }

    /// A time within which `side`'s encoder position cannot move by `states` quadrature
    /// states, from any instant up to the next change of the inputs or of the plant's own
    /// dynamics: the distance over the largest speed of the wheel's present motion (infinite
    /// for a wheel at rest). For a reader that knows the levels at an instant: a level that
    /// changes only a state or more away from there cannot have changed that much later.
    pub fn encoder_travel_time_bound(&self, side: Side, states: f64) -> Seconds {
        let wheel = self.dynamics.wheels.get(side);
        let speed = wheel.segment.speed_bound();
        if speed == 0.0 {
            return Seconds(f64::INFINITY);
        }
        // A hair under the quotient, so that its rounding cannot make the bound late.
        Seconds(states * wheel.encoder.state_angle().0 / speed * (1.0 - 1e-9))
    }

    /// Quadrature state index `q` of `side` now (see [`crate::encoder`]): the shaft's
    /// position, whatever the encoder effects make of it.
    pub fn quadrature_index(&self, side: Side) -> i64 {
        let wheel = self.dynamics.wheels.get(side);
        wheel
            .encoder
            .quadrature_index(Radians(wheel.angle_at(self.dynamics.now)))
    }

    /// Net signed channel-A edges of `side` since time 0 as the thesis' decoder counts the
    /// levels (on every A change: `+1` if A differs from B, else `-1`), encoder effects
    /// included (missed pulses count nothing; a glitch counts `-1` while it lasts).
    pub fn a_edges(&self, side: Side) -> i64 {
        let wheel = self.dynamics.wheels.get(side);
        if wheel.encoder.is_flawed() {
            let s = wheel.position(self.dynamics.now);
            self.decoded.get(side).count + wheel.encoder.glitch_count_offset(s)
        } else {
            encoder::net_a_edges(self.quadrature_index(side))
        }
    }

    /// Net signed edges of both channels of `side` since time 0 as a decoder of all four
    /// edges counts the levels (+1 a step with A leading B, -1 the other way), missed
    /// pulses included (B's edges around a missing A pulse net zero); a glitch once passed
    /// nets zero, and inside one the count is the state's.
    pub fn all_edges(&self, side: Side) -> i64 {
        let wheel = self.dynamics.wheels.get(side);
        if wheel.encoder.is_flawed() {
            self.decoded.get(side).all
        } else {
            self.quadrature_index(side)
        }
    }

    /// Let the firmware count every edge of `side`'s encoder (`all`: an xor wiring, whose
    /// interrupt pin changes at each) or channel A's: what [`Robot::counted_edges`] gives.
    pub fn count_all_edges(&mut self, side: Side, all: bool) {
        *self.all_edges_counted.get_mut(side) = all;
    }

    /// The plant's edges of `side` as the firmware's wiring counts them:
    /// [`Robot::all_edges`] or [`Robot::a_edges`] ([`Robot::count_all_edges`]).
    pub fn counted_edges(&self, side: Side) -> i64 {
        if *self.all_edges_counted.get(side) {
            self.all_edges(side)
        } else {
            self.a_edges(side)
        }
    }

    /// The encoder of `side`.
    pub fn encoder(&self, side: Side) -> &Encoder {
        &self.dynamics.wheels.get(side).encoder
    }

    /// Wheel speed of `side` now, positive rolling forward (the shaft's, before backlash and
    /// slip).
    pub fn wheel_speed(&self, side: Side) -> RadPerSec {
        self.dynamics
            .wheels
            .get(side)
            .segment
            .speed_at(self.dynamics.now)
    }

    /// Wheel speed of `side` now in the thesis' "RPM" (true RPM / 6).
    pub fn wheel_speed_thesis_rpm(&self, side: Side) -> ThesisRpm {
        self.wheel_speed(side).to_thesis_rpm()
    }

    /// Wheel angle of `side` since time 0, positive rolling forward: the angle the encoder
    /// measures (the motor shaft's over the gear ratio).
    pub fn wheel_angle(&self, side: Side) -> Radians {
        self.dynamics
            .wheels
            .get(side)
            .segment
            .angle_at(self.dynamics.now)
    }

    /// Signed arc rolled by the wheel of `side` since time 0: [`Robot::wheel_angle`] times the
    /// wheel's effective radius (with `wheel_diameter_ratio` and `distance_scale`), before
    /// backlash and slip.
    pub fn distance_travelled(&self, side: Side) -> Millimetres {
        Millimetres(self.ground.radius_mm(side) * self.wheel_angle(side).0)
    }

    /// The robot's pose in the [`World`] frame (origin and axes at the start pose).
    ///
    /// The pose is stepped at the instants of a fixed grid (multiples of
    /// [`MAX_POSE_STEP`](super::MAX_POSE_STEP)) and at the changes of the motion (inputs,
    /// faults, the battery's steps), which are the same however the plant is advanced: so is
    /// the pose, bit for bit. Between them it is the last step's pose plus the arc to now,
    /// computed here and not kept.
    pub fn pose(&self) -> Pose<World> {
        if self.pose_time == self.dynamics.now {
            return self.ground.pose();
        }
        let mut ground = self.ground.clone();
        integrate(
            &mut ground,
            &self.dynamics.wheels,
            self.pose_time,
            self.dynamics.now,
        );
        ground.pose()
    }
}
