//! `motor_gain_asymmetry`: one motor is stronger than the fit says (winding or magnet
//! tolerances, a gearbox that loses more, a different batch).
//!
//! A gain ratio per side multiplies the motor's steady speed at every duty (the fitted `K`
//! becomes `g K`); the dead band and the time constant stay. The back EMF per rad/s scales
//! as `1 / g` (a motor that turns faster for the same voltage generates less per turn).
//!
//! # Signature
//!
//! Open loop (equal duties): the robot curves towards the weaker side, at a rate set by the
//! speed difference. Under per-wheel speed control the steady speeds are the set-points
//! whatever the gains, so the gain difference shows only in the transients: each start from
//! rest kicks the heading towards the weaker side until the controllers catch up (the gap
//! crate calls this "a heading kick at each segment start").
//!
//! # Keys
//!
//! | key | unit | meaning |
//! |---|---|---|
//! | `left_gain_ratio` | 1 | `g` of the left motor, in `[0.5, 2]` |
//! | `right_gain_ratio` | 1 | `g` of the right motor |

use serde::{Deserialize, Serialize};

use crate::check::check_ratio;
use crate::effects::key;
use crate::side::Side;
use crate::Error;

/// Parameters of `[effects.motor_gain_asymmetry]` (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotorGainAsymmetry {
    /// Gain factor of the left motor.
    pub left_gain_ratio: f64,
    /// Gain factor of the right motor.
    pub right_gain_ratio: f64,
}

impl MotorGainAsymmetry {
    /// Checks the parameters; `prefix` is `effects.motor_gain_asymmetry`.
    pub fn validate(&self, prefix: &str) -> Result<(), Error> {
        check_ratio(
            &key(prefix, "left_gain_ratio"),
            self.left_gain_ratio,
            "gain factor of the left motor",
        )?;
        check_ratio(
            &key(prefix, "right_gain_ratio"),
            self.right_gain_ratio,
            "gain factor of the right motor",
        )
    }

    /// The gain factor of `side`.
    pub fn ratio(&self, side: Side) -> f64 {
        match side {
            Side::Left => self.left_gain_ratio,
            Side::Right => self.right_gain_ratio,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::test_support::{drive, run, symmetric};
    use crate::units::Seconds;
    use crate::Robot;

    /// Signature: the steady speeds are in the ratio of the gains, and equal duties curve the
    /// robot towards the weaker (left) side, forwards.
    #[test]
    fn equal_duties_curve_towards_the_weaker_motor() {
        let config = symmetric(|c| {
            c.effects.motor_gain_asymmetry = Some(MotorGainAsymmetry {
                left_gain_ratio: 0.95,
                right_gain_ratio: 1.0,
            })
        });
        let mut robot = Robot::new(&config, 0).unwrap();
        drive(&mut robot, 0.9, 0.9);
        robot.advance_to(Seconds(2.0)).unwrap();
        let ratio = robot.wheel_speed(Side::Left).0 / robot.wheel_speed(Side::Right).0;
        assert!((ratio - 0.95).abs() < 1e-9, "{ratio}");
        let pose = run(&config, 0, 0.9, 0.9, 2.0, 0.3).pose();
        assert!(
            pose.theta().0 > 0.05 && pose.y().0 > 10.0,
            "curves left: {pose}"
        );
    }
}
