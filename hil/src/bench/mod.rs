//! The bench: one emulated MCU running the firmware ELF, wired to the plant.
//!
//! Everything that happens in the plant is an event on one simavr cycle timer:
//! the next encoder transition of either wheel (computed exactly by the plant),
//! the next buffered PWM update (at the PWM timer's TOP), and a periodic plant
//! step (pose integration and trace samples). Register writes that change what
//! the H-bridge sees advance the plant to the cycle of the write and re-plan
//! the queue. Nothing polls the MCU per instruction, and nothing reads the
//! host clock: a run is a pure function of the ELF, the config and the seed.

use plant_model::{Duty, Robot, RobotConfig, Seconds, Side};
use serde::{Deserialize, Serialize};
use std::collections::VecDeque;
use thiserror::Error;

use crate::inject::{Channel, EncoderFault, Injection, LinkFault};
use crate::supply::{Bod, Supply};

use crate::elf::{ElfError, Firmware};
use crate::fwvars::{FwState, FwVars};
use crate::pwm::{PinDrive, PwmError, PwmTimer};
use crate::sim::{Avr, Core, CpuState, Handler, IoClaim, Irq, SimError};
use crate::time::Clock;
use crate::wiring::{BridgeInput, PwmSource, Wiring, HENRYTWO};
use plant_model::encoder::Watch;

/// Where in the firmware something happened.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Location {
    pub cycle: u64,
    pub robot_time_s: f64,
    pub pc: u32,
    pub function: Option<String>,
}

impl std::fmt::Display for Location {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "at robot time {:.6} s (cycle {}), PC 0x{:05x}",
            self.robot_time_s, self.cycle, self.pc
        )?;
        if let Some(func) = &self.function {
            write!(f, " in {func}")?;
        }
        Ok(())
    }
}

#[derive(Debug, Error)]
pub enum BenchError {
    #[error(transparent)]
    Elf(#[from] ElfError),
    #[error(transparent)]
    Sim(#[from] SimError),
    #[error(transparent)]
    Plant(#[from] plant_model::Error),
    #[error("{error} ({at})")]
    Pwm { error: PwmError, at: Location },
    #[error("timer {timer}: waveform mode {wgm} with clock select {cs} is not verified on this bench ({at}); the bench runs simavr's timers only in modes it has tested (timers 1 and 3: CTC; timer 0: fast PWM at /64)")]
    UnverifiedTimer {
        timer: u8,
        wgm: u8,
        cs: u8,
        at: Location,
    },
    #[error("the firmware crashed {at}")]
    Crashed { at: Location },
    #[error("the firmware stopped (sleep with interrupts disabled or a break) {at}")]
    Stopped { at: Location },
    #[error("{what}: no progress within {robot_s} s of robot time ({at})")]
    Timeout {
        what: String,
        robot_s: f64,
        at: Location,
    },
    /// The firmware was busy in a test without progress (see [`crate::hang`]).
    #[error("the firmware hung: busy in a test without progress (no wheel motion, no change of state, phase, segment or fault) for {still:.3} s of robot time, {report}", still = .0.still_s, report = .0)]
    Hang(crate::hang::HangReport),
}

/// Bench settings that are not the robot's.
#[derive(Debug, Clone, Copy)]
pub struct BenchOptions {
    pub clock: Clock,
    /// Plant step for pose integration when no other event happens.
    pub plant_step_s: f64,
    /// Interval of trace samples (a multiple of the plant step).
    pub trace_interval_s: f64,
    pub seed: u64,
    /// The battery divider on A0: volts at A0 per battery volt. 0.55 puts
    /// the thesis' LED thresholds (ADC 942 and 901 of 1023 at 5 V) at a
    /// battery of 8.37 V and 8.01 V: a 2S LiPo full, half, low.
    pub battery_divider: f64,
    /// The MCU's supply from the battery, and its brown-out detector.
    pub supply: Supply,
}

impl Default for BenchOptions {
    fn default() -> Self {
        Self {
            clock: Clock::MEGA_16MHZ,
            // The pose is stepped on its own 1 ms grid whenever the plant is
            // advanced; the step bounds the gap between the bench's looks at
            // the plant (A0, the trace) while nothing else happens.
            plant_step_s: 10e-3,
            trace_interval_s: 10e-3,
            seed: 0,
            battery_divider: 0.55,
            supply: Supply::default(),
        }
    }
}

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

/// A planned transition of an encoder: its cycle, and the plant's levels
/// `(A, B)` there when they are known from the plan (up to the plant's next
/// internal change).
#[derive(Debug, Clone, Copy)]
struct PlannedEdge {
    cycle: u64,
    levels: Option<(bool, bool)>,
}

/// How often [`Bench::run_until`] checks its `done` (robot time: 1024
/// cycles at 16 MHz). Short beside anything a test waits for, long beside
/// the 100-odd host instructions a check costs, so that the run loop is
/// simavr's own loop with one bound (the check's cycle) most of the time.
pub const CHECK_PERIOD_S: f64 = 64e-6;

/// Transitions planned per wheel beyond the next when nothing tells how
/// long the inputs will last (see `BenchCore::plan_edge`).
const EDGES_PLANNED: usize = 8;

/// At most this many transitions planned beyond the next up to the time
/// the inputs are expected to change (see `BenchCore::plan_edge`).
const EDGES_PLANNED_TO_CHANGE: usize = 32;

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
    /// When the timer drives the pin: the counter's BOTTOM cycle and
    /// prescaler, from which the exact waveform follows (see pwm.rs).
    #[serde(skip)]
    pub wave: Option<(crate::pwm::PhaseCorrect, u32, crate::pwm::Com)>,
}

/// The plant and the firmware's counters at one cycle.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Snapshot {
    pub cycle: u64,
    pub x_mm: f64,
    pub y_mm: f64,
    pub theta_rad: f64,
    /// The firmware's counters, read from SRAM at that cycle.
    pub left_count: i32,
    pub right_count: i32,
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
    pub side: SideName,
    #[serde(flatten)]
    pub at: Snapshot,
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

#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SideName {
    Left,
    Right,
}

impl From<SideName> for Side {
    fn from(s: SideName) -> Self {
        match s {
            SideName::Left => Side::Left,
            SideName::Right => Side::Right,
        }
    }
}

impl From<Side> for SideName {
    fn from(s: Side) -> Self {
        match s {
            Side::Left => SideName::Left,
            Side::Right => SideName::Right,
        }
    }
}

/// Per-pin PWM statistics.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct PinStats {
    pub pin: u8,
    /// Frequency of the waveform last seen on the pin while it was PWM.
    pub hz: f64,
    /// Time-weighted duty while the pin was not at 0.
    pub mean_active_duty: f64,
    pub active_s: f64,
    #[serde(skip)]
    duty_integral: f64,
}

/// A change the bench makes at a cycle: a fault starting or ending.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "action")]
pub enum Action {
    Encoder {
        side: SideName,
        fault: EncoderFault,
    },
    Link {
        fault: LinkFault,
    },
    MotorDisconnected {
        side: SideName,
        disconnected: bool,
    },
    /// Pull the MCU's reset line (the firmware restarts; the plant goes on).
    Reset,
    /// A fault of a motor and its wheel, in the plant (stall, load step, ...).
    Motor {
        side: SideName,
        fault: plant_model::MotorFault,
    },
    /// The ground sees only (1 - slip) of a wheel's travel.
    SlipBurst {
        side: SideName,
        slip: f64,
    },
    /// The battery's terminal voltage forced (None: the battery model again).
    /// Below the regulator's headroom VCC follows it; below the brown-out
    /// level the MCU is held in reset (see [`crate::supply`]).
    BatteryVolts {
        volts: Option<f64>,
    },
    /// A burst of glitch pulses on one encoder channel (EMI from the motor,
    /// a loose connector): `pulses` pulses `width_us` wide, one every
    /// `period_us`, each inverting the pin's level for its width.
    EncoderGlitch {
        side: SideName,
        channel: Channel,
        pulses: u32,
        width_us: f64,
        period_us: f64,
    },
    /// The host sends these bytes on the Bluetooth link (a command, a retry),
    /// one per byte time, through the link's faults.
    HostSend {
        bytes: Vec<u8>,
    },
}

/// When a scheduled action happens.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "at")]
pub enum Trigger {
    /// At a robot time (seconds since reset).
    Time { s: f64 },
    /// When the n-th spin turn (1-based) of the run starts.
    TurnStart { n: u32 },
    /// When the n-th straight leg (1-based) of the run starts.
    LegStart { n: u32 },
    /// When the n-th byte (1-based) from the host goes on the air on the
    /// Bluetooth link, before the link's faults apply to it.
    HostByte { n: u32 },
}

/// A fault to inject: when, what, and what undoes it how long after (s).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ScheduledFault {
    pub trigger: Trigger,
    pub action: Action,
    pub undo: Option<(f64, Action)>,
}

impl ScheduledFault {
    pub fn new(trigger: Trigger, action: Action) -> Self {
        Self {
            trigger,
            action,
            undo: None,
        }
    }
}

/// An action waiting for its trigger, and its undo after so many cycles.
type Armed = (Trigger, Action, Option<(u64, Action)>);

const TAG_PORT_REG: u32 = 1;
const TAG_PORT_DDR: u32 = 2;
const TAG_LED_PORT: u32 = 3;
const TAG_UART_OUT: u32 = 16; // + USART number

const SIDES: [Side; 2] = [Side::Left, Side::Right];
/// MCUSR (data space) and its brown-out reset flag.
const MCUSR: u16 = 0x54;
const MCUSR_BORF: u8 = 1 << 2;
const NEVER: u64 = u64::MAX;
/// Analog comparator control and status (data-space address) and its
/// interrupt-enable and input-capture-enable bits (ATmega2560 datasheet).
const ACSR: u16 = 0x50;
const ACSR_ACIE: u8 = 1 << 3;
const ACSR_ACIC: u8 = 1 << 2;

/// simavr-owned timers whose modes the bench checks: (timer, TCCRnA, TCCRnB).
const CHECKED_TIMERS: [(u8, u16, u16); 4] = [
    (0, 0x44, 0x45),
    (1, 0x80, 0x81),
    (3, 0x90, 0x91),
    (5, 0x120, 0x121),
];

/// The bench's side of the simulation (see the module docs).
pub struct BenchCore {
    clock: Clock,
    wiring: Wiring,
    pub robot: Robot,
    timer2: PwmTimer,
    timer4: PwmTimer,
    pending_top: [u64; 2],
    port_value: u8,
    port_ddr: u8,
    /// (forward, reverse) duty applied to each motor's bridge, by side index.
    bridge: [(f64, f64); 2],
    enc_irq: [[Option<Irq>; 2]; 2],
    enc_level: [[bool; 2]; 2],
    /// Per side: channel B is raised only when the firmware reads its PIN
    /// register (or with an A edge), not at its own transitions. Exact while
    /// nothing but a read can see B (see `update_lazy_b`).
    lazy_b: [bool; 2],
    /// Lazy B is allowed at all (off when the true waveform is wanted, e.g.
    /// for a VCD).
    lazy_b_allowed: bool,
    /// A planned edge may be raised from the plan alone, the plant left
    /// where it is, and a lazy B read right after an A edge answered
    /// without it (off only to check that this changes nothing).
    lean_edges: bool,
    /// Callbacks that raised planned edges from the plan alone.
    pub lean_edge_callbacks: u64,
    /// The analog comparator's interrupt or input capture is on (ACSR): a
    /// B line on AIN1 is then watched by hardware.
    comparator_on: bool,
    /// PIN reads that brought a lazy B up to date.
    pub lazy_b_reads: u64,
    /// PIN reads of a lazy B answered from the last A edge, the plant not
    /// looked at.
    pub quiet_b_reads: u64,
    /// PIN reads of a lazy B that evaluated the plant.
    pub b_reads_evaluated: u64,
    /// A edges raised on the pins, signed as the thesis' decoder counts them.
    pub edges_raised: [i64; 2],
    /// Cycle at which the last A edge of each encoder was due (the plant's
    /// edge time; simavr raises it at the first instruction boundary after).
    pub last_a_edge: [u64; 2],
    next_edge: [u64; 2],
    /// The transitions planned after `next_edge` under the present inputs,
    /// latest first: an edge's callback pops the next one instead of
    /// searching (any change re-plans from scratch).
    planned: [Vec<PlannedEdge>; 2],
    /// Cycle of each wheel's last input change, and the cycles between its
    /// last two (0: not seen yet): a controller changes them at its own
    /// period, and a plan made at a change reaches about that far.
    input_changed_at: [u64; 2],
    input_period: [u64; 2],
    /// The plant's levels `(A, B)` at `next_edge`, when known in advance.
    next_levels: [Option<(bool, bool)>; 2],
    /// Cycles after a planned A edge during which the wheel cannot reach a
    /// B boundary (half a state at its present motion's top speed), and
    /// the cycle up to which a read of a lazy B needs no look at the plant.
    b_quiet_cycles: [u64; 2],
    b_quiet_until: [u64; 2],
    /// Next change of the plant's own dynamics.
    next_internal: u64,
    next_step: u64,
    step_cycles: u64,
    trace_every: u32,
    steps: u32,
    plant_cycle: u64,
    /// Cycle up to which the PWM statistics are integrated.
    stats_cycle: u64,
    pub uart_out: [Vec<u8>; 4],
    /// Bytes the firmware sent: (cycle, USART, byte).
    pub uart_log: Vec<(u64, u8, u8)>,
    pub trace: Vec<Sample>,
    pub drive_log: Vec<DriveEvent>,
    pub cutoffs: Vec<Cutoff>,
    pub motions: Vec<MotionEvent>,
    pub pins: [PinStats; 4],
    vars: FwVars,
    pub inject: Injection,
    /// Bytes from the host waiting to go out on each USART, one per byte time.
    uart_tx: [VecDeque<u8>; 4],
    uart_next: [u64; 4],
    uart_irq: [Option<Irq>; 4],
    uart_byte_cycles: u64,
    /// A0, driven with the battery's voltage through the divider.
    adc0: Option<Irq>,
    adc_mv: u32,
    battery_divider: f64,
    /// Scheduled actions, sorted by cycle (stable for equal cycles).
    actions: Vec<(u64, Action)>,
    /// Encoder levels after the encoder faults, before glitches.
    enc_base: [[bool; 2]; 2],
    /// Glitch pulse edges to come: (cycle, side, channel, on), sorted.
    glitches: Vec<(u64, usize, usize, bool)>,
    /// Bytes from the host that went on the air on the Bluetooth link.
    host_bytes: u32,
    supply: Supply,
    startup_cycles: u64,
    /// The brown-out detector's state; while it holds the reset, the run
    /// loop executes nothing.
    bod: Bod,
    vcc_v: f64,
    /// Duty each bridge input sees (in `bridge_inputs` order).
    input_duties: [f64; 4],
    /// The battery voltage `update_supply` last saw.
    supply_battery_v: f64,
    /// Set when the detector lets go: the run loop restarts the MCU with
    /// BORF set.
    pub bod_release_pending: bool,
    /// Brown-out resets: the cycle the detector pulled the reset and the
    /// cycle it let go (None while it still holds).
    pub brownouts: Vec<(u64, Option<u64>)>,
    /// Battery LED changes.
    pub leds: Vec<LedEvent>,
    /// Actions waiting for an event, with an optional duration in cycles
    /// after which `undo` runs.
    triggered: Vec<Armed>,
    turns_started: u32,
    legs_started: u32,
    /// Set by a Reset action; the run loop resets the MCU after the step.
    pub reset_requested: bool,
    /// Log of the actions applied: (cycle, action).
    pub applied: Vec<(u64, Action)>,
    /// Encoder pin changes, when recording (for replays without the bench).
    pub recording: Option<Vec<PinEvent>>,
    /// Every change of the analog inputs since cycle 0 (rare: the battery's
    /// steps), for replays without the bench.
    pub analog_log: Vec<AnalogEvent>,
    /// Callbacks from simavr into the bench (timer, IO, IRQ).
    pub callbacks: u64,
    error: Option<PendingError>,
    /// Set with `error`.
    failed: bool,
    /// Something for the run loop: an error or a reset (one flag read per
    /// instruction).
    attention: bool,
}

enum PendingError {
    Pwm(PwmError, u64, u32),
    Timer {
        timer: u8,
        wgm: u8,
        cs: u8,
        cycle: u64,
        pc: u32,
    },
}

fn side_index(side: Side) -> usize {
    match side {
        Side::Left => 0,
        Side::Right => 1,
    }
}

/// The thesis' encoder ISR: the count change for an A edge to level `a`
/// while B is at `b`.
pub fn decode_a_edge(a: bool, b: bool) -> i64 {
    match (a, b) {
        (true, false) | (false, true) => 1,
        _ => -1,
    }
}

impl BenchCore {
    fn timer_mut(&mut self, which: usize) -> &mut PwmTimer {
        if which == 0 {
            &mut self.timer2
        } else {
            &mut self.timer4
        }
    }

    fn input_duty(&self, input: &BridgeInput) -> f64 {
        let bit = 1u8 << input.pin.bit;
        if self.port_ddr & bit == 0 {
            // An input pin floats; the DRV8833's inputs have internal
            // pull-downs, so the bridge sees low.
            return 0.0;
        }
        let drive = match input.pwm {
            PwmSource::Timer2(ch) => self.timer2.drive(ch, self.clock.hz()),
            PwmSource::Timer4(ch) => self.timer4.drive(ch, self.clock.hz()),
        };
        match drive {
            PinDrive::Gpio => f64::from(self.port_value & bit != 0),
            PinDrive::Pwm { duty, .. } => duty,
        }
    }

    fn input_hz(&self, input: &BridgeInput) -> Option<f64> {
        let drive = match input.pwm {
            PwmSource::Timer2(ch) => self.timer2.drive(ch, self.clock.hz()),
            PwmSource::Timer4(ch) => self.timer4.drive(ch, self.clock.hz()),
        };
        match drive {
            PinDrive::Pwm { hz, duty } if hz > 0.0 && duty > 0.0 && duty < 1.0 => Some(hz),
            _ => None,
        }
    }

    fn advance_plant(&mut self, cycle: u64) {
        if cycle > self.plant_cycle {
            // The plant refuses only time going backwards, which the check
            // above rules out.
            let _ = self.robot.advance_to(self.clock.seconds(cycle));
            self.plant_cycle = cycle;
        }
    }

    /// Bring the plant and the PWM statistics to `cycle`. Between its own
    /// events the bench lets the plant lag (a planned edge needs nothing of
    /// it); whoever looks at them from outside a callback sees them synced.
    pub fn sync(&mut self, cycle: u64) {
        self.advance_plant(cycle);
        self.integrate_pin_stats(cycle);
    }

    /// The PWM statistics integrate the duty held since the last change
    /// (or sync), in the same pieces however the plant is advanced.
    fn integrate_pin_stats(&mut self, cycle: u64) {
        if cycle > self.stats_cycle {
            let dt = self.clock.seconds(cycle - self.stats_cycle).0;
            for (i, &d) in self.input_duties.iter().enumerate() {
                if d > 0.0 {
                    self.pins[i].active_s += dt;
                    self.pins[i].duty_integral += d * dt;
                }
            }
            self.stats_cycle = cycle;
        }
    }

    /// What each bridge input sees, for the PWM statistics: recomputed
    /// after every change of the timers' and the port's registers (the
    /// statistics first integrate what was held up to `cycle`).
    fn update_input_duties(&mut self, cycle: u64) {
        self.integrate_pin_stats(cycle);
        let duties = self
            .wiring
            .bridge_inputs()
            .map(|input| self.input_duty(&input));
        self.input_duties = duties;
    }

    /// Re-read what the bridge inputs see; apply changes to the plant.
    fn refresh_bridge(&mut self, core: &Core, cycle: u64) {
        self.advance_plant(cycle);
        self.update_input_duties(cycle);
        let mut changed = [false; 2];
        for side in SIDES {
            let m = *self.wiring.motor(side);
            let i = side_index(side);
            let (fwd, rev) = if self.inject.motor_disconnected[i] {
                (0.0, 0.0)
            } else {
                (self.input_duty(&m.forward), self.input_duty(&m.reverse))
            };
            let (old_f, old_r) = self.bridge[i];
            if (fwd, rev) == (old_f, old_r) {
                continue;
            }
            changed[i] = true;
            for (input, old, new) in [(m.forward, old_f, fwd), (m.reverse, old_r, rev)] {
                if old != new {
                    let wave = match input.pwm {
                        PwmSource::Timer2(ch) => self.timer2.waveform(ch),
                        PwmSource::Timer4(ch) => self.timer4.waveform(ch),
                    }
                    .filter(|(_, _, com)| *com != crate::pwm::Com::Disconnected);
                    self.drive_log.push(DriveEvent {
                        cycle,
                        pin: input.pin.arduino,
                        duty: new,
                        wave,
                    });
                    if let Some(hz) = self.input_hz(&input) {
                        let k = self.pin_slot(input.pin.arduino);
                        self.pins[k].hz = hz;
                    }
                }
            }
            if (old_f > 0.0 && fwd == 0.0) || (old_r > 0.0 && rev == 0.0) {
                let at = self.snapshot(core, cycle);
                self.cutoffs.push(Cutoff {
                    side: side.into(),
                    at,
                });
            }
            self.bridge[i] = (fwd, rev);
            self.robot.set_bridge(
                side,
                Duty::new(fwd).unwrap_or(Duty::from_pwm8(0)),
                Duty::new(rev).unwrap_or(Duty::from_pwm8(0)),
            );
        }
        if changed != [false; 2] {
            // Only a changed wheel's motion changes (the battery follows at
            // its next internal change, which re-plans both).
            self.plan_internal(cycle);
            for side in SIDES {
                let i = side_index(side);
                if changed[i] {
                    if self.input_changed_at[i] != 0 {
                        self.input_period[i] = cycle - self.input_changed_at[i];
                    }
                    self.input_changed_at[i] = cycle;
                    self.plan_edge(side, cycle);
                }
            }
            let sign = |(f, r): (f64, f64)| match (f > 0.0, r > 0.0) {
                (false, false) => 0,
                (true, false) => 1,
                (false, true) => -1,
                (true, true) => 2,
            };
            let motion = Motion::classify(sign(self.bridge[0]), sign(self.bridge[1]));
            if self.motions.last().map(|m| m.motion) != Some(motion) {
                let at = self.snapshot(core, cycle);
                self.motions.push(MotionEvent { motion, at });
                self.fire_triggers(cycle, motion);
            }
        }
    }

    /// The plant and the firmware's counters now (`cycle` is the current one).
    pub fn snapshot(&self, core: &Core, cycle: u64) -> Snapshot {
        let pose = self.robot.pose();
        Snapshot {
            cycle,
            x_mm: pose.x().0,
            y_mm: pose.y().0,
            theta_rad: pose.theta().0,
            left_count: read_i32(core, self.vars.left_count),
            right_count: read_i32(core, self.vars.right_count),
            left_edges: self.robot.a_edges(Side::Left),
            right_edges: self.robot.a_edges(Side::Right),
            left_mm: self.robot.distance_travelled(Side::Left).0,
            right_mm: self.robot.distance_travelled(Side::Right).0,
        }
    }

    fn pin_slot(&self, arduino: u8) -> usize {
        self.wiring
            .bridge_inputs()
            .iter()
            .position(|b| b.pin.arduino == arduino)
            .expect("pin is a bridge input")
    }

    fn plan_edges(&mut self, now: u64) {
        // The edges are planned ahead up to the internal change: that first.
        self.plan_internal(now);
        for side in SIDES {
            self.plan_edge(side, now);
        }
    }

    /// When the plant's own dynamics change next (battery sag steps, ...):
    /// both wheels' predictions must be redone then.
    fn plan_internal(&mut self, now: u64) {
        self.next_internal = match self.robot.next_internal_change() {
            Some(t) => self.clock.cycle_at_or_after(t).max(now + 1),
            None => NEVER,
        };
    }

    /// Plan `side`'s next transitions from `now` under the present inputs:
    /// the next one and up to [`EDGES_PLANNED`] after it, with the
    /// plant's levels at each, so that the callbacks of the planned edges
    /// need nothing of the plant (`raise_planned_edges`).
    fn plan_edge(&mut self, side: Side, now: u64) {
        let i = side_index(side);
        let watch = self.watch(i);
        let grid = self.clock.grid();
        self.next_edge[i] = match self.robot.next_encoder_transition_on(side, watch, grid) {
            Some(cycle) => cycle.max(now + 1),
            None => NEVER,
        };
        self.next_levels[i] = self.planned_levels(side, self.next_edge[i]);
        // The motion changed: a quiet window from before no longer holds.
        self.b_quiet_until[i] = 0;
        let quiet = self.robot.encoder_travel_time_bound(side, 0.5).0 * self.clock.hz() as f64;
        self.b_quiet_cycles[i] = if quiet.is_finite() {
            quiet.max(0.0) as u64
        } else {
            NEVER
        };
        self.planned[i].clear();
        // Planned to the inputs' expected change (and the first edge after
        // it, in case the change is late): what is planned beyond a change
        // is wasted, and a plan that runs out early costs a refill.
        let period = self.input_period[i];
        let (most, horizon) = if period != 0 && now == self.input_changed_at[i] {
            (EDGES_PLANNED_TO_CHANGE, now.saturating_add(period))
        } else {
            (EDGES_PLANNED, NEVER)
        };
        self.fill_plan(side, watch, self.next_edge[i], most, horizon);
    }

    /// Plan up to `most` transitions of `side` after the one at `after` into
    /// its empty plan, stopping at the first at or after `horizon`.
    fn fill_plan(&mut self, side: Side, watch: Watch, mut after: u64, most: usize, horizon: u64) {
        let i = side_index(side);
        let grid = self.clock.grid();
        let mut planned = std::mem::take(&mut self.planned[i]);
        debug_assert!(planned.is_empty(), "a plan is filled when it ran out");
        // Planning ahead holds up to the plant's next internal change only.
        while planned.len() < most && after < horizon && after < self.next_internal {
            match self
                .robot
                .next_encoder_transition_on_after(side, watch, grid, after)
            {
                Some(cycle) => {
                    planned.push(PlannedEdge {
                        cycle,
                        levels: self.planned_levels(side, cycle),
                    });
                    after = cycle;
                }
                None => break,
            }
        }
        planned.reverse();
        self.planned[i] = planned;
    }

    /// The plant's levels of `side` at a planned transition, if the plan
    /// knows them: before the plant's next internal change, under the
    /// present inputs (the search just evaluated that instant, so this is
    /// cheap).
    fn planned_levels(&self, side: Side, cycle: u64) -> Option<(bool, bool)> {
        (cycle < self.next_internal && !self.robot.encoder(side).is_flawed()).then(|| {
            self.robot
                .encoder_levels_at(side, self.clock.seconds(cycle))
        })
    }

    /// What the firmware can see change on encoder `i`: A alone while B is
    /// raised lazily, both lines otherwise.
    fn watch(&self, i: usize) -> Watch {
        if self.lazy_b[i] {
            Watch::A
        } else {
            Watch::Both
        }
    }

    /// `side`'s plan ran out at its edge at `now`: planned on from that
    /// edge, without the plant, which need not be there (the plan's edges
    /// are the ones a plan made there would hold: the inputs are the same).
    /// False when it cannot be, or no edge is left to plan: the plant must
    /// come to `now` and plan from there.
    fn refill_plan(&mut self, side: Side, now: u64) -> bool {
        let i = side_index(side);
        if !self.planned[i].is_empty() {
            return true;
        }
        if self.next_edge[i] != now || self.next_levels[i].is_none() {
            return false;
        }
        let watch = self.watch(i);
        self.fill_plan(side, watch, now, EDGES_PLANNED, NEVER);
        !self.planned[i].is_empty()
    }

    /// `side`'s planned edge came: the next planned one, or a new plan.
    fn next_planned_edge(&mut self, side: Side, now: u64) {
        let i = side_index(side);
        match self.planned[i].pop() {
            Some(edge) => {
                self.next_edge[i] = edge.cycle;
                self.next_levels[i] = edge.levels;
            }
            None => self.plan_edge(side, now),
        }
    }

    fn next_event(&self) -> u64 {
        let bod = match self.bod {
            Bod::Releasing { at } => at,
            _ => NEVER,
        };
        self.next_edge[0]
            .min(self.next_edge[1])
            .min(self.next_other_event())
            .min(bod)
    }

    /// The next event that is not an encoder edge (nor the brown-out
    /// detector's release).
    fn next_other_event(&self) -> u64 {
        let uart = self.uart_next.iter().copied().min().unwrap_or(NEVER);
        let action = self.actions.first().map_or(NEVER, |a| a.0);
        let glitch = self.glitches.first().map_or(NEVER, |g| g.0);
        self.next_step
            .min(self.pending_top[0])
            .min(self.pending_top[1])
            .min(uart)
            .min(action)
            .min(self.next_internal)
            .min(glitch)
    }

    /// What a cycle timer callback returns: the next event, or 0 for none.
    fn next_timer(&self) -> u64 {
        match self.next_event() {
            NEVER => 0,
            next => next,
        }
    }

    /// The brown-out detector holds the MCU in reset.
    pub fn held_in_reset(&self) -> bool {
        self.bod.holds_reset()
    }

    /// VCC from the battery now, the ADC's reference with it, and the
    /// brown-out detector's reaction (see [`crate::supply`]).
    fn update_supply(&mut self, core: &mut Core, cycle: u64) {
        let battery = self.robot.battery_voltage().0;
        // With the battery as it was, only a detector counting down its
        // start-up time-out can change.
        if battery == self.supply_battery_v && !matches!(self.bod, Bod::Releasing { .. }) {
            return;
        }
        self.supply_battery_v = battery;
        let vcc = self.supply.vcc(battery);
        if vcc != self.vcc_v {
            self.vcc_v = vcc;
            let mv = (vcc * 1000.0).round() as u32;
            core.set_supply_mv(mv);
            self.analog_log.push(AnalogEvent {
                cycle,
                input: AnalogInput::Supply,
                mv,
            });
        }
        let before = self.bod.holds_reset();
        self.bod = self.bod.next(&self.supply, vcc, cycle, self.startup_cycles);
        match (before, self.bod.holds_reset()) {
            (false, true) => {
                self.brownouts.push((cycle, None));
                self.reset_requested = true;
                self.attention = true;
            }
            (true, false) => {
                if let Some(b) = self.brownouts.last_mut() {
                    b.1 = Some(cycle);
                }
                self.bod_release_pending = true;
                self.attention = true;
            }
            _ => {}
        }
    }

    /// Schedule `action` at `cycle` (kept sorted; equal cycles keep order).
    pub fn schedule_action(&mut self, cycle: u64, action: Action) {
        let pos = self.actions.partition_point(|a| a.0 <= cycle);
        self.actions.insert(pos, (cycle, action));
    }

    /// Run `action` when `trigger` fires, and `undo` `duration` cycles later.
    pub fn schedule_triggered(
        &mut self,
        trigger: Trigger,
        action: Action,
        undo: Option<(u64, Action)>,
    ) {
        match trigger {
            Trigger::Time { s } => {
                let at = self.clock.cycle_at_or_after(Seconds(s));
                if let Some((d, u)) = undo {
                    self.schedule_action(at + d, u);
                }
                self.schedule_action(at, action);
            }
            _ => self.triggered.push((trigger, action, undo)),
        }
    }

    fn apply_due_actions(&mut self, core: &mut Core, when: u64) {
        while self.actions.first().is_some_and(|a| a.0 <= when) {
            let (_, action) = self.actions.remove(0);
            self.apply_action(core, when, action);
        }
    }

    fn fire_triggers(&mut self, cycle: u64, motion: Motion) {
        let event = match motion {
            Motion::SpinCw | Motion::SpinCcw => {
                self.turns_started += 1;
                Trigger::TurnStart {
                    n: self.turns_started,
                }
            }
            Motion::Forward => {
                self.legs_started += 1;
                Trigger::LegStart {
                    n: self.legs_started,
                }
            }
            _ => return,
        };
        self.fire_event(event, cycle);
    }

    /// Schedule at `cycle` every action armed for `event`.
    fn fire_event(&mut self, event: Trigger, cycle: u64) {
        let mut i = 0;
        while i < self.triggered.len() {
            if self.triggered[i].0 == event {
                let (_, action, undo) = self.triggered.remove(i);
                if let Some((d, u)) = undo {
                    self.schedule_action(cycle + d, u);
                }
                self.schedule_action(cycle, action);
            } else {
                i += 1;
            }
        }
    }

    fn apply_action(&mut self, core: &mut Core, cycle: u64, action: Action) {
        self.applied.push((cycle, action.clone()));
        match action {
            Action::Encoder { side, fault } => {
                // B must be exact from here on if the fault acts on the lines.
                self.advance_plant(cycle);
                self.raise_encoders(core, cycle);
                self.inject.encoder[side as usize] = fault;
                self.update_lazy_b(core, cycle);
            }
            Action::Link { fault } => self.inject.link = fault,
            Action::MotorDisconnected { side, disconnected } => {
                self.inject.motor_disconnected[side as usize] = disconnected;
                // Force a re-read: the plant sees the bridge anew.
                self.bridge[side as usize] = (f64::NAN, f64::NAN);
                self.refresh_bridge(core, cycle);
            }
            Action::Reset => {
                self.reset_requested = true;
                self.attention = true;
            }
            Action::Motor { side, fault } => {
                let _ = self.robot.set_motor_fault(side.into(), fault);
                self.plan_edges(cycle);
            }
            Action::SlipBurst { side, slip } => {
                let _ = self.robot.set_slip_burst(side.into(), slip);
            }
            Action::BatteryVolts { volts } => {
                let _ = self
                    .robot
                    .set_battery_voltage_override(volts.map(plant_model::Volts));
                self.plan_edges(cycle);
                self.update_supply(core, cycle);
            }
            Action::EncoderGlitch {
                side,
                channel,
                pulses,
                width_us,
                period_us,
            } => {
                let width = self.clock.cycles_in(Seconds(width_us * 1e-6)).max(1);
                let period = self
                    .clock
                    .cycles_in(Seconds(period_us * 1e-6))
                    .max(width + 1);
                let (i, ch) = (side as usize, channel as usize);
                for k in 0..pulses as u64 {
                    let on = cycle + k * period;
                    self.glitches.push((on, i, ch, true));
                    self.glitches.push((on + width, i, ch, false));
                }
                self.glitches.sort_by_key(|g| g.0);
            }
            Action::HostSend { bytes } => {
                let n = self.wiring.bluetooth_uart as usize;
                self.queue_uart(n, &bytes, cycle);
            }
        }
    }

    /// Bring the bench's own peripheral models to their reset state.
    pub fn after_reset(&mut self, core: &mut Core) {
        let cycle = core.cycle();
        self.comparator_on = false;
        self.update_lazy_b(core, cycle);
        self.timer2 = PwmTimer::timer2();
        self.timer4 = PwmTimer::timer4();
        self.pending_top = [NEVER; 2];
        self.port_value = 0;
        self.port_ddr = 0;
        self.refresh_bridge(core, cycle);
        // The LED pins are inputs again: all dark.
        self.log_leds(cycle, 0);
    }

    fn log_leds(&mut self, cycle: u64, port: u8) {
        let l = self.wiring.battery_leds;
        let lit = |p: crate::wiring::Pin| port >> p.bit & 1 != 0;
        let e = LedEvent {
            cycle,
            green: lit(l.green),
            blue: lit(l.blue),
            red: lit(l.red),
        };
        let same = |x: &LedEvent| (x.green, x.blue, x.red) == (e.green, e.blue, e.red);
        // The log starts dark: only a change is an event.
        let dark_start = self.leds.is_empty() && port == 0;
        if !(dark_start || self.leds.last().is_some_and(same)) {
            self.leds.push(e);
        }
    }

    /// Queue bytes from the host for USART `n`.
    pub fn queue_uart(&mut self, n: usize, bytes: &[u8], now: u64) {
        // Link faults apply when a byte goes over the air (see `timer`).
        self.uart_tx[n].extend(bytes.iter().copied());
        if self.uart_next[n] == NEVER && !self.uart_tx[n].is_empty() {
            self.uart_next[n] = now + 1;
        }
    }

    /// Decide per side whether channel B may be raised lazily: only when the
    /// pin it is wired to can start nothing in the MCU by itself (no external
    /// or pin-change interrupt, input capture or counter input; on AIN1 only
    /// while the comparator's interrupt and capture are off), no encoder fault
    /// is active on that side, and the true waveform is not wanted. Then the
    /// firmware can see B only by reading its PIN register, and the bench
    /// brings B up to date right before every such read: what the firmware
    /// reads is exactly what it would read with every B edge raised, at half
    /// the events. On a change the lines are brought up to date and both
    /// wheels re-planned.
    fn update_lazy_b(&mut self, core: &mut Core, cycle: u64) {
        let mut lazy = [false; 2];
        for side in SIDES {
            let i = side_index(side);
            let b = self.wiring.encoder(side).b;
            lazy[i] = self.lazy_b_allowed
                && self.inject.encoder[i] == EncoderFault::Healthy
                && !b.can_interrupt()
                && !(b.is_comparator_input() && self.comparator_on);
        }
        if lazy != self.lazy_b {
            self.advance_plant(cycle);
            self.raise_encoders(core, cycle);
            self.lazy_b = lazy;
            self.plan_edges(cycle);
        }
    }

    fn raise_encoders(&mut self, core: &mut Core, when: u64) {
        for side in SIDES {
            let plant = self.robot.encoder_levels(side);
            self.raise_side(core, when, side_index(side), plant);
        }
    }

    /// Show the plant's levels `plant` of encoder `i` on its pins, through
    /// the encoder faults and glitches.
    fn raise_side(&mut self, core: &mut Core, when: u64, i: usize, plant: (bool, bool)) {
        let [base_a, base_b] = self.enc_base[i];
        let (base_a, base_b) = self.inject.encoder_levels(i, plant, (base_a, base_b));
        self.enc_base[i] = [base_a, base_b];
        // A glitch pulse inverts what the pin shows while it lasts.
        let [ga, gb] = self.inject.glitch[i];
        let (a, b) = (base_a ^ ga, base_b ^ gb);
        let [old_a, old_b] = self.enc_level[i];
        let [Some(irq_a), Some(irq_b)] = self.enc_irq[i] else {
            return;
        };
        if b != old_b {
            core.raise(irq_b, b as u32);
            self.enc_level[i][1] = b;
            if let Some(rec) = &mut self.recording {
                rec.push(PinEvent {
                    cycle: when,
                    line: 2 * i as u8 + 1,
                    level: b,
                });
            }
        }
        if a != old_a {
            core.raise(irq_a, a as u32);
            if let Some(rec) = &mut self.recording {
                rec.push(PinEvent {
                    cycle: when,
                    line: 2 * i as u8,
                    level: a,
                });
            }
            self.enc_level[i][0] = a;
            self.edges_raised[i] += decode_a_edge(a, b);
            self.last_a_edge[i] = when;
        }
    }

    /// The callback of planned encoder edges with nothing else due at
    /// `when`: the plan knows the levels, so the plant is left where it is
    /// (it catches up at the next event that needs it). False, having done
    /// nothing, when that is not the case.
    fn raise_planned_edges(&mut self, core: &mut Core, when: u64) -> bool {
        let others = self.next_other_event();
        if !self.lean_edges || others <= when || matches!(self.bod, Bod::Releasing { .. }) {
            return false;
        }
        let due = self.next_edge.map(|c| c <= when);
        if due == [false; 2] {
            return false;
        }
        for (i, due) in due.into_iter().enumerate() {
            let plain = self.next_levels[i].is_some()
                && self.inject.encoder[i] == EncoderFault::Healthy
                && self.inject.glitch[i] == [false; 2];
            if due && !(plain && self.refill_plan(SIDES[i], when)) {
                return false;
            }
        }
        for side in SIDES {
            let i = side_index(side);
            if let (true, Some(levels)) = (due[i], self.next_levels[i]) {
                self.raise_side(core, when, i, levels);
                if self.lazy_b[i] {
                    // Watching A alone, this was an A edge: B changes half a
                    // state away at the least.
                    self.b_quiet_until[i] = when.saturating_add(self.b_quiet_cycles[i]);
                }
                self.next_planned_edge(side, when);
            }
        }
        self.lean_edge_callbacks += 1;
        true
    }

    /// Drive A0 with the battery's voltage when it changed.
    fn update_adc(&mut self, core: &mut Core, cycle: u64) {
        // A pin cannot rise above VCC (its protection diodes clamp it).
        let mv = (self.robot.battery_voltage().0 * self.battery_divider * 1000.0)
            .round()
            .clamp(0.0, (self.vcc_v * 1000.0).round()) as u32;
        if mv != self.adc_mv {
            if let Some(irq) = self.adc0 {
                core.raise(irq, mv);
            }
            self.adc_mv = mv;
            self.analog_log.push(AnalogEvent {
                cycle,
                input: AnalogInput::Adc0,
                mv,
            });
        }
    }

    fn sample(&mut self, cycle: u64) {
        let pose = self.robot.pose();
        self.trace.push(Sample {
            t_s: self.clock.seconds(cycle).0,
            x_mm: pose.x().0,
            y_mm: pose.y().0,
            theta_rad: pose.theta().0,
            left_edges: self.robot.a_edges(Side::Left),
            right_edges: self.robot.a_edges(Side::Right),
            left_duty: self.bridge[0].0 - self.bridge[0].1,
            right_duty: self.bridge[1].0 - self.bridge[1].1,
        });
    }

    fn check_simavr_timer(&mut self, core: &Core, timer: u8, a: u16, b: u16) {
        let tccra = core.data(a);
        let tccrb = core.data(b);
        let cs = tccrb & 0b111;
        if cs == 0 {
            return; // not clocked: any mode is harmless
        }
        let wgm = ((tccrb >> 3) & 0b11) << 2 | (tccra & 0b11);
        // Verified by tests/timers.rs: CTC on timers 1 and 3 (the robust
        // build's tick and delays), and Arduino's timer 0 (fast PWM, /64,
        // overflow interrupt every 1024 us: millis and micros).
        let verified = matches!((timer, wgm, cs), (1, 4, 1..=5) | (3, 4, 1..=5) | (0, 3, 3));
        if !verified && self.error.is_none() {
            self.failed = true;
            self.attention = true;
            self.error = Some(PendingError::Timer {
                timer,
                wgm,
                cs,
                cycle: core.cycle(),
                pc: core.pc(),
            });
        }
    }

    /// Mean active duty per pin, finalised.
    pub fn pin_stats(&self) -> [PinStats; 4] {
        let mut out = self.pins;
        for p in &mut out {
            p.mean_active_duty = if p.active_s > 0.0 {
                p.duty_integral / p.active_s
            } else {
                0.0
            };
        }
        out
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

impl Handler for BenchCore {
    fn io_write(&mut self, core: &mut Core, addr: u16, value: u8) {
        self.callbacks += 1;
        let cycle = core.cycle();
        if addr == ACSR {
            // Observed: simavr's comparator has stored the value already.
            self.comparator_on = value & (ACSR_ACIE | ACSR_ACIC) != 0;
            self.update_lazy_b(core, cycle);
            core.schedule(self.next_event());
            return;
        }
        if let Some(&(timer, a, b)) = CHECKED_TIMERS.iter().find(|t| t.1 == addr || t.2 == addr) {
            self.check_simavr_timer(core, timer, a, b);
            return;
        }
        let which = if self.timer2.owns_write(addr) { 0 } else { 1 };
        // The bench emulates these registers; keep data space readable.
        core.set_data(addr, value);
        // Bring the plant to this cycle before the output can change.
        self.advance_plant(cycle);
        let written = self.timer_mut(which).write(addr, value, cycle);
        self.update_input_duties(cycle);
        match written {
            Ok(effect) => {
                if effect.pending_update {
                    self.pending_top[which] = self
                        .timer_mut(which)
                        .pending_update_at(cycle)
                        .unwrap_or(NEVER);
                }
                if effect.outputs_changed {
                    self.refresh_bridge(core, cycle);
                    if self.pending_top[which] == NEVER {
                        // A timer that just started applies buffered
                        // values at its first TOP.
                        self.pending_top[which] = self
                            .timer_mut(which)
                            .pending_update_at(cycle)
                            .unwrap_or(NEVER);
                    }
                }
                core.schedule(self.next_event());
            }
            Err(e) => {
                if self.error.is_none() {
                    self.failed = true;
                    self.attention = true;
                    self.error = Some(PendingError::Pwm(e, cycle, core.pc()));
                }
            }
        }
    }

    fn attention(&self) -> bool {
        self.attention
    }

    fn before_io_read(&mut self, core: &mut Core, addr: u16) {
        // A lazily raised B is brought to its level at this cycle (see
        // `update_lazy_b`). The plant is not advanced: its closed form holds
        // until its next event, which has not come yet.
        let cycle = core.cycle();
        for side in SIDES {
            let i = side_index(side);
            if !self.lazy_b[i] || self.wiring.encoder(side).b.pin_register() != addr {
                continue;
            }
            // Shortly after a planned A edge the plant's B is the one raised
            // with it (when nothing but the plant drives the line).
            if cycle < self.b_quiet_until[i]
                && self.inject.encoder[i] == EncoderFault::Healthy
                && self.inject.glitch[i] == [false; 2]
            {
                self.quiet_b_reads += 1;
                continue;
            }
            self.b_reads_evaluated += 1;
            let t = Seconds(self.clock.seconds(cycle).0.max(self.robot.now().0));
            // As `raise_encoders` computes it: the faults on the plant's
            // levels, then a glitch pulse's inversion.
            let (_, base_b) = self.inject.encoder_levels(
                i,
                self.robot.encoder_levels_at(side, t),
                (self.enc_base[i][0], self.enc_base[i][1]),
            );
            self.enc_base[i][1] = base_b;
            let b = base_b ^ self.inject.glitch[i][1];
            let old_b = self.enc_level[i][1];
            if b != old_b {
                if let Some(irq_b) = self.enc_irq[i][1] {
                    core.raise(irq_b, b as u32);
                }
                self.enc_level[i][1] = b;
                self.lazy_b_reads += 1;
                if let Some(rec) = &mut self.recording {
                    rec.push(PinEvent {
                        cycle,
                        line: 2 * i as u8 + 1,
                        level: b,
                    });
                }
            }
        }
    }

    fn io_read(&mut self, core: &mut Core, addr: u16) -> u8 {
        let timer = if self.timer2.read_addresses().contains(&addr) {
            &self.timer2
        } else {
            &self.timer4
        };
        let err = timer.read(addr);
        if self.error.is_none() {
            self.failed = true;
            self.attention = true;
            self.error = Some(PendingError::Pwm(err, core.cycle(), core.pc()));
        }
        0
    }

    fn timer(&mut self, core: &mut Core, when: u64) -> u64 {
        self.callbacks += 1;
        if self.raise_planned_edges(core, when) {
            return self.next_timer();
        }
        let edge_due = self.next_edge.map(|c| c <= when);
        self.advance_plant(when);
        for which in 0..2 {
            if self.pending_top[which] <= when {
                self.timer_mut(which).apply_buffered();
                self.pending_top[which] = NEVER;
                self.refresh_bridge(core, when);
            }
        }
        self.apply_due_actions(core, when);
        while self.glitches.first().is_some_and(|g| g.0 <= when) {
            let (_, i, ch, on) = self.glitches.remove(0);
            self.inject.glitch[i][ch] = on;
            // Each edge of a pulse at its own cycle.
            self.raise_encoders(core, when);
        }
        for n in 0..4 {
            if self.uart_next[n] <= when {
                if let (Some(b), Some(irq)) = (self.uart_tx[n].pop_front(), self.uart_irq[n]) {
                    // The Bluetooth link's faults hit the byte now, at the
                    // time it is on the air.
                    let arrived = if n == self.wiring.bluetooth_uart as usize {
                        self.host_bytes += 1;
                        self.fire_event(Trigger::HostByte { n: self.host_bytes }, when);
                        self.apply_due_actions(core, when);
                        self.inject.link_bytes(b)
                    } else {
                        vec![b]
                    };
                    for b in arrived {
                        core.raise(irq, b as u32);
                    }
                }
                self.uart_next[n] = if self.uart_tx[n].is_empty() {
                    NEVER
                } else {
                    when + self.uart_byte_cycles
                };
            }
        }
        self.raise_encoders(core, when);
        if self.next_step <= when {
            self.update_adc(core, when);
            self.steps += 1;
            if self.steps % self.trace_every == 0 {
                self.sample(when);
            }
            self.next_step = when + self.step_cycles;
        }
        self.update_supply(core, when);
        if self.next_internal <= when {
            // The plant changed its own dynamics: every prediction is stale.
            self.plan_edges(when);
        }
        // The other wheel's prediction stays valid: its input has not changed
        // (a change re-plans both in `refresh_bridge`).
        for side in SIDES {
            let i = side_index(side);
            if self.next_edge[i] <= when {
                self.next_planned_edge(side, when);
            }
            // As in `raise_planned_edges`: B is quiet for a while after an A
            // edge, under the motion as it is now (any change since re-planned).
            if edge_due[i]
                && self.lean_edges
                && self.lazy_b[i]
                && !self.robot.encoder(side).is_flawed()
            {
                self.b_quiet_until[i] = when.saturating_add(self.b_quiet_cycles[i]);
            }
        }
        self.next_timer()
    }

    fn irq(&mut self, core: &mut Core, tag: u32, value: u32) {
        self.callbacks += 1;
        match tag {
            TAG_LED_PORT => self.log_leds(core.cycle(), value as u8),
            TAG_PORT_REG => {
                self.port_value = value as u8;
                self.refresh_bridge(core, core.cycle());
                core.schedule(self.next_event());
            }
            TAG_PORT_DDR => {
                self.port_ddr = value as u8;
                self.refresh_bridge(core, core.cycle());
                core.schedule(self.next_event());
            }
            t if (TAG_UART_OUT..TAG_UART_OUT + 4).contains(&t) => {
                let n = (t - TAG_UART_OUT) as usize;
                self.uart_out[n].push(value as u8);
                self.uart_log.push((core.cycle(), n as u8, value as u8));
            }
            _ => {}
        }
    }
}

/// One executed step of the CPU, for observers that need instruction-level
/// detail (timing analysis, traces). Observing costs speed; the bench runs
/// without an observer by default.
#[derive(Debug, Clone, Copy)]
pub struct Step {
    pub pc_before: u32,
    pub pc_after: u32,
    pub cycle_before: u64,
    pub cycle_after: u64,
    pub sp_before: u16,
    pub sp_after: u16,
    pub interrupts_before: bool,
    pub interrupts_after: bool,
    /// The opcode at `pc_before` (the instruction executed, unless asleep).
    pub opcode: u16,
    /// The CPU slept during (part of) the step.
    pub slept: bool,
    /// Cycle of the last A-channel edge raised on each encoder (left, right).
    pub last_a_edge: [u64; 2],
}

/// Sees every step of the CPU.
pub trait Observer: std::any::Any {
    fn step(&mut self, step: &Step);
    /// For taking a concrete observer back out of the bench.
    fn into_any(self: Box<Self>) -> Box<dyn std::any::Any>;
}

/// The bench: firmware, MCU, plant.
pub struct Bench {
    avr: Avr<BenchCore>,
    firmware: Firmware,
    vars: FwVars,
    clock: Clock,
    sleep_cycles: u64,
    /// Awake cycles per flash word, when profiling.
    profile: Option<Vec<u64>>,
    observer: Option<Box<dyn Observer>>,
    hang: Option<crate::hang::HangWatch>,
}

impl Bench {
    pub fn new(
        firmware: Firmware,
        robot: &RobotConfig,
        options: BenchOptions,
    ) -> Result<Self, BenchError> {
        let vars = FwVars::resolve(&firmware)?;
        let clock = options.clock;
        let wiring = HENRYTWO;
        let step_cycles = clock.cycles_in(Seconds(options.plant_step_s)).max(1);
        let trace_every = ((options.trace_interval_s / options.plant_step_s).round() as u32).max(1);
        let core = BenchCore {
            clock,
            wiring,
            robot: Robot::new(robot, options.seed)?,
            timer2: PwmTimer::timer2(),
            timer4: PwmTimer::timer4(),
            pending_top: [NEVER; 2],
            port_value: 0,
            port_ddr: 0,
            bridge: [(0.0, 0.0); 2],
            enc_irq: [[None; 2]; 2],
            lazy_b: [false; 2],
            lazy_b_allowed: true,
            lean_edges: true,
            lean_edge_callbacks: 0,
            comparator_on: false,
            lazy_b_reads: 0,
            quiet_b_reads: 0,
            b_reads_evaluated: 0,
            enc_level: [[false; 2]; 2],
            edges_raised: [0; 2],
            last_a_edge: [0; 2],
            next_edge: [NEVER; 2],
            planned: [Vec::new(), Vec::new()],
            input_changed_at: [0; 2],
            input_period: [0; 2],
            next_levels: [None; 2],
            b_quiet_cycles: [0; 2],
            b_quiet_until: [0; 2],
            next_internal: NEVER,
            next_step: step_cycles,
            step_cycles,
            trace_every,
            steps: 0,
            plant_cycle: 0,
            stats_cycle: 0,
            uart_out: Default::default(),
            uart_log: Vec::new(),
            trace: Vec::new(),
            drive_log: Vec::new(),
            cutoffs: Vec::new(),
            motions: Vec::new(),
            pins: wiring.bridge_inputs().map(|b| PinStats {
                pin: b.pin.arduino,
                ..Default::default()
            }),
            vars,
            inject: Injection::new(options.seed ^ 0x5eed_f417),
            uart_tx: Default::default(),
            uart_next: [NEVER; 4],
            uart_irq: [None; 4],
            // 10 bits per byte (8N1) at 9600 baud, as the HC-05 sends them.
            uart_byte_cycles: (clock.hz() as u64 * 10).div_ceil(9600),
            adc0: None,
            adc_mv: u32::MAX,
            battery_divider: options.battery_divider,
            actions: Vec::new(),
            enc_base: [[false; 2]; 2],
            glitches: Vec::new(),
            host_bytes: 0,
            supply: options.supply,
            startup_cycles: clock.cycles_in(Seconds(options.supply.startup_s)),
            bod: Bod::Released,
            vcc_v: f64::NAN,
            supply_battery_v: f64::NAN,
            input_duties: [0.0; 4],
            bod_release_pending: false,
            brownouts: Vec::new(),
            leds: Vec::new(),
            triggered: Vec::new(),
            turns_started: 0,
            legs_started: 0,
            reset_requested: false,
            applied: Vec::new(),
            recording: None,
            analog_log: Vec::new(),
            callbacks: 0,
            error: None,
            failed: false,
            attention: false,
        };
        let mut avr = Avr::new("atmega2560", clock.hz(), core)?;
        for (addr, bytes) in &firmware.segments {
            avr.load_flash(*addr, bytes)?;
        }
        // Timers 2 and 4: emulated by the bench (see pwm.rs).
        for timer in [PwmTimer::timer2(), PwmTimer::timer4()] {
            for addr in timer.write_addresses() {
                avr.claim_io_write(addr, IoClaim::Replace)?;
            }
            for addr in timer.read_addresses() {
                avr.claim_io_read(addr)?;
            }
        }
        for (_, a, b) in CHECKED_TIMERS {
            avr.claim_io_write(a, IoClaim::Observe)?;
            avr.claim_io_write(b, IoClaim::Observe)?;
        }
        // All four bridge inputs are on one port (checked by a wiring test).
        let port = wiring.left_motor.forward.pin.port;
        let reg = avr.port_register(port)?;
        let ddr = avr.port_direction(port)?;
        avr.watch_irq(reg, TAG_PORT_REG);
        avr.watch_irq(ddr, TAG_PORT_DDR);
        let leds = avr.port_register(wiring.battery_leds.green.port)?;
        avr.watch_irq(leds, TAG_LED_PORT);
        let adc0 = avr.adc_input(0)?;
        avr.handler_mut().adc0 = Some(adc0);
        // B lines may be raised lazily, before reads of their PIN registers;
        // the comparator's control register says when AIN1 is watched.
        for side in SIDES {
            avr.observe_io_read(wiring.encoder(side).b.pin_register())?;
        }
        avr.claim_io_write(ACSR, IoClaim::Observe)?;
        let mut enc_irq = [[None; 2]; 2];
        for side in SIDES {
            let e = wiring.encoder(side);
            enc_irq[side_index(side)] = [
                Some(avr.port_pin(e.a.port, e.a.bit)?),
                Some(avr.port_pin(e.b.port, e.b.bit)?),
            ];
        }
        for n in [wiring.debug_uart, wiring.bluetooth_uart] {
            let (input, output) = avr.uart(n)?;
            avr.watch_irq(output, TAG_UART_OUT + n as u32);
            avr.handler_mut().uart_irq[n as usize] = Some(input);
        }
        avr.with_core(|core, c| {
            core.enc_irq = enc_irq;
            core.update_supply(c, 0);
            core.update_adc(c, 0);
            // Encoder lines start at the plant's levels.
            for side in SIDES {
                let i = side_index(side);
                let (a, b) = core.robot.encoder_levels(side);
                for (irq, level) in enc_irq[i].into_iter().zip([a, b]) {
                    if let Some(irq) = irq {
                        c.raise(irq, level as u32);
                    }
                }
                core.enc_level[i] = [a, b];
                core.enc_base[i] = [a, b];
            }
            core.update_lazy_b(c, 0);
            core.plan_edges(0);
        });
        let first = avr.handler().next_event();
        avr.schedule(first);
        Ok(Self {
            avr,
            firmware,
            vars,
            clock,
            sleep_cycles: 0,
            profile: None,
            observer: None,
            hang: None,
        })
    }

    pub fn clock(&self) -> Clock {
        self.clock
    }

    pub fn cycle(&self) -> u64 {
        self.avr.cycle()
    }

    pub fn robot_time_s(&self) -> f64 {
        self.clock.seconds(self.avr.cycle()).0
    }

    pub fn core(&self) -> &BenchCore {
        self.avr.handler()
    }

    pub fn vars(&self) -> &FwVars {
        &self.vars
    }

    pub fn firmware(&self) -> &Firmware {
        &self.firmware
    }

    /// Watch every step from now on (see [`Observer`]).
    pub fn set_observer(
        &mut self,
        observer: Option<Box<dyn Observer>>,
    ) -> Option<Box<dyn Observer>> {
        std::mem::replace(&mut self.observer, observer)
    }

    /// Take the observer back.
    pub fn take_observer(&mut self) -> Option<Box<dyn Observer>> {
        self.observer.take()
    }

    /// From now on, stop with [`BenchError::Hang`] when the firmware is busy
    /// in a test without progress for `after_s` of robot time (None: never).
    pub fn set_hang_after(&mut self, after_s: Option<f64>) {
        self.hang = after_s
            .map(|s| crate::hang::HangWatch::new(&self.firmware, self.clock.cycles_in(Seconds(s))));
    }

    /// Record every encoder pin change from now on. A lazily raised B line
    /// is recorded as the firmware saw it (changes at the reads that noticed
    /// them): a replay gives the firmware the same inputs. For B's true edge
    /// times, call [`Bench::true_waveforms`] first.
    /// The recording starts with the four lines' levels now.
    pub fn start_recording(&mut self) {
        let cycle = self.avr.cycle();
        let core = self.avr.handler_mut();
        let levels = core
            .enc_level
            .iter()
            .flatten()
            .enumerate()
            .map(|(line, &level)| PinEvent {
                cycle,
                line: line as u8,
                level,
            })
            .collect();
        core.recording = Some(levels);
    }

    /// Raise every encoder transition at its own cycle, B included (for
    /// traces that show the lines as they are). Costs speed, changes nothing
    /// the firmware sees.
    pub fn true_waveforms(&mut self) {
        self.avr.with_core(|core, c| {
            core.lazy_b_allowed = false;
            let cycle = c.cycle();
            core.update_lazy_b(c, cycle);
            c.schedule(core.next_event());
        });
    }

    /// Bring the plant to the cycle of every encoder edge, as for any other
    /// event, instead of raising planned edges from the plan alone (and
    /// answering reads of a lazy B right after them from it): slower, and
    /// the same run (to check that it is).
    pub fn advance_plant_at_every_edge(&mut self) {
        self.avr.handler_mut().lean_edges = false;
    }

    /// Attribute awake cycles to the instruction executing them, from now on.
    pub fn start_profiling(&mut self) {
        self.profile = Some(vec![0; 0x2_0000]);
    }

    /// Awake cycles per function since [`Bench::start_profiling`], most first.
    /// (Cycles spent in an interrupt's entry are the interrupted instruction's.)
    pub fn profile_by_function(&self) -> Vec<(String, u64)> {
        let Some(profile) = &self.profile else {
            return Vec::new();
        };
        let mut by: std::collections::BTreeMap<String, u64> = Default::default();
        for (word, &c) in profile.iter().enumerate() {
            if c > 0 {
                let name = self
                    .firmware
                    .function_at(word as u32 * 2)
                    .map(|(n, _)| n.to_owned())
                    .unwrap_or_else(|| format!("0x{:05x}", word * 2));
                *by.entry(name).or_default() += c;
            }
        }
        let mut v: Vec<_> = by.into_iter().collect();
        v.sort_by_key(|e| std::cmp::Reverse(e.1));
        v
    }

    /// Fraction of cycles the CPU was awake.
    pub fn awake_fraction(&self) -> f64 {
        let c = self.avr.cycle();
        if c == 0 {
            return 0.0;
        }
        1.0 - self.sleep_cycles as f64 / c as f64
    }

    pub fn location(&self) -> Location {
        let pc = self.avr.pc();
        self.location_at(self.avr.cycle(), pc)
    }

    fn location_at(&self, cycle: u64, pc: u32) -> Location {
        Location {
            cycle,
            robot_time_s: self.clock.seconds(cycle).0,
            pc,
            function: self
                .firmware
                .function_at(pc)
                .map(|(name, off)| format!("{name}+0x{off:x}")),
        }
    }

    pub fn read_u8(&self, addr: u16) -> u8 {
        self.avr.data(addr)
    }

    pub fn read_u16(&self, addr: u16) -> u16 {
        u16::from_le_bytes(self.avr.read_bytes::<2>(addr))
    }

    pub fn read_i32(&self, addr: u16) -> i32 {
        i32::from_le_bytes(self.avr.read_bytes::<4>(addr))
    }

    pub fn read_u32(&self, addr: u16) -> u32 {
        u32::from_le_bytes(self.avr.read_bytes::<4>(addr))
    }

    pub fn read_f32(&self, addr: u16) -> f32 {
        f32::from_le_bytes(self.avr.read_bytes::<4>(addr))
    }

    pub fn write_f32(&mut self, addr: u16, v: f32) {
        self.avr.write_bytes(addr, &v.to_le_bytes());
    }

    pub fn fw_state(&self) -> FwState {
        FwState::from(self.read_u8(self.vars.state))
    }

    /// Send bytes to USART `n`'s receiver (simavr paces them at the baud rate).
    pub fn send(&mut self, n: u8, bytes: &[u8]) {
        let now = self.avr.cycle();
        self.avr.handler_mut().queue_uart(n as usize, bytes, now);
        let next = self.avr.handler().next_event();
        self.avr.schedule(next);
    }

    /// Schedule a fault action (see [`Trigger`]); `undo` runs `duration_s`
    /// after it.
    pub fn schedule(&mut self, trigger: Trigger, action: Action, undo: Option<(f64, Action)>) {
        let clock = self.clock;
        let undo = undo.map(|(d, a)| (clock.cycles_in(Seconds(d)), a));
        self.avr
            .handler_mut()
            .schedule_triggered(trigger, action, undo);
        let next = self.avr.handler().next_event();
        self.avr.schedule(next);
    }

    /// Pull the reset line now: the firmware restarts from its reset vector,
    /// the plant carries on. simavr drops its cycle timers on reset, so the
    /// bench's is scheduled again.
    pub fn reset_mcu(&mut self) {
        self.avr.reset();
        // The MCU's registers are back at their reset values, the bench's
        // emulated timers and its view of port H too: all pins inputs, the
        // bridge sees low (its inputs have pull-downs).
        self.avr.with_core(|core, c| core.after_reset(c));
        let next = self.avr.handler().next_event();
        self.avr.schedule(next);
    }

    /// Bytes the firmware sent on USART `n` so far.
    pub fn uart_output(&self, n: u8) -> &[u8] {
        &self.avr.handler().uart_out[n as usize]
    }

    /// Run until `done` holds or `limit_s` of robot time pass; Ok(false) on
    /// the limit. `done` is checked after the first step, then after the
    /// first step that reaches each point of a grid of [`CHECK_PERIOD_S`]
    /// of robot time (a step is an instruction, or a sleep up to the next
    /// event; the grid starts at cycle 0, so the checks fall at the same
    /// cycles however a run is split into calls); the run ends after the
    /// first step that reaches the limit.
    /// `done` should look at the firmware (memory, pins), not at the plant,
    /// which may lag the CPU by an encoder edge or two between the bench's
    /// own events. On return the plant is at the current cycle.
    pub fn run_until(
        &mut self,
        limit_s: f64,
        done: impl FnMut(&Bench) -> bool,
    ) -> Result<bool, BenchError> {
        let result = self.run_until_unsynced(limit_s, done);
        self.sync_plant();
        result
    }

    /// Bring the plant (and the statistics) to the current cycle: the run
    /// loop lets them lag between the bench's own events.
    fn sync_plant(&mut self) {
        let now = self.avr.cycle();
        self.avr.handler_mut().sync(now);
    }

    /// [`Bench::run_until`] without the plant brought up to date at the end
    /// (`done` must not look at the plant).
    fn run_until_unsynced(
        &mut self,
        limit_s: f64,
        mut done: impl FnMut(&Bench) -> bool,
    ) -> Result<bool, BenchError> {
        let limit = self.avr.cycle() + self.clock.cycles_in(Seconds(limit_s));
        let ms = self.clock.cycles_per_ms();
        let period = self.clock.cycles_in(Seconds(CHECK_PERIOD_S)).max(1);
        // The first check after the first step, then one per grid point.
        let mut check_at = self.avr.cycle();
        // (At the limit the check ends the run: what follows is not used.)
        let next_check = |now: u64| ((now / period + 1) * period).min(limit);
        let mut hang_check_at = check_at;
        // Instruction-level detail costs speed: only when someone looks.
        let watch = self.profile.is_some() || self.observer.is_some();
        let mut sleeping = self.avr.state() == CpuState::Sleeping;
        if !watch {
            // The same steps and checks as the loop below, in bursts that
            // stay inside the simulator module up to the next check. (Holding
            // or releasing the reset always raises attention, which ends a
            // burst, so a burst never runs through a brown-out.)
            loop {
                let state = if self.avr.handler().held_in_reset() {
                    let before = self.avr.cycle();
                    self.avr.hold_step();
                    self.sleep_cycles += self.avr.cycle() - before;
                    sleeping = true;
                    CpuState::Running
                } else {
                    let burst = self.avr.run_burst(check_at, &mut sleeping);
                    self.sleep_cycles += burst.slept;
                    burst.state
                };
                if !matches!(state, CpuState::Running | CpuState::Sleeping) {
                    return Err(self.stop_error(state));
                }
                if self.avr.handler().attention {
                    self.attend()?;
                    sleeping = self.avr.state() == CpuState::Sleeping;
                }
                let now = self.avr.cycle();
                if now >= check_at {
                    check_at = next_check(now);
                    if let Some(end) =
                        self.check_point(now, &mut done, &mut hang_check_at, ms, limit)?
                    {
                        return Ok(end);
                    }
                }
            }
        }
        loop {
            let before = self.avr.cycle();
            let (pc_before, sp_before, i_before) = if watch {
                (self.avr.pc(), self.avr.sp(), self.avr.interrupts_enabled())
            } else {
                (0, 0, false)
            };
            // Held in reset by the brown-out detector: no instruction runs,
            // the plant and the bench's events go on.
            let held = self.avr.handler().held_in_reset();
            let state = if held {
                self.avr.hold_step();
                CpuState::Running
            } else {
                self.avr.step()
            };
            let now = self.avr.cycle();
            // simavr jumps over a sleep in the same step that executes the
            // `sleep` instruction, and again in each step while asleep.
            let asleep = state == CpuState::Sleeping || held;
            let slept = sleeping || asleep;
            sleeping = asleep;
            if slept {
                self.sleep_cycles += now - before;
            }
            if watch {
                if let (false, Some(profile)) = (slept, &mut self.profile) {
                    profile[(pc_before / 2) as usize] += now - before;
                }
                if self.observer.is_some() {
                    self.observe(pc_before, before, sp_before, i_before, slept);
                }
            }
            if !matches!(state, CpuState::Running | CpuState::Sleeping) {
                return Err(self.stop_error(state));
            }
            if self.avr.handler().attention {
                self.attend()?;
                sleeping = self.avr.state() == CpuState::Sleeping;
            }
            if now >= check_at {
                check_at = next_check(now);
                if let Some(end) =
                    self.check_point(now, &mut done, &mut hang_check_at, ms, limit)?
                {
                    return Ok(end);
                }
            }
        }
    }

    /// `run_until`'s periodic check at cycle `now`: `done`, the hang watch
    /// (once per `ms`), the time limit. Some(end) ends the run.
    fn check_point(
        &mut self,
        now: u64,
        done: &mut impl FnMut(&Bench) -> bool,
        hang_check_at: &mut u64,
        ms: u64,
        limit: u64,
    ) -> Result<Option<bool>, BenchError> {
        if done(self) {
            return Ok(Some(true));
        }
        if now >= *hang_check_at {
            *hang_check_at = now + ms;
            self.check_hang()?;
        }
        Ok((now >= limit).then_some(false))
    }

    /// The error for a CPU that stopped running and sleeping.
    fn stop_error(&self, state: CpuState) -> BenchError {
        let at = self.location();
        if state == CpuState::Crashed {
            BenchError::Crashed { at }
        } else {
            BenchError::Stopped { at }
        }
    }

    /// Stop a hung firmware (checked once per millisecond of robot time).
    fn check_hang(&mut self) -> Result<(), BenchError> {
        let Some(mut watch) = self.hang.take() else {
            return Ok(());
        };
        // The watch looks at the wheels.
        self.sync_plant();
        let still = watch.check(self);
        self.hang = Some(watch);
        match still {
            Some(cycles) => Err(BenchError::Hang(crate::hang::HangReport {
                still_s: self.clock.seconds(cycles).0,
                at: self.location(),
                callers: crate::hang::callers(self, 4),
            })),
            None => Ok(()),
        }
    }

    /// Handle what a callback flagged: a reset to perform, an error to report.
    fn attend(&mut self) -> Result<(), BenchError> {
        let core = self.avr.handler_mut();
        core.attention = false;
        if std::mem::take(&mut core.reset_requested) {
            self.reset_mcu();
        }
        if std::mem::take(&mut self.avr.handler_mut().bod_release_pending) {
            // The detector lets go: the MCU starts from its reset vector,
            // with BORF set in MCUSR as the datasheet says.
            self.reset_mcu();
            let mcusr = self.avr.data(MCUSR);
            self.avr.set_data(MCUSR, mcusr | MCUSR_BORF);
        }
        let core = self.avr.handler_mut();
        if std::mem::take(&mut core.failed) {
            if let Some(e) = core.error.take() {
                return Err(self.pending_error(e));
            }
        }
        Ok(())
    }

    fn observe(
        &mut self,
        pc_before: u32,
        cycle_before: u64,
        sp_before: u16,
        i_before: bool,
        slept: bool,
    ) {
        let step = Step {
            pc_before,
            pc_after: self.avr.pc(),
            cycle_before,
            cycle_after: self.avr.cycle(),
            sp_before,
            sp_after: self.avr.sp(),
            interrupts_before: i_before,
            interrupts_after: self.avr.interrupts_enabled(),
            opcode: self.avr.flash_word(pc_before),
            slept,
            last_a_edge: self.avr.handler().last_a_edge,
        };
        if let Some(o) = &mut self.observer {
            o.step(&step);
        }
    }

    fn pending_error(&self, e: PendingError) -> BenchError {
        match e {
            PendingError::Pwm(error, cycle, pc) => BenchError::Pwm {
                error,
                at: self.location_at(cycle, pc),
            },
            PendingError::Timer {
                timer,
                wgm,
                cs,
                cycle,
                pc,
            } => BenchError::UnverifiedTimer {
                timer,
                wgm,
                cs,
                at: self.location_at(cycle, pc),
            },
        }
    }

    /// Run until `done`, or fail with a timeout naming `what`.
    pub fn run_expect(
        &mut self,
        what: &str,
        limit_s: f64,
        done: impl FnMut(&Bench) -> bool,
    ) -> Result<(), BenchError> {
        if self.run_until(limit_s, done)? {
            Ok(())
        } else {
            Err(BenchError::Timeout {
                what: what.into(),
                robot_s: limit_s,
                at: self.location(),
            })
        }
    }

    /// The simulated MCU, for a debugger's register and memory access.
    pub fn mcu(&self) -> &Avr<BenchCore> {
        &self.avr
    }

    pub fn mcu_mut(&mut self) -> &mut Avr<BenchCore> {
        &mut self.avr
    }

    /// Execute one instruction (while asleep or held in reset: jump to the
    /// next event) with the bench's bookkeeping, for a debugger's step and
    /// continue. Hang detection and observers are the run loop's, not this.
    pub fn step_instruction(&mut self) -> Result<(), BenchError> {
        let before = self.avr.cycle();
        let held = self.avr.handler().held_in_reset();
        let state = if held {
            self.avr.hold_step();
            CpuState::Sleeping
        } else {
            self.avr.step()
        };
        if state == CpuState::Sleeping {
            self.sleep_cycles += self.avr.cycle() - before;
        }
        if !matches!(state, CpuState::Running | CpuState::Sleeping) {
            return Err(self.stop_error(state));
        }
        if self.avr.handler().attention {
            self.attend()?;
        }
        self.sync_plant();
        Ok(())
    }

    /// Run for `seconds` of robot time.
    pub fn run_for(&mut self, seconds: f64) -> Result<(), BenchError> {
        self.run_until(seconds, |_| false).map(|_| ())
    }
}
