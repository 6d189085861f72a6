//! The right encoder's B line sticks low: the 2x decoder counts +1, -1, +1 ...
//! so the count stops advancing although the wheel turns.

use super::{stopped_with_code, FaultCase, Observed};
use plant_model::Side;

use crate::bench::inject::EncoderFault;
use crate::bench::{Action, ScheduledFault, Trigger};
use crate::runs::experiment::Test;

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
                side: Side::Right,
                fault: EncoderFault::StuckB { level: false },
            },
        )],
        limit_s: 25.0,
        framed: false,
        check: Some(check),
    }
}

fn check(o: &Observed) -> Result<String, String> {
    stopped_with_code(o, 0.3)
}
