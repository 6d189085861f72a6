//! The left encoder's A and B are swapped (a wiring mistake after a repair):
//! the count runs backwards while the wheel turns forwards.

use super::{FaultCase, Observed};
use plant_model::Side;

use crate::bench::inject::EncoderFault;
use crate::bench::{Action, ScheduledFault, Trigger};
use crate::runs::experiment::Test;

pub fn case() -> FaultCase {
    FaultCase {
        name: "encoder-swapped",
        what: "left encoder A and B swapped from the start of a 1 m line",
        expected: "the count runs against the drive: motors off within 300 ms with a fault code, no runaway",
        test: Test::Line,
        leg_mm: 1000.0,
        faults: vec![ScheduledFault::new(
            Trigger::Time { s: 0.0 },
            Action::Encoder {
                side: Side::Left,
                fault: EncoderFault::Swapped,
            },
        )],
        limit_s: 25.0,
        framed: false,
        check: Some(check),
    }
}

fn check(o: &Observed) -> Result<String, String> {
    match (o.fault_code, o.end_distance_cm) {
        (Some(c), d) if c != 0 && d < 50.0 => {
            Ok(format!("fault code {c}, stopped {d:.0} cm from the start"))
        }
        (c, d) => Err(format!(
            "expected a fault code and a stop within 50 cm; saw code {c:?}, {d:.0} cm"
        )),
    }
}
