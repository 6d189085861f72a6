//! `dead_band`: more Coulomb friction in a motor and its gearbox than the fitted model has
//! (a dry bearing, a tight gear mesh, dirt).
//!
//! A Coulomb friction torque and a dead band are the same thing in a DC motor's steady
//! state, so the extra friction is given as the duty that balances it, `f` (a fraction of
//! the stall torque at full duty), per side. While driven it widens the motor's dead band,
//! `d0 -> d0 + f`, at the same slope: the steady speed drops by `K / (d_ref - d0) * f` at
//! every duty. While not driven it decelerates the wheel by the same torque, so a coasting
//! wheel stops in finite time instead of creeping; see [`crate::motor`] for the closed form.
//!
//! # Signature
//!
//! Open loop: slower at every duty, a wider range of duties that do not move the wheel at
//! all, shorter coasting. Under speed control: more duty for the same speed, and a
//! start-up that lags (the controller must wind up past the wider dead band), which kicks the
//! heading towards the stiffer side at the start of each leg and turn.
//!
//! # Keys
//!
//! | key | unit | meaning |
//! |---|---|---|
//! | `extra_left_duty` | duty (fraction of the PWM period) | `f` of the left motor, in `[0, 1)` |
//! | `extra_right_duty` | duty | `f` of the right motor |

use serde::{Deserialize, Serialize};

use crate::check::check_fraction;
use crate::effects::key;
use crate::side::Side;
use crate::Error;

/// Parameters of `[effects.dead_band]` (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DeadBand {
    /// Extra dead band of the left motor, duty.
    pub extra_left_duty: f64,
    /// Extra dead band of the right motor, duty.
    pub extra_right_duty: f64,
}

impl DeadBand {
    /// Checks the parameters; `prefix` is `effects.dead_band`.
    pub fn validate(&self, prefix: &str) -> Result<(), Error> {
        check_fraction(
            &key(prefix, "extra_left_duty"),
            self.extra_left_duty,
            "extra dead band of the left motor, as a duty",
        )?;
        check_fraction(
            &key(prefix, "extra_right_duty"),
            self.extra_right_duty,
            "extra dead band of the right motor, as a duty",
        )
    }

    /// The extra dead band of `side`, duty.
    pub fn extra(&self, side: Side) -> f64 {
        match side {
            Side::Left => self.extra_left_duty,
            Side::Right => self.extra_right_duty,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::test_support::{drive, symmetric};
    use crate::motor::{FirstOrderMotor, THESIS_REFERENCE_DUTY};
    use crate::units::Seconds;
    use crate::Robot;

    /// Signature: the steady speed at the reference duty drops by `K/(d_ref - d0) f`; a duty
    /// that turned the wheel before now does not; after cut-off the wheel stops at the
    /// closed-form time and stays stopped, where the base model only creeps towards zero.
    #[test]
    fn widens_the_dead_band_and_stops_coasting() {
        let f = 0.05;
        let config = symmetric(|c| {
            c.effects.dead_band = Some(DeadBand {
                extra_left_duty: f,
                extra_right_duty: 0.0,
            })
        });
        let mut robot = Robot::new(&config, 0).unwrap();
        drive(&mut robot, THESIS_REFERENCE_DUTY, THESIS_REFERENCE_DUTY);
        robot.advance_to(Seconds(2.0)).unwrap();
        let motor = FirstOrderMotor::henrytwo_right();
        let slope = motor.slope_rad_s_per_duty();
        let left = robot.wheel_speed(Side::Left).0;
        let right = robot.wheel_speed(Side::Right).0;
        assert!((right - left - slope * f).abs() < 1e-6, "{right} - {left}");

        // Just above the base dead band: the right wheel turns, the left does not.
        let mut robot = Robot::new(&config, 0).unwrap();
        let d = motor.dead_band_duty + 0.5 * f;
        drive(&mut robot, d, d);
        robot.advance_to(Seconds(1.0)).unwrap();
        assert_eq!(robot.wheel_speed(Side::Left).0, 0.0);
        assert!(robot.wheel_speed(Side::Right).0 > 0.5);

        // Cut-off: the left wheel stops at tau ln(1 + w0 / (c tau)), c = slope f / tau.
        let mut robot = Robot::new(&config, 0).unwrap();
        drive(&mut robot, 0.9, 0.9);
        robot.advance_to(Seconds(1.0)).unwrap();
        let w0 = robot.wheel_speed(Side::Left).0;
        drive(&mut robot, 0.0, 0.0);
        let tau = motor.tau_s;
        let c = slope * f / tau;
        let t_stop = tau * (1.0 + w0 / (c * tau)).ln();
        robot.advance_to(Seconds(1.0 + t_stop - 1e-6)).unwrap();
        assert!(robot.wheel_speed(Side::Left).0 > 0.0);
        robot.advance_to(Seconds(1.0 + t_stop + 1e-6)).unwrap();
        assert_eq!(robot.wheel_speed(Side::Left).0, 0.0);
        let stopped = robot.wheel_angle(Side::Left);
        assert_eq!(robot.next_encoder_transition(Side::Left), None);
        robot.advance_to(Seconds(5.0)).unwrap();
        assert_eq!(robot.wheel_angle(Side::Left), stopped);
        assert!(
            robot.wheel_speed(Side::Right).0 > 0.0,
            "the base model creeps on"
        );
    }
}
