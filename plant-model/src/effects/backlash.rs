//! `backlash`: gear backlash, lost motion between the motor shaft and the wheel.
//!
//! The encoder sits on the motor shaft, before the gearbox. When the shaft reverses, it
//! turns through the gear play before the teeth engage the other way: the wheel stands still
//! for `backlash` of (wheel) angle while the encoder counts on. The wheel angle follows the
//! shaft angle through a play operator of width `delta`: it moves only when the shaft pushes
//! it from one end of the play to the other. The gears start engaged forwards (the robot
//! last drove forwards), so the first forward motion moves the wheel at once.
//!
//! Ground only: the encoder timing is the shaft's and does not change. The pose integration
//! splits its steps at every reversal of a wheel's motion, so the play is applied exactly.
//!
//! # Signature
//!
//! Each reversal of a wheel loses `delta r` of that wheel's travel: a spin turn (one wheel
//! reverses after a forward leg) turns less by `delta r / b` per reversing wheel, a
//! forward-then-back manoeuvre ends `delta r` short of the start, and the odometry (which
//! counts the shaft) does not know.
//!
//! # Keys
//!
//! | key | unit | meaning |
//! |---|---|---|
//! | `left_wheel_deg` | degrees of wheel angle | play of the left gearbox |
//! | `right_wheel_deg` | degrees of wheel angle | play of the right gearbox |

use serde::{Deserialize, Serialize};

use crate::check::check_between;
use crate::effects::key;
use crate::side::Side;
use crate::Error;

/// Parameters of `[effects.backlash]` (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Backlash {
    /// Play of the left gearbox, degrees of wheel angle.
    pub left_wheel_deg: f64,
    /// Play of the right gearbox, degrees of wheel angle.
    pub right_wheel_deg: f64,
}

impl Backlash {
    /// Checks the parameters; `prefix` is `effects.backlash`.
    pub fn validate(&self, prefix: &str) -> Result<(), Error> {
        let check = |name: &str, value: f64| {
            check_between(
                &key(prefix, name),
                value,
                (0.0, 90.0),
                "gear play must lie in [0, 90] degrees of wheel angle",
                "gear play, degrees of wheel angle",
            )
        };
        check("left_wheel_deg", self.left_wheel_deg)?;
        check("right_wheel_deg", self.right_wheel_deg)
    }

    /// The play of `side`, wheel radians.
    pub fn play_rad(&self, side: Side) -> f64 {
        match side {
            Side::Left => self.left_wheel_deg,
            Side::Right => self.right_wheel_deg,
        }
        .to_radians()
    }
}

/// The play operator: the wheel angle after the shaft moved to `shaft`, from wheel angle
/// `wheel`, with play `play` and the shaft ahead of the wheel by `play / 2` when engaged
/// forwards.
pub(crate) fn follow(wheel: f64, shaft: f64, play: f64) -> f64 {
    let half = 0.5 * play;
    if shaft - wheel > half {
        shaft - half
    } else if shaft - wheel < -half {
        shaft + half
    } else {
        wheel
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::test_support::{drive, symmetric};
    use crate::units::Seconds;
    use crate::Robot;

    /// Signature: forwards, then backwards until the encoders are back at zero: the robot
    /// ends `delta r` ahead of its start (the backward run lost the play); without backlash
    /// it would be back to within the last state. The encoder timing does not change.
    #[test]
    fn reversal_loses_the_play() {
        let play_deg = 3.0;
        let config = symmetric(|c| {
            c.effects.backlash = Some(Backlash {
                left_wheel_deg: play_deg,
                right_wheel_deg: play_deg,
            })
        });
        let plain = symmetric(|_| {});
        let back_to_zero = |config: &crate::RobotConfig| {
            let mut robot = Robot::new(config, 0).unwrap();
            drive(&mut robot, 0.9, 0.9);
            robot.advance_to(Seconds(0.5)).unwrap();
            drive(&mut robot, -0.9, -0.9);
            let mut edges = Vec::new();
            while robot.wheel_angle(Side::Left).0 > 0.0 {
                let t = robot.next_encoder_transition(Side::Left).unwrap();
                edges.push(t);
                robot.advance_to(t).unwrap();
            }
            (robot, edges)
        };
        let (robot, edges) = back_to_zero(&config);
        let (reference, edges0) = back_to_zero(&plain);
        assert_eq!(edges, edges0, "encoder timing unchanged");
        let lost = robot.pose().x().0 - reference.pose().x().0;
        let expected = play_deg.to_radians() * 16.0;
        assert!(
            (lost - expected).abs() < 1e-9,
            "lost {lost} mm, expected {expected}"
        );
        assert!((robot.pose().theta().0).abs() < 1e-12);
    }

    /// The play operator holds the wheel inside the play and drags it outside.
    #[test]
    fn play_operator() {
        assert_eq!(follow(0.0, 0.4, 1.0), 0.0);
        assert_eq!(follow(0.0, 0.75, 1.0), 0.25);
        assert_eq!(follow(0.25, 0.0, 1.0), 0.25);
        assert_eq!(follow(0.25, -0.5, 1.0), 0.0);
    }
}
