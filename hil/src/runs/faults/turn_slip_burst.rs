//! The wheels slip on a polished patch during the third turn of a UMBmark:
//! the encoders count the full turn, the ground sees less of it.

use super::{FaultCase, Observed};
use plant_model::Side;

use crate::bench::{Action, ScheduledFault, Trigger};
use crate::runs::experiment::Test;

pub fn case() -> FaultCase {
    let slip = |side, slip| Action::SlipBurst { side, slip };
    let mut faults = Vec::new();
    for side in [Side::Left, Side::Right] {
        faults.push(ScheduledFault {
            trigger: Trigger::TurnStart { n: 3 },
            action: slip(side, 0.3),
            undo: Some((1.5, slip(side, 0.0))),
        });
    }
    FaultCase {
        name: "turn-slip-burst",
        what: "both wheels slip 30 % during the third turn of a UMBmark CW (600 mm legs)",
        expected: "undetectable by encoders: the test completes and every turn ends at its count; the robot ends off its start",
        test: Test::UmbmarkCw,
        leg_mm: 600.0,
        faults,
        limit_s: 80.0,
        framed: false,
        check: Some(check),
    }
}

fn check(o: &Observed) -> Result<String, String> {
    if o.completed && o.turns == 4 && o.legs == 4 {
        Ok(format!(
            "completed all 4 legs and 4 turns; ended {:.0} cm from the start",
            o.end_distance_cm
        ))
    } else {
        Err(format!(
            "expected a complete UMBmark; completed {}, {} legs, {} turns",
            o.completed, o.legs, o.turns
        ))
    }
}
