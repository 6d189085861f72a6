//! Every byte on the Bluetooth link has one bit flipped: the framed start
//! command arrives damaged.

use super::{FaultCase, Observed};
use crate::bench::{Action, ScheduledFault, Trigger};
use crate::experiment::Test;
use crate::inject::LinkFault;

pub fn case() -> FaultCase {
    FaultCase {
        name: "link-corruption",
        what: "every byte from the host arrives with one bit flipped; the start is a framed command (the thesis build reads its bytes as raw selectors)",
        expected: "the CRC rejects the corrupted frame: no test starts, the robot stays still",
        test: Test::Line,
        leg_mm: 500.0,
        faults: vec![ScheduledFault::new(
            Trigger::Time { s: 0.0 },
            Action::Link {
                fault: LinkFault {
                    corrupt: 1.0,
                    ..LinkFault::default()
                },
            },
        )],
        limit_s: 8.0,
        framed: true,
        check,
    }
}

fn check(o: &Observed) -> Result<String, String> {
    if o.legs == 0 && o.turns == 0 && o.end_distance_cm < 1.0 {
        Ok("no test started; the robot stayed still".into())
    } else {
        Err(format!(
            "the corrupted byte started something: {} legs, {} turns, {:.0} cm",
            o.legs, o.turns, o.end_distance_cm
        ))
    }
}
