//! `straight_slip`: in straight legs the wheels turn, the ground sees less.
//!
//! Wheel spin on a smooth or dusty floor, and the creep of a rubber tyre under traction.
//! With each wheel's ground travel split into a common part (translation) and a
//! differential part (rotation), as for `turn_slip`, the common part seen at each wheel
//! keeps `1 - fraction` of that side's: left `(1 - s_L) v - u`, right `(1 - s_R) v + u`.
//! Ground only: the encoders count the full wheel travel.
//!
//! # Signature
//!
//! Straight legs come out short by the mean slip; unequal slip curves them towards the
//! slipping side (like a smaller wheel there, but only while translating); spin turns are
//! untouched.
//!
//! # Keys
//!
//! | key | unit | meaning |
//! |---|---|---|
//! | `left_fraction` | 1 | share of the left wheel's forward travel lost, in `[0, 1)` |
//! | `right_fraction` | 1 | the same for the right wheel |

use serde::{Deserialize, Serialize};

use crate::check::check_fraction;
use crate::effects::key;
use crate::side::Side;
use crate::Error;

/// Parameters of `[effects.straight_slip]` (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StraightSlip {
    /// Share of the left wheel's translation lost.
    pub left_fraction: f64,
    /// Share of the right wheel's translation lost.
    pub right_fraction: f64,
}

impl StraightSlip {
    /// Checks the parameters; `prefix` is `effects.straight_slip`.
    pub fn validate(&self, prefix: &str) -> Result<(), Error> {
        check_fraction(
            &key(prefix, "left_fraction"),
            self.left_fraction,
            "share of the left wheel's forward travel lost to slip",
        )?;
        check_fraction(
            &key(prefix, "right_fraction"),
            self.right_fraction,
            "share of the right wheel's forward travel lost to slip",
        )
    }

    /// The slip fraction of `side`.
    pub fn fraction(&self, side: Side) -> f64 {
        match side {
            Side::Left => self.left_fraction,
            Side::Right => self.right_fraction,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::test_support::{run, symmetric};

    /// Signature: equal slip shortens a straight leg by `1 - s`; more slip on the left curves
    /// it left; a spin turn is unchanged.
    #[test]
    fn shortens_and_curves_straight_legs_only() {
        let with = |l: f64, r: f64| {
            symmetric(|c| {
                c.effects.straight_slip = Some(StraightSlip {
                    left_fraction: l,
                    right_fraction: r,
                })
            })
        };
        let plain = symmetric(|_| {});
        let line0 = run(&plain, 0, 0.9, 0.9, 1.0, 0.3).pose();
        let line = run(&with(0.05, 0.05), 0, 0.9, 0.9, 1.0, 0.3).pose();
        assert!((line.x().0 / line0.x().0 - 0.95).abs() < 1e-12);
        let curved = run(&with(0.05, 0.0), 0, 0.9, 0.9, 1.0, 0.3).pose();
        assert!(curved.theta().0 > 0.05 && curved.y().0 > 5.0, "{curved}");
        let spin0 = run(&plain, 0, -0.9, 0.9, 0.8, 0.3).pose();
        let spin = run(&with(0.05, 0.02), 0, -0.9, 0.9, 0.8, 0.3).pose();
        assert!((spin.theta().0 - spin0.theta().0).abs() < 1e-12);
        assert!(spin.distance_from_origin().0 < 1e-9);
    }
}
