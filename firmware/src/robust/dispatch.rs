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
                } else {
                    self.settings.set(p, v);
                    self.send_param(id, p);
                }
            }
            Command::GetParam(p) => self.send_param(id, p),
        }
    }

    fn send_param(&mut self, id: u8, p: Param) {
        let v = self.settings.get(p).to_le_bytes();
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
