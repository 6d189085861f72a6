//! `turn_slip`: in turns the wheels turn, the ground sees less.
//!
//! Spinning on the spot makes the tyres scrub and the castor swivel against the floor; part
//! of the wheels' differential travel is lost. Each wheel's ground travel is split into a
//! common part (the mean of the two, translation) and a differential part (half their
//! difference, rotation); this effect keeps `1 - fraction` of the differential part.
//! Ground only: the encoders count the full wheel travel.
//!
//! # Signature
//!
//! Every spin turn rotates by `1 - fraction` of what the wheel travel implies, in both
//! directions alike (like Eb > 1, but only where the wheels turn differently: a straight
//! leg is untouched, a curve is flattened).
//!
//! # Keys
//!
//! | key | unit | meaning |
//! |---|---|---|
//! | `fraction` | 1 | share of the rotation lost, in `[0, 1)` |

use serde::{Deserialize, Serialize};

use crate::check::check_fraction;
use crate::effects::key;
use crate::Error;

/// Parameters of `[effects.turn_slip]` (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TurnSlip {
    /// Share of the differential (rotational) travel lost.
    pub fraction: f64,
}

impl TurnSlip {
    /// Checks the parameters; `prefix` is `effects.turn_slip`.
    pub fn validate(&self, prefix: &str) -> Result<(), Error> {
        check_fraction(
            &key(prefix, "fraction"),
            self.fraction,
            "share of each turn's rotation lost to slip",
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::test_support::{run, symmetric};
    use crate::side::Side;

    /// Signature: a spin turn rotates `1 - s` of the nominal rotation in both directions; a
    /// straight leg is unchanged; the encoders count as without slip.
    #[test]
    fn spins_rotate_less_straight_legs_do_not_change() {
        let s = 0.04;
        let config = symmetric(|c| c.effects.turn_slip = Some(TurnSlip { fraction: s }));
        let plain = symmetric(|_| {});
        for dir in [1.0, -1.0] {
            let spin = run(&config, 0, -0.9 * dir, 0.9 * dir, 0.8, 0.3);
            let spin0 = run(&plain, 0, -0.9 * dir, 0.9 * dir, 0.8, 0.3);
            let ratio = spin.pose().theta().0 / spin0.pose().theta().0;
            assert!((ratio - (1.0 - s)).abs() < 1e-12, "{ratio}");
            assert_eq!(spin.a_edges(Side::Right), spin0.a_edges(Side::Right));
        }
        let line = run(&config, 0, 0.9, 0.9, 1.0, 0.3).pose();
        let line0 = run(&plain, 0, 0.9, 0.9, 1.0, 0.3).pose();
        assert!((line.x().0 - line0.x().0).abs() < 1e-9);
        assert_eq!(line.theta().0, 0.0);
    }
}
