//! `wheel_diameter_ratio` (Borenstein's Ed): the wheels' effective diameters differ.
//!
//! `Ed = D_R / D_L`, applied on top of `[geometry]` with the mean diameter kept (as
//! Borenstein and Feng define it): the left diameter is multiplied by `2 / (Ed + 1)`, the
//! right by `2 Ed / (Ed + 1)`. The motors and encoders do not notice (they turn the same
//! angle); the floor does: each wheel's arc is its angle times its own radius.
//!
//! # Signature
//!
//! Equal wheel angles no longer give equal arcs: a straight leg curves towards the smaller
//! wheel, by a heading of `(Ed - 1) / (Ed + 1) * 2 L / b` over a leg of length `L` and a
//! lateral end error of half that times `L`. It curves to the same side of the start line
//! forwards and backwards (backwards, the larger wheel turns the heading the other way, and
//! the motion is reversed too). In a UMBmark it is Borenstein's type B error: it adds to the
//! turn error in one direction and subtracts in the other. Spin turns are unchanged to first
//! order (the mean diameter is kept); the centre drifts by `(Ed - 1)/(Ed + 1)` of the wheel
//! travel.
//!
//! # Keys
//!
//! | key | unit | meaning |
//! |---|---|---|
//! | `right_over_left_ratio` | 1 | Ed = D_R / D_L, in `[0.5, 2]` |

use serde::{Deserialize, Serialize};

use crate::check::check_ratio;
use crate::effects::key;
use crate::side::PerSide;
use crate::Error;

/// Parameters of `[effects.wheel_diameter_ratio]` (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WheelDiameterRatio {
    /// Ed = D_R / D_L.
    pub right_over_left_ratio: f64,
}

impl WheelDiameterRatio {
    /// Checks the parameters; `prefix` is `effects.wheel_diameter_ratio`.
    pub fn validate(&self, prefix: &str) -> Result<(), Error> {
        check_ratio(
            &key(prefix, "right_over_left_ratio"),
            self.right_over_left_ratio,
            "Ed = right wheel diameter / left wheel diameter",
        )
    }

    /// The factors on each wheel's diameter (their mean is 1).
    pub fn diameter_factors(&self) -> PerSide<f64> {
        let ed = self.right_over_left_ratio;
        PerSide {
            left: 2.0 / (ed + 1.0),
            right: 2.0 * ed / (ed + 1.0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::test_support::{run, symmetric};
    use crate::side::Side;

    /// Signature: with the right wheel 2 % larger, a straight leg curves left (towards the
    /// smaller wheel... seen from the larger one) by the predicted heading, and to the same
    /// side of the start line forwards and backwards; the encoders count as without it.
    #[test]
    fn curves_a_straight_leg_one_way_in_both_directions() {
        let ed = 1.02;
        let config = symmetric(|c| {
            c.effects.wheel_diameter_ratio = Some(WheelDiameterRatio {
                right_over_left_ratio: ed,
            })
        });
        let plain = symmetric(|_| {});
        for dir in [1.0, -1.0] {
            let robot = run(&config, 0, 0.9 * dir, 0.9 * dir, 2.0, 0.5);
            let reference = run(&plain, 0, 0.9 * dir, 0.9 * dir, 2.0, 0.5);
            let pose = robot.pose();
            assert!(
                pose.y().0 > 5.0,
                "dir {dir}: ends to the left of the start line: {pose}"
            );
            assert_eq!(robot.a_edges(Side::Left), reference.a_edges(Side::Left));
            assert_eq!(robot.a_edges(Side::Right), reference.a_edges(Side::Right));
            // Heading: (d_R - d_L) / b with d = nominal arc times the factor.
            let arc = reference.distance_travelled(Side::Left).0;
            let expected = arc * (2.0 * ed - 2.0) / (ed + 1.0) / 130.0;
            assert!(
                (pose.theta().0 - expected).abs() < 1e-9,
                "{} vs {expected}",
                pose.theta()
            );
            assert_eq!(
                pose.theta().0.signum(),
                dir,
                "heading turns with the motion"
            );
        }
    }
}
