//! `wheelbase_ratio` (Borenstein's Eb): the actual wheelbase differs from the nominal one.
//!
//! `Eb = b_actual / b_nominal` multiplies `geometry.wheelbase_mm` for the floor: the
//! effective contact points of the wheels are not where the design puts them (wide tyres
//! touch across their width; the thesis measured 125 mm between the inner faces and 130 mm
//! between the wheel centres). The encoders do not notice.
//!
//! # Signature
//!
//! Every spin turn rotates by `1 / Eb` of what the wheel travel implies, the same way in both
//! directions (too little when `Eb > 1`). In a UMBmark it is Borenstein's type A error: the
//! CW and CCW end points lie mirror-symmetric. A straight leg is unaffected unless the wheels
//! already differ.
//!
//! # Keys
//!
//! | key | unit | meaning |
//! |---|---|---|
//! | `actual_over_nominal_ratio` | 1 | Eb, in `[0.5, 2]` |

use serde::{Deserialize, Serialize};

use crate::check::check_ratio;
use crate::effects::key;
use crate::Error;

/// Parameters of `[effects.wheelbase_ratio]` (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WheelbaseRatio {
    /// Eb = actual wheelbase / nominal wheelbase.
    pub actual_over_nominal_ratio: f64,
}

impl WheelbaseRatio {
    /// Checks the parameters; `prefix` is `effects.wheelbase_ratio`.
    pub fn validate(&self, prefix: &str) -> Result<(), Error> {
        check_ratio(
            &key(prefix, "actual_over_nominal_ratio"),
            self.actual_over_nominal_ratio,
            "Eb = actual wheelbase / nominal wheelbase",
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::test_support::{run, symmetric};

    /// Signature: spin turns both ways rotate by `1 / Eb` of the nominal rotation, the same
    /// error in both directions; the centre stays put.
    #[test]
    fn errs_every_turn_the_same_way() {
        let eb = 1.05;
        let config = symmetric(|c| {
            c.effects.wheelbase_ratio = Some(WheelbaseRatio {
                actual_over_nominal_ratio: eb,
            })
        });
        let plain = symmetric(|_| {});
        for dir in [1.0, -1.0] {
            let turned = run(&config, 0, -0.8 * dir, 0.8 * dir, 0.6, 0.5).pose();
            let nominal = run(&plain, 0, -0.8 * dir, 0.8 * dir, 0.6, 0.5).pose();
            assert!(dir * nominal.theta().0 > 1.0);
            let ratio = turned.theta().0 / nominal.theta().0;
            assert!((ratio - 1.0 / eb).abs() < 1e-12, "dir {dir}: ratio {ratio}");
            assert!(turned.distance_from_origin().0 < 1e-9);
        }
    }
}
