//! The battery collapses for 300 ms (a motor start on a worn pack, a loose
//! battery connector): 3.0 V leaves the 5 V regulator 2.0 V of output, below
//! the ATmega2560's brown-out level (2.7 V on the Mega's fuses), so the MCU
//! is held in reset until VCC recovers and 65 ms of start-up have passed
//! (see `crate::mcu::supply`).

use super::{FaultCase, Observed};
use crate::bench::{Action, ScheduledFault, Trigger};
use crate::runs::experiment::Test;

pub fn case() -> FaultCase {
    FaultCase {
        name: "battery-brownout-reset",
        what: "battery at 3.0 V for 300 ms from 3 s into a 2 m line: VCC 2.0 V, below the 2.7 V brown-out level",
        expected: "the MCU is held in reset during the dip: the bridge inputs fall low at once (motors off within 1 ms); it restarts 65 ms after VCC recovers, idle: no test resumes, no hang",
        test: Test::Line,
        leg_mm: 2000.0,
        faults: vec![ScheduledFault {
            trigger: Trigger::Time { s: DIP_S.0 },
            action: Action::BatteryVolts { volts: Some(3.0) },
            undo: Some((DIP_S.1 - DIP_S.0, Action::BatteryVolts { volts: None })),
        }],
        limit_s: 8.0,
        framed: false,
        check: Some(check),
    }
}

/// The dip, and when the reset must let go: VCC back at the dip's end,
/// plus the 65 ms start-up time-out.
const DIP_S: (f64, f64) = (3.0, 3.3);
const RELEASE_S: f64 = DIP_S.1 + 0.065;

fn check(o: &Observed) -> Result<String, String> {
    let held = match o.brownouts.as_slice() {
        [(on, Some(off))] => Some((*on, *off)),
        _ => None,
    };
    let at = |t: f64, want: f64| (t - want).abs() < 1e-3;
    match (o.motors_off_after_s, held) {
        (Some(t), Some((on, off)))
            if t < 1e-3
                && at(on, DIP_S.0)
                && at(off, RELEASE_S)
                && !o.completed
                && o.hang.is_none() =>
        {
            Ok(format!(
                "held in reset {on:.3}-{off:.3} s, motors off {:.2} ms after the dip, no test resumed",
                t * 1e3
            ))
        }
        (t, _) => Err(format!(
            "expected one brown-out reset from {:.3} to {RELEASE_S:.3} s, the motors off within 1 ms and no completion; saw resets {:?}, the motors {}, {}, {}",
            DIP_S.0,
            o.brownouts,
            super::off_after(t),
            if o.completed { "the test completed" } else { "no completion" },
            o.hang.as_ref().map_or("no hang".into(), |h| format!("hung: {h}"))
        )),
    }
}
