//! The MCU resets in the middle of a leg (a glitch on the reset line, the
//! watchdog, a brown-out): the firmware restarts, the robot is still rolling.

use super::{FaultCase, Observed};
use crate::bench::{Action, ScheduledFault, Trigger};
use crate::experiment::Test;

pub fn case() -> FaultCase {
    FaultCase {
        name: "reset-mid-test",
        what: "MCU reset 4 s into a 2 m line",
        expected: "after the reset the motors are off (the outputs reset low) and stay off: no test resumes by itself",
        test: Test::Line,
        leg_mm: 2000.0,
        faults: vec![ScheduledFault::new(
            Trigger::Time { s: 4.0 },
            Action::Reset,
        )],
        limit_s: 10.0,
        framed: false,
        check,
    }
}

fn check(o: &Observed) -> Result<String, String> {
    match o.motors_off_after_s {
        Some(t) if t < 0.01 && !o.completed => Ok(format!(
            "motors off {:.1} ms after the reset, no test resumed",
            t * 1e3
        )),
        t => Err(format!(
            "expected the motors off at once and no completion; saw {t:?} s, completed {}",
            o.completed
        )),
    }
}
