//! The battery collapses for 300 ms (a motor start on a worn pack, a loose
//! battery connector): 3.0 V leaves the 5 V regulator 2.0 V of output, below
//! the ATmega2560's brown-out level (2.7 V on the Mega's fuses), so the MCU
//! is held in reset until VCC recovers and 65 ms of start-up have passed
//! (see `crate::supply`).

use super::{FaultCase, Observed};
use crate::bench::{Action, ScheduledFault, Trigger};
use crate::experiment::Test;

pub fn case() -> FaultCase {
    FaultCase {
        name: "battery-brownout-reset",
        what: "battery at 3.0 V for 300 ms from 3 s into a 2 m line: VCC 2.0 V, below the 2.7 V brown-out level",
        expected: "the MCU is held in reset during the dip: the bridge inputs fall low at once (motors off within 1 ms); it restarts 65 ms after VCC recovers, idle: no test resumes, no hang",
        test: Test::Line,
        leg_mm: 2000.0,
        faults: vec![ScheduledFault {
            trigger: Trigger::Time { s: 3.0 },
            action: Action::BatteryVolts { volts: Some(3.0) },
            undo: Some((0.3, Action::BatteryVolts { volts: None })),
        }],
        limit_s: 8.0,
        framed: false,
        check,
    }
}

fn check(o: &Observed) -> Result<String, String> {
    match o.motors_off_after_s {
        Some(t) if t < 1e-3 && o.bod_resets == 1 && !o.completed && o.hang.is_none() => Ok(format!(
            "one brown-out reset, motors off {:.2} ms after the dip, no test resumed",
            t * 1e3
        )),
        t => Err(format!(
            "expected one brown-out reset, the motors off within 1 ms and no completion; saw {} resets, motors off after {t:?} s, completed {}, hang {:?}",
            o.bod_resets, o.completed, o.hang
        )),
    }
}
