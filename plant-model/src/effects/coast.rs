//! `coast`: how the wheels run on after the motor is switched off.
//!
//! With both bridge inputs low (the thesis firmware's off state, the DRV8833's fast decay)
//! the motor's current dies within microseconds and nothing brakes it electrically: the
//! rotor and, through the gearbox, the robot's own mass keep turning the wheel until
//! friction stops it. The fitted time constant is that of the *driven* motor, where the back
//! EMF damps it; coasting is slower. This effect gives each motor its own coast time
//! constant (the base model's `coast_tau_s` defaults to the driven `tau_s`; set one or the
//! other, not both).
//!
//! # Signature
//!
//! After a cut-off at speed `w0` the wheel rolls on by `w0 tau_c` (exponential coast), so a
//! spin turn cut off at its target count over-rotates by `2 r w0 tau_c / b`: an extra
//! rotation proportional to the speed at cut-off, the same sign in both directions (a type
//! A error in UMBmark, like a too-small wheelbase). The encoders count the coasting too,
//! which a firmware that stops counting at the target never looks at.
//!
//! # Keys
//!
//! | key | unit | meaning |
//! |---|---|---|
//! | `left_tau_s` | s | coast time constant of the left wheel |
//! | `right_tau_s` | s | coast time constant of the right wheel |

use serde::{Deserialize, Serialize};

use crate::check::{check_physical, TIME_CONSTANT_S};
use crate::effects::key;
use crate::side::Side;
use crate::units::Seconds;
use crate::Error;

/// Parameters of `[effects.coast]` (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Coast {
    /// Coast time constant of the left wheel, s.
    pub left_tau_s: f64,
    /// Coast time constant of the right wheel, s.
    pub right_tau_s: f64,
}

impl Coast {
    /// Checks the parameters; `prefix` is `effects.coast`.
    pub fn validate(&self, prefix: &str) -> Result<(), Error> {
        check_physical(
            &key(prefix, "left_tau_s"),
            self.left_tau_s,
            TIME_CONSTANT_S,
            "coast time constant of the left wheel",
        )?;
        check_physical(
            &key(prefix, "right_tau_s"),
            self.right_tau_s,
            TIME_CONSTANT_S,
            "coast time constant of the right wheel",
        )
    }

    /// The coast time constant of `side`.
    pub fn tau(&self, side: Side) -> Seconds {
        Seconds(match side {
            Side::Left => self.left_tau_s,
            Side::Right => self.right_tau_s,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::test_support::{drive, symmetric};
    use crate::units::Seconds;
    use crate::Robot;

    /// Spins at `duty` for 1 s, cuts both motors; returns (wheel speed at cut-off, rotation
    /// after it).
    fn coast_after_spin(config: &crate::RobotConfig, duty: f64) -> (f64, f64) {
        let mut robot = Robot::new(config, 0).unwrap();
        drive(&mut robot, -duty, duty);
        robot.advance_to(Seconds(1.0)).unwrap();
        let w0 = robot.wheel_speed(Side::Right).0;
        let at_cut = robot.pose().theta().0;
        drive(&mut robot, 0.0, 0.0);
        robot.advance_to(Seconds(4.0)).unwrap();
        (w0, robot.pose().theta().0 - at_cut)
    }

    /// Signature: the rotation after cut-off is `2 r w0 tau_c / b`, proportional to the speed
    /// at cut-off, and larger than with the driven time constant.
    #[test]
    fn adds_rotation_proportional_to_speed_at_cutoff() {
        let tau_c = 0.2;
        let config = symmetric(|c| {
            c.effects.coast = Some(Coast {
                left_tau_s: tau_c,
                right_tau_s: tau_c,
            })
        });
        let (w_fast, rot_fast) = coast_after_spin(&config, 0.95);
        let (w_slow, rot_slow) = coast_after_spin(&config, 0.7);
        assert!(w_fast > 1.5 * w_slow);
        let predicted = |w: f64| 2.0 * 16.0 * w * tau_c / 130.0;
        // Within the part of the coast not yet done after 3 s (e^-15).
        assert!((rot_fast - predicted(w_fast)).abs() < 1e-5, "{rot_fast}");
        assert!((rot_slow - predicted(w_slow)).abs() < 1e-5, "{rot_slow}");
        assert!((rot_fast / rot_slow - w_fast / w_slow).abs() < 1e-4);
        let (_, rot_base) = coast_after_spin(&symmetric(|_| {}), 0.95);
        assert!(rot_fast > 2.5 * rot_base, "{rot_fast} vs base {rot_base}");
    }
}
