//! The left wheel drags harder than the motor can pull at the set-point
//! (30 % of its stall torque: the set-point would need more than full duty).

use super::{leg_overrun, FaultCase, Observed};
use crate::runs::experiment::Test;

pub fn case() -> FaultCase {
    FaultCase {
        name: "motor-overload",
        what: "left wheel loaded with 30 % of its stall torque from 3 s into a 2 m line (beyond the motor's reserve)",
        // A gap of the robust build, written down so that it shows: only a
        // wheel that stops is a fault; one that runs slow at full duty is not.
        expected: "the left duty saturates and the wheel runs slow, so the leg curves and takes over 10 % longer; the robust build has no saturation check: the line completes without a fault code",
        test: Test::Line,
        leg_mm: 2000.0,
        faults: super::motor_load_step::left_load_from_3_s(0.3),
        limit_s: 30.0,
        framed: false,
        check: Some(check),
    }
}

fn check(o: &Observed) -> Result<String, String> {
    let code = o.fault_code.unwrap_or(0);
    match leg_overrun(o) {
        Some(over) if o.completed && code == 0 && over > 0.10 => Ok(format!(
            "completed without a fault, the leg {:+.0} % longer, heading {:+.0} deg",
            over * 100.0,
            o.first_leg_heading_deg.unwrap_or(0.0)
        )),
        over => Err(format!(
            "expected a slow, completed leg without a fault code; completed {}, code {code}, overrun {over:?}",
            o.completed
        )),
    }
}
