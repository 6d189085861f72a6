//! The control law of one period: each driving wheel's speed from its count
//! change, the PID, the output stage on its drive input, the bench
//! variables; then the watchdogs ([`super::progress`]).

use henrytwo_protocol::Fault;

use crate::bench;
use crate::io::{Bridges, Side, WheelEncoders};
use crate::pid::{duty_from_output, rpm_table, thesis_rpm};
use crate::robot;

pub use super::drive::TABLE_COUNTS;
use super::drive::{Drive, Stage, Wheel};
use super::progress::{fault_of, judge_progress, Check, WRONG_WAY_COUNTS};

/// Thesis RPM of one count in one control period (1.107).
pub const RPM_PER_COUNT: f32 = thesis_rpm(1, robot::SAMPLE_PERIOD_S);
/// Thesis RPM of 0..63 counts in one control period.
pub static RPM_OF_COUNTS: [f32; TABLE_COUNTS] = rpm_table(robot::SAMPLE_PERIOD_S);
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
fn rpm_over(counts: u32, n: u32) -> f32 {
    counts as f32 * RPM_PER_COUNT / n as f32
}

/// What one control period decided for one wheel.
pub(crate) struct WheelOutcome {
    pub(crate) rpm: f32,
    pub(crate) duty: u8,
    pub(crate) check: Check,
}

/// One control period of one driving wheel: speed over the last `n`
/// periods, PID, output stage, stall ([`judge_progress`]; only periods
/// driven at or above the stall duty after the start's grace are judged, any
/// other starts the window again) and wrong-direction checks.
#[inline(always)]
pub(crate) fn control_wheel(w: &mut Wheel, count: i32, n: u32, stall: StallLimits) -> WheelOutcome {
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

/// One control period for every wheel still driving: speed over the last
/// `n` periods, PID, duty on the drive input, bench variables; then the
/// stall and wrong-direction checks. Returns the fault found, if any.
///
/// Inlined into its caller: the firmware calls it from one named function
/// (`ht_control_tick`) that a timing tool finds by its symbol.
#[inline(always)]
pub fn tick<M: Bridges, E: WheelEncoders>(d: &mut Drive<M, E>, n: u32, stall: StallLimits) -> Fault {
    let c = d.encoders.counts();
    let mut fault = Fault::None;
    if d.left.stage == Stage::Driving {
        let o = control_wheel(&mut d.left, c.left, n, stall);
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
        let o = control_wheel(&mut d.right, c.right, n, stall);
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
    use crate::pid::FastPid;
    use crate::robust::fake::{self, Encoders, Motors};
    use crate::robust::progress::STALL_GRACE_TICKS;

    const LIMITS: StallLimits = StallLimits { duty: 200, ticks: 14 };

    /// A wheel driving from count 0, as a segment start leaves it.
    fn driving(forward: bool) -> Wheel {
        let mut w = Wheel::new();
        w.forward = forward;
        w.stage = Stage::Driving;
        w.pid.prepare(robot::GAINS_LEFT, robot::ROBUST_SETPOINT, robot::SAMPLE_PERIOD_S, &RPM_OF_COUNTS);
        w.applied = robot::START_DUTY;
        w.grace = STALL_GRACE_TICKS;
        w
    }

    #[test]
    fn the_pid_step_is_the_thesis_law_on_the_drive_input() {
        let _bench = fake::lock();
        let mut d = Drive::new(Motors::default(), Encoders::default());
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
            assert_eq!(tick(&mut d, n, LIMITS), Fault::None);
            assert_eq!(d.motors.left, (expected, 0), "left after {delta} counts");
            assert_eq!(d.motors.right, (0, expected), "right after {delta} counts");
            assert_eq!(bench::duty_left(), expected);
            assert!((bench::speed_left() - rpm).abs() < 1e-4, "{} vs {rpm}", bench::speed_left());
        }
    }

    #[test]
    fn only_driving_wheels_are_controlled() {
        let _bench = fake::lock();
        let mut d = Drive::new(Motors::default(), Encoders::default());
        d.left = driving(true);
        d.right.stage = Stage::Coast;
        tick(&mut d, 1, LIMITS);
        assert!(d.motors.log.iter().all(|&(side, _, _)| side == Side::Left), "{:?}", d.motors.log);
    }

    #[test]
    fn the_grace_periods_are_not_judged() {
        let mut w = driving(true);
        w.applied = 255;
        let still = StallLimits { duty: 1, ticks: 1 };
        for _ in 0..STALL_GRACE_TICKS {
            assert!(control_wheel(&mut w, 0, 1, still).check == Check::Ok);
        }
        assert!(control_wheel(&mut w, 0, 1, still).check == Check::Stall);
    }

    #[test]
    fn a_period_below_the_stall_duty_restarts_the_window() {
        let mut w = driving(true);
        w.grace = 0;
        w.still = 13;
        w.applied = LIMITS.duty - 1;
        assert!(control_wheel(&mut w, 2, 1, LIMITS).check == Check::Ok);
        assert_eq!((w.still, w.mark), (0, 2));
    }

    #[test]
    fn more_than_64_counts_backwards_is_the_wrong_way() {
        for (forward, sign) in [(true, -1), (false, 1)] {
            let mut w = driving(forward);
            w.grace = u8::MAX;
            assert!(control_wheel(&mut w, sign * WRONG_WAY_COUNTS, 1, LIMITS).check == Check::Ok);
            assert!(control_wheel(&mut w, sign * (WRONG_WAY_COUNTS + 1), 1, LIMITS).check == Check::WrongWay);
        }
    }

    #[test]
    fn the_left_fault_comes_first() {
        let _bench = fake::lock();
        let mut d = Drive::new(Motors::default(), Encoders::default());
        d.left = driving(true);
        d.right = driving(true);
        d.encoders.counts = crate::io::Counts { left: -100, right: -100 };
        assert_eq!(tick(&mut d, 1, LIMITS), Fault::WrongWayLeft);
        d.left.stage = Stage::Done;
        d.right.start_count = 0;
        assert_eq!(tick(&mut d, 1, LIMITS), Fault::WrongWayRight);
    }
}
