//! The left encoder's cable comes off in the middle of a leg: both lines hold
//! their level, the firmware sees the wheel stop while it drives it.

use super::{stopped_with_code, FaultCase, Observed};
use plant_model::Side;

use crate::bench::inject::EncoderFault;
use crate::bench::{Action, ScheduledFault, Trigger};
use crate::runs::experiment::Test;

pub fn case() -> FaultCase {
    FaultCase {
        name: "encoder-dropout",
        what: "left encoder lines frozen from 3 s into a 2 m line",
        expected:
            "stall/encoder-loss watchdog: motors off within 300 ms, fault code set, no runaway",
        test: Test::Line,
        leg_mm: 2000.0,
        faults: vec![ScheduledFault::new(
            Trigger::Time { s: 3.0 },
            Action::Encoder {
                side: Side::Left,
                fault: EncoderFault::Dropout,
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
