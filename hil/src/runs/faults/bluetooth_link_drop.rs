//! The Bluetooth link drops in the middle of the host's start command (the
//! HC-05 loses its pairing for 2 s); the host retries once the link is back.

use super::{FaultCase, Observed};
use crate::bench::inject::LinkFault;
use crate::bench::{Action, ScheduledFault, Trigger};
use crate::firmware::link::{frame, Command, ProtoTest};
use crate::runs::experiment::Test;

pub fn case() -> FaultCase {
    let link = |down| Action::Link {
        fault: LinkFault {
            down,
            ..LinkFault::default()
        },
    };
    FaultCase {
        name: "bluetooth-link-drop",
        what: "the link goes down at the 3rd byte of the framed start command for 2 s; the host sends the command again at 3 s",
        expected: "the fragment never starts a test (dropped after the 50 ms inter-byte time-out with an error reply); the retry starts the line, which completes",
        test: Test::Line,
        leg_mm: 500.0,
        faults: vec![
            ScheduledFault {
                trigger: Trigger::HostByte { n: 3 },
                action: link(true),
                undo: Some((2.0, link(false))),
            },
            ScheduledFault::new(
                Trigger::Time { s: 3.0 },
                Action::HostSend {
                    bytes: frame(&Command::StartTest(ProtoTest::Line)),
                },
            ),
        ],
        limit_s: 20.0,
        framed: true,
        check: Some(check),
    }
}

fn check(o: &Observed) -> Result<String, String> {
    if o.completed && o.legs == 1 && o.error_replies >= 1 {
        Ok(format!(
            "the fragment was rejected ({} error reply(ies)); the retry ran the line",
            o.error_replies
        ))
    } else {
        Err(format!(
            "expected an error reply for the fragment and the retried line completed; completed {}, {} legs, {} error replies",
            o.completed, o.legs, o.error_replies
        ))
    }
}
