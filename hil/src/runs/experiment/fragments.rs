//! A run that fragments: more legs or turns than its test's shape. The
//! firmware finished, but what it drove is not the test (a leg cut into
//! pieces is no leg of the test's length), so the run is not a complete run
//! of it: a finding, exit 3.
//!
//! The likely cause, counted from the bridge's inputs: a motor's drive
//! falling to 0 and coming back with no brake between (a PID whose output
//! chatters to 0 at this robot's counts per control period), not the
//! firmware's stop (a coast, then a reverse pulse or a turn).

use crate::bench::{Motion, MotionEvent};

use super::Shape;

/// More segments than the test's shape, and how often the drive fell to 0
/// and came back inside them.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct Fragments {
    /// Legs and turns the bench found.
    pub legs: usize,
    pub turns: usize,
    /// The test's shape: legs and turns it drives.
    pub shape_legs: usize,
    pub shape_turns: usize,
    /// Times a wheel's drive fell to 0 and came back, unbraked, while the
    /// robot drove straight (mid-leg) or spun (mid-turn).
    pub duty_zero_mid_leg: usize,
    pub duty_zero_mid_turn: usize,
}

impl Fragments {
    /// The fragments of a run of a test of `shape` with `legs` and `turns`,
    /// from its debounced `motions`; None when it has no more segments than
    /// its shape.
    pub fn of(shape: &Shape, legs: usize, turns: usize, motions: &[MotionEvent]) -> Option<Self> {
        if legs <= shape.legs && turns <= shape.turns {
            return None;
        }
        let (duty_zero_mid_leg, duty_zero_mid_turn) = duty_zero_returns(motions);
        Some(Fragments {
            legs,
            turns,
            shape_legs: shape.legs,
            shape_turns: shape.turns,
            duty_zero_mid_leg,
            duty_zero_mid_turn,
        })
    }

    /// One line: what fragmented (a run of the test named `test`), and the
    /// likely cause.
    pub fn describe(&self, test: &str) -> String {
        let cause = if self.duty_zero_mid_leg + self.duty_zero_mid_turn > 0 {
            format!(
                "likely cause: a wheel's PWM duty fell to 0 and came back {} times mid-leg and \
                 {} times mid-turn (the PID chattering at this robot's counts per control \
                 period); tune its gains ([firmware] in the robot config, or --param kp_left=...)",
                self.duty_zero_mid_leg, self.duty_zero_mid_turn
            )
        } else {
            "the drive never fell to 0 mid-segment: the firmware stopped and started again"
                .to_string()
        };
        format!(
            "fragmented: {} legs and {} turns where {} drives {} and {}; {cause}",
            self.legs, self.turns, test, self.shape_legs, self.shape_turns
        )
    }
}

/// (mid-leg, mid-turn): how often the motion left driving straight (or
/// spinning) for one or both wheels off, and came back to the same motion
/// with no brake, reverse or other motion between.
fn duty_zero_returns(motions: &[MotionEvent]) -> (usize, usize) {
    let off = |m: Motion| matches!(m, Motion::Stopped | Motion::OneWheel);
    let (mut leg, mut turn) = (0, 0);
    for k in 1..motions.len() {
        let before = motions[k - 1].motion;
        let driving = matches!(before, Motion::Forward | Motion::SpinCw | Motion::SpinCcw);
        if !driving || !off(motions[k].motion) {
            continue;
        }
        let back = motions[k..].iter().find(|e| !off(e.motion));
        if back.is_some_and(|e| e.motion == before) {
            if before == Motion::Forward {
                leg += 1;
            } else {
                turn += 1;
            }
        }
    }
    (leg, turn)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::runs::experiment::analyse::tests::at;
    use crate::runs::experiment::Test;

    /// A leg whose drive falls to 0 twice and a turn whose drive falls to 0
    /// once; the stops between (a coast, then a reverse pulse or the turn)
    /// are no such fall.
    #[test]
    fn counts_the_unbraked_returns_only() {
        use Motion::*;
        let m: Vec<MotionEvent> = [
            Forward, Stopped, Forward, OneWheel, Stopped, Forward, Stopped, Reverse, Stopped,
            SpinCw, OneWheel, SpinCw, Stopped, Reverse, Stopped, Forward, Stopped,
        ]
        .into_iter()
        .enumerate()
        .map(|(i, m)| at(m, i as u64))
        .collect();
        assert_eq!(duty_zero_returns(&m), (2, 1));
    }

    #[test]
    fn no_more_segments_than_the_shape_is_no_finding() {
        assert_eq!(Fragments::of(&Shape::of(Test::UmbmarkCw), 4, 4, &[]), None);
        assert_eq!(Fragments::of(&Shape::of(Test::Line), 1, 0, &[]), None);
        let f = Fragments::of(&Shape::of(Test::Line), 2, 0, &[]).expect("two legs on a line");
        assert_eq!((f.legs, f.shape_legs), (2, 1));
        let f =
            Fragments::of(&Shape::of(Test::Triangle), 3, 4, &[]).expect("four turns on a triangle");
        assert_eq!((f.turns, f.shape_turns), (4, 3));
    }
}
