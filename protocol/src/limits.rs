//! The ranges the robust firmware accepts for the robot's parameters it is told over the
//! protocol (`SET_PARAM`, and those it loads from its EEPROM), by name: what
//! [`Param::check`] applies in the firmware, for a host to check a robot's numbers against
//! before a run. The plant model accepts wider ones (a wheelbase of 20 to 2000 mm); a robot
//! the firmware is to drive must fit these too. Each is its parameter's [`Param::range`],
//! the one table of the values.
//!
//! A value travels as an `f32`: a host checks the `f32` it will send
//! ([`Range::contains`]); a range displays as `50-500 mm`.

use crate::param::Param;
pub use crate::param::Range;

/// Wheel distance-per-count correction factors c_L and c_R (dimensionless): 0.5-1.5.
pub const CORRECTION: Range = Param::CorrLeft.range();
/// Wheelbase b, millimetres: 50-500 mm.
pub const WHEELBASE_MM: Range = Param::WheelbaseMm.range();
/// Length of a straight leg, millimetres: 10-5000 mm.
pub const LEG_LENGTH_MM: Range = Param::LegLengthMm.range();
/// Spin-turn angle of the UMBmark and triangle tests, degrees: 1-360 deg.
pub const TURN_DEG: Range = Param::TurnUmbmarkDeg.range();
/// Wheel speed set-point, thesis "RPM" (wheel RPM / 6): 1-500 (a host checks a robot's
/// set-point against its motor's top speed, far below that).
pub const SETPOINT_THESIS_RPM: Range = Param::SetpointLeft.range();
/// PID proportional gain (duty-map units per thesis RPM): 0-100.
pub const PID_KP: Range = Param::KpLeft.range();
/// PID integral gain (per thesis RPM second): 0-1000.
pub const PID_KI: Range = Param::KiLeft.range();
/// PID derivative gain (per thesis RPM per second): 0-10.
pub const PID_KD: Range = Param::KdLeft.range();
/// Stall watchdog time without a count, milliseconds, whole: 45-5000 ms.
pub const STALL_TIMEOUT_MS: Range = Param::StallTimeoutMs.range();
/// Duty (of 255) at or above which a wheel counts as driven for the stall watchdog, whole:
/// 1-255.
pub const STALL_DUTY: Range = Param::StallDuty.range();
/// Distance a wheel travels per encoder count before correction, millimetres: 0.001-50 mm.
pub const MM_PER_COUNT: Range = Param::MmPerCountLeft.range();
/// Encoder counts per wheel turn: 1-100000.
pub const COUNTS_PER_WHEEL_REV: Range = Param::CountsPerWheelRev.range();
/// Motor driver wiring, a [`DriverKind`](crate::DriverKind) code, whole: 0-2.
pub const DRIVER_KIND: Range = Param::DriverKind.range();
/// A motor driver pin, an Arduino Mega pin number or [`NO_PIN`](crate::NO_PIN), whole: 0-255.
pub const DRIVER_PIN: Range = Param::LeftPin1.range();
/// A cut wheel's coast before its counter-pulse, milliseconds, whole: 0-1000 ms.
pub const BRAKE_COAST_MS: Range = Param::BrakeCoastMs.range();
/// The counter-pulse, milliseconds, whole: 0-200 ms.
pub const BRAKE_PULSE_MS: Range = Param::BrakePulseMs.range();
/// The stop lead (the cut moved earlier by the distance covered in it at the set-point),
/// milliseconds, whole: 0-2000 ms.
pub const STOP_LEAD_MS: Range = Param::StopLeadMs.range();
/// Net progress the stall watchdog asks of a driven wheel, counts, whole: 1-1000.
pub const STALL_PROGRESS_COUNTS: Range = Param::StallProgressCounts.range();
/// Counts against the commanded direction that are a wrong-direction fault, whole: 1-5000.
pub const WRONG_WAY_COUNTS: Range = Param::WrongWayCounts.range();

// A pair of parameters shares one name only while they share one range.
const _: () = {
    let pairs = [
        (Param::CorrLeft, Param::CorrRight),
        (Param::TurnUmbmarkDeg, Param::TurnTriangleDeg),
        (Param::SetpointLeft, Param::SetpointRight),
        (Param::KpLeft, Param::KpRight),
        (Param::KiLeft, Param::KiRight),
        (Param::KdLeft, Param::KdRight),
        (Param::MmPerCountLeft, Param::MmPerCountRight),
        (Param::LeftPin1, Param::LeftPin2),
        (Param::LeftPin1, Param::LeftPin3),
        (Param::LeftPin1, Param::RightPin1),
        (Param::LeftPin1, Param::RightPin2),
        (Param::LeftPin1, Param::RightPin3),
    ];
    let mut i = 0;
    while i < pairs.len() {
        let (a, b) = (pairs[i].0.range(), pairs[i].1.range());
        assert!(a.min == b.min && a.max == b.max && a.integer == b.integer);
        i += 1;
    }
};

// `Range::contains` casts whole numbers through `i32`, exactly while they stay small.
const _: () = {
    let mut i = 0;
    while i < Param::ALL.len() {
        let r = Param::ALL[i].range();
        assert!(!r.integer || (r.min >= -5000.0 && r.max <= 5000.0));
        i += 1;
    }
};

#[cfg(test)]
mod tests {
    extern crate std;

    use super::*;
    use std::format;

    #[test]
    fn ranges_display_with_their_units() {
        assert_eq!(format!("{WHEELBASE_MM}"), "50-500 mm");
        assert_eq!(format!("{LEG_LENGTH_MM}"), "10-5000 mm");
        assert_eq!(format!("{MM_PER_COUNT}"), "0.001-50 mm");
        assert_eq!(format!("{COUNTS_PER_WHEEL_REV}"), "1-100000 counts");
        assert_eq!(format!("{STALL_TIMEOUT_MS}"), "45-5000 ms");
        assert_eq!(format!("{CORRECTION}"), "0.5-1.5");
    }

    /// The firmware's values, as `README.md` next to this crate lists them.
    #[test]
    fn the_limits_are_the_documented_ones() {
        let r = |r: Range| (r.min, r.max, r.integer);
        assert_eq!(r(CORRECTION), (0.5, 1.5, false));
        assert_eq!(r(WHEELBASE_MM), (50.0, 500.0, false));
        assert_eq!(r(LEG_LENGTH_MM), (10.0, 5000.0, false));
        assert_eq!(r(TURN_DEG), (1.0, 360.0, false));
        assert_eq!(r(SETPOINT_THESIS_RPM), (1.0, 500.0, false));
        assert_eq!(r(PID_KP), (0.0, 100.0, false));
        assert_eq!(r(PID_KI), (0.0, 1000.0, false));
        assert_eq!(r(PID_KD), (0.0, 10.0, false));
        assert_eq!(r(STALL_TIMEOUT_MS), (45.0, 5000.0, true));
        assert_eq!(r(STALL_DUTY), (1.0, 255.0, true));
        assert_eq!(r(MM_PER_COUNT), (0.001, 50.0, false));
        assert_eq!(r(COUNTS_PER_WHEEL_REV), (1.0, 100_000.0, false));
        assert_eq!(r(DRIVER_KIND), (0.0, 2.0, true));
        assert_eq!(r(DRIVER_PIN), (0.0, 255.0, true));
        assert_eq!(r(BRAKE_COAST_MS), (0.0, 1000.0, true));
        assert_eq!(r(BRAKE_PULSE_MS), (0.0, 200.0, true));
        assert_eq!(r(STOP_LEAD_MS), (0.0, 2000.0, true));
        assert_eq!(r(STALL_PROGRESS_COUNTS), (1.0, 1000.0, true));
        assert_eq!(r(WRONG_WAY_COUNTS), (1.0, 5000.0, true));
    }

    #[test]
    fn contains_takes_the_ends_and_refuses_beyond() {
        assert!(WHEELBASE_MM.contains(50.0) && WHEELBASE_MM.contains(500.0));
        assert!(!WHEELBASE_MM.contains(49.99) && !WHEELBASE_MM.contains(500.01));
        assert!(!WHEELBASE_MM.contains(f32::NAN) && !WHEELBASE_MM.contains(f32::INFINITY));
        assert!(STALL_TIMEOUT_MS.contains(45.0) && !STALL_TIMEOUT_MS.contains(45.5));
    }
}
