//! Commands: their ids and argument lengths, decoded from a payload (with the status to
//! reply with when they cannot be) and encoded into one.

use super::bytes::{f32_at, put};
use super::{Status, Test, FRAME_ERROR_ID, REPLY_FLAG};
use crate::param::Param;

/// Command ids (first payload byte of a command).
#[derive(Clone, Copy, PartialEq, Eq, Debug, Hash)]
#[repr(u8)]
pub enum CommandId {
    /// No arguments; reply data `[VERSION]`.
    Ping = 0x01,
    /// `[test]`: start a test; reply without data.
    StartTest = 0x10,
    /// No arguments: abort the running test (motors off, idle); reply
    /// without data, also when idle.
    Stop = 0x11,
    /// No arguments; reply data: [`StateReport`](super::StateReport).
    GetState = 0x20,
    /// No arguments; reply data: [`Telemetry`](super::Telemetry).
    GetTelemetry = 0x21,
    /// `[param, value f32]`; reply data `[param, value f32]` as stored.
    SetParam = 0x30,
    /// `[param]`; reply data `[param, value f32]`.
    GetParam = 0x31,
}

impl CommandId {
    /// The command with id `b`.
    pub const fn from_u8(b: u8) -> Option<CommandId> {
        Some(match b {
            0x01 => CommandId::Ping,
            0x10 => CommandId::StartTest,
            0x11 => CommandId::Stop,
            0x20 => CommandId::GetState,
            0x21 => CommandId::GetTelemetry,
            0x30 => CommandId::SetParam,
            0x31 => CommandId::GetParam,
            _ => return None,
        })
    }

    /// Number of argument bytes after the id.
    pub const fn arg_len(self) -> usize {
        match self {
            CommandId::Ping | CommandId::Stop | CommandId::GetState | CommandId::GetTelemetry => 0,
            CommandId::StartTest | CommandId::GetParam => 1,
            CommandId::SetParam => 5,
        }
    }

    /// Id of the reply to this command.
    pub const fn reply_id(self) -> u8 {
        self as u8 | REPLY_FLAG
    }
}

/// A decoded command.
#[derive(Clone, Copy, PartialEq, Debug)]
pub enum Command {
    /// Ask for the protocol version.
    Ping,
    /// Start a test.
    StartTest(Test),
    /// Abort the running test.
    Stop,
    /// Read the state.
    GetState,
    /// Read the telemetry.
    GetTelemetry,
    /// Set a parameter; the value is already checked against its range.
    SetParam(Param, f32),
    /// Read a parameter.
    GetParam(Param),
}
impl Command {
    /// The command id.
    pub const fn id(&self) -> CommandId {
        match self {
            Command::Ping => CommandId::Ping,
            Command::StartTest(_) => CommandId::StartTest,
            Command::Stop => CommandId::Stop,
            Command::GetState => CommandId::GetState,
            Command::GetTelemetry => CommandId::GetTelemetry,
            Command::SetParam(..) => CommandId::SetParam,
            Command::GetParam(_) => CommandId::GetParam,
        }
    }

    /// Decodes a command payload. The error is the status to reply with
    /// (under [`Command::reply_id_for`]): unknown id, wrong length, unknown
    /// parameter, or a test id or parameter value out of range.
    pub fn decode(payload: &[u8]) -> Result<Command, Status> {
        let (&id, args) = payload.split_first().ok_or(Status::BadLength)?;
        let id = CommandId::from_u8(id).ok_or(Status::UnknownCommand)?;
        if args.len() != id.arg_len() {
            return Err(Status::BadLength);
        }
        let param = || {
            args.first()
                .and_then(|&p| Param::from_u8(p))
                .ok_or(Status::UnknownParam)
        };
        Ok(match id {
            CommandId::Ping => Command::Ping,
            CommandId::Stop => Command::Stop,
            CommandId::GetState => Command::GetState,
            CommandId::GetTelemetry => Command::GetTelemetry,
            CommandId::StartTest => {
                let t = args
                    .first()
                    .and_then(|&t| Test::from_u8(t))
                    .ok_or(Status::OutOfRange)?;
                Command::StartTest(t)
            }
            CommandId::GetParam => Command::GetParam(param()?),
            CommandId::SetParam => {
                let p = param()?;
                let v = f32_at(args, 1).ok_or(Status::BadLength)?;
                Command::SetParam(p, p.check(v)?)
            }
        })
    }

    /// Reply id for a received payload: the command's reply id when the
    /// first byte is a known command, else [`FRAME_ERROR_ID`].
    pub fn reply_id_for(payload: &[u8]) -> u8 {
        match payload.first().and_then(|&b| CommandId::from_u8(b)) {
            Some(id) => id.reply_id(),
            None => FRAME_ERROR_ID,
        }
    }

    /// Writes the command's payload to `out`; returns its length.
    pub fn encode(&self, out: &mut [u8]) -> Option<usize> {
        put(out, 0, &[self.id() as u8])?;
        match *self {
            Command::Ping | Command::Stop | Command::GetState | Command::GetTelemetry => Some(1),
            Command::StartTest(t) => put(out, 1, &[t as u8]).map(|_| 2),
            Command::GetParam(p) => put(out, 1, &[p as u8]).map(|_| 2),
            Command::SetParam(p, v) => {
                put(out, 1, &[p as u8])?;
                put(out, 2, &v.to_le_bytes()).map(|_| 6)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::{encode_frame, MAX_FRAME};
    use crate::message::NOTIFY_TEST_DONE;

    fn round_trip(c: Command) -> Result<Command, Status> {
        let mut buf = [0u8; 32];
        let n = c.encode(&mut buf).unwrap();
        Command::decode(&buf[..n])
    }

    #[test]
    fn every_command_round_trips() {
        let cmds = [
            Command::Ping,
            Command::StartTest(Test::UmbmarkCw),
            Command::StartTest(Test::UmbmarkCcw),
            Command::StartTest(Test::Line),
            Command::StartTest(Test::Triangle),
            Command::Stop,
            Command::GetState,
            Command::GetTelemetry,
            Command::SetParam(Param::CorrLeft, 1.0013),
            Command::SetParam(Param::StallTimeoutMs, 300.0),
            Command::GetParam(Param::KdRight),
        ];
        for c in cmds {
            assert_eq!(round_trip(c), Ok(c));
        }
    }

    #[test]
    fn documented_bytes() {
        let mut buf = [0u8; 32];
        // SET_PARAM leg length 2000.0 mm: 2000.0f32 = 0x44FA0000.
        let n = Command::SetParam(Param::LegLengthMm, 2000.0)
            .encode(&mut buf)
            .unwrap();
        assert_eq!(&buf[..n], &[0x30, 0x04, 0x00, 0x00, 0xFA, 0x44]);
        let mut frame = [0u8; MAX_FRAME];
        let m = encode_frame(&buf[..n], &mut frame).unwrap();
        assert_eq!(
            &frame[..m],
            &[0xA5, 0x06, 0x30, 0x04, 0x00, 0x00, 0xFA, 0x44, 0xAB]
        );
        // START_TEST UMBmark CW.
        let n = Command::StartTest(Test::UmbmarkCw)
            .encode(&mut buf)
            .unwrap();
        let m = encode_frame(&buf[..n], &mut frame).unwrap();
        assert_eq!(&frame[..m], &[0xA5, 0x02, 0x10, 0x02, 0x8F]);
    }

    #[test]
    fn decode_errors() {
        assert_eq!(Command::decode(&[]), Err(Status::BadLength));
        assert_eq!(Command::decode(&[0x7E]), Err(Status::UnknownCommand));
        assert_eq!(Command::decode(&[0x20, 0x00]), Err(Status::BadLength));
        assert_eq!(Command::decode(&[0x10]), Err(Status::BadLength));
        assert_eq!(Command::decode(&[0x10, 6]), Err(Status::OutOfRange));
        assert_eq!(Command::decode(&[0x10, 1]), Err(Status::OutOfRange));
        assert_eq!(Command::decode(&[0x31, 0]), Err(Status::UnknownParam));
        assert_eq!(Command::decode(&[0x31, 32]), Err(Status::UnknownParam));
        let mut set = [0x30, 1, 0, 0, 0, 0];
        set[2..].copy_from_slice(&2.0f32.to_le_bytes());
        assert_eq!(Command::decode(&set), Err(Status::OutOfRange));
        set[2..].copy_from_slice(&f32::NAN.to_le_bytes());
        assert_eq!(Command::decode(&set), Err(Status::OutOfRange));
        assert_eq!(Command::decode(&set[..5]), Err(Status::BadLength));
    }

    #[test]
    fn reply_ids() {
        assert_eq!(Command::reply_id_for(&[0x20]), 0xA0);
        assert_eq!(Command::reply_id_for(&[0x30, 1]), 0xB0);
        assert_eq!(Command::reply_id_for(&[0x7E]), FRAME_ERROR_ID);
        assert_eq!(Command::reply_id_for(&[]), FRAME_ERROR_ID);
        // Replies never collide with notifications or the frame-error id.
        for b in 0..=255u8 {
            if let Some(id) = CommandId::from_u8(b) {
                let r = id.reply_id();
                assert!(r < NOTIFY_TEST_DONE && r != FRAME_ERROR_ID, "{id:?}");
                assert_eq!(b & REPLY_FLAG, 0);
            }
        }
    }
}
