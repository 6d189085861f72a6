//! The MCU resets in the middle of a leg (a glitch on the reset line, the
//! watchdog, a brown-out): the firmware restarts, the robot is still rolling.
//!
//! The reset itself drives every output low, so "motors off after the reset"
//! holds for any firmware; what tells a firmware that resumes or restarts the
//! interrupted test is the drive after that, watched long enough for the
//! whole line to be driven again.

use super::{FaultCase, Observed};
use crate::bench::{Action, ScheduledFault, Trigger};
use crate::runs::experiment::Test;

/// Robot time of the reset, s.
const RESET_AT_S: f64 = 4.0;

pub fn case() -> FaultCase {
    FaultCase {
        name: "reset-mid-test",
        what: "MCU reset 4 s into a 2 m line",
        expected: "after the reset the motors are off (the outputs reset low) and stay off: no test resumes or restarts by itself",
        test: Test::Line,
        leg_mm: 2000.0,
        faults: vec![ScheduledFault::new(
            Trigger::Time { s: RESET_AT_S },
            Action::Reset,
        )],
        // The whole 2 m line takes about 15 s at the set-points: a firmware
        // that started it again after the reset would drive it, and complete
        // it, within this limit.
        limit_s: RESET_AT_S + 25.0,
        framed: false,
        check: Some(check),
    }
}

fn check(o: &Observed) -> Result<String, String> {
    match (o.motors_off_after_s, o.driven_again_after_s) {
        (Some(t), None) if t < 0.01 && !o.completed => Ok(format!(
            "motors off {:.1} ms after the reset and never driven again in the {:.0} s after it; no test resumed",
            t * 1e3,
            o.robot_time_s - o.fault_at_s.unwrap_or(0.0)
        )),
        (t, again) => Err(format!(
            "expected the motors off at once, never driven again, no completion; saw the motors {}, {}, {}",
            super::off_after(t),
            again.map_or("never driven again".into(), |a| format!("driven again after {:.0} ms", a * 1e3)),
            if o.completed { "the test completed" } else { "no completion" }
        )),
    }
}
