//! One bit of the host's framed start command is flipped on the Bluetooth
//! link (in its CRC byte, so a firmware that skipped the check would run the
//! command); a clean frame follows.

use super::{FaultCase, Observed};
use crate::bench::inject::LinkFault;
use crate::bench::{Action, ScheduledFault, Trigger};
use crate::firmware::link::{frame, Command};
use crate::runs::experiment::Test;

/// The start command's frame is `START, LEN, 0x10, test, CRC`: its 5th byte.
const CRC_BYTE: u32 = 5;
/// Robot time the host sends a clean PING, long after the damaged frame.
const PING_AT_S: f64 = 1.0;
/// Bytes of the two replies: the frame error `[0xFF, status]` and the PING's
/// `[0x81, Ok, VERSION]`, each framed (3 bytes more).
const REPLY_BYTES: usize = (2 + 3) + (3 + 3);

pub fn case() -> FaultCase {
    let link = |corrupt| Action::Link {
        fault: LinkFault {
            corrupt,
            ..LinkFault::default()
        },
    };
    FaultCase {
        name: "link-corruption",
        what: "one bit of the framed start command's CRC byte flipped on the link, then a clean PING a second later (the thesis build reads the bytes as raw selectors)",
        expected: "the CRC rejects the corrupted frame with an error reply: no test starts, the robot stays still; the clean PING after it is answered",
        test: Test::Line,
        leg_mm: 500.0,
        // Healthy again half a byte time later, before any other byte.
        faults: vec![
            ScheduledFault {
                trigger: Trigger::HostByte { n: CRC_BYTE },
                action: link(1.0),
                undo: Some((0.5e-3, link(0.0))),
            },
            ScheduledFault::new(
                Trigger::Time { s: PING_AT_S },
                Action::HostSend {
                    bytes: frame(&Command::Ping),
                },
            ),
        ],
        limit_s: 8.0,
        framed: true,
        check: Some(check),
    }
}

/// Evidence from the firmware's replies on the link: exactly two, the first
/// an error with no data (the frame error; an UNKNOWN_COMMAND would carry the
/// id, an accepted start would be Ok and drive), the second the PING's Ok.
/// A firmware deaf to the link sends nothing and fails; one that skips the
/// CRC starts the line and fails.
fn check(o: &Observed) -> Result<String, String> {
    let still = o.legs == 0 && o.turns == 0 && o.end_distance_cm < 1.0;
    let replies = o.replies == 2 && o.error_replies == 1 && o.bluetooth_reply_bytes == REPLY_BYTES;
    if still && replies {
        Ok(
            "the damaged frame got an error reply and started nothing; the clean PING was answered"
                .into(),
        )
    } else {
        Err(format!(
            "expected no test, one error reply and the PING's reply ({REPLY_BYTES} bytes); {} legs, {} turns, {:.0} cm, {} replies ({} errors, {} bytes)",
            o.legs, o.turns, o.end_distance_cm, o.replies, o.error_replies, o.bluetooth_reply_bytes
        ))
    }
}
