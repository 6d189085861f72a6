//! The third byte of the host's framed start command is lost on the
//! Bluetooth link (a dropped HC-05 packet).

use super::{FaultCase, Observed};
use crate::bench::inject::LinkFault;
use crate::bench::{Action, ScheduledFault, Trigger};
use crate::runs::experiment::Test;

pub fn case() -> FaultCase {
    let link = |loss| Action::Link {
        fault: LinkFault {
            loss,
            ..LinkFault::default()
        },
    };
    FaultCase {
        name: "uart-byte-loss",
        what: "the 3rd byte of the framed start command is lost (the thesis build reads the bytes as raw selectors)",
        expected: "the damaged frame never starts a test: the parser drops it (CRC or inter-byte time-out) with an error reply; the robot stays still",
        test: Test::Line,
        leg_mm: 500.0,
        // Healthy again half a byte time later, before the next byte.
        faults: vec![ScheduledFault {
            trigger: Trigger::HostByte { n: 3 },
            action: link(1.0),
            undo: Some((0.5e-3, link(0.0))),
        }],
        limit_s: 8.0,
        framed: true,
        check: Some(check),
    }
}

fn check(o: &Observed) -> Result<String, String> {
    if o.legs == 0 && o.end_distance_cm < 1.0 && o.error_replies >= 1 {
        Ok(format!(
            "no test started, {} error reply(ies)",
            o.error_replies
        ))
    } else {
        Err(format!(
            "expected no test and an error reply; {} legs, {:.0} cm, {} error replies",
            o.legs, o.end_distance_cm, o.error_replies
        ))
    }
}
