//! The wheel's motion over an interval of constant input, in closed form (the formulas are in
//! [the motor module](super)), and its expansion about a time for the transition search.

use super::Relaxation;
use crate::units::{RadPerSec, Radians, Seconds};

/// The wheel's motion over an interval of constant input, in closed form ([`motor`](super)
/// module docs).
///
/// Evaluated at absolute plant times `t >= start`. Evaluating the same segment at the same
/// time always gives the same bits, which is what makes encoder transition times found on a
/// segment consistent with the states reached by advancing to them.
///
/// A relaxation that [stops at zero](Relaxation::stops_at_zero) holds the angle it reached
/// from the stop time on ([`Segment::stop_time`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    start: Seconds,
    angle0: f64,
    speed0: f64,
    target: f64,
    tau: f64,
    /// Time at which the wheel stops for good (infinite if it does not).
    stop: f64,
    /// The angle from `stop` on.
    angle_stop: f64,
}

impl Segment {
    /// Motion from `angle`, `speed` at time `start` under `relaxation`.
    pub fn new(start: Seconds, angle: Radians, speed: RadPerSec, relaxation: Relaxation) -> Self {
        let mut segment = Segment {
            start,
            angle0: angle.0,
            speed0: speed.0,
            target: relaxation.target.0,
            tau: relaxation.tau.0,
            stop: f64::INFINITY,
            angle_stop: angle.0,
        };
        if relaxation.stops_at_zero {
            if segment.speed0 == 0.0 {
                segment.target = 0.0;
            } else if let Some(tz) = segment.zero_crossing() {
                segment.angle_stop = segment.angle_at(tz).0;
                segment.stop = tz.0;
            }
        }
        segment
    }

    /// A wheel held still at `angle` from `start` on (a stalled wheel).
    pub fn held(start: Seconds, angle: Radians) -> Self {
        Segment::new(
            start,
            angle,
            RadPerSec::ZERO,
            Relaxation::towards(RadPerSec::ZERO, Seconds(1.0)),
        )
    }

    /// The time at which the wheel stops for good under Coulomb friction, if it does.
    pub fn stop_time(&self) -> Option<Seconds> {
        self.stop.is_finite().then_some(Seconds(self.stop))
    }

    /// Time at which the segment starts.
    pub fn start(&self) -> Seconds {
        self.start
    }

    /// The relaxation the segment follows.
    pub fn relaxation(&self) -> Relaxation {
        Relaxation {
            target: RadPerSec(self.target),
            tau: Seconds(self.tau),
            stops_at_zero: self.stop.is_finite(),
        }
    }

    /// The largest wheel speed (rad/s, unsigned) of the segment: the speed goes from its
    /// start value towards the target without overshoot (and stops at zero under Coulomb
    /// friction).
    pub fn speed_bound(&self) -> f64 {
        self.speed0.abs().max(self.target.abs())
    }

    /// True when the wheel is still and will stay so.
    pub fn is_at_rest(&self) -> bool {
        self.speed0 == 0.0 && self.target == 0.0
    }

    /// True when the wheel is still at `t` and will stay so.
    pub fn is_at_rest_from(&self, t: Seconds) -> bool {
        self.is_at_rest() || t.0 >= self.stop
    }

    /// Wheel angle at time `t` (`t >= start`).
    pub fn angle_at(&self, t: Seconds) -> Radians {
        if t.0 >= self.stop {
            return Radians(self.angle_stop);
        }
        let dt = t.0 - self.start.0;
        // 1 - e^(-dt/tau), accurate for small dt too.
        let settled = -(-dt / self.tau).exp_m1();
        self.angle_with(dt, settled)
    }

    /// The angle at `t` (`t >= start`) with the exponential it took, `e^(-(t - start)/tau)
    /// - 1` (NaN from the stop time on, where none is taken): the angle is
    /// [`Segment::angle_at`]'s, bit for bit, and the exponential lets [`Segment::around`]
    /// expand the motion about `t` without another.
    pub(crate) fn evaluate(&self, t: Seconds) -> (Radians, f64) {
        if t.0 >= self.stop {
            return (Radians(self.angle_stop), f64::NAN);
        }
        let dt = t.0 - self.start.0;
        let decay_m1 = (-dt / self.tau).exp_m1();
        (self.angle_with(dt, -decay_m1), decay_m1)
    }

    /// The angle `dt` after the start, with `settled = 1 - e^(-dt/tau)`.
    fn angle_with(&self, dt: f64, settled: f64) -> Radians {
        Radians(self.angle0 + self.target * dt + (self.speed0 - self.target) * self.tau * settled)
    }

    /// The motion about `a` (before the stop time), from [`Segment::evaluate`]'s answer there:
    /// cheap to evaluate near `a`, equal to the segment's closed form to rounding.
    pub(crate) fn around(&self, a: Seconds, (angle, decay_m1): (Radians, f64)) -> Around {
        debug_assert!(a.0 < self.stop, "expanded at or past the stop time");
        Around {
            angle: angle.0,
            target: self.target,
            transient: (self.speed0 - self.target) * (1.0 + decay_m1),
            tau: self.tau,
        }
    }

    /// Wheel speed at time `t` (`t >= start`).
    pub fn speed_at(&self, t: Seconds) -> RadPerSec {
        if t.0 >= self.stop {
            return RadPerSec::ZERO;
        }
        let dt = t.0 - self.start.0;
        RadPerSec(self.target + (self.speed0 - self.target) * (-dt / self.tau).exp())
    }

    /// The time after `start` at which the speed passes through zero, if it does: only when
    /// the wheel turns one way and is driven the other. The angle is monotone on each side of
    /// this time. (A wheel slowed by Coulomb friction stops there instead:
    /// [`Segment::stop_time`].)
    pub fn speed_reversal(&self) -> Option<Seconds> {
        if self.stop.is_finite() {
            None
        } else {
            self.zero_crossing()
        }
    }

    fn zero_crossing(&self) -> Option<Seconds> {
        if self.speed0 != 0.0 && self.target != 0.0 && self.speed0.signum() != self.target.signum()
        {
            // w_ss + (w0 - w_ss) e^(-t/tau) = 0  =>  t = tau ln(1 - w0 / w_ss)
            Some(Seconds(
                self.start.0 + self.tau * (-self.speed0 / self.target).ln_1p(),
            ))
        } else {
            None
        }
    }

    /// The times in `(from, to)` at which the direction of motion changes or the motion ends
    /// (speed reversal, Coulomb stop): the angle is monotone between them.
    pub fn turning_points(&self, from: Seconds, to: Seconds) -> impl Iterator<Item = Seconds> {
        [self.speed_reversal(), self.stop_time()]
            .into_iter()
            .flatten()
            .filter(move |&t| t > from && t < to)
    }
}

/// A [`Segment`] expanded about a time `a`: angle and speed at `a + u`, with `e^(-u/tau)`
/// from a short series when `u` is small against `tau` (the usual case: the next encoder
/// edge is a fraction of a millisecond away, the time constants tens of milliseconds). For
/// solving where the angle reaches a value; the answer is then checked on the closed form.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Around {
    angle: f64,
    target: f64,
    /// The speed's distance from its target at `a`.
    transient: f64,
    tau: f64,
}

impl Around {
    /// Angle (rad) and speed (rad/s) at `a + u`.
    pub(crate) fn state(&self, u: f64) -> (f64, f64) {
        let decay_m1 = expm1_near_zero(-u / self.tau);
        (
            self.angle + self.target * u - self.transient * self.tau * decay_m1,
            self.target + self.transient * (1.0 + decay_m1),
        )
    }

    /// The angular acceleration (rad/s^2) at `a + u`, given the speed there.
    pub(crate) fn acceleration(&self, speed: f64) -> f64 {
        (self.target - speed) / self.tau
    }
}

/// `e^x - 1`: a series for `|x| <= 1/32` (error below 1e-16 relative), the library's beyond.
fn expm1_near_zero(x: f64) -> f64 {
    if x.abs() <= 1.0 / 32.0 {
        // Horner on x + x^2/2 + ... + x^8/8!; the next term is below 2^-45 x.
        x * (1.0
            + x * (1.0 / 2.0
                + x * (1.0 / 6.0
                    + x * (1.0 / 24.0
                        + x * (1.0 / 120.0
                            + x * (1.0 / 720.0 + x * (1.0 / 5040.0 + x * (1.0 / 40320.0))))))))
    } else {
        x.exp_m1()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bridge::DriveState;
    use crate::motor::FirstOrderMotor;
    use crate::units::Volts;
    use crate::Duty;
    use approx::assert_relative_eq;
    use proptest::prelude::*;

    fn fwd(duty: f64) -> DriveState {
        DriveState::from_inputs(Duty::new(duty).unwrap(), Duty::OFF)
    }

    const V: Volts = Volts(7.4);

    /// The closed form agrees with a fine RK4 integration of
    /// `d omega/dt = (w_ss - omega)/tau, d angle/dt = omega`, for driving, reversing through
    /// zero, coasting and braking.
    #[test]
    fn closed_form_matches_numerical_integration() {
        let m = FirstOrderMotor::henrytwo_right();
        let cases = [
            (0.0, fwd(0.98)),
            (
                20.0,
                DriveState::from_inputs(Duty::OFF, Duty::new(0.9).unwrap()),
            ),
            (-15.0, DriveState::COAST),
            (24.0, DriveState::from_inputs(Duty::FULL, Duty::FULL)),
        ];
        for (w0, drive) in cases {
            let relax = m.relaxation(drive, V);
            let seg = Segment::new(Seconds(0.5), Radians(1.0), RadPerSec(w0), relax);
            let (w_ss, tau) = (relax.target.0, relax.tau.0);
            let f = |w: f64| (w_ss - w) / tau;
            let (mut w, mut a) = (w0, 1.0);
            let h = 1e-5;
            for step in 1..=30_000 {
                let k1w = f(w);
                let k2w = f(w + 0.5 * h * k1w);
                let k3w = f(w + 0.5 * h * k2w);
                let k4w = f(w + h * k3w);
                let (k1a, k2a, k3a, k4a) = (w, w + 0.5 * h * k1w, w + 0.5 * h * k2w, w + h * k3w);
                w += h / 6.0 * (k1w + 2.0 * k2w + 2.0 * k3w + k4w);
                a += h / 6.0 * (k1a + 2.0 * k2a + 2.0 * k3a + k4a);
                if step % 1000 == 0 {
                    let t = Seconds(0.5 + h * f64::from(step));
                    assert_relative_eq!(seg.speed_at(t).0, w, epsilon = 1e-9);
                    assert_relative_eq!(seg.angle_at(t).0, a, epsilon = 1e-9);
                }
            }
        }
    }

    /// The reversal time is where the closed-form speed is zero.
    #[test]
    fn speed_reversal_is_a_zero_of_the_speed() {
        let m = FirstOrderMotor::henrytwo_left();
        let reverse = DriveState::from_inputs(Duty::OFF, Duty::FULL);
        let seg = Segment::new(
            Seconds(2.0),
            Radians::ZERO,
            RadPerSec(20.0),
            m.relaxation(reverse, V),
        );
        let tz = seg.speed_reversal().unwrap();
        assert!(tz > Seconds(2.0));
        assert!(seg.speed_at(tz).0.abs() < 1e-12);
        assert!(seg.speed_at(tz - Seconds(1e-6)).0 > 0.0);
        assert!(seg.speed_at(tz + Seconds(1e-6)).0 < 0.0);
    }

    /// The short series for `e^x - 1` is the library's to rounding over its whole range
    /// (|x| <= 1/32), where the next term it drops is below 2^-45 x: a wrong coefficient
    /// anywhere up to the x^7 term is off by more than 1e-15 relative somewhere.
    #[test]
    fn series_for_expm1_is_the_library_to_rounding() {
        for i in -256..=256 {
            let x = f64::from(i) / (256.0 * 32.0);
            let (series, library) = (expm1_near_zero(x), x.exp_m1());
            assert!(
                (series - library).abs() <= 1e-15 * library.abs(),
                "x = {x}: series {series}, library {library}"
            );
        }
        // Beyond the series' range it is the library's.
        assert_eq!(expm1_near_zero(0.5), 0.5f64.exp_m1());
    }

    /// The expansion about `a` gives the closed form's angle and speed at `a + u`, for
    /// steps where the series serves (u much shorter than tau) and where it does not.
    #[test]
    fn expansion_about_a_time_is_the_closed_form() {
        let m = FirstOrderMotor::henrytwo_left();
        let seg = Segment::new(
            Seconds(0.1),
            Radians(2.0),
            RadPerSec(-3.0),
            m.relaxation(fwd(0.8), V),
        );
        let a = Seconds(0.13);
        let around = seg.around(a, seg.evaluate(a));
        for u in [0.0, 1e-4, 1.5e-3, 0.02, 0.2] {
            let (angle, speed) = around.state(u);
            let t = Seconds(a.0 + u);
            assert_relative_eq!(angle, seg.angle_at(t).0, max_relative = 1e-13);
            assert_relative_eq!(speed, seg.speed_at(t).0, max_relative = 1e-13);
        }
    }

    proptest! {
        /// Coasting or braking from any speed never reverses the wheel: the speed keeps its
        /// sign and shrinks, for any mix of brake and coast time.
        #[test]
        fn decay_never_reverses(w0 in -40.0f64..40.0, brake in 0.0f64..=1.0, dt in 0.0f64..5.0) {
            let m = FirstOrderMotor::henrytwo_right();
            let drive = DriveState::from_inputs(Duty::new(brake).unwrap(), Duty::new(brake).unwrap());
            let seg = Segment::new(Seconds::ZERO, Radians::ZERO, RadPerSec(w0), m.relaxation(drive, V));
            let w = seg.speed_at(Seconds(dt)).0;
            prop_assert!(w * w0 >= 0.0);
            prop_assert!(w.abs() <= w0.abs());
            prop_assert!(seg.speed_reversal().is_none());
        }
    }
}
