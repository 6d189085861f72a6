//! The host's side of the firmware's framed protocol (crate
//! `henrytwo-protocol`, the same code the firmware runs): commands to frames,
//! the firmware's bytes back to replies and notifications.

use henrytwo_protocol::frame::{encode_frame, Event, Parser, MAX_FRAME, MAX_PAYLOAD};
pub use henrytwo_protocol::message::{Command, CommandId, Test as ProtoTest};
use henrytwo_protocol::message::{
    Reply, Status, FRAME_ERROR_ID, NOTIFY_FAULT, NOTIFY_TEST_DONE, REPLY_FLAG,
};
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

/// The id of a frame the firmware sends (`protocol/README.md`): the reply
/// to a command, a notice, or the reply to a frame it could not read. Its
/// byte is [`FrameId::byte`]; any byte is one ([`FrameId::Other`] for ids
/// the protocol does not define), so `FrameId::from(0x81)` still reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FrameId {
    /// The reply to this command (its id with [`REPLY_FLAG`]).
    Reply(CommandId),
    /// `NOTIFY_TEST_DONE`: a test ended.
    TestDone,
    /// `NOTIFY_FAULT`: the firmware stopped on a fault.
    Fault,
    /// The reply to a frame whose command the firmware could not tell.
    FrameError,
    /// An id the protocol does not define.
    Other(u8),
}

impl FrameId {
    /// The id byte on the wire.
    pub const fn byte(self) -> u8 {
        match self {
            FrameId::Reply(c) => c.reply_id(),
            FrameId::TestDone => NOTIFY_TEST_DONE,
            FrameId::Fault => NOTIFY_FAULT,
            FrameId::FrameError => FRAME_ERROR_ID,
            FrameId::Other(b) => b,
        }
    }

    /// The id `b` means.
    pub const fn from_byte(b: u8) -> FrameId {
        match b {
            NOTIFY_TEST_DONE => FrameId::TestDone,
            NOTIFY_FAULT => FrameId::Fault,
            FRAME_ERROR_ID => FrameId::FrameError,
            _ if b & REPLY_FLAG != 0 => match CommandId::from_u8(b & !REPLY_FLAG) {
                Some(c) => FrameId::Reply(c),
                None => FrameId::Other(b),
            },
            _ => FrameId::Other(b),
        }
    }
}

impl From<u8> for FrameId {
    fn from(b: u8) -> Self {
        FrameId::from_byte(b)
    }
}

/// A command's id stands for the reply to it.
impl From<CommandId> for FrameId {
    fn from(c: CommandId) -> Self {
        FrameId::Reply(c)
    }
}

impl std::fmt::Display for FrameId {
    /// `reply to Ping (0x81)`, `TEST_DONE (0xc0)`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let b = self.byte();
        match self {
            FrameId::Reply(c) => write!(f, "reply to {c:?} (0x{b:02x})"),
            FrameId::TestDone => write!(f, "TEST_DONE (0x{b:02x})"),
            FrameId::Fault => write!(f, "FAULT (0x{b:02x})"),
            FrameId::FrameError => write!(f, "frame error (0x{b:02x})"),
            FrameId::Other(_) => write!(f, "0x{b:02x}"),
        }
    }
}

/// A reply or notification the firmware sent, owned.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct Received {
    pub id: u8,
    pub status: String,
    pub ok: bool,
    pub data: Vec<u8>,
}

impl Received {
    /// What its id means.
    pub fn frame_id(&self) -> FrameId {
        FrameId::from_byte(self.id)
    }
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

    /// Every byte is one frame id and back; the protocol's ids by name.
    #[test]
    fn frame_ids_name_every_byte_and_round_trip() {
        use henrytwo_protocol::message::{FRAME_ERROR_ID, NOTIFY_FAULT, NOTIFY_TEST_DONE};
        for b in 0..=255u8 {
            assert_eq!(FrameId::from_byte(b).byte(), b, "{b:#04x}");
        }
        assert_eq!(FrameId::from(0x81), FrameId::Reply(CommandId::Ping));
        assert_eq!(FrameId::from(0xB1), FrameId::Reply(CommandId::GetParam));
        assert_eq!(FrameId::from(NOTIFY_TEST_DONE), FrameId::TestDone);
        assert_eq!(FrameId::from(NOTIFY_FAULT), FrameId::Fault);
        assert_eq!(FrameId::from(FRAME_ERROR_ID), FrameId::FrameError);
        // A command id without the reply flag, and a reply to no command.
        assert_eq!(FrameId::from(0x01), FrameId::Other(0x01));
        assert_eq!(FrameId::from(0x82), FrameId::Other(0x82));
        assert_eq!(FrameId::from(CommandId::Stop).byte(), 0x91);
        assert_eq!(FrameId::TestDone.to_string(), "TEST_DONE (0xc0)");
        let reply = replies(&frame(&Command::Ping)); // a command frame read as a reply
        assert!(reply.iter().all(|r| r.frame_id() == FrameId::Other(0x01)));
    }
}
