//! The left encoder loses two counts in every ten edges (pulses too short for
//! the MCU at a high edge rate): odometry under-counts one wheel.

use super::{FaultCase, Observed};
use plant_model::Side;

use crate::bench::inject::EncoderFault;
use crate::bench::{Action, ScheduledFault, Trigger};
use crate::runs::experiment::Test;

pub fn case() -> FaultCase {
    FaultCase {
        name: "missed-counts",
        what: "left encoder loses every 10th edge and the next, for a whole 1 m line",
        expected: "undetectable by the firmware: the line completes, but the robot drives more than 5 % further than its odometry says",
        test: Test::Line,
        leg_mm: 1000.0,
        faults: vec![ScheduledFault::new(
            Trigger::Time { s: 0.0 },
            Action::Encoder {
                side: Side::Left,
                fault: EncoderFault::MissPairs { every: 10 },
            },
        )],
        limit_s: 30.0,
        framed: false,
        check: Some(check),
    }
}

fn check(o: &Observed) -> Result<String, String> {
    let plant = o.first_leg_arc_mm.unwrap_or(0.0);
    if o.completed && plant > 1000.0 * 1.05 {
        Ok(format!("completed; drove {plant:.0} mm for a 1000 mm line"))
    } else {
        Err(format!(
            "expected completion with more than 1050 mm driven; completed {}, {plant:.0} mm",
            o.completed
        ))
    }
}
