//! `encoder_glitches`: edges of the plant's encoder that bounce.
//!
//! After an edge, with probability `fraction` (drawn once per edge position from the
//! robot's seed), the channel that changed falls back for a moment and changes again:
//! three edges where there was one, from slow signal edges near a magnet's threshold or
//! vibration. The glitch spans `width_motor_deg` of motor-shaft angle, so it lasts longer at
//! low speed (0.5 degrees: 9.5 us at the thesis' set-point speed, 0.1 ms at a crawl), and the
//! levels stay a function of the shaft angle: the transitions stay exact ([`crate::encoder`]).
//!
//! The bench has its own injection point between the plant and the pins
//! (`hil::inject::EncoderFault`); these glitches are the encoder's own.
//!
//! # Signature
//!
//! Extra level changes in pairs: a decoder that sees all three edges counts the same net
//! total (+1 -1 +1). One that misses the short pulse (interrupt latency) or reads B in the
//! middle of a B glitch miscounts: the count drifts, more at low speed. The pose does not
//! change.
//!
//! # Keys
//!
//! | key | unit | meaning |
//! |---|---|---|
//! | `left_fraction` | 1 | share of the left encoder's edges that bounce, in `[0, 1)` |
//! | `right_fraction` | 1 | the same for the right encoder |
//! | `width_motor_deg` | degrees of motor-shaft angle | how long the fallback lasts, less than a third of a state (10 degrees with 12 states per motor turn) |

use serde::{Deserialize, Serialize};

use crate::check::{check_fraction, check_physical, Bounds};
use crate::effects::key;
use crate::side::Side;
use crate::Error;

/// Parameters of `[effects.encoder_glitches]` (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EncoderGlitches {
    /// Share of the left encoder's edges followed by a glitch.
    pub left_fraction: f64,
    /// Share of the right encoder's edges followed by a glitch.
    pub right_fraction: f64,
    /// Width of a glitch, degrees of motor-shaft angle.
    pub width_motor_deg: f64,
}

impl EncoderGlitches {
    /// Checks the parameters; `prefix` is `effects.encoder_glitches`. The width is checked
    /// against the encoder's state size when the robot is built.
    pub fn validate(&self, prefix: &str) -> Result<(), Error> {
        check_fraction(
            &key(prefix, "left_fraction"),
            self.left_fraction,
            "share of the left encoder's edges that bounce",
        )?;
        check_fraction(
            &key(prefix, "right_fraction"),
            self.right_fraction,
            "share of the right encoder's edges that bounce",
        )?;
        // The upper bound is half a quadrature state, checked against the encoder.
        check_physical(
            &key(prefix, "width_motor_deg"),
            self.width_motor_deg,
            Bounds {
                low: 1e-3,
                high: 180.0,
                unit: "degrees of motor-shaft angle",
            },
            "width of a glitch",
        )
    }

    /// The glitching share of `side`.
    pub fn fraction(&self, side: Side) -> f64 {
        match side {
            Side::Left => self.left_fraction,
            Side::Right => self.right_fraction,
        }
    }

    /// The width in quadrature states, for an encoder with `a_edges_per_motor_rev` A edges
    /// per motor turn (`2 a` states per turn).
    pub fn width_states(&self, a_edges_per_motor_rev: u32) -> f64 {
        self.width_motor_deg * 2.0 * f64::from(a_edges_per_motor_rev) / 360.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::test_support::{drive, symmetric};
    use crate::encoder::net_a_edges;
    use crate::units::Seconds;
    use crate::Robot;

    /// Signature: the bench loop sees about `1 + 2 fraction` level changes per state, each
    /// step exactly one level, glitch pulses as short as the width at that speed, and the
    /// decoder's count equal to the shaft's once past each glitch.
    #[test]
    fn adds_short_pulses_and_keeps_the_net_count() {
        let p = 0.2;
        let width = 0.5;
        let config = symmetric(|c| {
            c.effects.encoder_glitches = Some(EncoderGlitches {
                left_fraction: 0.0,
                right_fraction: p,
                width_motor_deg: width,
            })
        });
        let mut robot = Robot::new(&config, 3).unwrap();
        drive(&mut robot, 0.9, 0.9);
        robot.advance_to(Seconds(0.5)).unwrap();
        let side = Side::Right;
        let q0 = robot.quadrature_index(side);
        let mut levels = robot.encoder_levels(side);
        let mut count = robot.a_edges(side);
        let (mut changes, mut shortest) = (0, f64::INFINITY);
        let mut last = robot.now().0;
        while robot.now().0 < 1.5 {
            let t = robot.next_encoder_transition(side).unwrap();
            robot.advance_to(t).unwrap();
            let (a, b) = robot.encoder_levels(side);
            assert!((a != levels.0) ^ (b != levels.1), "one level per step");
            if a != levels.0 {
                count += if a != b { 1 } else { -1 };
            }
            assert_eq!(count, robot.a_edges(side));
            levels = (a, b);
            shortest = shortest.min(t.0 - last);
            last = t.0;
            changes += 1;
        }
        let states = (robot.quadrature_index(side) - q0) as f64;
        let per_state = f64::from(changes) / states;
        assert!(
            (per_state - (1.0 + 2.0 * p)).abs() < 0.05,
            "{per_state} changes per state"
        );
        // A glitch lasts width / motor speed: at ~19.5 wheel rad/s, 0.5 deg of the motor.
        let motor_speed = robot.wheel_speed(side).0 * 100.37;
        let glitch = width.to_radians() / motor_speed;
        assert!(
            (shortest - glitch).abs() < 0.05 * glitch,
            "{shortest} vs {glitch}"
        );
        let shaft = net_a_edges(robot.quadrature_index(side));
        assert!((robot.a_edges(side) - shaft).abs() <= 1);
    }
}
