//! The right encoder's B line sticks low: the 2x decoder counts +1, -1, +1 ...
//! so the count stops advancing although the wheel turns.

use super::{FaultCase, Observed};
use crate::bench::{Action, ScheduledFault, SideName, Trigger};
use crate::experiment::Test;
use crate::inject::EncoderFault;

pub fn case() -> FaultCase {
    FaultCase {
        name: "encoder-stuck-b",
        what: "right encoder channel B stuck low from 3 s into a 2 m line",
        expected: "the count no longer advances: watchdog stops the motors within 300 ms with a fault code",
        test: Test::Line,
        leg_mm: 2000.0,
        faults: vec![ScheduledFault::new(
            Trigger::Time { s: 3.0 },
            Action::Encoder {
                side: SideName::Right,
                fault: EncoderFault::StuckB { level: false },
            },
        )],
        limit_s: 25.0,
        framed: false,
        check,
    }
}

fn check(o: &Observed) -> Result<String, String> {
    match (o.motors_off_after_s, o.fault_code) {
        (Some(t), Some(c)) if t <= 0.3 && c != 0 => Ok(format!(
            "motors off after {:.0} ms with fault code {c}",
            t * 1e3
        )),
        (t, c) => Err(format!(
            "expected motors off within 300 ms and a fault code; saw {t:?} s and code {c:?}"
        )),
    }
}
