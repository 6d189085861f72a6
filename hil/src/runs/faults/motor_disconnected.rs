//! The right motor's wires come off during a leg: the bridge drives nothing,
//! the wheel coasts to a stop while the firmware keeps asking for speed.

use super::{stopped_with_code, FaultCase, Observed};
use plant_model::Side;

use crate::bench::{Action, ScheduledFault, Trigger};
use crate::runs::experiment::Test;

pub fn case() -> FaultCase {
    FaultCase {
        name: "motor-disconnected",
        what: "right motor disconnected from 3 s into a 2 m line",
        expected: "stall watchdog: motors off within 500 ms of the wheel stopping, fault code set, no endless spinning",
        test: Test::Line,
        leg_mm: 2000.0,
        faults: vec![ScheduledFault::new(
            Trigger::Time { s: 3.0 },
            Action::MotorDisconnected {
                side: Side::Right,
                disconnected: true,
            },
        )],
        limit_s: 25.0,
        framed: false,
        check: Some(check),
    }
}

fn check(o: &Observed) -> Result<String, String> {
    stopped_with_code(o, 0.8)
}
