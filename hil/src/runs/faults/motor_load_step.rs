//! The left wheel starts dragging (a cable caught in the axle, a rug): a load
//! torque of 15 % of the motor's stall torque from the middle of a leg.

use super::{leg_overrun, FaultCase, Observed};
use plant_model::Side;

use crate::bench::{Action, ScheduledFault, Trigger};
use crate::runs::experiment::Test;

/// A load of `torque_fraction` of the stall torque on the left wheel from
/// 3 s into the run (this fault and `motor-overload`).
pub(super) fn left_load_from_3_s(torque_fraction: f64) -> Vec<ScheduledFault> {
    vec![ScheduledFault::new(
        Trigger::Time { s: 3.0 },
        Action::Motor {
            side: Side::Left,
            fault: plant_model::MotorFault::LoadStep { torque_fraction },
        },
    )]
}

pub fn case() -> FaultCase {
    FaultCase {
        name: "motor-load-step",
        what: "left wheel loaded with 15 % of its stall torque from 3 s into a 2 m line",
        expected: "the PID raises the left duty and holds the set-point (the load is within the motor's reserve): the line completes with no fault code, its leg no more than 2 % longer than at the set-points",
        test: Test::Line,
        leg_mm: 2000.0,
        faults: left_load_from_3_s(0.15),
        limit_s: 30.0,
        framed: false,
        check: Some(check),
    }
}

// The robot's own effects change how far it rolls, not how long its wheels
// take to make their counts: the leg's time shows whether the set-point held.
fn check(o: &Observed) -> Result<String, String> {
    let code = o.fault_code.unwrap_or(0);
    match leg_overrun(o) {
        Some(over) if o.completed && code == 0 && over <= 0.02 => Ok(format!(
            "completed without a fault; the leg took {:+.1} % of its time at the set-points",
            over * 100.0
        )),
        over => Err(format!(
            "expected completion, no fault code and the leg within 2 % of its time at the set-points; completed {}, code {code}, overrun {over:?}",
            o.completed
        )),
    }
}
