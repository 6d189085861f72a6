//! The bench: one emulated MCU running the firmware ELF, wired to the plant.
//!
//! Everything that happens in the plant is an event on one simavr cycle timer:
//! the next encoder transition of either wheel (computed exactly by the plant),
//! the next buffered PWM update (at the PWM timer's TOP), and a periodic plant
//! step (pose integration and trace samples). Register writes that change what
//! the H-bridge sees advance the plant to the cycle of the write and re-plan
//! the queue. Nothing polls the MCU per instruction, and nothing reads the
//! host clock: a run is a pure function of the ELF, the config and the seed.
//!
//! Where each concern lives (the core on top; the parts below it know
//! nothing of it, and are given what they need of one another):
//!
//! | file | what |
//! |---|---|
//! | `mod.rs` | [`Bench`], its public API, [`BenchOptions`] |
//! | `setup.rs` | building a bench: flash, register claims, the IRQs a [`Board`] connects |
//! | `run.rs` | the run loops ([`Bench::run_until`]), [`Step`] and [`Observer`] |
//! | `core/` | [`BenchCore`], the handler simavr calls back, dispatching to the parts below (`mod.rs`); what needs several parts, a bridge change reaching the plant or a fault action (`parts.rs`); what they hold, for the facade (`records.rs`) |
//! | `inject.rs` | injection points: where the bench can bend what the firmware sees |
//! | `hang.rs` | hang detection: a firmware in a test that makes no progress |
//! | `gdb/` | the GDB Remote Serial Protocol stub, on loopback |
//! | `bridge.rs` | the motor driver's inputs from the PWM timers and ports, to the plant; [`PinStats`] |
//! | `driver.rs` | each driver's truth table (DRV8833, L298N, TB6612, PWM/DIR) as the plant's bridge inputs |
//! | `edges.rs` | where an encoder edge is born: planning, raising, lazy channel B |
//! | `uart.rs` | the host's side of the USARTs (and the USB serial's bytes) |
//! | `usb.rs` | the USB host of an MCU with USB: enumeration, the CDC serial |
//! | `power.rs` | A0, VCC and the brown-out detector |
//! | `faults.rs` | [`Action`], [`Trigger`], [`ScheduledFault`] and their schedule |
//! | `recorder.rs` | what a run records: [`Sample`], [`DriveEvent`], [`Cutoff`], [`Motion`], ... |
//! | `log.rs` | how much of each record is kept: a cap, or the latest item only ([`Retention`]) |
//! | `error.rs` | [`BenchError`] |
//! | `requests.rs` | what a callback leaves for the run loop: an error, a reset |
//! | `registers.rs` | the MCU registers the bench reads or watches, by address |
//! | `timers.rs` | when a timer's configuration is judged (the bench's and simavr's timers) |

mod bridge;
mod core;
mod driver;
mod edges;
mod error;
mod faults;
pub mod gdb;
pub mod hang;
pub mod inject;
mod log;
mod power;
mod recorder;
mod registers;
mod requests;
mod run;
mod setup;
mod timers;
mod uart;
mod usb;

use henrytwo_protocol::{Phase, RunState};
use plant_model::{RobotConfig, Seconds, Side};

pub use self::bridge::PinStats;
pub use self::core::BenchCore;
pub use self::edges::decode_a_edge;
pub use self::error::BenchError;
pub use self::faults::{Action, ScheduledFault, Trigger};
pub use self::log::Retention;
pub use self::recorder::{
    AnalogEvent, AnalogInput, Cutoff, DriveEvent, LedEvent, Motion, MotionEvent, PinEvent,
    Retained, Sample, SharedTap, Snapshot, Tap,
};
pub use self::run::{Debugger, Observer, Step, CHECK_PERIOD_S};
pub use self::setup::encoder_pins;
pub use self::timers::emulated as emulated_timers;
pub use self::uart::{serial_name, SERIALS, USB_SERIAL};
pub use self::usb::{UsbEvents, UsbState, FRAME_S as USB_FRAME_S};
pub use crate::firmware::elf::Location;

use self::registers::{MCUSR, MCUSR_EXTRF};
use crate::bench::hang::{HangWatch, Progress};
use crate::board::Board;
use crate::firmware::elf::Firmware;
use crate::firmware::vars::FwVars;
use crate::mcu::clock::Clock;
use crate::mcu::sim::Avr;
use crate::mcu::supply::Supply;

/// No event: a cycle never reached.
const NEVER: u64 = u64::MAX;

/// Bench settings that are not the robot's.
#[derive(Debug, Clone, Copy)]
pub struct BenchOptions {
    pub clock: Clock,
    /// Plant step for pose integration when no other event happens.
    pub plant_step_s: f64,
    /// Interval of trace samples (a multiple of the plant step).
    pub trace_interval_s: f64,
    pub seed: u64,
    /// Which MCU pin each part is on, the links' USARTs, the battery's
    /// divider (default: Henrytwo's, [`crate::board::HENRYTWO`]).
    pub board: Board,
    /// The MCU's supply from the battery, and its brown-out detector.
    pub supply: Supply,
    /// simavr runs free between its cycle timers (the default), or steps
    /// one instruction at a time as it does by default. The results are the
    /// same to the cycle and the bit (tests/free_run.rs); free is faster.
    pub free_run: bool,
    /// Fast-forward over the repeats of a polling loop the bench proves
    /// change nothing before the next event (the default; `--no-skip`
    /// turns it off). The results are the same to the cycle and the bit
    /// (tests/skip.rs); skipping is faster on busy firmware.
    pub skip: bool,
    /// On an MCU with USB, the bench's USB host is on the cable (VBUS,
    /// enumeration, start of frame every millisecond). Off, the cable is
    /// out, as on a robot driving on the floor: the firmware's USB
    /// interrupts never run.
    pub usb_cable: bool,
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
            board: Board::default(),
            supply: Supply::default(),
            free_run: true,
            skip: true,
            usb_cable: true,
        }
    }
}

/// The bench: firmware, MCU, plant.
pub struct Bench {
    avr: Avr<BenchCore>,
    firmware: Firmware,
    /// The bench interface of the firmware, when it has one (our builds);
    /// a firmware that knows nothing of the bench runs without it (see
    /// [`crate::firmware::description`]).
    vars: Result<FwVars, String>,
    clock: Clock,
    sleep_cycles: u64,
    /// Awake cycles per flash word, when profiling.
    profile: Option<Vec<u64>>,
    observer: Option<Box<dyn Observer>>,
    debugger: Option<Box<dyn Debugger>>,
    hang: Option<HangWatch>,
    board: Board,
}

impl Bench {
    /// The firmware on `robot`, its parts on the MCU pins `options.board`
    /// names.
    pub fn new(
        firmware: Firmware,
        robot: &RobotConfig,
        options: BenchOptions,
    ) -> Result<Self, BenchError> {
        // Only a missing symbol means "no interface": a variable of the
        // wrong size is an error of the build.
        let vars = match FwVars::resolve(&firmware) {
            Ok(v) => Ok(v),
            Err(e @ crate::firmware::elf::ElfError::MissingSymbol { .. }) => Err(e.to_string()),
            Err(e) => return Err(e.into()),
        };
        let counts = vars.as_ref().ok().map(|v| [v.left_count, v.right_count]);
        let avr = setup::build(&firmware, robot, &options, counts)?;
        Ok(Self {
            avr,
            firmware,
            vars,
            clock: options.clock,
            sleep_cycles: 0,
            profile: None,
            observer: None,
            debugger: None,
            hang: None,
            board: options.board,
        })
    }

    /// The board the firmware's parts are wired by.
    pub fn board(&self) -> &Board {
        &self.board
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

    /// Cycles the run fast-forwarded over polling loops
    /// ([`BenchOptions::skip`]).
    pub fn skipped_cycles(&self) -> u64 {
        self.avr.skipped_cycles()
    }

    pub fn core(&self) -> &BenchCore {
        self.avr.handler()
    }

    /// The faults armed with [`Self::schedule`] (indexes in the order they
    /// were scheduled) whose action has not come due: their time is past
    /// the run, or their event never happened.
    pub fn faults_never_fired(&self) -> Vec<usize> {
        self.avr.handler().faults.never_fired()
    }

    /// The firmware's bench interface (`HT_` variables); an error naming
    /// the first missing symbol for a firmware without it.
    pub fn vars(&self) -> Result<&FwVars, BenchError> {
        self.vars
            .as_ref()
            .map_err(|missing| BenchError::NoInterface(missing.clone()))
    }

    /// Whether the firmware has the bench interface (see [`Bench::vars`]).
    pub fn knows_the_bench(&self) -> bool {
        self.vars.is_ok()
    }

    /// Read the firmware's wheel counters from these 32-bit variables (for
    /// a firmware without the bench interface whose description names its
    /// counters): what cut-off snapshots record.
    pub fn set_count_variables(&mut self, counts: [u16; 2]) {
        self.avr.handler_mut().set_count_variables(counts);
    }

    /// The firmware's wheel counters now, when the bench knows where they are.
    pub fn counts(&self) -> Option<[i32; 2]> {
        self.core()
            .count_variables()
            .map(|[l, r]| [self.read_i32(l), self.read_i32(r)])
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

    /// Let a debugger drive every run loop from now on (see [`Debugger`]).
    pub(crate) fn set_debugger(&mut self, debugger: Option<Box<dyn Debugger>>) {
        self.debugger = debugger;
    }

    /// Take the debugger back (None once it detached).
    pub(crate) fn take_debugger(&mut self) -> Option<Box<dyn Debugger>> {
        self.debugger.take()
    }

    /// From now on, stop with [`BenchError::Hang`] when the firmware is busy
    /// in a test without progress for `after_s` of robot time (None: never).
    pub fn set_hang_after(&mut self, after_s: Option<f64>) {
        self.hang = after_s.map(|s| HangWatch::new(self.clock.cycles_in(Seconds(s))));
    }

    /// What the hang watch looks at, now.
    fn progress(&self) -> Progress {
        let read = |a: Option<u16>| a.map_or(0, |a| self.read_u8(a));
        let core = self.core();
        let v = self.vars.as_ref().ok();
        Progress {
            cycle: self.cycle(),
            left_edges: core.robot().counted_edges(Side::Left),
            right_edges: core.robot().counted_edges(Side::Right),
            // Without the interface the firmware is busy while the watch
            // is on (the caller arms it for the test only), and what it
            // drives is its progress.
            state: v.map_or(RunState::Driving as u8, |v| self.read_u8(v.state)),
            phase: read(v.and_then(|v| v.phase)),
            segment: read(v.and_then(|v| v.segment)),
            done: v.map_or(0, |v| self.read_u16(v.done_count)),
            fault: read(v.and_then(|v| v.fault)),
            outputs: if v.is_none() {
                core.motion_changes() as usize
            } else {
                0
            },
            held_in_reset: core.held_in_reset(),
        }
    }

    /// Record every encoder pin change from now on. A lazily raised B line
    /// is recorded as the firmware saw it (changes at the reads that noticed
    /// them): a replay gives the firmware the same inputs. For B's true edge
    /// times, call [`Bench::true_waveforms`] first.
    /// The recording starts with the four lines' levels now.
    pub fn start_recording(&mut self) {
        let cycle = self.avr.cycle();
        self.avr.handler_mut().start_recording(cycle);
    }

    /// [`Bench::start_recording`], with every record given to `tap` as it
    /// is made (see [`Tap`]) instead of the pin changes kept: a trace
    /// written as the run goes, from what the records hold now on.
    pub fn stream_records(&mut self, tap: SharedTap) {
        let cycle = self.avr.cycle();
        self.avr.handler_mut().stream_records(cycle, tap);
    }

    /// Raise every encoder transition at its own cycle, B included (for
    /// traces that show the lines as they are). Costs speed, changes nothing
    /// the firmware sees.
    pub fn true_waveforms(&mut self) {
        self.avr.with_core(|core, c| {
            core.true_waveforms(c);
            c.schedule(core.next_event());
        });
    }

    /// Bring the plant to the cycle of every encoder edge, as for any other
    /// event, instead of raising planned edges from the plan alone (and
    /// answering reads of a lazy B right after them from it): slower, and
    /// the same run (to check that it is).
    pub fn advance_plant_at_every_edge(&mut self) {
        self.avr.handler_mut().edges.keep_plant_at_every_edge();
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
        self.firmware
            .location(self.clock, self.avr.cycle(), self.avr.pc())
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

    /// The firmware's `HT_STATE` (None: a byte no firmware sends, or a
    /// firmware without the bench interface).
    pub fn run_state(&self) -> Option<RunState> {
        RunState::from_u8(self.read_u8(self.vars.as_ref().ok()?.state))
    }

    /// The firmware is idle: ready for a command (`HT_STATE` = 1).
    pub fn is_idle(&self) -> bool {
        self.run_state() == Some(RunState::Idle)
    }

    /// The firmware's `HT_PHASE` (None: a build without it, or a byte no
    /// firmware sends).
    pub fn phase(&self) -> Option<Phase> {
        self.vars
            .as_ref()
            .ok()?
            .phase
            .and_then(|a| Phase::from_u8(self.read_u8(a)))
    }

    /// Send bytes to USART `n`'s receiver (simavr paces them at the baud
    /// rate), or with `n` = [`USB_SERIAL`] on the USB serial (the host
    /// sends them once the port is open, a packet a frame).
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
    /// Reset the MCU as its reset pin would (a debugger's `monitor
    /// reset`): the plant carries on, MCUSR keeps its flags and gains EXTRF.
    pub fn external_reset(&mut self) {
        let mcusr = self.avr.data(MCUSR);
        self.reset_mcu();
        self.avr.set_data(MCUSR, mcusr | MCUSR_EXTRF);
    }

    pub fn reset_mcu(&mut self) {
        self.avr.reset();
        // The MCU's registers are back at their reset values, the bench's
        // emulated timers and its view of the driver's ports too: all pins
        // inputs, the driver sees low (its inputs have pull-downs).
        self.avr.with_core(|core, c| core.after_reset(c));
        let next = self.avr.handler().next_event();
        self.avr.schedule(next);
    }

    /// Hold `pin` at a level from now on, as a button or a jumper would:
    /// the firmware reads that level while the pin is an input, whatever it
    /// writes to the pin's port (its pull-up included), as on silicon.
    pub fn drive_pin(&mut self, pin: crate::board::Pin, high: bool) -> Result<(), BenchError> {
        self.avr.driven_pin(pin.port, pin.bit, high)?;
        Ok(())
    }

    /// Where the USB host is with the device; None on an MCU without USB.
    pub fn usb_state(&self) -> Option<&UsbState> {
        self.avr.handler().usb_state()
    }

    /// The USB host's moments (attach, bus reset, each request done):
    /// (cycle, what); empty on an MCU without USB.
    pub fn usb_events(&self) -> &[(u64, &'static str)] {
        self.avr.handler().usb_events()
    }

    /// Bytes the firmware sent on USART `n` so far (since the last
    /// [`Bench::take_uart_output`]).
    pub fn uart_output(&self, n: u8) -> &[u8] {
        self.avr.handler().uart_out(n as usize)
    }

    /// The bytes the firmware sent on USART `n` since the last call, taken:
    /// for a reader that streams them on, so that the bench keeps none.
    pub fn take_uart_output(&mut self, n: u8) -> Vec<u8> {
        self.avr.handler_mut().take_uart_out(n as usize)
    }

    /// Keep only the latest item of each record from now on (see
    /// [`Retention::Latest`]): for a bench that runs for days and whose
    /// records no one reads (`hil serve`). The firmware's bytes stay until
    /// [`Bench::take_uart_output`] takes them.
    pub fn keep_latest_records(&mut self) {
        self.avr.handler_mut().keep_latest_records();
    }

    /// The simulated MCU, for a debugger's register and memory access.
    pub fn mcu(&self) -> &Avr<BenchCore> {
        &self.avr
    }

    pub(crate) fn mcu_mut(&mut self) -> &mut Avr<BenchCore> {
        &mut self.avr
    }
}
