//! The left wheel starts dragging (a cable caught in the axle, a rug): a load
//! torque of 15 % of the motor's stall torque from the middle of a leg.

use super::{FaultCase, Observed};
use crate::bench::{Action, ScheduledFault, SideName, Trigger};
use crate::experiment::Test;

pub fn case() -> FaultCase {
    FaultCase {
        name: "motor-load-step",
        what: "left wheel loaded with 15 % of its stall torque from 3 s into a 2 m line",
        expected: "the PID raises the left duty and holds the set-point: the line completes with no fault code and the robot drives its 2 m within 2 %",
        test: Test::Line,
        leg_mm: 2000.0,
        faults: vec![ScheduledFault::new(
            Trigger::Time { s: 3.0 },
            Action::Motor {
                side: SideName::Left,
                fault: plant_model::MotorFault::LoadStep {
                    torque_fraction: 0.15,
                },
            },
        )],
        limit_s: 30.0,
        framed: false,
        check,
    }
}

fn check(o: &Observed) -> Result<String, String> {
    let arc = o.first_leg_arc_mm.unwrap_or(0.0);
    let code = o.fault_code.unwrap_or(0);
    if o.completed && code == 0 && (arc - 2000.0).abs() <= 40.0 {
        Ok(format!("completed without a fault; drove {arc:.0} mm"))
    } else {
        Err(format!(
            "expected completion, no fault code and 2000 mm within 2 %; completed {}, code {code}, {arc:.0} mm",
            o.completed
        ))
    }
}
