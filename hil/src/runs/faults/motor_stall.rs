//! The left wheel is blocked (caught on a cable, against an obstacle) in the
//! middle of a leg: the plant holds it still whatever the bridge does.

use super::{stopped_with_code, FaultCase, Observed};
use plant_model::Side;

use crate::bench::{Action, ScheduledFault, Trigger};
use crate::runs::experiment::Test;

pub fn case() -> FaultCase {
    FaultCase {
        name: "motor-stall",
        what: "left wheel blocked from 3 s into a 2 m line",
        expected: "stall watchdog: motors off within 300 ms with a fault code; the counts stop (no phantom counts)",
        test: Test::Line,
        leg_mm: 2000.0,
        faults: vec![ScheduledFault::new(
            Trigger::Time { s: 3.0 },
            Action::Motor {
                side: Side::Left,
                fault: plant_model::MotorFault::Stall,
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
