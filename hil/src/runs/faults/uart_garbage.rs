//! Noise on the Bluetooth link: a random byte arrives before every byte of
//! the host's framed start command.

use super::{FaultCase, Observed};
use crate::bench::inject::LinkFault;
use crate::bench::{Action, ScheduledFault, Trigger};
use crate::runs::experiment::Test;

pub fn case() -> FaultCase {
    FaultCase {
        name: "uart-garbage",
        what: "a random byte inserted before every byte of the framed start command (the thesis build reads the bytes as raw selectors)",
        expected: "garbage never starts a test: the interleaved frame is rejected with error replies; the robot stays still",
        test: Test::Line,
        leg_mm: 500.0,
        faults: vec![ScheduledFault::new(
            Trigger::Time { s: 0.0 },
            Action::Link {
                fault: LinkFault {
                    garbage: 1.0,
                    ..LinkFault::default()
                },
            },
        )],
        limit_s: 8.0,
        framed: true,
        check: Some(check),
    }
}

fn check(o: &Observed) -> Result<String, String> {
    if o.legs == 0 && o.turns == 0 && o.end_distance_cm < 1.0 && o.error_replies >= 1 {
        Ok(format!(
            "no test started, {} error reply(ies)",
            o.error_replies
        ))
    } else {
        Err(format!(
            "expected no test and an error reply; {} legs, {} turns, {:.0} cm, {} error replies",
            o.legs, o.turns, o.end_distance_cm, o.error_replies
        ))
    }
}
