//! The host's side of the firmware's framed protocol (crate
//! `henrytwo-protocol`, the same code the firmware runs): commands to frames,
//! the firmware's bytes back to replies and notifications.

use henrytwo_protocol::frame::{encode_frame, Event, Parser, MAX_FRAME, MAX_PAYLOAD};
pub use henrytwo_protocol::message::{Command, Test as ProtoTest};
use henrytwo_protocol::message::{Reply, Status};
pub use henrytwo_protocol::param::Param;

/// The frame carrying `cmd`.
pub fn frame(cmd: &Command) -> Vec<u8> {
    let mut payload = [0u8; MAX_PAYLOAD];
    let n = cmd
        .encode(&mut payload)
        .expect("every command fits a frame");
    let mut out = [0u8; MAX_FRAME];
    let len = encode_frame(&payload[..n], &mut out).expect("a command payload is 1..=32 bytes");
    out[..len].to_vec()
}

/// A reply or notification the firmware sent, owned.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct Received {
    pub id: u8,
    pub status: String,
    pub ok: bool,
    pub data: Vec<u8>,
}

/// Every frame in `bytes` (the firmware's output on the Bluetooth UART),
/// decoded; bytes outside frames are skipped.
pub fn replies(bytes: &[u8]) -> Vec<Received> {
    // Bytes are taken as one burst: no timeout applies between them.
    let mut parser = Parser::new(u32::MAX);
    let mut out = Vec::new();
    for &b in bytes {
        if let Some(Event::Frame(payload)) = parser.push(b, 0) {
            if let Some(r) = Reply::decode(payload) {
                out.push(Received {
                    id: r.id,
                    status: format!("{:?}", r.status),
                    ok: r.status == Status::Ok,
                    data: r.data.to_vec(),
                });
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use henrytwo_protocol::message::Test;

    #[test]
    fn a_start_frame_round_trips_through_the_firmware_parser() {
        let bytes = frame(&Command::StartTest(ProtoTest::Line));
        let mut p = Parser::new(50);
        let mut got = None;
        for b in &bytes {
            if let Some(Event::Frame(payload)) = p.push(*b, 0) {
                got = Some(Command::decode(payload).unwrap());
            }
        }
        assert_eq!(got, Some(Command::StartTest(ProtoTest::Line)));
    }

    /// Scenario files, plans and JSON outputs write a test by the name the
    /// command line takes: the protocol's serde names must stay those.
    #[test]
    fn a_test_is_written_and_parsed_by_its_name() {
        let names = ["umbmark-cw", "umbmark-ccw", "line", "triangle"];
        for (test, name) in Test::ALL.into_iter().zip(names) {
            assert_eq!(test.name(), name);
            assert_eq!(serde_json::to_string(&test).unwrap(), format!("\"{name}\""));
            assert_eq!(
                serde_json::from_str::<Test>(&format!("\"{name}\"")).unwrap(),
                test
            );
            assert_eq!(name.parse::<Test>(), Ok(test));
            assert_eq!(Test::from_u8(test.command_byte()), Some(test));
        }
        assert!("umbmark_cw".parse::<Test>().is_err());
    }
}
