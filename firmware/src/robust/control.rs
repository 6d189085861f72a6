//! The control law of one period: each driving wheel's speed from its count
//! change, the PID, the output stage on its drive input, the bench
//! variables; then the watchdogs ([`super::progress`]).

use henrytwo_protocol::Fault;

use crate::bench;
use crate::io::{Bridges, Side, WheelEncoders};
use crate::pid::duty_from_output;
use crate::robot;

pub use super::drive::TABLE_COUNTS;
use super::drive::{Drive, Speeds, Stage, Wheel};
use super::progress::{fault_of, judge_progress, Check};
pub use super::progress::{Factory, Thresholds, Tuned};

/// One control period in microseconds, as `HT_PERIOD_US` shows it.
pub const PERIOD_US: f32 = robot::SAMPLE_PERIOD_US as f32;

/// Limits of the stall watchdog, from the settings.
#[derive(Clone, Copy, Debug)]
pub struct StallLimits {
    /// Periods driven at or above this duty are judged.
    pub duty: u8,
    /// Judged periods without net progress that make a fault.
    pub ticks: u16,
}

/// Speed from `counts` over `n` periods when the table does not apply (a
/// missed period, or a count beyond the table; both rare). Out of line so
/// the common path has no conversion and no division.
#[cold]
#[inline(never)]
fn rpm_over(counts: u32, n: u32, per_count: f32) -> f32 {
    counts as f32 * per_count / n as f32
}

/// What one control period decided for one wheel.
pub(crate) struct WheelOutcome {
    pub(crate) rpm: f32,
    pub(crate) duty: u8,
    pub(crate) check: Check,
}

/// One control period of one driving wheel: speed over the last `n`
/// periods (`speeds`: the robot's conversion), PID, output stage, stall ([`judge_progress`]; only periods
/// driven at or above the stall duty after the start's grace are judged, any
/// other starts the window again) and wrong-direction checks.
#[inline(always)]
pub(crate) fn control_wheel<T: Thresholds>(
    w: &mut Wheel,
    speeds: &Speeds,
    count: i32,
    n: u32,
    stall: StallLimits,
    t: T,
) -> WheelOutcome {
    let delta = count.wrapping_sub(w.last_count);
    w.last_count = count;
    let counts = delta.unsigned_abs();
    let rpm = match speeds.of_counts.get(counts as usize) {
        Some(&r) if n == 1 => r,
        _ => rpm_over(counts, n, speeds.per_count),
    };
    let duty = duty_from_output(w.pid.update(counts, rpm, n == 1));
    let mut check = Check::Ok;
    if w.applied >= stall.duty && w.grace == 0 {
        let moved = if counts > u16::MAX as u32 { u16::MAX } else { counts as u16 };
        check = judge_progress(w, count as i16, moved, n as u16, stall.ticks, t);
    } else {
        w.grace = w.grace.saturating_sub(1);
        w.mark = count as i16;
        w.still = 0;
    }
    w.applied = duty;
    if check == Check::Ok {
        let progress = count.wrapping_sub(w.start_count);
        let limit = t.wrong_way();
        let wrong_way = if w.forward { progress < -limit } else { progress > limit };
        if wrong_way {
            check = Check::WrongWay;
        }
    }
    WheelOutcome { rpm, duty, check }
}

/// One control period for every wheel still driving: speed over the last
/// `n` periods, PID, duty on the drive input, bench variables; then the
/// stall and wrong-direction checks. Returns the fault found, if any.
///
/// Inlined into its caller: the firmware calls it from one named function
/// (`ht_control_tick`) that a timing tool finds by its symbol.
#[inline(always)]
pub fn tick<M: Bridges, E: WheelEncoders, T: Thresholds>(
    d: &mut Drive<M, E>,
    n: u32,
    stall: StallLimits,
    t: T,
) -> Fault {
    let c = d.encoders.counts();
    let mut fault = Fault::None;
    if d.left.stage == Stage::Driving {
        let o = control_wheel(&mut d.left, &d.speeds, c.left, n, stall, t);
        if d.left.forward {
            d.motors.set_forward(Side::Left, o.duty);
        } else {
            d.motors.set_reverse(Side::Left, o.duty);
        }
        bench::set_speed_left(o.rpm);
        bench::set_duty_left(o.duty);
        fault = fault_of(o.check, Fault::StallLeft, Fault::WrongWayLeft);
    }
    if d.right.stage == Stage::Driving {
        let o = control_wheel(&mut d.right, &d.speeds, c.right, n, stall, t);
        if d.right.forward {
            d.motors.set_forward(Side::Right, o.duty);
        } else {
            d.motors.set_reverse(Side::Right, o.duty);
        }
        bench::set_speed_right(o.rpm);
        bench::set_duty_right(o.duty);
        if fault == Fault::None {
            fault = fault_of(o.check, Fault::StallRight, Fault::WrongWayRight);
        }
    }
    fault
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pid::{thesis_rpm, FastPid};
    use crate::robust::fake::{self, Encoders, Motors};
    use crate::robust::progress::STALL_GRACE_TICKS;
    use crate::settings::Settings;

    use crate::robust::progress::{STALL_PROGRESS_COUNTS, WRONG_WAY_COUNTS};

    const LIMITS: StallLimits = StallLimits { duty: 200, ticks: 14 };

    /// Henrytwo's conversion (the factory settings').
    fn henrytwo() -> Speeds {
        let mut s = Speeds::new();
        s.set(Settings::DEFAULT.counts_per_wheel_rev);
        s
    }

    /// A drive at rest with Henrytwo's conversion.
    fn drive() -> Drive<Motors, Encoders> {
        let mut d = Drive::new(Motors::default(), Encoders::default());
        d.speeds = henrytwo();
        d
    }

    /// A wheel driving from count 0, as a segment start leaves it.
    fn driving(forward: bool) -> Wheel {
        let mut w = Wheel::new();
        w.forward = forward;
        w.stage = Stage::Driving;
        w.pid.prepare(robot::GAINS_LEFT, robot::ROBUST_SETPOINT, robot::SAMPLE_PERIOD_S, &henrytwo().of_counts);
        w.applied = robot::START_DUTY;
        w.grace = STALL_GRACE_TICKS;
        w
    }

    #[test]
    fn henrytwo_speeds_are_the_thesis_formula_bit_for_bit() {
        let s = henrytwo();
        // 1 / 0.015 * 60 / 6 * 0.0016605 = 1.107.
        assert_eq!(s.per_count, thesis_rpm(1, robot::SAMPLE_PERIOD_S));
        assert!((s.per_count - 1.107).abs() < 1e-6, "{}", s.per_count);
        for (i, &r) in s.of_counts.iter().enumerate() {
            assert_eq!(r, i as f32 * thesis_rpm(1, robot::SAMPLE_PERIOD_S), "{i} counts");
        }
    }

    #[test]
    fn another_robots_speeds_follow_its_counts_per_wheel_turn() {
        // 360 counts per wheel turn: one count per 15 ms is 1/360 turn in
        // 15 ms, 11.11 wheel RPM, thesis "RPM" (wheel RPM / 6) 1.852, up to
        // the thesis' rounding of 1 / 602.22 (1.4e-5).
        let mut s = Speeds::new();
        s.set(360.0);
        assert!((s.per_count - 1.0 / 0.015 * 60.0 / 360.0 / 6.0).abs() < 1e-4, "{}", s.per_count);
        assert!((s.of_counts[13] - 13.0 * 1.851_85).abs() < 1e-3, "{}", s.of_counts[13]);
        // The control tick measures with it: 13 counts in one period.
        let _bench = fake::lock();
        let mut d = Drive::new(Motors::default(), Encoders::default());
        d.speeds = s;
        d.left = driving(true);
        d.encoders.counts = crate::io::Counts { left: 13, right: 0 };
        tick(&mut d, 1, LIMITS, Factory);
        assert!((bench::speed_left() - 24.074).abs() < 1e-2, "{}", bench::speed_left());
        // Beyond the table, and over two periods.
        d.encoders.counts = crate::io::Counts { left: 13 + 100, right: 0 };
        tick(&mut d, 2, LIMITS, Factory);
        assert!((bench::speed_left() - 92.59).abs() < 1e-1, "{}", bench::speed_left());
    }

    #[test]
    fn the_pid_step_is_the_thesis_law_on_the_drive_input() {
        let _bench = fake::lock();
        let mut d = drive();
        d.left = driving(true);
        d.right = driving(false);
        let mut reference = FastPid::new(robot::GAINS_LEFT, robot::ROBUST_SETPOINT, robot::SAMPLE_PERIOD_S);
        // Counts per period, the right wheel going backwards; 70 is beyond the
        // tables, and one step spans two periods.
        let (mut left, mut right) = (0, 0);
        for (delta, n) in [(0, 1), (5, 1), (13, 1), (20, 1), (70, 1), (26, 2), (13, 1)] {
            left += delta;
            right -= delta;
            d.encoders.counts = crate::io::Counts { left, right };
            let rpm = thesis_rpm(delta, robot::SAMPLE_PERIOD_S * n as f32);
            let expected = duty_from_output(reference.update(rpm));
            assert_eq!(tick(&mut d, n, LIMITS, Factory), Fault::None);
            assert_eq!(d.motors.left, (expected, 0), "left after {delta} counts");
            assert_eq!(d.motors.right, (0, expected), "right after {delta} counts");
            assert_eq!(bench::duty_left(), expected);
            assert!((bench::speed_left() - rpm).abs() < 1e-4, "{} vs {rpm}", bench::speed_left());
        }
    }

    #[test]
    fn only_driving_wheels_are_controlled() {
        let _bench = fake::lock();
        let mut d = drive();
        d.left = driving(true);
        d.right.stage = Stage::Coast;
        tick(&mut d, 1, LIMITS, Factory);
        assert!(d.motors.log.iter().all(|&(side, _, _)| side == Side::Left), "{:?}", d.motors.log);
    }

    #[test]
    fn the_grace_periods_are_not_judged() {
        let (mut w, s) = (driving(true), henrytwo());
        w.applied = 255;
        let still = StallLimits { duty: 1, ticks: 1 };
        for _ in 0..STALL_GRACE_TICKS {
            assert!(control_wheel(&mut w, &s, 0, 1, still, Factory).check == Check::Ok);
        }
        assert!(control_wheel(&mut w, &s, 0, 1, still, Factory).check == Check::Stall);
    }

    #[test]
    fn a_period_below_the_stall_duty_restarts_the_window() {
        let (mut w, s) = (driving(true), henrytwo());
        w.grace = 0;
        w.still = 13;
        w.applied = LIMITS.duty - 1;
        assert!(control_wheel(&mut w, &s, 2, 1, LIMITS, Factory).check == Check::Ok);
        assert_eq!((w.still, w.mark), (0, 2));
    }

    #[test]
    fn more_than_64_counts_backwards_is_the_wrong_way() {
        let s = henrytwo();
        for (forward, sign) in [(true, -1), (false, 1)] {
            let mut w = driving(forward);
            w.grace = u8::MAX;
            let limit = WRONG_WAY_COUNTS as i32;
            assert!(control_wheel(&mut w, &s, sign * limit, 1, LIMITS, Factory).check == Check::Ok);
            assert!(control_wheel(&mut w, &s, sign * (limit + 1), 1, LIMITS, Factory).check == Check::WrongWay);
        }
    }

    /// The wrong-way limit is the settings', not the constant's.
    #[test]
    fn the_wrong_way_limit_is_the_one_passed() {
        let s = henrytwo();
        let t = Tuned::of(STALL_PROGRESS_COUNTS, 200).unwrap();
        let mut w = driving(true);
        w.grace = u8::MAX;
        assert!(control_wheel(&mut w, &s, -200, 1, LIMITS, t).check == Check::Ok);
        assert!(control_wheel(&mut w, &s, -201, 1, LIMITS, t).check == Check::WrongWay);
        assert!(Tuned::of(STALL_PROGRESS_COUNTS, WRONG_WAY_COUNTS).is_none());
    }

    /// A late step that moved more counts than 16 bits hold counts as the
    /// most travel there is, never as the wrapped remainder: 65 536 counts,
    /// whose 16-bit count shows no progress, are an encoder fault (edges
    /// came, the count did not advance), not a stall without travel.
    #[test]
    fn a_step_of_more_than_u16_counts_saturates_the_travel() {
        let s = henrytwo();
        let mut w = driving(true);
        w.grace = 0;
        w.applied = LIMITS.duty;
        let step = u16::MAX as i32 + 1;
        assert_eq!((step as i16, step as u16), (0, 0));
        let out = control_wheel(&mut w, &s, step, LIMITS.ticks as u32, LIMITS, Factory);
        assert!(out.check == Check::EncoderInconsistent);
        assert_eq!(w.travel, u16::MAX);
    }

    #[test]
    fn the_left_fault_comes_first() {
        let _bench = fake::lock();
        let mut d = drive();
        d.left = driving(true);
        d.right = driving(true);
        d.encoders.counts = crate::io::Counts { left: -100, right: -100 };
        assert_eq!(tick(&mut d, 1, LIMITS, Factory), Fault::WrongWayLeft);
        d.left.stage = Stage::Done;
        d.right.start_count = 0;
        assert_eq!(tick(&mut d, 1, LIMITS, Factory), Fault::WrongWayRight);
    }
}
