//! A test's run: its segments in order ([`crate::plan`]), each driven until
//! its stop rule, then the thesis' braking and waits; the control tick and
//! its faults; the end of the test.
//!
//! - A leg ends when `w_left * dL + w_right * dR >= target`
//!   ([`crate::odometry::leg_target`]): the encoder trips are armed at half
//!   the remaining weighted distance ahead, so the main loop wakes a dozen
//!   times per leg and both wheels are cut within one count of the end.
//! - In a spin turn each wheel is cut when its own count reaches its own
//!   target.
//! - A cut wheel coasts `brake_coast_ms` (factory [`BRAKE_COAST`]), then
//!   gets a counter-pulse of `brake_pulse_ms` (factory [`BRAKE_PULSE`]);
//!   when both are done, [`INERTIA_WAIT`] and [`STOP_WAIT`] pass before the
//!   next segment (the thesis' `Inercia_Stop_*` and `Stop_General`).
//! - A stop lead (`stop_lead_ms`, factory 0) moves the cut earlier by the
//!   distance a wheel covers in that time at its set-point, the coast a
//!   robot with slow motors makes after it: taken off the leg's target and
//!   the turn wheels' counts once, at the segment start (never in the
//!   control tick).
//! - A fault (from the watchdogs, or the segment time-out) stops the motors
//!   at once and ends the test.

use henrytwo_protocol::{
    Fault, FaultNotice, Param, Phase, RunState, Status, Test, TestDoneNotice, NOTIFY_FAULT, NOTIFY_TEST_DONE,
};

use crate::battery;
use crate::bench;
use crate::critical;
use crate::io::{BatteryInput, BatteryLeds, Bridges, Counts, Side, TickClock, WheelEncoders, TRIP_LEFT, TRIP_RIGHT};
use crate::odometry::{leg_progress, leg_reference_mm, leg_target, leg_trip_ahead, leg_weight, spin_target_counts};
use crate::plan::{self, Segment};
use crate::robot;
use crate::settings::PerWheel;
use crate::time;

use super::control::{StallLimits, Tuned, PERIOD_US};
use super::drive::{Stage, Wheel};
use super::progress::STALL_GRACE_TICKS;
use super::{App, Hardware};

/// Thesis `Inercia_Stop_*`: after a wheel is cut, 20 ms until its
/// counter-pulse (the factory `brake_coast_ms`) ...
pub const BRAKE_COAST: u32 = time::ms(20);
/// ... which lasts 5 ms at full duty (the factory `brake_pulse_ms`) ...
pub const BRAKE_PULSE: u32 = time::ms(5);
/// ... then the `delay(1000)` that ends `Inercia_Stop_*` ...
pub const INERTIA_WAIT: u32 = time::ms(1000);
/// ... and `Stop_General`'s `delay(1000)`.
pub const STOP_WAIT: u32 = time::ms(1000);
/// Segment time-out: this many times the nominal duration ...
pub const TIMEOUT_FACTOR: f32 = 4.0;
/// ... plus this many ticks (2 s).
pub const TIMEOUT_EXTRA_TICKS: u32 = 134;

/// A turn wheel's cut with a stop lead this close (counts) is armed as the
/// cut; a farther one is looked at again halfway there.
pub const TURN_CUT_NEAR: i32 = 4;

/// What the robot is doing.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Mode {
    /// Waiting for a command.
    Idle,
    /// Driving segment `index` of `test` (or braking its wheels).
    Segment {
        /// The running test.
        test: Test,
        /// The segment's index within it.
        index: u8,
        /// A leg's stop rule; `None` in a turn.
        leg: Option<Leg>,
    },
    /// After segment `index`: the inertia wait, then (`stop_general`) the
    /// `Stop_General` wait.
    Wait {
        /// The running test.
        test: Test,
        /// The segment just driven.
        index: u8,
        /// In the second wait.
        stop_general: bool,
        /// End of the wait.
        until: u32,
    },
}

/// The stop rule of the leg being driven: it ends when
/// `w_left * dL + w_right * dR >= target` (see `odometry::leg_target`).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Leg {
    /// Weight of the left wheel's counts.
    pub w_left: i32,
    /// Weight of the right wheel's counts.
    pub w_right: i32,
    /// The weighted distance to reach.
    pub target: i64,
}

impl<H: Hardware> App<H> {
    /// Starts `test` if idle, the leg length is valid and the motor driver's
    /// wiring can be driven (it is applied then).
    pub(crate) fn start_test(&mut self, test: Test) -> Result<(), Status> {
        if self.mode != Mode::Idle {
            return Err(Status::Busy);
        }
        self.leg_mm = Param::LegLengthMm.check(bench::leg_length_mm())?;
        self.apply_wiring()?;
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
        let s = self.stored.settings;
        let c = self.drive.encoders.counts();
        bench::record_segment_start(index, c.left, c.right);
        self.drive.encoders.disarm_all();
        let mut leg = None;
        let (forward, wheel_counts) = match segment {
            Segment::Leg => {
                let m = s.mm_per_count;
                let r = leg_reference_mm(m.left, m.right);
                let to_cut = if s.stop.lead_ms == 0 { self.leg_mm } else { self.leg_mm - self.leg_lead_mm() };
                let l = Leg {
                    w_left: leg_weight(s.correction.left, m.left, r),
                    w_right: leg_weight(s.correction.right, m.right, r),
                    target: leg_target(to_cut, r),
                };
                leg = Some(l);
                self.arm_leg(l, c, c);
                // The wheel with the shortest corrected distance per count
                // makes the most counts.
                let (dl, dr) = (s.correction.left * m.left, s.correction.right * m.right);
                ((true, true), self.leg_mm / if dl < dr { dl } else { dr })
            }
            Segment::Turn { spin, triangle } => {
                let angle = if triangle { s.turn_triangle_deg } else { s.turn_umbmark_deg };
                let m = s.mm_per_count;
                let nl = spin_target_counts(angle, s.wheelbase_mm, s.correction.left, m.left);
                let nr = spin_target_counts(angle, s.wheelbase_mm, s.correction.right, m.right);
                let (fl, fr) = spin.forward();
                let at = |start: i32, up: bool, n: i32| if up { start.wrapping_add(n) } else { start.wrapping_sub(n) };
                let (mut al, mut ar) = (nl, nr);
                if s.stop.lead_ms != 0 {
                    al = self.turn_look_ahead(nl, Side::Left);
                    ar = self.turn_look_ahead(nr, Side::Right);
                    self.turn_ahead = [Some(at(c.left, fl, nl)), Some(at(c.right, fr, nr))];
                }
                self.drive.encoders.arm(Side::Left, fl, at(c.left, fl, al));
                self.drive.encoders.arm(Side::Right, fr, at(c.right, fr, ar));
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
        let nominal = wheel_counts / (set_min / self.drive.speeds.per_count);
        self.segment_limit = (TIMEOUT_FACTOR * nominal) as u32 + TIMEOUT_EXTRA_TICKS;
        self.segment_ticks = 0;
        self.tuned = Tuned::of(s.stop.progress_counts, s.stop.wrong_way_counts);
        for (side, fwd, count, gains, set) in [
            (Side::Left, forward.0, c.left, s.gains.left, raw.left),
            (Side::Right, forward.1, c.right, s.gains.right, raw.right),
        ] {
            let (w, speeds) = self.drive.wheel_and_speeds(side);
            w.forward = fwd;
            w.stage = Stage::Driving;
            w.pid.prepare(gains, set, robot::SAMPLE_PERIOD_S, &speeds.of_counts);
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
        bench::set_state(RunState::Driving);
        self.mode = Mode::Segment { test, index, leg };
    }

    /// Counts a wheel makes in the stop lead at its set-point (`set`, thesis
    /// RPM in counts, i.e. set-point / c): lead periods times counts per
    /// period. Out of line and cold: a factory robot (lead 0) never calls it.
    #[cold]
    #[inline(never)]
    fn lead_counts(&self, set: f32) -> f32 {
        let periods = self.stored.settings.stop.lead_ms as f32 * 1000.0 / robot::SAMPLE_PERIOD_US as f32;
        periods * set / self.drive.speeds.per_count
    }

    /// The leg's stop lead in millimetres of the mean corrected wheel
    /// distance (each wheel's counts in the lead times its corrected
    /// distance per count), at most half the leg: a short leg never reaches
    /// the set-point, and a cut at its start would drive nothing.
    #[cold]
    #[inline(never)]
    fn leg_lead_mm(&self) -> f32 {
        let s = &self.stored.settings;
        let (c, m, sp) = (s.correction, s.mm_per_count, s.setpoint);
        let left = self.lead_counts(sp.left / c.left) * c.left * m.left;
        let right = self.lead_counts(sp.right / c.right) * c.right * m.right;
        let lead = (left + right) / 2.0;
        let half = self.leg_mm / 2.0;
        if lead > half {
            half
        } else {
            lead
        }
    }

    /// Where a turn wheel with a stop lead is first looked at: twice the
    /// lead's counts at its set-point before its target `n` (the wheel may
    /// be faster than the set-point by then), leaving at least a quarter
    /// of `n`; its cut is then placed from its speed ([`Self::lead_cut`]).
    #[cold]
    #[inline(never)]
    fn turn_look_ahead(&self, n: i32, side: Side) -> i32 {
        let s = &self.stored.settings;
        let (sp, c) = match side {
            Side::Left => (s.setpoint.left, s.correction.left),
            Side::Right => (s.setpoint.right, s.correction.right),
        };
        let lead = (2.0 * self.lead_counts(sp / c) + 0.5) as i32;
        let most = n - n / 4;
        n - if lead > most { most } else { lead }
    }

    /// A turn wheel's look-ahead trip fired: its cut is the counts it
    /// covers in the stop lead at its speed of the last control period
    /// (`rpm`, thesis RPM in counts) before `target`. The wheel may still be
    /// speeding up, so a cut far ahead is looked at again halfway there (as
    /// a leg's trips close in); a near one (within [`TURN_CUT_NEAR`] counts)
    /// is armed as the cut. Returns true when the wheel is at or past its
    /// cut: cut it now.
    #[cold]
    #[inline(never)]
    fn lead_cut(&mut self, side: Side, target: i32, now: i32, rpm: f32) -> bool {
        let lead = (self.lead_counts(rpm) + 0.5) as i32;
        let fwd = self.drive.wheel(side).forward;
        let cut = if fwd { target.wrapping_sub(lead) } else { target.wrapping_add(lead) };
        let ahead = if fwd { cut.wrapping_sub(now) } else { now.wrapping_sub(cut) };
        if ahead <= 0 {
            return true;
        }
        let step = if ahead <= TURN_CUT_NEAR { ahead } else { ahead / 2 };
        if step == ahead {
            self.turn_ahead[side as usize] = None;
        }
        self.drive.encoders.arm(side, fwd, if fwd { now.wrapping_add(step) } else { now.wrapping_sub(step) });
        false
    }

    /// Arms both trips of a leg from the counts `now` (start: `start`): each
    /// wheel at half the remaining weighted distance ahead, so that the sum
    /// cannot reach the target before one of them fires. Returns true when
    /// the leg's end is already reached.
    fn arm_leg(&mut self, l: Leg, start: Counts, now: Counts) -> bool {
        let done =
            leg_progress(l.w_left, l.w_right, now.left.wrapping_sub(start.left), now.right.wrapping_sub(start.right));
        let remaining = l.target - done;
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
    pub(crate) fn on_trips(&mut self, tripped: u8, counts: Counts) {
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
            let c = critical::free(|_| {
                d.motors.all_off();
                d.encoders.counts()
            });
            self.drive.encoders.disarm_all();
            bench::set_stop_left(c.left);
            bench::set_stop_right(c.right);
            bench::record_cut(3, c.left, c.right);
            let coast = time::ms_of(self.stored.settings.stop.coast_ms);
            for side in [Side::Left, Side::Right] {
                let w = self.drive.wheel(side);
                w.stage = Stage::Coast;
                w.until = now.wrapping_add(coast);
            }
        } else {
            for (bit, side, mask) in [(TRIP_LEFT, Side::Left, 1), (TRIP_RIGHT, Side::Right, 2)] {
                if tripped & bit == 0 || self.drive.wheel(side).stage != Stage::Driving {
                    continue;
                }
                let i = side as usize;
                if let Some(target) = self.turn_ahead[i] {
                    let (now_count, rpm) = match side {
                        Side::Left => (counts.left, bench::speed_left()),
                        Side::Right => (counts.right, bench::speed_right()),
                    };
                    if !self.lead_cut(side, target, now_count, rpm) {
                        continue;
                    }
                    self.turn_ahead[i] = None;
                }
                let fwd = self.drive.wheel(side).forward;
                let d = &mut self.drive;
                let c = critical::free(|_| {
                    d.set(side, fwd, 0);
                    d.encoders.counts()
                });
                bench::record_cut(mask, c.left, c.right);
                let coast = time::ms_of(self.stored.settings.stop.coast_ms);
                let w = self.drive.wheel(side);
                w.stage = Stage::Coast;
                w.until = now.wrapping_add(coast);
            }
        }
        if self.drive.left.stage != Stage::Driving && self.drive.right.stage != Stage::Driving {
            bench::set_phase(Phase::Braking);
            bench::set_state(RunState::Braking);
        }
    }

    /// Moves every deadline that has come: wheel braking stages, waits.
    pub(crate) fn on_time(&mut self, now: u32) {
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
                            let pulse = time::ms_of(self.stored.settings.stop.pulse_ms);
                            let w = self.drive.wheel(side);
                            w.stage = Stage::Pulse;
                            w.until = now.wrapping_add(pulse);
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
    pub(crate) fn next_deadline(&self) -> Option<u32> {
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
    pub(crate) fn arm_next_deadline(&mut self) {
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
    pub(crate) fn on_tick(&mut self, n: u32) {
        self.battery();
        let Mode::Segment { .. } = self.mode else { return };
        if self.drive.left.stage != Stage::Driving && self.drive.right.stage != Stage::Driving {
            return;
        }
        bench::set_period_us(if n == 1 { PERIOD_US } else { PERIOD_US * n as f32 });
        let stall_ticks = (self.stored.settings.stall_timeout_ms as u32).div_ceil(robot::SAMPLE_PERIOD_US / 1000);
        let stall = StallLimits { duty: self.stored.settings.stall_duty, ticks: stall_ticks as u16 };
        let mut fault = match self.tuned {
            None => H::control_tick(&mut self.drive, n, stall),
            Some(t) => H::control_tick_tuned(&mut self.drive, n, stall, t),
        };
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
        let c = critical::free(|_| {
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
    pub(crate) fn stop_all(&mut self) {
        self.drive.motors.all_off();
        self.drive.encoders.disarm_all();
        self.turn_ahead = [None; 2];
        self.drive.left.stage = Stage::Done;
        self.drive.right.stage = Stage::Done;
        self.clock.disarm_alarm();
        self.mode = Mode::Idle;
        bench::set_phase(Phase::Idle);
        bench::set_state(RunState::Idle);
    }

    /// End of a test: count it, report it.
    fn finish_test(&mut self, test: Test) {
        self.mode = Mode::Idle;
        let done = bench::done_count().wrapping_add(1);
        bench::set_done_count(done);
        bench::set_phase(Phase::Idle);
        bench::set_state(RunState::Idle);
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
}

#[cfg(test)]
mod tests;
