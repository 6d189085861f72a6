//! `encoder_missed_counts`: the plant's encoder does not produce some of its pulses.
//!
//! Each A pulse (two edges) is missing with probability `fraction`, drawn once per pulse
//! position from the robot's seed: a weak magnet pole, a sensor at the edge of its range.
//! Channel A stays low through a missing pulse and B keeps toggling, so the thesis' decoder
//! loses two counts and keeps the direction. Missing pulses belong to shaft positions, so
//! the levels stay a function of the shaft angle and the transitions stay exact (silent
//! boundaries are skipped); see [`crate::encoder`].
//!
//! The bench has its own injection point between the plant and the pins
//! (`hil::inject::EncoderFault::MissPairs`, every n-th pair, for edge rates the MCU cannot
//! follow): use this effect for a flaw of the encoder itself, that one for the wiring or
//! the MCU.
//!
//! # Signature
//!
//! The side's count runs `fraction` slow on average: odometry sees that wheel as smaller
//! (aliased onto Ed and Es in an endpoint test; a speed controller drives the wheel faster
//! to make up). The pose does not change: the wheel turns as before.
//!
//! # Keys
//!
//! | key | unit | meaning |
//! |---|---|---|
//! | `left_fraction` | 1 | share of the left encoder's A pulses missing, in `[0, 1)` |
//! | `right_fraction` | 1 | the same for the right encoder |

use serde::{Deserialize, Serialize};

use crate::check::check_fraction;
use crate::effects::key;
use crate::side::Side;
use crate::Error;

/// Parameters of `[effects.encoder_missed_counts]` (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EncoderMissedCounts {
    /// Share of the left encoder's A pulses missing.
    pub left_fraction: f64,
    /// Share of the right encoder's A pulses missing.
    pub right_fraction: f64,
}

impl EncoderMissedCounts {
    /// Checks the parameters; `prefix` is `effects.encoder_missed_counts`.
    pub fn validate(&self, prefix: &str) -> Result<(), Error> {
        check_fraction(
            &key(prefix, "left_fraction"),
            self.left_fraction,
            "share of the left encoder's A pulses missing",
        )?;
        check_fraction(
            &key(prefix, "right_fraction"),
            self.right_fraction,
            "share of the right encoder's A pulses missing",
        )
    }

    /// The missing share of `side`.
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
    use crate::effects::test_support::{drive, symmetric};
    use crate::encoder::net_a_edges;
    use crate::Robot;

    /// Signature: stepping from transition to transition as the bench does, every step
    /// changes exactly one level; the thesis decoder run on the levels counts exactly
    /// `a_edges`, which falls short of the shaft's count by about the missing share; the
    /// pose is as without the effect.
    #[test]
    fn counts_run_slow_and_transitions_stay_exact() {
        let p = 0.1;
        let config = symmetric(|c| {
            c.effects.encoder_missed_counts = Some(EncoderMissedCounts {
                left_fraction: p,
                right_fraction: 0.0,
            })
        });
        let mut robot = Robot::new(&config, 9).unwrap();
        let mut reference = Robot::new(&symmetric(|_| {}), 9).unwrap();
        drive(&mut robot, 0.9, 0.9);
        drive(&mut reference, 0.9, 0.9);
        let side = Side::Left;
        let mut levels = robot.encoder_levels(side);
        let mut count = 0;
        let mut steps = 0;
        while robot.now().0 < 1.5 {
            let t = robot.next_encoder_transition(side).unwrap();
            robot.advance_to(t).unwrap();
            let (a, b) = robot.encoder_levels(side);
            assert!((a != levels.0) ^ (b != levels.1), "one level per step");
            if a != levels.0 {
                count += if a != b { 1 } else { -1 };
            }
            levels = (a, b);
            assert_eq!(count, robot.a_edges(side));
            steps += 1;
        }
        let shaft = net_a_edges(robot.quadrature_index(side));
        let kept = robot.a_edges(side) as f64 / shaft as f64;
        assert!(
            (kept - (1.0 - p)).abs() < 0.03,
            "kept {kept} of {shaft} over {steps} steps"
        );
        reference.advance_to(robot.now()).unwrap();
        assert_eq!(
            robot.quadrature_index(side),
            reference.quadrature_index(side)
        );
        assert!((robot.pose().x().0 - reference.pose().x().0).abs() < 1e-6);
    }
}
