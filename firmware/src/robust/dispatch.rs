//! Commands in, replies out: the framed protocol (`henrytwo-protocol`) on
//! the command link, and the thesis' single-byte selectors when they come
//! isolated on the line ([`crate::selector`]).
//!
//! Every frame gets one reply `[id, status, data]`: `PING` the protocol
//! version, `START_TEST` Ok or why not (busy, bad leg length), `STOP` Ok
//! (stopping a running test), `GET_STATE` a [`StateReport`], `GET_TELEMETRY`
//! a [`Telemetry`], `SET_PARAM` (refused while busy) and `GET_PARAM` the
//! parameter's value; a frame that does not decode gets its error status
//! (an unknown command echoes its id byte), a damaged frame a reply to
//! [`FRAME_ERROR_ID`].

use henrytwo_protocol::{
    encode_frame, Command, Event, Param, Reply, StateReport, Status, Telemetry, Test, FRAME_ERROR_ID, MAX_FRAME,
    MAX_PAYLOAD, VERSION,
};

use crate::bench;
use crate::critical;
use crate::io::{Line, TickClock, WheelEncoders};
use crate::time;

use super::sequencer::Mode;
use super::{App, Hardware};

/// A frame whose next byte does not come within this is truncated.
pub const INTER_BYTE_TIMEOUT: u32 = time::ms(50);
/// A raw selector byte counts only with no other byte this long before and
/// after it: the inter-byte timeout, so a byte that could belong to a frame
/// (whose bytes may be up to 50 ms apart; they come back to back, 1.04 ms)
/// is never one. Checked on each tick: acted upon 50 to 65 ms after it came.
pub const RAW_QUIET: u32 = INTER_BYTE_TIMEOUT;

/// A command or event taken out of the parser (which it must not borrow).
pub(crate) enum Input {
    Raw(u8),
    Command(u8, Result<Command, Status>, u8),
    FrameError(Status),
}

impl<H: Hardware> App<H> {
    /// Reads what the Bluetooth UART received (bounded by the ring size),
    /// ends a frame the line left incomplete, and takes a raw byte once the
    /// line has stayed quiet after it.
    pub(crate) fn poll_commands(&mut self) {
        let now = self.clock.now();
        if let Some(Event::Error(e)) = self.parser.poll(now) {
            self.handle(Input::FrameError(e.into()));
        }
        for _ in 0..H::Link::RX_LEN {
            let Some(byte) = self.bluetooth.read() else { break };
            let now = self.clock.now();
            if let Some(Event::Error(e)) = self.parser.poll(now) {
                self.handle(Input::FrameError(e.into()));
            }
            let quiet_before = self.raw.received(now);
            let input = match self.parser.push(byte, now) {
                None => continue,
                // Outside a frame (a discarding parser gives none); dropped
                // while a test runs.
                Some(Event::Raw(b)) => {
                    if quiet_before && self.mode == Mode::Idle {
                        self.raw.hold(b);
                    }
                    continue;
                }
                Some(Event::Error(e)) => Input::FrameError(e.into()),
                Some(Event::Frame(p)) => {
                    Input::Command(Command::reply_id_for(p), Command::decode(p), p.first().copied().unwrap_or(0))
                }
            };
            self.handle(input);
        }
        // `now` is from before the ring was read: a byte that came before it
        // was read above and dropped the held one.
        if let Some(b) = self.raw.poll(now) {
            if self.parser.is_idle() {
                self.handle(Input::Raw(b));
            }
        }
    }

    fn handle(&mut self, input: Input) {
        match input {
            Input::Raw(b) => {
                // The thesis' selectors, isolated on the line (see
                // `poll_commands`); dropped while a test runs.
                if let Some(t) = Test::from_u8(b) {
                    let _ = self.start_test(t);
                }
            }
            Input::FrameError(s) => self.send(FRAME_ERROR_ID, s, &[]),
            Input::Command(id, Err(s), first) => {
                let data = [first];
                let data: &[u8] = if s == Status::UnknownCommand { &data } else { &[] };
                self.send(id, s, data);
            }
            Input::Command(id, Ok(cmd), _) => self.execute(id, cmd),
        }
    }

    fn execute(&mut self, id: u8, cmd: Command) {
        let busy = self.mode != Mode::Idle;
        match cmd {
            Command::Ping => self.send(id, Status::Ok, &[VERSION]),
            Command::StartTest(t) => {
                let s = match self.start_test(t) {
                    Ok(()) => Status::Ok,
                    Err(s) => s,
                };
                self.send(id, s, &[]);
            }
            Command::Stop => {
                if busy {
                    self.stop_all();
                }
                self.send(id, Status::Ok, &[]);
            }
            Command::GetState => {
                let r = StateReport {
                    state: bench::state_code(),
                    phase: bench::phase_code(),
                    test: bench::test(),
                    segment: bench::segment(),
                    fault: bench::fault(),
                    tests_done: bench::done_count(),
                };
                self.send(id, Status::Ok, &r.to_bytes());
            }
            Command::GetTelemetry => {
                let c = self.drive.encoders.counts();
                let t = Telemetry {
                    left_count: c.left,
                    right_count: c.right,
                    speed_left: bench::speed_left(),
                    speed_right: bench::speed_right(),
                    duty_left: bench::duty_left(),
                    duty_right: bench::duty_right(),
                    ticks: critical::free(bench::ticks),
                    battery_adc: bench::battery_adc(),
                };
                self.send(id, Status::Ok, &t.to_bytes());
            }
            Command::SetParam(p, v) => {
                if busy {
                    self.send(id, Status::Busy, &[]);
                } else if !super::wiring::settable(p, v) {
                    self.send(id, Status::OutOfRange, &[]);
                } else {
                    self.set_param(p, v);
                    self.send_param(id, p);
                }
            }
            Command::GetParam(p) => self.send_param(id, p),
        }
    }

    /// Sets `p` (checked), queues it for the EEPROM, and recomputes what
    /// depends on it outside a segment's start: the speed conversion.
    pub(crate) fn set_param(&mut self, p: Param, v: f32) {
        self.stored.set(p, v);
        if p == Param::CountsPerWheelRev {
            self.drive.speeds.set(v);
        }
    }

    fn send_param(&mut self, id: u8, p: Param) {
        let v = self.stored.settings.get(p).to_le_bytes();
        self.send(id, Status::Ok, &[p as u8, v[0], v[1], v[2], v[3]]);
    }

    /// Frames `[id, status, data]` and queues it on the Bluetooth UART; a
    /// frame that does not fit the transmit buffer is dropped.
    pub(crate) fn send(&mut self, id: u8, status: Status, data: &[u8]) {
        let mut payload = [0u8; MAX_PAYLOAD];
        let Some(n) = (Reply { id, status, data }).encode(&mut payload) else { return };
        let mut frame = [0u8; MAX_FRAME];
        let Some(p) = payload.get(..n) else { return };
        let Ok(m) = encode_frame(p, &mut frame) else { return };
        if let Some(f) = frame.get(..m) {
            let _ = self.bluetooth.write_all(f);
        }
    }
}

#[cfg(test)]
mod tests {
    use std::vec;
    use std::vec::Vec;

    use henrytwo_protocol::{CommandId, Fault, Phase, RunState, START};

    use super::*;
    use crate::io::{Counts, Side};
    use crate::robust::fake::{self, Fake, Sent};

    /// `cmd` received and handled: the replies.
    fn ask(app: &mut App<Fake>, cmd: Command) -> Vec<Sent> {
        app.receive(cmd);
        app.poll();
        app.sent()
    }

    fn ok(id: CommandId, data: &[u8]) -> Vec<Sent> {
        vec![(id.reply_id(), Status::Ok as u8, data.to_vec())]
    }

    #[test]
    fn ping_replies_the_protocol_version() {
        let _bench = fake::lock();
        let mut app = App::fake();
        assert_eq!(ask(&mut app, Command::Ping), ok(CommandId::Ping, &[VERSION]));
    }

    #[test]
    fn start_test_starts_it_once() {
        let _bench = fake::lock();
        let mut app = App::fake();
        assert_eq!(ask(&mut app, Command::StartTest(Test::Line)), ok(CommandId::StartTest, &[]));
        assert!(matches!(app.mode, Mode::Segment { test: Test::Line, index: 0, .. }));
        assert_eq!((bench::test(), bench::state_code()), (Test::Line as u8, RunState::Driving as u8));
        let busy = vec![(CommandId::StartTest.reply_id(), Status::Busy as u8, vec![])];
        assert_eq!(ask(&mut app, Command::StartTest(Test::Triangle)), busy);
        assert!(matches!(app.mode, Mode::Segment { test: Test::Line, .. }));
    }

    #[test]
    fn start_test_refuses_a_leg_length_out_of_range() {
        let _bench = fake::lock();
        let mut app = App::fake();
        bench::set_leg_length_mm(5.0);
        let refused = vec![(CommandId::StartTest.reply_id(), Status::OutOfRange as u8, vec![])];
        assert_eq!(ask(&mut app, Command::StartTest(Test::Line)), refused);
        assert_eq!(app.mode, Mode::Idle);
    }

    #[test]
    fn stop_ends_a_running_test_with_the_motors_off() {
        let _bench = fake::lock();
        let mut app = App::fake();
        assert_eq!(ask(&mut app, Command::Stop), ok(CommandId::Stop, &[]));
        assert!(app.drive.motors.log.is_empty(), "idle: nothing to stop");
        ask(&mut app, Command::StartTest(Test::Line));
        assert_eq!(ask(&mut app, Command::Stop), ok(CommandId::Stop, &[]));
        assert_eq!(app.mode, Mode::Idle);
        assert_eq!((app.drive.motors.left, app.drive.motors.right), ((0, 0), (0, 0)));
        assert_eq!((bench::phase_code(), bench::state_code()), (Phase::Idle as u8, RunState::Idle as u8));
    }

    #[test]
    fn get_state_reports_the_bench_variables() {
        let _bench = fake::lock();
        let mut app = App::fake();
        bench::set_fault(Fault::StallRight as u8);
        bench::set_done_count(3);
        ask(&mut app, Command::StartTest(Test::Triangle));
        let r = ask(&mut app, Command::GetState);
        let report = StateReport {
            state: RunState::Driving as u8,
            phase: Phase::Leg as u8,
            test: Test::Triangle as u8,
            segment: 0,
            fault: Fault::None as u8,
            tests_done: 3,
        };
        assert_eq!(r, ok(CommandId::GetState, &report.to_bytes()));
    }

    #[test]
    fn get_telemetry_reports_the_counts_and_the_bench_variables() {
        let _bench = fake::lock();
        let mut app = App::fake();
        app.drive.encoders.counts = Counts { left: 1234, right: -56 };
        bench::set_duty_left(77);
        bench::set_speed_right(12.5);
        let r = ask(&mut app, Command::GetTelemetry);
        let t = Telemetry::decode(&r[0].2).unwrap();
        assert_eq!(r[0].0, CommandId::GetTelemetry.reply_id());
        assert_eq!((t.left_count, t.right_count, t.duty_left, t.speed_right), (1234, -56, 77, 12.5));
        assert_eq!(t.ticks, critical::free(bench::ticks));
    }

    #[test]
    fn set_param_changes_it_when_idle_only_and_get_param_reads_it() {
        let _bench = fake::lock();
        let mut app = App::fake();
        let v = 1.25f32.to_le_bytes();
        let echo = [Param::CorrLeft as u8, v[0], v[1], v[2], v[3]];
        assert_eq!(ask(&mut app, Command::SetParam(Param::CorrLeft, 1.25)), ok(CommandId::SetParam, &echo));
        assert_eq!(app.stored.settings.correction.left, 1.25);
        assert_eq!(ask(&mut app, Command::GetParam(Param::CorrLeft)), ok(CommandId::GetParam, &echo));
        ask(&mut app, Command::StartTest(Test::Line));
        let busy = vec![(CommandId::SetParam.reply_id(), Status::Busy as u8, vec![])];
        assert_eq!(ask(&mut app, Command::SetParam(Param::CorrLeft, 0.75)), busy);
        assert_eq!(app.stored.settings.correction.left, 1.25);
    }

    #[test]
    fn a_frame_that_does_not_decode_gets_its_error() {
        let _bench = fake::lock();
        let mut app = App::fake();
        // An unknown id is echoed; a known one with the wrong length is not.
        app.receive_payload(&[0x7E]);
        app.receive_payload(&[CommandId::Ping as u8, 9]);
        app.poll();
        let unknown = (FRAME_ERROR_ID, Status::UnknownCommand as u8, vec![0x7E]);
        let length = (CommandId::Ping.reply_id(), Status::BadLength as u8, vec![]);
        assert_eq!(app.sent(), [unknown, length]);
    }

    #[test]
    fn a_damaged_frame_gets_a_frame_error() {
        let _bench = fake::lock();
        let mut app = App::fake();
        app.receive(Command::Ping);
        let crc = app.bluetooth.rx.back_mut().unwrap();
        *crc ^= 0x01;
        app.poll();
        assert_eq!(app.sent(), [(FRAME_ERROR_ID, Status::BadCrc as u8, vec![])]);
        // A frame that stops arriving ends after the inter-byte timeout.
        app.bluetooth.rx.extend([START, 1]);
        app.poll();
        app.wait(INTER_BYTE_TIMEOUT - 1);
        assert!(app.sent().is_empty());
        app.wait(1);
        assert_eq!(app.sent(), [(FRAME_ERROR_ID, Status::Truncated as u8, vec![])]);
    }

    #[test]
    fn an_isolated_selector_byte_starts_its_test_once_the_line_stays_quiet() {
        let _bench = fake::lock();
        let mut app = App::fake();
        app.wait(RAW_QUIET);
        app.bluetooth.rx.push_back(Test::Line as u8);
        app.poll();
        app.wait(RAW_QUIET - 1);
        assert_eq!(app.mode, Mode::Idle);
        app.wait(1);
        assert!(matches!(app.mode, Mode::Segment { test: Test::Line, .. }));
        assert!(app.sent().is_empty(), "a selector byte gets no reply");
        assert_eq!(app.drive.motors.of(Side::Left), (crate::robot::START_DUTY, 0));
    }

    #[test]
    fn selector_bytes_that_are_not_isolated_are_dropped() {
        let _bench = fake::lock();
        let mut app = App::fake();
        app.wait(RAW_QUIET);
        app.bluetooth.rx.push_back(Test::Line as u8);
        app.poll();
        // A second byte within the quiet time: neither counts.
        app.wait(RAW_QUIET / 2);
        app.bluetooth.rx.push_back(Test::Line as u8);
        app.poll();
        app.wait(3 * RAW_QUIET);
        assert_eq!(app.mode, Mode::Idle);
    }
}
