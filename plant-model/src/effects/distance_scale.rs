//! `distance_scale` (Es): both wheels' effective diameter scaled.
//!
//! `Es = L_odometry / L_actual` (the convention of the thesis and of the calibration
//! crate): odometry that assumes the configured diameters measures `Es` times the true
//! distance, so both true diameters are the configured ones divided by `Es`. Typical
//! cause: tyre compression under load, a diameter measured over the tread. The encoders do
//! not notice.
//!
//! # Signature
//!
//! Every distance and every rotation the floor sees is `1 / Es` of what the encoders imply:
//! straight legs end short (`Es > 1`) or long, spin turns under- or over-rotate in both
//! directions alike (like Eb). A closed square with exact turns stays closed (only scaled);
//! the turn error is what shows in a UMBmark.
//!
//! # Keys
//!
//! | key | unit | meaning |
//! |---|---|---|
//! | `odometry_over_actual_ratio` | 1 | Es, in `[0.5, 2]` |

use serde::{Deserialize, Serialize};

use crate::check::check_ratio;
use crate::effects::key;
use crate::Error;

/// Parameters of `[effects.distance_scale]` (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DistanceScale {
    /// Es = distance by odometry / actual distance.
    pub odometry_over_actual_ratio: f64,
}

impl DistanceScale {
    /// Checks the parameters; `prefix` is `effects.distance_scale`.
    pub fn validate(&self, prefix: &str) -> Result<(), Error> {
        check_ratio(
            &key(prefix, "odometry_over_actual_ratio"),
            self.odometry_over_actual_ratio,
            "Es = distance by odometry / actual distance",
        )
    }

    /// The factor on both wheels' diameters: `1 / Es`.
    pub fn diameter_factor(&self) -> f64 {
        1.0 / self.odometry_over_actual_ratio
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::test_support::{run, symmetric};
    use crate::side::Side;

    /// Signature: a straight leg and a spin turn both come out `1 / Es` of their nominal
    /// size for the same encoder counts.
    #[test]
    fn scales_distance_and_rotation_alike() {
        let es = 1.03;
        let config = symmetric(|c| {
            c.effects.distance_scale = Some(DistanceScale {
                odometry_over_actual_ratio: es,
            })
        });
        let plain = symmetric(|_| {});
        let line = run(&config, 0, 0.9, 0.9, 1.0, 0.3);
        let line0 = run(&plain, 0, 0.9, 0.9, 1.0, 0.3);
        assert_eq!(line.a_edges(Side::Left), line0.a_edges(Side::Left));
        assert!((line.pose().x().0 / line0.pose().x().0 - 1.0 / es).abs() < 1e-12);
        let spin = run(&config, 0, -0.9, 0.9, 1.0, 0.3);
        let spin0 = run(&plain, 0, -0.9, 0.9, 1.0, 0.3);
        assert!((spin.pose().theta().0 / spin0.pose().theta().0 - 1.0 / es).abs() < 1e-12);
    }
}
