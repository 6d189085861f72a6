//! The "robust" build: the thesis' four tests (straight line, UMBmark CW and
//! CCW, triangle) with the thesis' control law, driven by a framed command
//! protocol (`henrytwo-protocol`) or the thesis' single-byte selectors on
//! the Bluetooth UART.
//!
//! What it does differently from the thesis (README.md has the full table):
//! - the control tick is timer 1 (exactly 15 ms), the PID's constant factors
//!   are folded, the CPU sleeps whenever nothing is due;
//! - a segment ends on an encoder-handler trip, so the cut-off happens
//!   within one count of the target and the CPU is not woken per edge;
//! - in a spin turn each wheel is cut when its own count reaches its target,
//!   then gets its own braking pulse;
//! - stall (no net progress), encoder-inconsistent, wrong-direction and
//!   segment time-out faults stop the motors; the MCU watchdog resets a main
//!   loop that stops running;
//! - every wait is a deadline on the timer 1 clock: no busy loop anywhere.

#![no_std]
#![no_main]
#![feature(abi_avr_interrupt)]

use avr_device::atmega2560::{Peripherals, USART0, USART1};
use avr_device::interrupt;

use henrytwo_firmware::battery::{self, Leds};
use henrytwo_firmware::bench::{self, Phase, State};
use henrytwo_firmware::board::{self, DriveMotors};
use henrytwo_firmware::encoder::{Counts, Encoders, Side, TRIP_LEFT, TRIP_RIGHT};
use henrytwo_firmware::hal::adc::Adc;
use henrytwo_firmware::hal::exint::ExtInts;
use henrytwo_firmware::hal::sleep::Sleeper;
use henrytwo_firmware::hal::usart::{self, Serial, RX_LEN};
use henrytwo_firmware::hal::wdt::{self, Watchdog};
use henrytwo_firmware::odometry::{leg_progress, leg_target, leg_trip_ahead, leg_weight, spin_target_counts};
use henrytwo_firmware::pid::{duty_from_output, rpm_table, thesis_rpm, TablePid};
use henrytwo_firmware::plan::{self, Segment};
use henrytwo_firmware::robot;
use henrytwo_firmware::selector::Isolation;
use henrytwo_firmware::settings::{PerWheel, Settings};
use henrytwo_firmware::time::{self, Clock};
use henrytwo_protocol::{
    encode_frame, Command, Event, Fault, FaultNotice, Param, Parser, Reply, StateReport, Status, Telemetry, Test,
    TestDoneNotice, FRAME_ERROR_ID, MAX_FRAME, MAX_PAYLOAD, NOTIFY_FAULT, NOTIFY_TEST_DONE, VERSION,
};

// ---- interrupt vectors of this build ----
//
// INT4 and INT5 (the encoders) are the library's assembly handlers
// (`henrytwo_firmware::encoder`), the same in both builds.

#[avr_device::interrupt(atmega2560)]
fn TIMER1_COMPA() {
    // SAFETY: this is the TIMER1_COMPA vector.
    unsafe { time::on_tick() }
}

#[avr_device::interrupt(atmega2560)]
fn TIMER1_COMPB() {
    // SAFETY: this is the TIMER1_COMPB vector.
    unsafe { time::on_alarm() }
}

// Both USARTs' RX-complete and data-register-empty vectors.
henrytwo_firmware::usart_vectors!();

// ---- constants ----

/// Boot message on the debug UART.
const BOOT_LINE: &[u8] = b"henrytwo robust ready\r\n";

/// Thesis `Inercia_Stop_*`: after a wheel is cut, 20 ms until its
/// counter-pulse ...
const BRAKE_COAST: u32 = time::ms(20);
/// ... which lasts 5 ms at full duty ...
const BRAKE_PULSE: u32 = time::ms(5);
/// ... then the `delay(1000)` that ends `Inercia_Stop_*` ...
const INERTIA_WAIT: u32 = time::ms(1000);
/// ... and `Stop_General`'s `delay(1000)`.
const STOP_WAIT: u32 = time::ms(1000);
/// A frame whose next byte does not come within this is truncated.
const INTER_BYTE_TIMEOUT: u32 = time::ms(50);
/// A raw selector byte counts only with no other byte this long before and
/// after it: the inter-byte timeout, so a byte that could belong to a frame
/// (whose bytes may be up to 50 ms apart; they come back to back, 1.04 ms)
/// is never one. Checked on each tick: acted upon 50 to 65 ms after it came.
const RAW_QUIET: u32 = INTER_BYTE_TIMEOUT;
/// A wheel that goes this many counts against its commanded direction
/// within a segment is a fault.
const WRONG_WAY_COUNTS: i32 = 64;
/// Thesis RPM of one count in one control period (1.107).
const RPM_PER_COUNT: f32 = thesis_rpm(1, robot::SAMPLE_PERIOD_S);
/// Counts per control period the lookup tables cover (a wheel at the
/// set-point makes about 13; the motors' top speed is below 30).
const TABLE_COUNTS: usize = 64;
/// Thesis RPM of 0..63 counts in one control period.
static RPM_OF_COUNTS: [f32; TABLE_COUNTS] = rpm_table(robot::SAMPLE_PERIOD_S);
/// One control period in microseconds, as `HT_PERIOD_US` shows it.
const PERIOD_US: f32 = robot::SAMPLE_PERIOD_US as f32;
/// Stall watchdog: net progress, in counts in the commanded direction, that
/// a wheel driven at or above the stall duty must make within the stall
/// time. At the set-points a wheel makes about 13 counts per tick; a wheel
/// that turns while its count does not advance (the 2x decoder with channel
/// B stuck counts +1, -1, +1 ...) or that creeps a count or two is stopped.
const STALL_PROGRESS_COUNTS: i16 = 3;
/// ... and counts moved within that time (each tick's change, either way,
/// added up) that make it an encoder fault rather than a stall. Movement in
/// the commanded direction alone adds up to at most 2 under the net progress
/// above (a wheel coasting to a stop), so 3 means the count went back and
/// forth: edges arrive but do not add up. Sampled once per tick, the count
/// shows only the parity of each tick's edges (channel B stuck: about half
/// the ticks change it by one; 5 in the 14 ticks on the bench), so an
/// encoder whose edges come in even numbers per tick looks like a stall.
const ENCODER_TRAVEL_COUNTS: u16 = 3;
/// Ticks after a segment start the stall watchdog leaves alone (the first
/// runs at the start duty, below any sensible stall duty; then the wheels
/// spin up from rest).
const STALL_GRACE_TICKS: u8 = 3;
/// Segment time-out: this many times the nominal duration ...
const TIMEOUT_FACTOR: f32 = 4.0;
/// ... plus this many ticks (2 s).
const TIMEOUT_EXTRA_TICKS: u32 = 134;

// ---- one wheel's run through a segment ----

/// Where a wheel is within its segment.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Stage {
    /// Under PID control on its drive input.
    Driving,
    /// Cut (drive input 0), waiting for the counter-pulse.
    Coast,
    /// Counter-pulse: the opposite input at 255.
    Pulse,
    /// Both inputs 0.
    Done,
}

/// One wheel's state.
struct Wheel {
    /// The wheel's drive input is its forward one.
    forward: bool,
    stage: Stage,
    /// Deadline of the `Coast` or `Pulse` stage.
    until: u32,
    pid: TablePid<TABLE_COUNTS>,
    /// Count at the last control period.
    last_count: i32,
    /// Count at the segment start.
    start_count: i32,
    /// Duty applied during the current control period.
    applied: u8,
    /// Stall watchdog: count at the start of the current window (the last
    /// period not judged, or the last net progress of
    /// [`STALL_PROGRESS_COUNTS`]), low 16 bits: within a window the count
    /// stays far closer to it than 2^15 (forward it restarts the window,
    /// backward the wrong-way check stops the wheel) ...
    mark: i16,
    /// ... periods judged since then (driven at or above the stall duty) ...
    still: u16,
    /// ... and counts moved since then, each period's change either way
    /// (valid while `still` > 0).
    travel: u16,
    /// Periods left before the watchdog judges this wheel.
    grace: u8,
}

impl Wheel {
    const fn new() -> Self {
        Wheel {
            forward: true,
            stage: Stage::Done,
            until: 0,
            pid: TablePid::new(robot::GAINS_LEFT, robot::ROBUST_SETPOINT, robot::SAMPLE_PERIOD_S),
            last_count: 0,
            start_count: 0,
            applied: 0,
            mark: 0,
            still: 0,
            travel: 0,
            grace: 0,
        }
    }
}

/// Motors, encoders and both wheels: everything the control tick touches.
pub struct Drive {
    motors: DriveMotors,
    encoders: Encoders,
    left: Wheel,
    right: Wheel,
}

impl Drive {
    /// Sets one bridge input: the wheel's forward (`forward_input`) or
    /// reverse input.
    fn set(&mut self, side: Side, forward_input: bool, duty: u8) {
        match (side, forward_input) {
            (Side::Left, true) => self.motors.left.set_forward(duty),
            (Side::Left, false) => self.motors.left.set_reverse(duty),
            (Side::Right, true) => self.motors.right.set_forward(duty),
            (Side::Right, false) => self.motors.right.set_reverse(duty),
        }
    }

    fn wheel(&mut self, side: Side) -> &mut Wheel {
        match side {
            Side::Left => &mut self.left,
            Side::Right => &mut self.right,
        }
    }
}

/// Limits of the stall watchdog, from the settings.
#[derive(Clone, Copy)]
pub struct StallLimits {
    duty: u8,
    ticks: u16,
}

/// Speed from `counts` over `n` periods when the table does not apply (a
/// missed period, or a count beyond the table; both rare). Out of line so
/// the common path has no conversion and no division.
#[cold]
#[inline(never)]
fn rpm_over(counts: u32, n: u32) -> f32 {
    counts as f32 * RPM_PER_COUNT / n as f32
}

/// What the watchdogs found on one wheel.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Check {
    Ok,
    /// Driven at or above the stall duty without net progress, the count
    /// (nearly) still.
    Stall,
    /// Likewise, but the count moved back and forth.
    EncoderInconsistent,
    /// Too far against the commanded direction.
    WrongWay,
}

/// What one control period decided for one wheel.
struct WheelOutcome {
    rpm: f32,
    duty: u8,
    check: Check,
}

/// One control period of one driving wheel: speed over the last `n`
/// periods, PID, output stage, stall ([`judge_progress`]; only periods
/// driven at or above the stall duty after the start's grace are judged, any
/// other starts the window again) and wrong-direction checks.
#[inline(always)]
fn control_wheel(w: &mut Wheel, count: i32, n: u32, stall: StallLimits) -> WheelOutcome {
    let delta = count.wrapping_sub(w.last_count);
    w.last_count = count;
    let counts = delta.unsigned_abs();
    let rpm = match RPM_OF_COUNTS.get(counts as usize) {
        Some(&r) if n == 1 => r,
        _ => rpm_over(counts, n),
    };
    let duty = duty_from_output(w.pid.update(counts, rpm, n == 1));
    let mut check = Check::Ok;
    if w.applied >= stall.duty && w.grace == 0 {
        let moved = if counts > u16::MAX as u32 { u16::MAX } else { counts as u16 };
        check = judge_progress(w, count as i16, moved, n as u16, stall.ticks);
    } else {
        w.grace = w.grace.saturating_sub(1);
        w.mark = count as i16;
        w.still = 0;
    }
    w.applied = duty;
    if check == Check::Ok {
        let progress = count.wrapping_sub(w.start_count);
        let wrong_way = if w.forward { progress < -WRONG_WAY_COUNTS } else { progress > WRONG_WAY_COUNTS };
        if wrong_way {
            check = Check::WrongWay;
        }
    }
    WheelOutcome { rpm, duty, check }
}

/// The stall watchdog's judgement of one period driven at or above the
/// stall duty (`count` at its end, `counts` moved during it, `n` periods
/// long). Out of line: one copy for both wheels, and a wheel under normal
/// control (below the stall duty) does not call it.
///
/// It judges net progress, once per period (the encoder handlers do nothing
/// for it): once the count has advanced [`STALL_PROGRESS_COUNTS`] in the
/// commanded direction from the window's mark, the window starts again (as
/// it does on any period not judged). `ticks` judged periods without that
/// progress are a fault: an encoder fault if the count moved
/// [`ENCODER_TRAVEL_COUNTS`] or more in that window (edges arrive, the count
/// does not advance), a stall otherwise.
#[inline(never)]
fn judge_progress(w: &mut Wheel, count: i16, counts: u16, n: u16, ticks: u16) -> Check {
    if w.still == 0 {
        w.travel = 0;
    }
    let net = count.wrapping_sub(w.mark);
    let net = if w.forward { net } else { net.wrapping_neg() };
    if net >= STALL_PROGRESS_COUNTS {
        w.mark = count;
        w.still = 0;
        return Check::Ok;
    }
    w.still = w.still.saturating_add(n);
    w.travel = w.travel.saturating_add(counts);
    if w.still < ticks {
        Check::Ok
    } else if w.travel >= ENCODER_TRAVEL_COUNTS {
        Check::EncoderInconsistent
    } else {
        Check::Stall
    }
}

/// The fault code of a wheel's check.
#[inline(always)]
fn fault_of(check: Check, stall: Fault, wrong_way: Fault) -> Fault {
    match check {
        Check::Ok => Fault::None,
        Check::Stall => stall,
        Check::EncoderInconsistent => Fault::EncoderInconsistent,
        Check::WrongWay => wrong_way,
    }
}

/// One control period for every wheel still driving: speed over the last
/// `n` periods, PID, duty on the drive input, bench variables; then the
/// stall and wrong-direction checks. Returns the fault found, if any.
///
/// Not inlined and named, so a timing tool can find its entry and exit.
#[inline(never)]
#[no_mangle]
pub fn ht_control_tick(d: &mut Drive, n: u32, stall: StallLimits) -> Fault {
    let c = d.encoders.counts();
    let mut fault = Fault::None;
    if d.left.stage == Stage::Driving {
        let o = control_wheel(&mut d.left, c.left, n, stall);
        if d.left.forward {
            d.motors.left.set_forward(o.duty);
        } else {
            d.motors.left.set_reverse(o.duty);
        }
        bench::set_speed_left(o.rpm);
        bench::set_duty_left(o.duty);
        fault = fault_of(o.check, Fault::StallLeft, Fault::WrongWayLeft);
    }
    if d.right.stage == Stage::Driving {
        let o = control_wheel(&mut d.right, c.right, n, stall);
        if d.right.forward {
            d.motors.right.set_forward(o.duty);
        } else {
            d.motors.right.set_reverse(o.duty);
        }
        bench::set_speed_right(o.rpm);
        bench::set_duty_right(o.duty);
        if fault == Fault::None {
            fault = fault_of(o.check, Fault::StallRight, Fault::WrongWayRight);
        }
    }
    fault
}

// ---- the application ----

/// What the robot is doing.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Mode {
    /// Waiting for a command.
    Idle,
    /// Driving segment `index` of `test` (or braking its wheels).
    Segment { test: Test, index: u8, leg: Option<Leg> },
    /// After segment `index`: the inertia wait, then (`stop_general`) the
    /// `Stop_General` wait.
    Wait { test: Test, index: u8, stop_general: bool, until: u32 },
}

/// The stop rule of the leg being driven: it ends when
/// `w_left * dL + w_right * dR >= target` (see `odometry::leg_target`).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
struct Leg {
    w_left: i32,
    w_right: i32,
    target: i32,
}

/// A command or event taken out of the parser (which it must not borrow).
enum Input {
    Raw(u8),
    Command(u8, Result<Command, Status>, u8),
    FrameError(Status),
}

struct App {
    drive: Drive,
    clock: Clock,
    leds: Leds,
    adc: Adc,
    adc_running: bool,
    bluetooth: Serial<USART1>,
    debug: Serial<USART0>,
    parser: Parser,
    /// The isolation rule for raw selector bytes.
    raw: Isolation,
    settings: Settings,
    mode: Mode,
    /// Leg length of the running test (read at its start).
    leg_mm: f32,
    /// Ticks since the segment started, and its limit.
    segment_ticks: u32,
    segment_limit: u32,
}

impl App {
    /// Looks at every event source once. Called after each wake-up.
    fn poll(&mut self) {
        let (tripped, counts) = self.drive.encoders.take_tripped();
        if tripped != 0 {
            self.on_trips(tripped, counts);
        }
        if self.next_deadline().is_some() {
            self.on_time(self.clock.now());
        }
        let n = self.clock.take_ticks();
        if n > 0 {
            self.on_tick(n);
        }
        self.poll_commands();
        self.arm_next_deadline();
    }

    // -- segments --

    /// Starts `test` if idle and the leg length is valid.
    fn start_test(&mut self, test: Test) -> Result<(), Status> {
        if self.mode != Mode::Idle {
            return Err(Status::Busy);
        }
        self.leg_mm = Param::LegLengthMm.check(bench::leg_length_mm())?;
        bench::set_fault(Fault::None as u8);
        bench::set_test(test as u8);
        self.start_segment(test, 0);
        Ok(())
    }

    /// Starts segment `index` of `test`, or finishes the test after its last.
    fn start_segment(&mut self, test: Test, index: u8) {
        let Some(segment) = plan::segment(test, index) else {
            self.finish_test(test);
            return;
        };
        let s = self.settings;
        let c = self.drive.encoders.counts();
        bench::record_segment_start(index, c.left, c.right);
        self.drive.encoders.disarm_all();
        let mut leg = None;
        let (forward, wheel_counts) = match segment {
            Segment::Leg => {
                let l = Leg {
                    w_left: leg_weight(s.correction.left),
                    w_right: leg_weight(s.correction.right),
                    target: leg_target(self.leg_mm),
                };
                leg = Some(l);
                self.arm_leg(l, c, c);
                let c_min = if s.correction.left < s.correction.right { s.correction.left } else { s.correction.right };
                ((true, true), self.leg_mm / (c_min * robot::MM_PER_COUNT))
            }
            Segment::Turn { spin, triangle } => {
                let angle = if triangle { s.turn_triangle_deg } else { s.turn_umbmark_deg };
                let nl = spin_target_counts(angle, s.wheelbase_mm, s.correction.left);
                let nr = spin_target_counts(angle, s.wheelbase_mm, s.correction.right);
                let (fl, fr) = spin.forward();
                let at = |start: i32, up: bool, n: i32| if up { start.wrapping_add(n) } else { start.wrapping_sub(n) };
                self.drive.encoders.arm(Side::Left, fl, at(c.left, fl, nl));
                self.drive.encoders.arm(Side::Right, fr, at(c.right, fr, nr));
                ((fl, fr), (if nl > nr { nl } else { nr }) as f32)
            }
        };
        // The set-points are ground speeds: a wheel whose counts are worth
        // c times the nominal distance must turn 1/c times as fast in counts.
        // That is where c_L, c_R straighten a leg (the wheels then cover equal
        // ground per period); in the stop rules above they only measure it.
        let raw = PerWheel { left: s.setpoint.left / s.correction.left, right: s.setpoint.right / s.correction.right };
        // Time-out from the slower wheel's counts per period.
        let set_min = if raw.left < raw.right { raw.left } else { raw.right };
        let nominal = wheel_counts / (set_min / RPM_PER_COUNT);
        self.segment_limit = (TIMEOUT_FACTOR * nominal) as u32 + TIMEOUT_EXTRA_TICKS;
        self.segment_ticks = 0;
        for (side, fwd, count, gains, set) in [
            (Side::Left, forward.0, c.left, s.gains.left, raw.left),
            (Side::Right, forward.1, c.right, s.gains.right, raw.right),
        ] {
            let w = self.drive.wheel(side);
            w.forward = fwd;
            w.stage = Stage::Driving;
            w.pid.prepare(gains, set, robot::SAMPLE_PERIOD_S, &RPM_OF_COUNTS);
            w.last_count = count;
            w.start_count = count;
            w.applied = robot::START_DUTY;
            w.mark = count as i16;
            w.still = 0;
            w.grace = STALL_GRACE_TICKS;
        }
        self.clock.restart_period();
        let duty = robot::START_DUTY;
        self.drive.set(Side::Left, !forward.0, 0);
        self.drive.set(Side::Right, !forward.1, 0);
        self.drive.set(Side::Left, forward.0, duty);
        self.drive.set(Side::Right, forward.1, duty);
        bench::set_duty_left(duty);
        bench::set_duty_right(duty);
        bench::set_phase(if segment == Segment::Leg { Phase::Leg } else { Phase::Turn });
        bench::set_state(State::Driving);
        self.mode = Mode::Segment { test, index, leg };
    }

    /// Arms both trips of a leg from the counts `now` (start: `start`): each
    /// wheel at half the remaining weighted distance ahead, so that the sum
    /// cannot reach the target before one of them fires. Returns true when
    /// the leg's end is already reached.
    fn arm_leg(&mut self, l: Leg, start: Counts, now: Counts) -> bool {
        let done =
            leg_progress(l.w_left, l.w_right, now.left.wrapping_sub(start.left), now.right.wrapping_sub(start.right));
        let remaining = l.target as i64 - done;
        if remaining <= 0 {
            return true;
        }
        let (al, ar) = (leg_trip_ahead(remaining, l.w_left), leg_trip_ahead(remaining, l.w_right));
        self.drive.encoders.arm(Side::Left, true, now.left.wrapping_add(al));
        self.drive.encoders.arm(Side::Right, true, now.right.wrapping_add(ar));
        false
    }

    /// Trips fired: cut the wheels whose segment end came (a turn), or check
    /// the leg's stop rule and re-arm closer to the end (a leg).
    fn on_trips(&mut self, tripped: u8, counts: Counts) {
        let Mode::Segment { leg, .. } = self.mode else { return };
        let now = self.clock.now();
        if let Some(l) = leg {
            if self.drive.left.stage != Stage::Driving {
                return;
            }
            let start = Counts { left: self.drive.left.start_count, right: self.drive.right.start_count };
            if !self.arm_leg(l, start, counts) {
                return;
            }
            // End of a leg: all four inputs to 0 first, then the counts.
            let d = &mut self.drive;
            let c = interrupt::free(|_| {
                d.motors.all_off();
                d.encoders.counts()
            });
            self.drive.encoders.disarm_all();
            bench::set_stop_left(c.left);
            bench::set_stop_right(c.right);
            bench::record_cut(3, c.left, c.right);
            for side in [Side::Left, Side::Right] {
                let w = self.drive.wheel(side);
                w.stage = Stage::Coast;
                w.until = now.wrapping_add(BRAKE_COAST);
            }
        } else {
            for (bit, side, mask) in [(TRIP_LEFT, Side::Left, 1), (TRIP_RIGHT, Side::Right, 2)] {
                if tripped & bit == 0 || self.drive.wheel(side).stage != Stage::Driving {
                    continue;
                }
                let fwd = self.drive.wheel(side).forward;
                let d = &mut self.drive;
                let c = interrupt::free(|_| {
                    d.set(side, fwd, 0);
                    d.encoders.counts()
                });
                bench::record_cut(mask, c.left, c.right);
                let w = self.drive.wheel(side);
                w.stage = Stage::Coast;
                w.until = now.wrapping_add(BRAKE_COAST);
            }
        }
        if self.drive.left.stage != Stage::Driving && self.drive.right.stage != Stage::Driving {
            bench::set_phase(Phase::Braking);
            bench::set_state(State::Braking);
        }
    }

    /// Moves every deadline that has come: wheel braking stages, waits.
    fn on_time(&mut self, now: u32) {
        match self.mode {
            Mode::Idle => {}
            Mode::Segment { test, index, .. } => {
                if self.drive.left.stage == Stage::Driving && self.drive.right.stage == Stage::Driving {
                    return;
                }
                for side in [Side::Left, Side::Right] {
                    let w = self.drive.wheel(side);
                    let (stage, until, fwd) = (w.stage, w.until, w.forward);
                    if !time::reached(now, until) {
                        continue;
                    }
                    match stage {
                        Stage::Coast => {
                            self.drive.set(side, !fwd, 255);
                            let w = self.drive.wheel(side);
                            w.stage = Stage::Pulse;
                            w.until = now.wrapping_add(BRAKE_PULSE);
                        }
                        Stage::Pulse => {
                            self.drive.set(side, !fwd, 0);
                            self.drive.wheel(side).stage = Stage::Done;
                        }
                        Stage::Driving | Stage::Done => {}
                    }
                }
                if self.drive.left.stage == Stage::Done && self.drive.right.stage == Stage::Done {
                    self.mode = Mode::Wait { test, index, stop_general: false, until: now.wrapping_add(INERTIA_WAIT) };
                }
            }
            Mode::Wait { test, index, stop_general, until } => {
                if !time::reached(now, until) {
                    return;
                }
                if stop_general {
                    self.start_segment(test, index + 1);
                } else {
                    self.drive.motors.all_off();
                    self.mode = Mode::Wait { test, index, stop_general: true, until: now.wrapping_add(STOP_WAIT) };
                }
            }
        }
    }

    /// The earliest pending deadline, if any.
    #[inline(always)]
    fn next_deadline(&self) -> Option<u32> {
        match self.mode {
            Mode::Idle => None,
            Mode::Wait { until, .. } => Some(until),
            Mode::Segment { .. } => {
                let pending = |w: &Wheel| matches!(w.stage, Stage::Coast | Stage::Pulse).then_some(w.until);
                match (pending(&self.drive.left), pending(&self.drive.right)) {
                    (Some(a), Some(b)) => Some(if time::reached(b, a) { a } else { b }),
                    (a, b) => a.or(b),
                }
            }
        }
    }

    /// Arms the timer 1 alarm for the next deadline (handling the ones that
    /// come while arming); bounded: at most four rounds, the tick catches
    /// anything left.
    fn arm_next_deadline(&mut self) {
        for _ in 0..4 {
            let Some(at) = self.next_deadline() else {
                self.clock.disarm_alarm();
                return;
            };
            if self.clock.arm_alarm(at) {
                return;
            }
            self.on_time(self.clock.now());
        }
    }

    /// A control tick: battery, control, watchdogs of the segment.
    fn on_tick(&mut self, n: u32) {
        self.battery();
        let Mode::Segment { .. } = self.mode else { return };
        if self.drive.left.stage != Stage::Driving && self.drive.right.stage != Stage::Driving {
            return;
        }
        bench::set_period_us(if n == 1 { PERIOD_US } else { PERIOD_US * n as f32 });
        let stall_ticks = (self.settings.stall_timeout_ms as u32).div_ceil(robot::SAMPLE_PERIOD_US / 1000);
        let stall = StallLimits { duty: self.settings.stall_duty, ticks: stall_ticks as u16 };
        let mut fault = ht_control_tick(&mut self.drive, n, stall);
        self.segment_ticks = self.segment_ticks.saturating_add(n);
        if fault == Fault::None && self.segment_ticks > self.segment_limit {
            fault = Fault::SegmentTimeout;
        }
        if fault != Fault::None {
            self.fault(fault);
        }
    }

    /// Reads the conversion started on the previous tick, shows its colour,
    /// starts the next.
    fn battery(&mut self) {
        if self.adc_running && !self.adc.busy() {
            let v = self.adc.result();
            bench::set_battery_adc(v);
            self.leds.show_if_changed(battery::robust_colour(v));
        }
        self.adc.start();
        self.adc_running = true;
    }

    /// Motors off now, the fault reported; idle.
    fn fault(&mut self, fault: Fault) {
        let phase = bench::phase_code();
        let d = &mut self.drive;
        let c = interrupt::free(|_| {
            d.motors.all_off();
            d.encoders.counts()
        });
        self.stop_all();
        bench::set_fault(fault as u8);
        bench::set_phase(Phase::Fault);
        let notice = FaultNotice {
            fault: fault as u8,
            test: bench::test(),
            segment: bench::segment(),
            phase,
            left: c.left.wrapping_sub(bench::seg_start_left()),
            right: c.right.wrapping_sub(bench::seg_start_right()),
        };
        self.send(NOTIFY_FAULT, Status::Ok, &notice.to_bytes());
        let _ = ufmt::uwrite!(
            &mut self.debug,
            "fault {} in test {} segment {}: left={} right={}\r\n",
            fault as u8,
            notice.test,
            notice.segment,
            notice.left,
            notice.right
        );
    }

    /// Motors off, trips and alarm off, idle (phase 0).
    fn stop_all(&mut self) {
        self.drive.motors.all_off();
        self.drive.encoders.disarm_all();
        self.drive.left.stage = Stage::Done;
        self.drive.right.stage = Stage::Done;
        self.clock.disarm_alarm();
        self.mode = Mode::Idle;
        bench::set_phase(Phase::Idle);
        bench::set_state(State::Idle);
    }

    /// End of a test: count it, report it.
    fn finish_test(&mut self, test: Test) {
        self.mode = Mode::Idle;
        let done = bench::done_count().wrapping_add(1);
        bench::set_done_count(done);
        bench::set_phase(Phase::Idle);
        bench::set_state(State::Idle);
        self.send(NOTIFY_TEST_DONE, Status::Ok, &TestDoneNotice { test: test as u8, tests_done: done }.to_bytes());
        // Queued, never waited for; a full buffer cuts the line.
        let _ = ufmt::uwrite!(
            &mut self.debug,
            "test {} done: stop left={} right={}\r\n",
            done,
            bench::stop_left(),
            bench::stop_right()
        );
    }

    // -- commands --

    /// Reads what the Bluetooth UART received (bounded by the ring size),
    /// ends a frame the line left incomplete, and takes a raw byte once the
    /// line has stayed quiet after it.
    fn poll_commands(&mut self) {
        let now = self.clock.now();
        if let Some(Event::Error(e)) = self.parser.poll(now) {
            self.handle(Input::FrameError(e.into()));
        }
        for _ in 0..RX_LEN {
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
                    ticks: interrupt::free(bench::ticks),
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
    fn send(&mut self, id: u8, status: Status, data: &[u8]) {
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

#[avr_device::entry]
fn main() -> ! {
    // SAFETY: first thing after reset, called once; every peripheral is then
    // moved into exactly one driver.
    let dp = unsafe { Peripherals::steal() };
    // The watchdog first: after a watchdog reset it runs with its shortest
    // period until WDRF is cleared and it is turned off.
    let reset_cause = wdt::take_reset_cause(&dp.CPU);
    let mut watchdog = Watchdog::disabled(dp.WDT);
    let pins = board::Pins::new(dp.PORTB, dp.PORTD, dp.PORTE, dp.PORTF, dp.PORTG, dp.PORTH);

    // Motors first, so the bridge inputs are low from the start.
    let motors = board::drive_motors(
        dp.TC4,
        dp.TC2,
        pins.right_reverse,
        pins.right_forward,
        pins.left_reverse,
        pins.left_forward,
    );
    let encoders = Encoders::new(
        ExtInts::new(dp.EXINT),
        pins.left_encoder_a,
        pins.left_encoder_b,
        pins.right_encoder_a,
        pins.right_encoder_b,
    );
    let leds = Leds::new(pins.led_green, pins.led_blue, pins.led_red);
    let _battery_pin = pins.battery_sense;
    let adc = Adc::new(dp.ADC);
    let debug = Serial::new(dp.USART0, board::DEBUG_BAUD);
    let bluetooth = Serial::new(dp.USART1, board::BLUETOOTH_BAUD);
    let mut sleeper = Sleeper::new(dp.CPU);
    let clock = Clock::start(dp.TC1);

    let mut app = App {
        drive: Drive { motors, encoders, left: Wheel::new(), right: Wheel::new() },
        clock,
        leds,
        adc,
        adc_running: false,
        bluetooth,
        debug,
        parser: Parser::new(INTER_BYTE_TIMEOUT),
        raw: Isolation::new(RAW_QUIET),
        settings: Settings::DEFAULT,
        mode: Mode::Idle,
        leg_mm: robot::DEFAULT_LEG_MM,
        segment_ticks: 0,
        segment_limit: 0,
    };

    // SAFETY: every handler's state is initialised above.
    unsafe { interrupt::enable() };
    let _ = app.debug.write_all(BOOT_LINE);
    if reset_cause & wdt::WDRF != 0 {
        bench::set_fault(Fault::WatchdogReset as u8);
        bench::set_phase(Phase::Fault);
        let notice = FaultNotice { fault: Fault::WatchdogReset as u8, ..FaultNotice::default() };
        app.send(NOTIFY_FAULT, Status::Ok, &notice.to_bytes());
    }
    watchdog.enable_250ms();
    bench::set_state(State::Idle);

    loop {
        app.poll();
        watchdog.feed();
        sleeper.idle();
    }
}
