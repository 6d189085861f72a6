//! Messages: commands (host to firmware), replies and notifications
//! (firmware to host).
//!
//! - Command payload: `[id, args...]`, `id` in 0x01..=0x3F.
//! - Reply payload: `[id | 0x80, status, data...]`. A frame the firmware
//!   could not attribute to a known command (bad CRC, bad length, truncated,
//!   unknown command id) is answered with id [`FRAME_ERROR_ID`] (0xFF).
//! - Notification payload: `[id, status, data...]` with `id` >= 0xC0 and
//!   status [`Status::Ok`]; the firmware sends them unasked.

use crate::param::Param;
pub use crate::status::Status;
pub use crate::test_kind::{Test, UnknownTest};

/// Protocol version reported by [`Command::Ping`].
pub const VERSION: u8 = 1;
/// Bit set in a reply's id (the command id it answers, plus this bit).
pub const REPLY_FLAG: u8 = 0x80;
/// Reply id for frames that cannot be attributed to a known command.
pub const FRAME_ERROR_ID: u8 = 0xFF;
/// Notification: a test ran to its end.
pub const NOTIFY_TEST_DONE: u8 = 0xC0;
/// Notification: a fault stopped the motors.
pub const NOTIFY_FAULT: u8 = 0xC1;

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
    /// No arguments; reply data: [`StateReport`].
    GetState = 0x20,
    /// No arguments; reply data: [`Telemetry`].
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

fn f32_at(b: &[u8], at: usize) -> Option<f32> {
    let bytes: [u8; 4] = b.get(at..at + 4)?.try_into().ok()?;
    Some(f32::from_le_bytes(bytes))
}

fn u32_at(b: &[u8], at: usize) -> Option<u32> {
    let bytes: [u8; 4] = b.get(at..at + 4)?.try_into().ok()?;
    Some(u32::from_le_bytes(bytes))
}

fn u16_at(b: &[u8], at: usize) -> Option<u16> {
    let bytes: [u8; 2] = b.get(at..at + 2)?.try_into().ok()?;
    Some(u16::from_le_bytes(bytes))
}

/// Copies `src` to the start of `out`; `None` if it does not fit.
fn put(out: &mut [u8], at: usize, src: &[u8]) -> Option<()> {
    out.get_mut(at..at + src.len())?.copy_from_slice(src);
    Some(())
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

/// A reply or notification payload, split.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Reply<'a> {
    /// Reply id (command id | 0x80), [`FRAME_ERROR_ID`] or a notification id.
    pub id: u8,
    /// Result code.
    pub status: Status,
    /// The data after the status byte.
    pub data: &'a [u8],
}

impl<'a> Reply<'a> {
    /// Splits a firmware payload; `None` if shorter than 2 bytes or the
    /// status code is unknown.
    pub fn decode(payload: &'a [u8]) -> Option<Reply<'a>> {
        let (&id, rest) = payload.split_first()?;
        let (&status, data) = rest.split_first()?;
        Some(Reply {
            id,
            status: Status::from_u8(status)?,
            data,
        })
    }

    /// Writes `[id, status, data...]` to `out`; returns its length.
    pub fn encode(&self, out: &mut [u8]) -> Option<usize> {
        put(out, 0, &[self.id, self.status as u8])?;
        put(out, 2, self.data)?;
        Some(2 + self.data.len())
    }
}

/// `HT_STATE` / the state byte of [`StateReport`].
#[derive(Clone, Copy, PartialEq, Eq, Debug, Hash)]
#[repr(u8)]
pub enum RunState {
    /// Reset until initialised.
    Booting = 0,
    /// Ready for a command.
    Idle = 1,
    /// Driving a leg or a turn.
    Driving = 2,
    /// Braking and waiting between segments.
    Braking = 3,
}

impl RunState {
    /// The state with wire value `b`, or None for a value no firmware sends.
    pub const fn from_u8(b: u8) -> Option<RunState> {
        Some(match b {
            0 => RunState::Booting,
            1 => RunState::Idle,
            2 => RunState::Driving,
            3 => RunState::Braking,
            _ => return None,
        })
    }
}

/// `HT_PHASE` / the phase byte of [`StateReport`].
#[derive(Clone, Copy, PartialEq, Eq, Debug, Hash)]
#[repr(u8)]
pub enum Phase {
    /// No test running.
    Idle = 0,
    /// Driving a straight leg.
    Leg = 1,
    /// Spinning in place.
    Turn = 2,
    /// Braking pulses and waits after a segment.
    Braking = 3,
    /// Stopped by a fault (see [`Fault`]); idle otherwise.
    Fault = 4,
}

impl Phase {
    /// The phase with wire value `b`, or None for a value no firmware sends.
    pub const fn from_u8(b: u8) -> Option<Phase> {
        Some(match b {
            0 => Phase::Idle,
            1 => Phase::Leg,
            2 => Phase::Turn,
            3 => Phase::Braking,
            4 => Phase::Fault,
            _ => return None,
        })
    }
}

/// `HT_FAULT` / the fault byte of [`StateReport`] and [`FaultNotice`].
#[derive(Clone, Copy, PartialEq, Eq, Debug, Hash)]
#[repr(u8)]
pub enum Fault {
    /// No fault since the last test start.
    None = 0,
    /// Left wheel driven at or above the stall duty without advancing 3
    /// counts in the commanded direction within the stall timeout (its count
    /// nearly still).
    StallLeft = 1,
    /// Right wheel, likewise.
    StallRight = 2,
    /// A leg or turn took more than 4 times its nominal time plus 2 s.
    SegmentTimeout = 3,
    /// The left wheel moved more than 64 counts against its commanded
    /// direction during a segment.
    WrongWayLeft = 4,
    /// The right wheel, likewise.
    WrongWayRight = 5,
    /// The last reset was a watchdog reset (reported at boot).
    WatchdogReset = 6,
    /// A wheel (either; the notice's counts show which one stopped
    /// advancing) driven at or above the stall duty whose count moved back
    /// and forth (3 or more counts, tick by tick) without advancing 3 counts
    /// in the commanded direction within the stall timeout: edges arrive but
    /// do not add up, e.g. encoder channel B stuck.
    EncoderInconsistent = 7,
}

impl Fault {
    /// The fault with code `b`.
    pub const fn from_u8(b: u8) -> Option<Fault> {
        Some(match b {
            0 => Fault::None,
            1 => Fault::StallLeft,
            2 => Fault::StallRight,
            3 => Fault::SegmentTimeout,
            4 => Fault::WrongWayLeft,
            5 => Fault::WrongWayRight,
            6 => Fault::WatchdogReset,
            7 => Fault::EncoderInconsistent,
            _ => return None,
        })
    }
}

/// Data of the [`CommandId::GetState`] reply (7 bytes).
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct StateReport {
    /// [`RunState`] code.
    pub state: u8,
    /// [`Phase`] code.
    pub phase: u8,
    /// Running or last test (2..=5), 0 before the first.
    pub test: u8,
    /// Index of the current segment (legs and turns numbered together from 0).
    pub segment: u8,
    /// [`Fault`] code.
    pub fault: u8,
    /// Tests completed since reset.
    pub tests_done: u16,
}

impl StateReport {
    /// Encoded length.
    pub const LEN: usize = 7;

    /// The encoded bytes.
    pub fn to_bytes(&self) -> [u8; Self::LEN] {
        let d = self.tests_done.to_le_bytes();
        [
            self.state,
            self.phase,
            self.test,
            self.segment,
            self.fault,
            d[0],
            d[1],
        ]
    }

    /// Decodes reply data; `None` if the length is wrong.
    pub fn decode(b: &[u8]) -> Option<Self> {
        if b.len() != Self::LEN {
            return None;
        }
        Some(StateReport {
            state: b[0],
            phase: b[1],
            test: b[2],
            segment: b[3],
            fault: b[4],
            tests_done: u16_at(b, 5)?,
        })
    }
}

/// Data of the [`CommandId::GetTelemetry`] reply (24 bytes).
#[derive(Clone, Copy, PartialEq, Debug, Default)]
pub struct Telemetry {
    /// Left encoder count since reset (`HT_LEFT_COUNT`).
    pub left_count: i32,
    /// Right encoder count since reset.
    pub right_count: i32,
    /// Last measured left speed, thesis "RPM".
    pub speed_left: f32,
    /// Last measured right speed, thesis "RPM".
    pub speed_right: f32,
    /// Last left duty, 0..=255.
    pub duty_left: u8,
    /// Last right duty, 0..=255.
    pub duty_right: u8,
    /// Control ticks (15 ms) since reset.
    pub ticks: u32,
    /// Last battery reading, ADC counts 0..=1023.
    pub battery_adc: u16,
}

impl Telemetry {
    /// Encoded length.
    pub const LEN: usize = 24;

    /// The encoded bytes.
    pub fn to_bytes(&self) -> [u8; Self::LEN] {
        let mut b = [0u8; Self::LEN];
        let _ = put(&mut b, 0, &self.left_count.to_le_bytes());
        let _ = put(&mut b, 4, &self.right_count.to_le_bytes());
        let _ = put(&mut b, 8, &self.speed_left.to_le_bytes());
        let _ = put(&mut b, 12, &self.speed_right.to_le_bytes());
        let _ = put(&mut b, 16, &[self.duty_left, self.duty_right]);
        let _ = put(&mut b, 18, &self.ticks.to_le_bytes());
        let _ = put(&mut b, 22, &self.battery_adc.to_le_bytes());
        b
    }

    /// Decodes reply data; `None` if the length is wrong.
    pub fn decode(b: &[u8]) -> Option<Self> {
        if b.len() != Self::LEN {
            return None;
        }
        Some(Telemetry {
            left_count: u32_at(b, 0)? as i32,
            right_count: u32_at(b, 4)? as i32,
            speed_left: f32_at(b, 8)?,
            speed_right: f32_at(b, 12)?,
            duty_left: b[16],
            duty_right: b[17],
            ticks: u32_at(b, 18)?,
            battery_adc: u16_at(b, 22)?,
        })
    }
}

/// Data of the [`NOTIFY_FAULT`] notification (12 bytes).
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct FaultNotice {
    /// [`Fault`] code.
    pub fault: u8,
    /// The test that was running (2..=5).
    pub test: u8,
    /// Its segment index.
    pub segment: u8,
    /// [`Phase`] code at the fault (1 leg, 2 turn).
    pub phase: u8,
    /// Left count relative to the segment's start.
    pub left: i32,
    /// Right count relative to the segment's start.
    pub right: i32,
}

impl FaultNotice {
    /// Encoded length.
    pub const LEN: usize = 12;

    /// The encoded bytes.
    pub fn to_bytes(&self) -> [u8; Self::LEN] {
        let mut b = [0u8; Self::LEN];
        let _ = put(
            &mut b,
            0,
            &[self.fault, self.test, self.segment, self.phase],
        );
        let _ = put(&mut b, 4, &self.left.to_le_bytes());
        let _ = put(&mut b, 8, &self.right.to_le_bytes());
        b
    }

    /// Decodes notification data; `None` if the length is wrong.
    pub fn decode(b: &[u8]) -> Option<Self> {
        if b.len() != Self::LEN {
            return None;
        }
        Some(FaultNotice {
            fault: b[0],
            test: b[1],
            segment: b[2],
            phase: b[3],
            left: u32_at(b, 4)? as i32,
            right: u32_at(b, 8)? as i32,
        })
    }
}

/// Data of the [`NOTIFY_TEST_DONE`] notification (3 bytes).
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct TestDoneNotice {
    /// The test that ended (2..=5).
    pub test: u8,
    /// Tests completed since reset, this one included.
    pub tests_done: u16,
}

impl TestDoneNotice {
    /// Encoded length.
    pub const LEN: usize = 3;

    /// The encoded bytes.
    pub fn to_bytes(&self) -> [u8; Self::LEN] {
        let d = self.tests_done.to_le_bytes();
        [self.test, d[0], d[1]]
    }

    /// Decodes notification data; `None` if the length is wrong.
    pub fn decode(b: &[u8]) -> Option<Self> {
        if b.len() != Self::LEN {
            return None;
        }
        Some(TestDoneNotice {
            test: b[0],
            tests_done: u16_at(b, 1)?,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::{encode_frame, Event, Parser, MAX_FRAME};

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
    fn run_state_and_phase_decode_exactly_their_wire_values() {
        let states = [
            RunState::Booting,
            RunState::Idle,
            RunState::Driving,
            RunState::Braking,
        ];
        let phases = [
            Phase::Idle,
            Phase::Leg,
            Phase::Turn,
            Phase::Braking,
            Phase::Fault,
        ];
        for b in 0..=u8::MAX {
            assert_eq!(
                RunState::from_u8(b),
                states.iter().copied().find(|s| *s as u8 == b)
            );
            assert_eq!(
                Phase::from_u8(b),
                phases.iter().copied().find(|p| *p as u8 == b)
            );
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
        assert_eq!(Command::decode(&[0x31, 27]), Err(Status::UnknownParam));
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

    #[test]
    fn status_codes_round_trip() {
        for b in 0..=255u8 {
            if let Some(s) = Status::from_u8(b) {
                assert_eq!(s as u8, b);
            }
        }
        assert_eq!(Status::from_u8(8), None);
    }

    #[test]
    fn fault_codes_round_trip() {
        let mut known = 0;
        for b in 0..=255u8 {
            if let Some(f) = Fault::from_u8(b) {
                assert_eq!(f as u8, b);
                known += 1;
            }
        }
        assert_eq!(known, 8);
        assert_eq!(Fault::from_u8(7), Some(Fault::EncoderInconsistent));
        assert_eq!(Fault::from_u8(8), None);
        let f = FaultNotice {
            fault: Fault::EncoderInconsistent as u8,
            test: 4,
            segment: 0,
            phase: 1,
            left: 2100,
            right: 75,
        };
        assert_eq!(f.to_bytes()[0], 7);
        assert_eq!(FaultNotice::decode(&f.to_bytes()), Some(f));
    }

    #[test]
    fn data_blocks_round_trip() {
        let s = StateReport {
            state: 2,
            phase: 2,
            test: 3,
            segment: 5,
            fault: 0,
            tests_done: 0x1234,
        };
        assert_eq!(s.to_bytes(), [2, 2, 3, 5, 0, 0x34, 0x12]);
        assert_eq!(StateReport::decode(&s.to_bytes()), Some(s));
        let t = Telemetry {
            left_count: -5,
            right_count: 70_000,
            speed_left: 15.25,
            speed_right: -0.0,
            duty_left: 200,
            duty_right: 7,
            ticks: 0xDEADBEEF,
            battery_adc: 1023,
        };
        assert_eq!(Telemetry::decode(&t.to_bytes()), Some(t));
        assert_eq!(&t.to_bytes()[0..4], &[0xFB, 0xFF, 0xFF, 0xFF]);
        let f = FaultNotice {
            fault: 1,
            test: 2,
            segment: 4,
            phase: 1,
            left: 3,
            right: -700,
        };
        assert_eq!(FaultNotice::decode(&f.to_bytes()), Some(f));
        let d = TestDoneNotice {
            test: 5,
            tests_done: 9,
        };
        assert_eq!(TestDoneNotice::decode(&d.to_bytes()), Some(d));
        assert_eq!(StateReport::decode(&[0; 6]), None);
        assert_eq!(Telemetry::decode(&[0; 25]), None);
    }

    /// A host's view: encode a reply frame, parse it back byte by byte.
    #[test]
    fn reply_through_the_parser() {
        let data = StateReport {
            state: 1,
            phase: 0,
            test: 4,
            segment: 0,
            fault: 0,
            tests_done: 1,
        }
        .to_bytes();
        let mut payload = [0u8; 32];
        let n = Reply {
            id: CommandId::GetState.reply_id(),
            status: Status::Ok,
            data: &data,
        }
        .encode(&mut payload)
        .unwrap();
        let mut frame = [0u8; MAX_FRAME];
        let m = encode_frame(&payload[..n], &mut frame).unwrap();
        let mut p = Parser::new(50);
        let mut got = None;
        for (i, &b) in frame[..m].iter().enumerate() {
            assert_eq!(p.poll(i as u32), None);
            if let Some(Event::Frame(f)) = p.push(b, i as u32) {
                let r = Reply::decode(f).unwrap();
                got = Some((r.id, r.status, StateReport::decode(r.data).unwrap()));
            }
        }
        assert_eq!(
            got,
            Some((0xA0, Status::Ok, StateReport::decode(&data).unwrap()))
        );
    }
}
