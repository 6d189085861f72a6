//! Fake hardware for the host tests of the logic: every part records what
//! the logic did to it, and a small plant moves the counts from the duties.
//!
//! The bench variables are process-wide statics, so the tests that use them
//! hold [`lock`] (and start from [`reset_bench`]).

extern crate std;

use std::collections::VecDeque;
use std::string::String;
use std::sync::{Mutex, MutexGuard};
use std::vec::Vec;

use henrytwo_protocol::{encode_frame, Command, Event, Parser, Reply, MAX_FRAME, MAX_PAYLOAD};

use crate::battery::Colour;
use crate::bench;
use crate::io::{BatteryInput, BatteryLeds, Bridges, Counts, Line, Side, TickClock, WheelEncoders};
use crate::io::{TRIP_LEFT, TRIP_RIGHT};
use crate::settings::Settings;
use crate::time::{self, reached};
use crate::{robot, Error};

use super::persist::{ByteStore, Stored};
use super::{App, Drive, Hardware};

/// Timer clocks per control tick (15 ms).
pub const TICK: u32 = time::ms(15);

static BENCH: Mutex<()> = Mutex::new(());

/// Serialises the tests that touch the bench variables, and resets them.
pub fn lock() -> MutexGuard<'static, ()> {
    let g = BENCH.lock().unwrap_or_else(|e| e.into_inner());
    reset_bench();
    g
}

/// The bench variables as after reset (the leg length at its default).
pub fn reset_bench() {
    bench::set_leg_length_mm(robot::DEFAULT_LEG_MM);
    bench::set_state_code(1);
    bench::set_phase_code(0);
    bench::set_fault(0);
    bench::set_test(0);
    bench::set_segment(0);
    bench::set_done_count(0);
    bench::set_cut_mask(0);
    bench::set_cut_count(0);
    bench::set_stop_left(0);
    bench::set_stop_right(0);
    bench::set_speed_left(0.0);
    bench::set_speed_right(0.0);
    bench::set_duty_left(0);
    bench::set_duty_right(0);
}

/// The fake board.
pub struct Fake;

impl Hardware for Fake {
    type Motors = Motors;
    type Encoders = Encoders;
    type Clock = Clock;
    type Leds = Leds;
    type Adc = Adc;
    type Link = Link;
    type Debug = Link;
    type Store = Eeprom;
}

/// The EEPROM: 4 KiB, erased (0xFF) when new; each write keeps it busy for
/// the next `write_time` calls of `busy`.
pub struct Eeprom {
    /// The bytes.
    pub bytes: Vec<u8>,
    /// Every write, in order: address, byte.
    pub writes: Vec<(u16, u8)>,
    /// Reads of a byte while busy (a driver error).
    pub reads_while_busy: u32,
    /// How many `busy` calls a write stays busy for.
    pub write_time: u32,
    busy_left: core::cell::Cell<u32>,
}

impl Default for Eeprom {
    fn default() -> Self {
        Eeprom {
            bytes: std::vec![0xFF; 4096],
            writes: Vec::new(),
            reads_while_busy: 0,
            write_time: 0,
            busy_left: core::cell::Cell::new(0),
        }
    }
}

impl Eeprom {
    /// An EEPROM holding what `other` holds (as after a reset).
    pub fn holding(other: &Eeprom) -> Self {
        Eeprom { bytes: other.bytes.clone(), ..Eeprom::default() }
    }
}

impl ByteStore for Eeprom {
    fn read(&mut self, addr: u16) -> u8 {
        if self.busy_left.get() > 0 {
            self.reads_while_busy += 1;
        }
        self.bytes[addr as usize]
    }

    fn busy(&self) -> bool {
        let left = self.busy_left.get();
        if left > 0 {
            self.busy_left.set(left - 1);
        }
        left > 0
    }

    fn write(&mut self, addr: u16, byte: u8) {
        assert_eq!(self.busy_left.get(), 0, "a write started while the EEPROM was busy");
        self.bytes[addr as usize] = byte;
        self.writes.push((addr, byte));
        self.busy_left.set(self.write_time);
    }
}

/// Both bridges: the last duty of each input, and every write in order.
#[derive(Default)]
pub struct Motors {
    /// Left (forward, reverse) inputs.
    pub left: (u8, u8),
    /// Right (forward, reverse) inputs.
    pub right: (u8, u8),
    /// Every write: side, forward input, duty.
    pub log: Vec<(Side, bool, u8)>,
}

impl Motors {
    fn input(&mut self, side: Side, forward: bool) -> &mut u8 {
        let pair = match side {
            Side::Left => &mut self.left,
            Side::Right => &mut self.right,
        };
        if forward {
            &mut pair.0
        } else {
            &mut pair.1
        }
    }

    /// The inputs of `side`: (forward, reverse).
    pub fn of(&self, side: Side) -> (u8, u8) {
        match side {
            Side::Left => self.left,
            Side::Right => self.right,
        }
    }
}

impl Bridges for Motors {
    fn set_forward(&mut self, side: Side, duty: u8) {
        *self.input(side, true) = duty;
        self.log.push((side, true, duty));
    }

    fn set_reverse(&mut self, side: Side, duty: u8) {
        *self.input(side, false) = duty;
        self.log.push((side, false, duty));
    }

    fn all_off(&mut self) {
        self.set_forward(Side::Right, 0);
        self.set_forward(Side::Left, 0);
        self.set_reverse(Side::Right, 0);
        self.set_reverse(Side::Left, 0);
    }
}

/// The encoders: counts the test moves, trips as the real handlers keep
/// them (fired by the edge that reaches the armed count).
#[derive(Default)]
pub struct Encoders {
    /// The counts.
    pub counts: Counts,
    /// Armed trips, left and right: (up, at).
    pub trips: [Option<(bool, i32)>; 2],
    /// Fired trips not yet taken.
    pub tripped: u8,
}

impl Encoders {
    fn slot(side: Side) -> (usize, u8) {
        match side {
            Side::Left => (0, TRIP_LEFT),
            Side::Right => (1, TRIP_RIGHT),
        }
    }

    /// One edge on `side`: the count moves by `step` (+1 or -1).
    pub fn edge(&mut self, side: Side, step: i32) {
        let (i, bit) = Self::slot(side);
        let c = match side {
            Side::Left => &mut self.counts.left,
            Side::Right => &mut self.counts.right,
        };
        *c += step;
        if let Some((up, at)) = self.trips[i] {
            if *c == at && (step > 0) == up {
                self.trips[i] = None;
                self.tripped |= bit;
            }
        }
    }

    /// Moves `side`'s count by `delta`, edge by edge.
    pub fn move_by(&mut self, side: Side, delta: i32) {
        for _ in 0..delta.unsigned_abs() {
            self.edge(side, delta.signum());
        }
    }
}

impl WheelEncoders for Encoders {
    fn counts(&self) -> Counts {
        self.counts
    }

    fn arm(&mut self, side: Side, up: bool, at: i32) {
        let (i, bit) = Self::slot(side);
        let count = match side {
            Side::Left => self.counts.left,
            Side::Right => self.counts.right,
        };
        let ahead = if up { at - count } else { count - at };
        if ahead <= 0 {
            self.trips[i] = None;
            self.tripped |= bit;
        } else {
            self.trips[i] = Some((up, at));
        }
    }

    fn disarm_all(&mut self) {
        self.trips = [None, None];
        self.tripped = 0;
    }

    fn take_tripped(&mut self) -> (u8, Counts) {
        let t = self.tripped;
        self.tripped = 0;
        (t, self.counts)
    }
}

/// The clock: the time and the ticks the test makes pass.
#[derive(Default)]
pub struct Clock {
    /// Now, timer clocks.
    pub now: u32,
    /// Ticks not yet taken.
    pub ticks: u32,
    /// The armed alarm.
    pub alarm: Option<u32>,
    /// Start of the current control period.
    pub period_start: u32,
}

impl TickClock for Clock {
    fn now(&self) -> u32 {
        self.now
    }

    fn take_ticks(&mut self) -> u32 {
        core::mem::take(&mut self.ticks)
    }

    fn restart_period(&mut self) {
        self.ticks = 0;
        self.alarm = None;
        self.period_start = self.now;
    }

    fn arm_alarm(&mut self, at: u32) -> bool {
        if reached(self.now, at) {
            self.alarm = None;
            return false;
        }
        self.alarm = Some(at);
        true
    }

    fn disarm_alarm(&mut self) {
        self.alarm = None;
    }
}

/// The battery input: a fixed reading, converted at once.
pub struct Adc {
    /// The reading.
    pub value: u16,
    /// Conversions started.
    pub started: u32,
}

impl BatteryInput for Adc {
    fn start(&mut self) {
        self.started += 1;
    }

    fn busy(&self) -> bool {
        false
    }

    fn result(&self) -> u16 {
        self.value
    }
}

/// The LEDs: what they show, and how many times they were written.
#[derive(Default)]
pub struct Leds {
    /// The lit colour.
    pub shown: Option<Colour>,
    /// Writes.
    pub writes: u32,
}

impl BatteryLeds for Leds {
    fn show_if_changed(&mut self, c: Colour) {
        if self.shown != Some(c) {
            self.shown = Some(c);
            self.writes += 1;
        }
    }
}

/// A serial line: bytes to receive, bytes sent.
#[derive(Default)]
pub struct Link {
    /// Received, not yet read.
    pub rx: VecDeque<u8>,
    /// Sent.
    pub tx: Vec<u8>,
}

impl Link {
    /// The text sent (the debug UART).
    pub fn text(&self) -> String {
        String::from_utf8_lossy(&self.tx).into_owned()
    }
}

impl Line for Link {
    const RX_LEN: usize = 64;

    fn read(&mut self) -> Option<u8> {
        self.rx.pop_front()
    }

    fn write_all(&mut self, bytes: &[u8]) -> Result<(), Error> {
        self.tx.extend_from_slice(bytes);
        Ok(())
    }
}

impl ufmt::uWrite for Link {
    type Error = Error;

    fn write_str(&mut self, s: &str) -> Result<(), Error> {
        self.tx.extend_from_slice(s.as_bytes());
        Ok(())
    }
}

/// A reply or notice the application sent: id, status byte, data.
pub type Sent = (u8, u8, Vec<u8>);

impl App<Fake> {
    /// An idle application on fresh fake hardware (battery reading 950),
    /// the EEPROM erased.
    pub fn fake() -> Self {
        Self::fake_with(Eeprom::default())
    }

    /// As [`App::fake`], booting from the EEPROM `eeprom`.
    pub fn fake_with(eeprom: Eeprom) -> Self {
        App::new(
            Drive::new(Motors::default(), Encoders::default()),
            Clock::default(),
            Leds::default(),
            Adc { value: 950, started: 0 },
            Link::default(),
            Link::default(),
            Stored::load(eeprom, Settings::DEFAULT),
        )
    }

    /// Queues `cmd` as a frame on the command link.
    pub fn receive(&mut self, cmd: Command) {
        let mut payload = [0u8; MAX_PAYLOAD];
        let n = cmd.encode(&mut payload).expect("command fits");
        self.receive_payload(&payload[..n]);
    }

    /// Queues `payload` framed on the command link.
    pub fn receive_payload(&mut self, payload: &[u8]) {
        let mut frame = [0u8; MAX_FRAME];
        let m = encode_frame(payload, &mut frame).expect("payload fits");
        self.bluetooth.rx.extend(&frame[..m]);
    }

    /// Takes every frame sent on the command link since the last call.
    pub fn sent(&mut self) -> Vec<Sent> {
        let mut parser = Parser::new(u32::MAX);
        let mut out = Vec::new();
        for b in core::mem::take(&mut self.bluetooth.tx) {
            if let Some(Event::Frame(p)) = parser.push(b, 0) {
                let r = Reply::decode(p).expect("a reply");
                out.push((r.id, r.status as u8, r.data.to_vec()));
            }
        }
        out
    }

    /// Lets `clocks` timer clocks pass (no tick), then polls.
    pub fn wait(&mut self, clocks: u32) {
        self.clock.now = self.clock.now.wrapping_add(clocks);
        self.poll();
    }

    /// One control period of the fake plant: each wheel moves `per_tick`
    /// counts in the direction of its driven input (none when both inputs
    /// are 0, or both driven), edge by edge, then the tick comes and the
    /// application polls.
    pub fn tick_plant(&mut self, per_tick: i32) {
        for side in [Side::Left, Side::Right] {
            let dir = match self.drive.motors.of(side) {
                (f, 0) if f > 0 => 1,
                (0, r) if r > 0 => -1,
                _ => 0,
            };
            for _ in 0..per_tick {
                if dir != 0 {
                    self.drive.encoders.edge(side, dir);
                }
            }
        }
        self.clock.now = self.clock.now.wrapping_add(TICK);
        self.clock.ticks += 1;
        self.poll();
    }
}
