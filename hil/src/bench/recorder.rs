//! What the bench records of a run, for reports, traces and replays: trace
//! samples of the plant, every change of the H-bridge inputs (the drive
//! log), motor cut-offs, [`Motion`] changes, the battery LEDs, encoder pin
//! changes (when recording) and the analog inputs.

use plant_model::{Robot, Side};

use super::log::{Log, Retention, Thinned};
use crate::board::{LedWiring, Pin};
use crate::mcu::sim::Core;

/// One trace sample of the plant.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Sample {
    pub t_s: f64,
    pub x_mm: f64,
    pub y_mm: f64,
    pub theta_rad: f64,
    pub left_edges: i64,
    pub right_edges: i64,
    pub left_duty: f64,
    pub right_duty: f64,
}

/// An encoder line change raised on a pin: line 0/1 = left A/B, 2/3 = right A/B.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct PinEvent {
    pub cycle: u64,
    pub line: u8,
    pub level: bool,
}

/// An analog input the bench drives, changed at `cycle` to `mv` millivolts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct AnalogEvent {
    pub cycle: u64,
    pub input: AnalogInput,
    pub mv: u32,
}

/// The analog inputs the bench drives.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum AnalogInput {
    /// A0: the battery through its divider.
    Adc0,
    /// VCC, AVCC and AREF (one rail on the Mega).
    Supply,
}

/// The battery LEDs after a change (each lit by a high pin).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct LedEvent {
    pub cycle: u64,
    pub green: bool,
    pub blue: bool,
    pub red: bool,
}

impl LedEvent {
    /// The colour shown: one LED lit, else a description.
    pub fn colour(&self) -> &'static str {
        match (self.green, self.blue, self.red) {
            (false, false, false) => "off",
            (true, false, false) => "green",
            (false, true, false) => "blue",
            (false, false, true) => "red",
            _ => "several",
        }
    }
}

/// A change of one H-bridge input, as the plant saw it.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct DriveEvent {
    pub cycle: u64,
    /// Arduino pin number.
    pub pin: u8,
    pub duty: f64,
    /// When the timer drives the pin: its counter, compare value and
    /// output action, from which the exact waveform follows (see pwm.rs).
    #[serde(skip)]
    pub wave: Option<crate::mcu::pwm::ChannelWave>,
}

/// The plant and the firmware's counters at one cycle.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Snapshot {
    pub cycle: u64,
    pub x_mm: f64,
    pub y_mm: f64,
    pub theta_rad: f64,
    /// The firmware's counters, read from SRAM at that cycle (None: the
    /// bench does not know where a firmware without its interface keeps them).
    pub left_count: Option<i32>,
    pub right_count: Option<i32>,
    /// Net A edges the plant produced.
    pub left_edges: i64,
    pub right_edges: i64,
    /// Wheel arcs travelled by the plant.
    pub left_mm: f64,
    pub right_mm: f64,
}

/// A motor switched off: its forward or reverse drive went to zero.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Cutoff {
    pub side: Side,
    #[serde(flatten)]
    pub at: Snapshot,
    /// The drive cut was the forward one (else the reverse).
    #[serde(skip)]
    pub forward: bool,
    /// When the same drive of the same motor came back, if it did.
    #[serde(skip)]
    pub resumed_cycle: Option<u64>,
}

impl Cutoff {
    /// A real cut-off, not a stale level: the drive stayed off for at least
    /// `debounce` cycles (firmware that writes a bridge's two inputs one
    /// after the other leaves the motor undriven for a few instructions).
    pub fn lasted(&self, debounce: u64) -> bool {
        self.resumed_cycle
            .is_none_or(|back| back - self.at.cycle >= debounce)
    }
}

/// What the two motors do together, from the H-bridge inputs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Motion {
    Stopped,
    Forward,
    Reverse,
    /// Spin in place, clockwise seen from above (left forward, right back).
    SpinCw,
    SpinCcw,
    /// One motor driven, the other off.
    OneWheel,
    /// At least one motor braking (both inputs high).
    Brake,
    /// Anything else (e.g. one forward, one braking).
    Mixed,
}

impl Motion {
    /// From each motor's drive: +1 forward, -1 reverse, 0 off, 2 brake.
    pub fn classify(left: i8, right: i8) -> Motion {
        match (left, right) {
            (0, 0) => Motion::Stopped,
            (1, 1) => Motion::Forward,
            (-1, -1) => Motion::Reverse,
            (1, -1) => Motion::SpinCw,
            (-1, 1) => Motion::SpinCcw,
            (2, _) | (_, 2) => Motion::Brake,
            (0, _) | (_, 0) => Motion::OneWheel,
            _ => Motion::Mixed,
        }
    }
}

/// A change of [`Motion`], with the state at that cycle.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct MotionEvent {
    pub motion: Motion,
    #[serde(flatten)]
    pub at: Snapshot,
}

/// Where a run's records go as the bench makes them, besides what it keeps:
/// a trace written while the run goes (see `Bench::stream_records`), so
/// that what only the trace needs (every encoder pin change, every drive
/// change, every sample) is not kept for the whole run.
pub trait Tap: Send {
    fn pin(&mut self, e: PinEvent);
    fn drive(&mut self, e: &DriveEvent);
    /// A byte on a UART: sent by the firmware (`cycle` its frame started on
    /// the TX pin) or received (`cycle` the receiver had it).
    fn uart(&mut self, received: bool, cycle: u64, usart: u8, byte: u8);
    fn sample(&mut self, s: &Sample);
    /// Nothing the bench records from now on changes anything before
    /// `cycle`.
    fn settle(&mut self, cycle: u64);
}

/// A [`Tap`] shared between the bench and whoever finishes it after the run.
#[derive(Clone)]
pub struct SharedTap(pub std::sync::Arc<std::sync::Mutex<dyn Tap>>);

impl SharedTap {
    fn with(&self, f: impl FnOnce(&mut dyn Tap)) {
        let mut tap = self.0.lock().unwrap_or_else(|p| p.into_inner());
        f(&mut *tap);
    }
}

impl std::fmt::Debug for SharedTap {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("SharedTap")
    }
}

/// The records of one run, each bounded (see `log.rs`).
pub(super) struct Recorder {
    led_wiring: Option<LedWiring>,
    trace: Thinned<Sample>,
    drive_log: Log<DriveEvent>,
    cutoffs: Log<Cutoff>,
    motions: Log<MotionEvent>,
    leds: Log<LedEvent>,
    /// Encoder pin changes, when recording (for replays without the bench).
    pins: Option<Log<PinEvent>>,
    /// Every change of the analog inputs since cycle 0 (rare: the battery's
    /// steps), for replays without the bench.
    analog: Log<AnalogEvent>,
    /// The motion now (the log may keep only the first or the latest).
    motion: Option<Motion>,
    retention: Retention,
    /// Where the records go as they are made, when a trace is written as
    /// the run goes; then the pin changes are not kept.
    tap: Option<SharedTap>,
    /// The UART log entries (sent, received) given to the tap so far.
    uart_fed: [usize; 2],
}

/// The caps of the records in a test run (see `log.rs`): 2^16 trace
/// samples are 11 minutes at 10 ms before the trace is thinned; 2^19 drive
/// events are 87 minutes of driving (the robust build changes the bridge
/// about 100 times a robot second on a leg); 2^21 pin changes, several
/// minutes of both encoders' four lines (a recording for a replay; a VCD
/// trace written as the run goes keeps none, see [`Tap`]).
pub(super) const TRACE_CAP: usize = 1 << 16;
pub(super) const DRIVE_CAP: usize = 1 << 19;
pub(super) const PIN_CAP: usize = 1 << 21;
/// Motion changes, cut-offs, LED and analog changes: a few per leg.
pub(super) const EVENT_CAP: usize = 1 << 16;

/// How many items each record holds now: what a run retains.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct Retained {
    pub trace: usize,
    pub drive: usize,
    pub cutoffs: usize,
    pub motions: usize,
    pub leds: usize,
    pub pins: usize,
    pub analog: usize,
    /// Bytes from the firmware and their log entries, all USARTs.
    pub uart_bytes: usize,
    pub uart_log: usize,
    /// Fault actions applied.
    pub applied: usize,
}

impl Retained {
    pub fn total(&self) -> usize {
        self.trace
            + self.drive
            + self.cutoffs
            + self.motions
            + self.leds
            + self.pins
            + self.analog
            + self.uart_bytes
            + self.uart_log
            + self.applied
    }
}

impl Recorder {
    pub(super) fn new(led_wiring: Option<LedWiring>) -> Self {
        Self {
            led_wiring,
            trace: Thinned::new(TRACE_CAP),
            drive_log: Log::new(DRIVE_CAP),
            cutoffs: Log::new(EVENT_CAP),
            motions: Log::new(EVENT_CAP),
            leds: Log::new(EVENT_CAP),
            pins: None,
            analog: Log::new(EVENT_CAP),
            motion: None,
            retention: Retention::Run,
            tap: None,
            uart_fed: [0; 2],
        }
    }

    /// Keep only the latest item of each record from now on.
    pub(super) fn keep_latest(&mut self) {
        self.retention = Retention::Latest;
        self.trace.keep_latest();
        self.drive_log.keep_latest();
        self.cutoffs.keep_latest();
        self.motions.keep_latest();
        self.leds.keep_latest();
        if let Some(p) = &mut self.pins {
            p.keep_latest();
        }
        self.analog.keep_latest();
    }

    /// What each record holds (the UART's and the faults' left at 0).
    pub(super) fn retained(&self) -> Retained {
        Retained {
            trace: self.trace.as_slice().len(),
            drive: self.drive_log.as_slice().len(),
            cutoffs: self.cutoffs.as_slice().len(),
            motions: self.motions.as_slice().len(),
            leds: self.leds.as_slice().len(),
            pins: self.pins.as_ref().map_or(0, |p| p.as_slice().len()),
            analog: self.analog.as_slice().len(),
            ..Retained::default()
        }
    }

    /// A notice for each record that reached its cap in this run.
    pub(super) fn notices(&self, trace_interval_s: f64) -> Vec<String> {
        let mut v = Vec::new();
        if self.trace.every() > 1 {
            v.push(format!(
                "the trace reached its cap of {TRACE_CAP} samples: it was thinned to one sample every {} ms over the whole run",
                (trace_interval_s * self.trace.every() as f64 * 1000.0).round()
            ));
        }
        v.extend(self.drive_log.notice("drive log (VCD, fault timings)"));
        v.extend(self.cutoffs.notice("log of motor cut-offs"));
        v.extend(
            self.motions
                .notice("log of motion changes (legs and turns)"),
        );
        v.extend(self.leds.notice("log of LED changes"));
        v.extend(
            self.pins
                .as_ref()
                .and_then(|p| p.notice("log of encoder pin changes (VCD)")),
        );
        v.extend(self.analog.notice("log of analog input changes"));
        v
    }

    pub(super) fn drive(&mut self, e: DriveEvent) {
        if let Some(t) = &self.tap {
            t.with(|t| t.drive(&e));
        }
        self.drive_log.push(e);
    }

    pub(super) fn cutoff(&mut self, side: Side, forward: bool, at: Snapshot) {
        self.cutoffs.push(Cutoff {
            side,
            at,
            forward,
            resumed_cycle: None,
        });
    }

    /// `side`'s forward (or reverse) drive is on at `cycle`: its last
    /// cut-off of that drive, if still open, ends here.
    pub(super) fn drive_on(&mut self, side: Side, forward: bool, cycle: u64) {
        if let Some(c) = self
            .cutoffs
            .as_mut_slice()
            .iter_mut()
            .rev()
            .find(|c| c.side == side)
        {
            if c.forward == forward && c.resumed_cycle.is_none() && cycle > c.at.cycle {
                c.resumed_cycle = Some(cycle);
            }
        }
    }

    /// The motion last recorded.
    pub(super) fn motion(&self) -> Option<Motion> {
        self.motion
    }

    pub(super) fn motion_changed(&mut self, e: MotionEvent) {
        self.motion = Some(e.motion);
        self.motions.push(e);
    }

    pub(super) fn analog(&mut self, e: AnalogEvent) {
        self.analog.push(e);
    }

    /// An encoder line changed on its pin (kept only while recording).
    pub(super) fn pin(&mut self, cycle: u64, line: u8, level: bool) {
        if let Some(t) = &self.tap {
            t.with(|t| t.pin(PinEvent { cycle, line, level }));
        } else if let Some(rec) = &mut self.pins {
            rec.push(PinEvent { cycle, line, level });
        }
    }

    /// The LED port now shows `port`.
    pub(super) fn leds_changed(&mut self, cycle: u64, port: u8) {
        let Some(l) = self.led_wiring else {
            return;
        };
        let lit = |p: Pin| port >> p.bit & 1 != 0;
        let e = LedEvent {
            cycle,
            green: lit(l.green),
            blue: lit(l.blue),
            red: lit(l.red),
        };
        let same = |x: &LedEvent| (x.green, x.blue, x.red) == (e.green, e.blue, e.red);
        // The log starts dark: only a change is an event.
        let dark_start = self.leds.pushed() == 0 && port == 0;
        if !(dark_start || self.leds.last().is_some_and(same)) {
            self.leds.push(e);
        }
    }
}

fn read_i32(core: &Core, addr: u16) -> i32 {
    i32::from_le_bytes([
        core.data(addr),
        core.data(addr + 1),
        core.data(addr + 2),
        core.data(addr + 3),
    ])
}

impl Snapshot {
    /// The plant and the firmware's counters now (`cycle` is the current one).
    pub(super) fn take(
        robot: &Robot,
        counts: Option<[u16; 2]>,
        core: &Core,
        cycle: u64,
    ) -> Snapshot {
        let pose = robot.pose();
        Snapshot {
            cycle,
            x_mm: pose.x().0,
            y_mm: pose.y().0,
            theta_rad: pose.theta().0,
            left_count: counts.map(|c| read_i32(core, c[0])),
            right_count: counts.map(|c| read_i32(core, c[1])),
            left_edges: robot.counted_edges(Side::Left),
            right_edges: robot.counted_edges(Side::Right),
            left_mm: robot.distance_travelled(Side::Left).0,
            right_mm: robot.distance_travelled(Side::Right).0,
        }
    }
}

impl Recorder {
    /// A trace sample of the plant at `t_s`, the motors' signed duties
    /// `duty` (by side index).
    pub(super) fn sample(&mut self, t_s: f64, robot: &Robot, duty: [f64; 2]) {
        let pose = robot.pose();
        let s = Sample {
            t_s,
            x_mm: pose.x().0,
            y_mm: pose.y().0,
            theta_rad: pose.theta().0,
            left_edges: robot.counted_edges(Side::Left),
            right_edges: robot.counted_edges(Side::Right),
            left_duty: duty[0],
            right_duty: duty[1],
        };
        if let Some(t) = &self.tap {
            t.with(|t| t.sample(&s));
        }
        self.trace.push(s);
    }

    /// Record every encoder pin change from now on (see
    /// `Bench::start_recording`), starting with the wired lines' levels
    /// `levels` at `cycle`.
    pub(super) fn start_pins(&mut self, cycle: u64, levels: &[(u8, bool)]) {
        let levels = levels
            .iter()
            .map(|&(line, level)| PinEvent { cycle, line, level })
            .collect::<Vec<_>>();
        let mut log = Log::new(PIN_CAP);
        for e in levels {
            log.push(e);
        }
        if self.retention == Retention::Latest {
            log.keep_latest();
        }
        self.pins = Some(log);
    }

    /// Give every record from now on to `tap` as it is made, starting with
    /// what the records hold now (the trace, the drive changes since reset)
    /// and the wired encoder lines' `levels` (by line) at `cycle`; the pin changes are
    /// not kept (see [`Tap`]).
    pub(super) fn stream_to(&mut self, tap: SharedTap, cycle: u64, levels: &[(u8, bool)]) {
        tap.with(|t| {
            for s in self.trace.as_slice() {
                t.sample(s);
            }
            for e in self.drive_log.as_slice() {
                t.drive(e);
            }
            for &(line, level) in levels {
                t.pin(PinEvent { cycle, line, level });
            }
        });
        self.pins = None;
        self.uart_fed = [0; 2];
        self.tap = Some(tap);
    }

    /// Give the tap the UART bytes logged since the last call (`sent`,
    /// `received`: the logs since reset), and tell it the run has settled
    /// up to `settled`.
    pub(super) fn feed_tap(
        &mut self,
        sent: &[(u64, u8, u8)],
        received: &[(u64, u8, u8)],
        settled: u64,
    ) {
        let Some(tap) = &self.tap else {
            return;
        };
        let fed = &mut self.uart_fed;
        tap.with(|t| {
            for (d, log) in [sent, received].into_iter().enumerate() {
                for &(cycle, usart, byte) in log.get(fed[d]..).unwrap_or_default() {
                    t.uart(d == 1, cycle, usart, byte);
                }
                fed[d] = log.len();
            }
            t.settle(settled);
        });
    }

    pub(super) fn trace(&self) -> &[Sample] {
        self.trace.as_slice()
    }

    pub(super) fn drive_log(&self) -> &[DriveEvent] {
        self.drive_log.as_slice()
    }

    pub(super) fn cutoffs(&self) -> &[Cutoff] {
        self.cutoffs.as_slice()
    }

    pub(super) fn motions(&self) -> &[MotionEvent] {
        self.motions.as_slice()
    }

    /// Motion changes since the start, kept or not.
    pub(super) fn motion_changes(&self) -> u64 {
        self.motions.pushed()
    }

    pub(super) fn leds(&self) -> &[LedEvent] {
        self.leds.as_slice()
    }

    pub(super) fn recording(&self) -> Option<&[PinEvent]> {
        self.pins.as_ref().map(|p| p.as_slice())
    }

    pub(super) fn analog_log(&self) -> &[AnalogEvent] {
        self.analog.as_slice()
    }
}
