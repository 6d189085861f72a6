//! `castor_drag`: the castor (the robot's third point of contact) drags.
//!
//! A drag force `F` at the castor's contact, `e` to the left of the robot's centre line,
//! opposes the motion. The wheels must supply it; balancing forces and moments about the
//! axle midpoint, the left wheel carries `F (1/2 + e/b)` and the right `F (1/2 - e/b)`. At
//! the wheel of radius `r` that is a load torque, expressed for the motor model as a
//! fraction of the wheel's stall torque at full duty (`wheel_stall_torque_nm`): a friction
//! duty ([`crate::motor`]), which lowers that wheel's steady speed at every duty and stops it
//! sooner when it coasts.
//!
//! # Signature
//!
//! Both wheels slower at the same duty; with the castor off-centre one side is slowed more,
//! so equal duties curve the robot towards the castor's side (a turning moment). Under speed
//! control it shows as more duty, and in each leg's start-up as a heading kick towards that
//! side.
//!
//! # Keys
//!
//! | key | unit | meaning |
//! |---|---|---|
//! | `force_n` | N | drag force at the castor |
//! | `lateral_offset_mm` | mm | castor contact left of the centre line (negative: right), within half the wheelbase |
//! | `wheel_stall_torque_nm` | N m | one wheel's stall torque at full duty and the fit voltage (the identify module's physical fit with R = 10 ohm: `kt V / R` x 100.37 = 0.11 N m) |

use serde::{Deserialize, Serialize};

use crate::check::{check_between, check_physical, Bounds};
use crate::effects::key;
use crate::side::Side;
use crate::Error;

/// Parameters of `[effects.castor_drag]` (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CastorDrag {
    /// Drag force at the castor, N.
    pub force_n: f64,
    /// Castor contact left of the centre line, mm.
    pub lateral_offset_mm: f64,
    /// A wheel's stall torque at full duty and the fit voltage, N m.
    pub wheel_stall_torque_nm: f64,
}

impl CastorDrag {
    /// Checks the parameters; `prefix` is `effects.castor_drag`. The offset is checked
    /// against the wheelbase when the robot is built.
    pub fn validate(&self, prefix: &str) -> Result<(), Error> {
        check_physical(
            &key(prefix, "force_n"),
            self.force_n,
            Bounds {
                low: 0.0,
                high: 1000.0,
                unit: "N",
            },
            "drag force at the castor",
        )?;
        check_between(
            &key(prefix, "lateral_offset_mm"),
            self.lateral_offset_mm,
            (-1000.0, 1000.0),
            "it must lie within +-1000 mm",
            "castor contact left of the centre line, mm",
        )?;
        check_physical(
            &key(prefix, "wheel_stall_torque_nm"),
            self.wheel_stall_torque_nm,
            Bounds {
                low: 1e-4,
                high: 100.0,
                unit: "N m",
            },
            "a wheel's stall torque at full duty",
        )
    }

    /// The load on `side` as a duty (fraction of the stall torque), for wheelbase
    /// `wheelbase_mm` and wheel radius `radius_mm`.
    pub fn friction_duty(&self, side: Side, wheelbase_mm: f64, radius_mm: f64) -> f64 {
        let lever = self.lateral_offset_mm / wheelbase_mm;
        let share = match side {
            Side::Left => 0.5 + lever,
            Side::Right => 0.5 - lever,
        }
        .clamp(0.0, 1.0);
        self.force_n * share * radius_mm / 1000.0 / self.wheel_stall_torque_nm
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::test_support::{run, symmetric};

    /// Signature: a castor left of centre slows both wheels, the left more, so equal duties
    /// curve the robot left; centred, it only slows it.
    #[test]
    fn off_centre_drag_turns_towards_the_castor() {
        let with = |offset: f64| {
            symmetric(|c| {
                c.effects.castor_drag = Some(CastorDrag {
                    force_n: 0.5,
                    lateral_offset_mm: offset,
                    wheel_stall_torque_nm: 0.11,
                })
            })
        };
        let plain = run(&symmetric(|_| {}), 0, 0.9, 0.9, 2.0, 0.0);
        let left = run(&with(30.0), 0, 0.9, 0.9, 2.0, 0.0);
        let centred = run(&with(0.0), 0, 0.9, 0.9, 2.0, 0.0);
        assert!(left.pose().theta().0 > 0.02, "{}", left.pose());
        assert!(left.pose().y().0 > 5.0);
        assert_eq!(centred.pose().theta().0, 0.0);
        assert!(centred.pose().x().0 < plain.pose().x().0 - 5.0);
        assert!(left.wheel_speed(Side::Left).0 < left.wheel_speed(Side::Right).0);
        assert!(left.wheel_speed(Side::Right).0 < plain.wheel_speed(Side::Right).0);
    }
}
