//! The robot drives into an obstacle and wedges: both wheels blocked in the
//! middle of a leg. Nothing moves any more, whatever the bridge does.

use super::{stopped_with_code, FaultCase, Observed};
use plant_model::Side;

use crate::bench::{Action, ScheduledFault, Trigger};
use crate::runs::experiment::Test;

pub fn case() -> FaultCase {
    let stall = |side| {
        ScheduledFault::new(
            Trigger::Time { s: 3.0 },
            Action::Motor {
                side,
                fault: plant_model::MotorFault::Stall,
            },
        )
    };
    FaultCase {
        name: "robot-wedged",
        what: "both wheels blocked from 3 s into a 2 m line (the robot wedged against an obstacle)",
        expected: "stall watchdog: motors off within 300 ms with a fault code; the firmware goes idle and keeps answering (no hang)",
        test: Test::Line,
        leg_mm: 2000.0,
        faults: vec![stall(Side::Left), stall(Side::Right)],
        limit_s: 25.0,
        framed: false,
        check: Some(check),
    }
}

fn check(o: &Observed) -> Result<String, String> {
    if let Some(at) = &o.hang {
        return Err(format!("the firmware hung {at}"));
    }
    stopped_with_code(o, 0.3)
}
