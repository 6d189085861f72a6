//! The whole plant: two bridges, two motors, two wheels with encoders, the battery, the pose.
//!
//! # How the bench drives it
//!
//! ```text
//! loop {
//!     t = min(next_encoder_transition(Left), next_encoder_transition(Right), next firmware event)
//!     advance_to(t rounded up to an emulated cycle)
//!     raise the encoder levels that changed; on a PWM register write: set_bridge(...)
//! }
//! ```
//!
//! Time is the plant's own: it starts at 0 and moves only through [`Robot::advance_to`]; no
//! host clock is read and no randomness is used yet (the seed is kept for the noise models to
//! come), so the same calls give the same results bit for bit.
//!
//! # Exactness
//!
//! Each wheel's motion since its last input change is one closed-form [`Segment`]; its angle
//! at any time is that segment evaluated at that time, never a sum of small steps, so
//! [`Robot::next_encoder_transition`] and [`Robot::advance_to`] see the same angle function.
//! The pose is integrated from the wheel-angle increments by exact arcs over steps of at most
//! [`MAX_POSE_STEP`] (the arc is exact while the ratio of the wheel speeds is constant; over
//! 1 ms with 55-69 ms time constants the error is far below a micrometre).

use crate::bridge::DriveState;
use crate::config::RobotConfig;
use crate::encoder::{self, Encoder};
use crate::motor::{MotorModel, Segment};
use crate::pose::{Pose, World};
use crate::side::{PerSide, Side};
use crate::units::{Duty, Millimetres, RadPerSec, Radians, Seconds, ThesisRpm, Volts};
use crate::Error;

/// How far ahead [`Robot::next_encoder_transition`] looks. A wheel that will not change its
/// encoder state within this time (at rest, or creeping to a stop short of the next state)
/// gets `None`; ask again after the next input change or after advancing this far.
pub const TRANSITION_HORIZON: Seconds = Seconds(10.0);

/// Longest step of the pose integration; [`Robot::advance_to`] subdivides longer intervals.
pub const MAX_POSE_STEP: Seconds = Seconds(1e-3);

/// Resolution of [`Robot::next_encoder_transition`]: the time returned is at most this much
/// (or one `f64` step of the time, if that is larger) after a time at which the encoder state
/// has not changed yet.
pub const TRANSITION_RESOLUTION: Seconds = Seconds(1e-12);

/// The simulated robot: the plant the bench drives.
#[derive(Debug, Clone)]
pub struct Robot {
    config: RobotConfig,
    seed: u64,
    now: Seconds,
    battery: Volts,
    wheelbase_mm: f64,
    wheels: PerSide<Wheel>,
    pose: Pose<World>,
}

/// One side: bridge inputs, motor, wheel, encoder.
#[derive(Debug, Clone)]
struct Wheel {
    motor: MotorModel,
    encoder: Encoder,
    radius_mm: f64,
    in1: Duty,
    in2: Duty,
    /// Motion since the last input change.
    segment: Segment,
    /// `segment.angle_at(now)`, kept for the pose increments.
    angle: Radians,
}

impl Wheel {
    fn quadrature_index(&self) -> i64 {
        self.encoder.quadrature_index(self.angle)
    }

    /// Earliest time after `now` at which the encoder state differs from its state at `now`.
    fn next_transition(&self, now: Seconds) -> Option<Seconds> {
        let segment = &self.segment;
        if segment.is_at_rest() {
            return None;
        }
        let q0 = self.quadrature_index();
        let changed = |t: Seconds| self.encoder.quadrature_index(segment.angle_at(t)) != q0;
        let end = now + TRANSITION_HORIZON;
        // The angle is monotone before and after the speed's zero crossing, so the encoder
        // state is too: on each piece, it changes if and only if it differs at the end.
        let split = segment.speed_reversal().filter(|&tz| tz > now && tz < end);
        let pieces = match split {
            Some(tz) => [(now, tz), (tz, end)],
            None => [(now, end), (end, end)],
        };
        for (a, b) in pieces {
            if b > a && changed(b) {
                return Some(self.refine(a, b, q0, &changed));
            }
        }
        None
    }

    /// The transition time on a monotone piece `[a, b]` where the state is `q0` at `a` and
    /// differs at `b`: Newton's method on the continuous angle (safeguarded by bisection)
    /// finds the boundary crossing, then bisection on the state itself pins the first time at
    /// which the state differs, so the answer agrees exactly with evaluating the segment.
    fn refine(
        &self,
        a: Seconds,
        b: Seconds,
        q0: i64,
        changed: &impl Fn(Seconds) -> bool,
    ) -> Seconds {
        let segment = &self.segment;
        let dq = self.encoder.state_angle().0;
        // Work in the encoder's sense of rotation.
        let sense = if self.encoder.is_reversed() {
            -1.0
        } else {
            1.0
        };
        let rising = sense * (segment.angle_at(b).0 - segment.angle_at(a).0) > 0.0;
        let dir = if rising { 1.0 } else { -1.0 };
        let boundary = (q0 as f64 + 0.5 * dir) * dq;
        // g(t) >= 0 once the boundary is passed; g is increasing on the piece.
        let g = |t: Seconds| dir * (sense * segment.angle_at(t).0 - boundary);
        let dg = |t: Seconds| dir * sense * segment.speed_at(t).0;

        let (mut lo, mut hi) = (a, b);
        let speed_a = dg(a);
        let mut t = if speed_a > 0.0 {
            a + Seconds(-g(a) / speed_a)
        } else {
            Seconds(0.5 * (a.0 + b.0))
        };
        for _ in 0..200 {
            if !(t > lo && t < hi) {
                t = Seconds(lo.0 + 0.5 * (hi.0 - lo.0));
            }
            let value = g(t);
            if value >= 0.0 {
                hi = t;
            } else {
                lo = t;
            }
            if hi.0 - lo.0 <= TRANSITION_RESOLUTION.0 {
                break;
            }
            let slope = dg(t);
            let next = t - Seconds(value / slope);
            if (next.0 - t.0).abs() <= 0.25 * TRANSITION_RESOLUTION.0 {
                t = next;
                break;
            }
            t = next;
        }
        let guess = Seconds(t.0.clamp(a.0, b.0));

        // Bracket the first changed state tightly around the guess, then bisect on it.
        let mut lo = a;
        let mut hi;
        let mut eps = TRANSITION_RESOLUTION.0;
        loop {
            let above = Seconds((guess.0 + eps).min(b.0));
            if changed(above) {
                hi = above;
                break;
            }
            lo = Seconds(lo.0.max(above.0));
            eps *= 4.0;
        }
        let mut eps = TRANSITION_RESOLUTION.0;
        loop {
            let below = Seconds((guess.0 - eps).max(lo.0));
            if !changed(below) {
                lo = below;
                break;
            }
            hi = Seconds(hi.0.min(below.0));
            eps *= 4.0;
        }
        while hi.0 - lo.0 > TRANSITION_RESOLUTION.0 {
            let mid = Seconds(lo.0 + 0.5 * (hi.0 - lo.0));
            if mid <= lo || mid >= hi {
                break;
            }
            if changed(mid) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        hi
    }
}

impl Robot {
    /// The robot of `config` at rest at the origin of [`World`], bridges coasting, time 0.
    /// `seed` is kept for the noise models to come; nothing is random yet.
    pub fn new(config: &RobotConfig, seed: u64) -> Result<Robot, Error> {
        config.validate()?;
        let battery = Volts(config.battery.voltage_v);
        let make_wheel = |side: Side| {
            let encoder = Encoder::new(
                config.encoder.gear_ratio,
                config.encoder.a_edges_per_motor_rev,
                config.encoder.reversed(side),
            );
            let motor = config.motor.get(side).clone();
            let segment = Segment::new(
                Seconds::ZERO,
                Radians::ZERO,
                RadPerSec::ZERO,
                motor.relaxation(DriveState::COAST, battery),
            );
            Wheel {
                motor,
                encoder,
                radius_mm: 0.5 * config.wheel_diameter_mm(side),
                in1: Duty::OFF,
                in2: Duty::OFF,
                segment,
                angle: Radians::ZERO,
            }
        };
        let wheels = PerSide {
            left: make_wheel(Side::Left),
            right: make_wheel(Side::Right),
        };
        Ok(Robot {
            config: config.clone(),
            seed,
            now: Seconds::ZERO,
            battery,
            wheelbase_mm: config.geometry.wheelbase_mm,
            wheels,
            pose: Pose::origin(),
        })
    }

    /// The config the robot was made from.
    pub fn config(&self) -> &RobotConfig {
        &self.config
    }

    /// The seed given to [`Robot::new`].
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// Plant time.
    pub fn now(&self) -> Seconds {
        self.now
    }

    /// Battery voltage (constant for now).
    pub fn battery_voltage(&self) -> Volts {
        self.battery
    }

    /// Sets the H-bridge inputs of `side` from now on (advance to the time of the change
    /// first). Both inputs are duties of PWM signals assumed to start their high time
    /// together; `in1` high alone drives the wheel forward (see [`crate::bridge`]). Setting the
    /// inputs a bridge already has changes nothing.
    pub fn set_bridge(&mut self, side: Side, in1: Duty, in2: Duty) {
        let now = self.now;
        let battery = self.battery;
        let wheel = self.wheels.get_mut(side);
        if (wheel.in1, wheel.in2) == (in1, in2) {
            return;
        }
        let speed = wheel.segment.speed_at(now);
        let relaxation = wheel
            .motor
            .relaxation(DriveState::from_inputs(in1, in2), battery);
        wheel.in1 = in1;
        wheel.in2 = in2;
        wheel.segment = Segment::new(now, wheel.angle, speed, relaxation);
    }

    /// The bridge inputs `(in1, in2)` of `side`.
    pub fn bridge_inputs(&self, side: Side) -> (Duty, Duty) {
        let wheel = self.wheels.get(side);
        (wheel.in1, wheel.in2)
    }

    /// The averaged bridge state of `side`.
    pub fn drive_state(&self, side: Side) -> DriveState {
        let (in1, in2) = self.bridge_inputs(side);
        DriveState::from_inputs(in1, in2)
    }

    /// Moves the plant to time `t` under the current inputs: wheel angles and speeds in closed
    /// form, the pose by arcs of at most [`MAX_POSE_STEP`].
    ///
    /// `t == now` does nothing. `t < now` (or a `t` that is not finite) is an error,
    /// [`Error::TimeWentBackwards`], and leaves the plant unchanged.
    pub fn advance_to(&mut self, t: Seconds) -> Result<(), Error> {
        if !t.0.is_finite() || t < self.now {
            return Err(Error::TimeWentBackwards {
                now: self.now,
                requested: t,
            });
        }
        let start = self.now;
        let span = t.0 - start.0;
        let steps = (span / MAX_POSE_STEP.0).ceil().max(1.0) as u64;
        for k in 1..=steps {
            let tk = if k == steps {
                t
            } else {
                Seconds(start.0 + span * (k as f64 / steps as f64))
            };
            self.step_pose_to(tk);
        }
        self.now = t;
        Ok(())
    }

    fn step_pose_to(&mut self, t: Seconds) {
        let mut arc = [0.0; 2];
        for (i, side) in Side::BOTH.into_iter().enumerate() {
            let wheel = self.wheels.get_mut(side);
            let angle = wheel.segment.angle_at(t);
            arc[i] = wheel.radius_mm * (angle.0 - wheel.angle.0);
            wheel.angle = angle;
        }
        let [left, right] = arc;
        if left != 0.0 || right != 0.0 {
            self.pose.move_along_arc(
                Millimetres(0.5 * (right + left)),
                Radians((right - left) / self.wheelbase_mm),
            );
        }
    }

    /// The earliest time after [`Robot::now`] at which the encoder state of `side` changes
    /// under the current inputs, or `None` if it does not change within
    /// [`TRANSITION_HORIZON`] (ask again after the next input change, or after advancing).
    ///
    /// # Guarantee
    ///
    /// With `t_next` the answer and no input change before it:
    /// - `advance_to(t)` for any `t` from `t_next` up to the following transition (one state
    ///   is about 210 us at the top speed of the nominal robot, 24.5 rad/s) leaves
    ///   [`Robot::quadrature_index`] changed by exactly one. So the bench may round `t_next`
    ///   up to its next emulated cycle (62.5 ns).
    /// - There is a time `t_lo` with `t_next - t_lo <= max(1e-12 s, one f64 step of t_next)`
    ///   at which the state has not changed yet: `advance_to(t_next - 1e-9)` leaves it
    ///   unchanged.
    ///
    /// Both hold bit for bit because the answer is found by bisection on the very function
    /// `advance_to` evaluates (the wheel's closed-form angle), after Newton's method has
    /// located the boundary crossing. The angle is split at the speed's zero crossing (a wheel
    /// driven against its motion turns round), so a boundary reached only after turning back
    /// is found too.
    pub fn next_encoder_transition(&self, side: Side) -> Option<Seconds> {
        self.wheels.get(side).next_transition(self.now)
    }

    /// Encoder levels `(A, B)` of `side` now.
    pub fn encoder_levels(&self, side: Side) -> (bool, bool) {
        encoder::levels(self.quadrature_index(side))
    }

    /// Quadrature state index `q` of `side` now (see [`crate::encoder`]).
    pub fn quadrature_index(&self, side: Side) -> i64 {
        self.wheels.get(side).quadrature_index()
    }

    /// Net signed channel-A edges of `side` since time 0: what the thesis firmware counts.
    pub fn a_edges(&self, side: Side) -> i64 {
        encoder::net_a_edges(self.quadrature_index(side))
    }

    /// The encoder of `side`.
    pub fn encoder(&self, side: Side) -> &Encoder {
        &self.wheels.get(side).encoder
    }

    /// Wheel speed of `side` now, positive rolling forward.
    pub fn wheel_speed(&self, side: Side) -> RadPerSec {
        self.wheels.get(side).segment.speed_at(self.now)
    }

    /// Wheel speed of `side` now in the thesis' "RPM" (true RPM / 6).
    pub fn wheel_speed_thesis_rpm(&self, side: Side) -> ThesisRpm {
        self.wheel_speed(side).to_thesis_rpm()
    }

    /// Wheel angle of `side` since time 0, positive rolling forward.
    pub fn wheel_angle(&self, side: Side) -> Radians {
        self.wheels.get(side).angle
    }

    /// Signed arc rolled by the wheel of `side` since time 0 (angle times radius).
    pub fn distance_travelled(&self, side: Side) -> Millimetres {
        let wheel = self.wheels.get(side);
        Millimetres(wheel.radius_mm * wheel.angle.0)
    }

    /// The robot's pose in the [`World`] frame (origin and axes at the start pose).
    pub fn pose(&self) -> Pose<World> {
        self.pose
    }
}
