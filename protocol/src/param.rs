//! Run-time parameters: ids, units and the ranges the firmware accepts
//! ([`Param::range`]; [`crate::limits`] names each).
//!
//! Every value travels as an `f32` (IEEE 754, little-endian). A value is
//! accepted when it is finite, within `min..=max` (both inclusive) and, for
//! the parameters marked integer, a whole number. Anything else is refused
//! with [`Status::OutOfRange`] and changes nothing.

use core::fmt;

use crate::status::Status;

/// A run-time parameter of the robust firmware.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Hash)]
#[repr(u8)]
pub enum Param {
    /// Left wheel distance-per-count correction factor c_L (Borenstein):
    /// left distance = c_L * [`Param::MmPerCountLeft`] * counts. Dimensionless.
    CorrLeft = 1,
    /// Right wheel correction factor c_R. Dimensionless.
    CorrRight = 2,
    /// Wheelbase b in millimetres; sets the spin-turn targets: counts for an
    /// angle A = A * (b / 2) / (c_side * mm_per_count_side).
    WheelbaseMm = 3,
    /// Length of every straight leg, millimetres (also the bench variable
    /// `HT_LEG_LENGTH_MM`).
    LegLengthMm = 4,
    /// Spin-turn angle of the UMBmark tests, degrees.
    TurnUmbmarkDeg = 5,
    /// Spin-turn angle of the triangle test, degrees.
    TurnTriangleDeg = 6,
    /// Left wheel speed set-point, thesis "RPM" (wheel RPM / 6).
    SetpointLeft = 7,
    /// Right wheel speed set-point, thesis "RPM".
    SetpointRight = 8,
    /// Left PID proportional gain (duty-map units per thesis RPM).
    KpLeft = 9,
    /// Left PID integral gain (per thesis RPM second).
    KiLeft = 10,
    /// Left PID derivative gain (per thesis RPM per second).
    KdLeft = 11,
    /// Right PID proportional gain.
    KpRight = 12,
    /// Right PID integral gain.
    KiRight = 13,
    /// Right PID derivative gain.
    KdRight = 14,
    /// Stall watchdog: time without a count on a wheel driven at or above
    /// [`Param::StallDuty`] before the fault, milliseconds (whole number).
    StallTimeoutMs = 15,
    /// Stall watchdog: duty (0..=255) at or above which a wheel counts as
    /// driven (whole number).
    StallDuty = 16,
    /// Distance the left wheel travels per encoder count before correction
    /// (pi * wheel diameter / counts per wheel turn), millimetres.
    MmPerCountLeft = 17,
    /// Same, right wheel.
    MmPerCountRight = 18,
    /// Encoder counts per wheel turn (gear ratio * counts per motor turn):
    /// converts counts per control period into the set-points' thesis RPM.
    CountsPerWheelRev = 19,
    /// How the motor driver is wired ([`DriverKind`], whole number).
    DriverKind = 20,
    /// Left motor driver pin 1, an Arduino Mega pin number (whole number;
    /// [`NO_PIN`] for none): what it is depends on [`Param::DriverKind`].
    LeftPin1 = 21,
    /// Left motor driver pin 2.
    LeftPin2 = 22,
    /// Left motor driver pin 3.
    LeftPin3 = 23,
    /// Right motor driver pin 1.
    RightPin1 = 24,
    /// Right motor driver pin 2.
    RightPin2 = 25,
    /// Right motor driver pin 3.
    RightPin3 = 26,
    /// After a wheel is cut, milliseconds it coasts before its
    /// counter-pulse (whole number; the thesis' 20 ms).
    BrakeCoastMs = 27,
    /// The counter-pulse at full duty against the wheel's direction,
    /// milliseconds (whole number; the thesis' 5 ms, 0 for none).
    BrakePulseMs = 28,
    /// Stop lead, milliseconds (whole number): a leg's and a turn wheel's cut
    /// comes the distance earlier that the wheel covers in this time at its
    /// set-point, the coast it makes after the cut. 0 cuts at the target.
    StopLeadMs = 29,
    /// Stall watchdog: net progress in counts a wheel driven at or above
    /// [`Param::StallDuty`] must make within the stall time (whole number).
    StallProgressCounts = 30,
    /// Counts against its commanded direction within a segment that make a
    /// wrong-direction fault (whole number).
    WrongWayCounts = 31,
}

/// The pin value of a driver pin that is not connected.
pub const NO_PIN: u8 = 255;

/// How each motor's driver inputs are wired, the value of
/// [`Param::DriverKind`]. Pins 1-3 of each motor mean, per kind:
#[derive(Clone, Copy, PartialEq, Eq, Debug, Hash)]
#[repr(u8)]
pub enum DriverKind {
    /// Two PWM inputs per motor (DRV8833, TB6612 in PWM-on-IN mode): pin 1
    /// forward (IN1), pin 2 reverse (IN2), pin 3 none.
    TwoPwm = 0,
    /// A PWM enable and two direction inputs (L298N, TB6612): pin 1 the
    /// enable (PWM), pin 2 IN1 (high with IN2 low drives forward), pin 3 IN2.
    EnableTwoDir = 1,
    /// A PWM input and one direction input: pin 1 PWM, pin 2 direction (high
    /// drives forward), pin 3 none.
    PwmDir = 2,
}

impl DriverKind {
    /// The kind with wire value `v`.
    pub const fn from_u8(v: u8) -> Option<DriverKind> {
        match v {
            0 => Some(DriverKind::TwoPwm),
            1 => Some(DriverKind::EnableTwoDir),
            2 => Some(DriverKind::PwmDir),
            _ => None,
        }
    }
}

/// The values a parameter accepts: finite, within `min..=max` (both
/// inclusive) and, for the whole-number parameters, integral. Displays as
/// `min-max unit`, e.g. `50-500 mm`.
#[derive(Clone, Copy, PartialEq, Debug)]
pub struct Range {
    /// Smallest value accepted.
    pub min: f32,
    /// Largest value accepted.
    pub max: f32,
    /// Only whole numbers are accepted.
    pub integer: bool,
    /// The unit of the values, for messages; empty for factors, gains, codes
    /// and pins.
    pub unit: &'static str,
}

const fn real(min: f32, max: f32, unit: &'static str) -> Range {
    Range {
        min,
        max,
        integer: false,
        unit,
    }
}

const fn whole(min: f32, max: f32, unit: &'static str) -> Range {
    Range {
        min,
        max,
        integer: true,
        unit,
    }
}

impl Range {
    /// Whether the range accepts `value` (the `f32` that travels: a host
    /// converts first).
    pub const fn contains(self, value: f32) -> bool {
        // NaN fails both comparisons; infinities fail one.
        if !(value >= self.min && value <= self.max) {
            return false;
        }
        // In range, |value| <= 5000 for every whole-number range (checked in
        // `limits`), so the cast is exact for whole numbers.
        if self.integer && (value as i32) as f32 != value {
            return false;
        }
        true
    }
}

impl fmt::Display for Range {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}-{}", self.min, self.max)?;
        if !self.unit.is_empty() {
            write!(f, " {}", self.unit)?;
        }
        Ok(())
    }
}

impl Param {
    /// Every parameter, in id order.
    pub const ALL: [Param; 31] = [
        Param::CorrLeft,
        Param::CorrRight,
        Param::WheelbaseMm,
        Param::LegLengthMm,
        Param::TurnUmbmarkDeg,
        Param::TurnTriangleDeg,
        Param::SetpointLeft,
        Param::SetpointRight,
        Param::KpLeft,
        Param::KiLeft,
        Param::KdLeft,
        Param::KpRight,
        Param::KiRight,
        Param::KdRight,
        Param::StallTimeoutMs,
        Param::StallDuty,
        Param::MmPerCountLeft,
        Param::MmPerCountRight,
        Param::CountsPerWheelRev,
        Param::DriverKind,
        Param::LeftPin1,
        Param::LeftPin2,
        Param::LeftPin3,
        Param::RightPin1,
        Param::RightPin2,
        Param::RightPin3,
        Param::BrakeCoastMs,
        Param::BrakePulseMs,
        Param::StopLeadMs,
        Param::StallProgressCounts,
        Param::WrongWayCounts,
    ];

    /// The parameter with id `id`.
    pub const fn from_u8(id: u8) -> Option<Param> {
        if id >= 1 && id as usize <= Self::ALL.len() {
            Some(Self::ALL[id as usize - 1])
        } else {
            None
        }
    }

    /// The parameter's id on the wire.
    pub const fn id(self) -> u8 {
        self as u8
    }

    /// The values the firmware accepts: the one table of them, which
    /// [`Param::check`] applies and [`crate::limits`] names. (The values are
    /// written here rather than in `limits`: built in the match, the AVR code of
    /// `check` stays what it is.)
    pub const fn range(self) -> Range {
        match self {
            Param::CorrLeft | Param::CorrRight => real(0.5, 1.5, ""),
            Param::WheelbaseMm => real(50.0, 500.0, "mm"),
            Param::LegLengthMm => real(10.0, 5000.0, "mm"),
            Param::TurnUmbmarkDeg | Param::TurnTriangleDeg => real(1.0, 360.0, "deg"),
            Param::SetpointLeft | Param::SetpointRight => real(1.0, 500.0, "thesis RPM"),
            Param::KpLeft | Param::KpRight => real(0.0, 100.0, ""),
            Param::KiLeft | Param::KiRight => real(0.0, 1000.0, ""),
            Param::KdLeft | Param::KdRight => real(0.0, 10.0, ""),
            Param::StallTimeoutMs => whole(45.0, 5000.0, "ms"),
            Param::StallDuty => whole(1.0, 255.0, ""),
            Param::MmPerCountLeft | Param::MmPerCountRight => real(0.001, 50.0, "mm"),
            Param::CountsPerWheelRev => real(1.0, 100_000.0, "counts"),
            Param::DriverKind => whole(0.0, 2.0, ""),
            Param::LeftPin1
            | Param::LeftPin2
            | Param::LeftPin3
            | Param::RightPin1
            | Param::RightPin2
            | Param::RightPin3 => whole(0.0, 255.0, ""),
            Param::BrakeCoastMs => whole(0.0, 1000.0, "ms"),
            Param::BrakePulseMs => whole(0.0, 200.0, "ms"),
            Param::StopLeadMs => whole(0.0, 2000.0, "ms"),
            Param::StallProgressCounts => whole(1.0, 1000.0, "counts"),
            Param::WrongWayCounts => whole(1.0, 5000.0, "counts"),
        }
    }

    /// The robust firmware's factory value (the thesis robot's, Henrytwo:
    /// 32 mm wheels, 100.37:1 gears, 6 counts per motor turn, a DRV8833 on
    /// D6-D9), what it runs with until told otherwise.
    pub const fn factory_default(self) -> f32 {
        match self {
            Param::CorrLeft | Param::CorrRight => 1.0,
            Param::WheelbaseMm => 130.0,
            Param::LegLengthMm => 2000.0,
            Param::TurnUmbmarkDeg => 90.0,
            Param::TurnTriangleDeg => 120.0,
            // The sketch's right-wheel 14.47 on both wheels (firmware/src/robot.rs).
            Param::SetpointLeft | Param::SetpointRight => 14.47,
            Param::KpLeft => 2.20,
            Param::KiLeft => 36.666,
            Param::KdLeft => 0.033,
            Param::KpRight => 2.74,
            Param::KiRight => 45.66,
            Param::KdRight => 0.0411,
            Param::StallTimeoutMs => 200.0,
            Param::StallDuty => 200.0,
            // pi * 32 mm / 602.22, the thesis' `Constante` as it prints it.
            #[allow(clippy::excessive_precision)]
            Param::MmPerCountLeft | Param::MmPerCountRight => 0.1669339526,
            Param::CountsPerWheelRev => 602.22,
            Param::DriverKind => DriverKind::TwoPwm as u8 as f32,
            // D9 (OC2B) left forward, D8 (OC4C) left reverse, D7 (OC4B)
            // right forward, D6 (OC4A) right reverse.
            Param::LeftPin1 => 9.0,
            Param::LeftPin2 => 8.0,
            Param::RightPin1 => 7.0,
            Param::RightPin2 => 6.0,
            Param::LeftPin3 | Param::RightPin3 => NO_PIN as f32,
            // The thesis' Inercia_Stop_*: a 20 ms coast, a 5 ms counter-pulse,
            // cut at the target.
            Param::BrakeCoastMs => 20.0,
            Param::BrakePulseMs => 5.0,
            Param::StopLeadMs => 0.0,
            // Henrytwo makes about 13 counts per period at the set-point.
            Param::StallProgressCounts => 3.0,
            Param::WrongWayCounts => 64.0,
        }
    }

    /// `value` if the parameter accepts it, else [`Status::OutOfRange`].
    pub const fn check(self, value: f32) -> Result<f32, Status> {
        if !self.range().contains(value) {
            return Err(Status::OutOfRange);
        }
        Ok(value)
    }

    /// Short name, for host tools.
    pub const fn name(self) -> &'static str {
        match self {
            Param::CorrLeft => "c_left",
            Param::CorrRight => "c_right",
            Param::WheelbaseMm => "wheelbase_mm",
            Param::LegLengthMm => "leg_length_mm",
            Param::TurnUmbmarkDeg => "turn_umbmark_deg",
            Param::TurnTriangleDeg => "turn_triangle_deg",
            Param::SetpointLeft => "setpoint_left",
            Param::SetpointRight => "setpoint_right",
            Param::KpLeft => "kp_left",
            Param::KiLeft => "ki_left",
            Param::KdLeft => "kd_left",
            Param::KpRight => "kp_right",
            Param::KiRight => "ki_right",
            Param::KdRight => "kd_right",
            Param::StallTimeoutMs => "stall_timeout_ms",
            Param::StallDuty => "stall_duty",
            Param::MmPerCountLeft => "mm_per_count_left",
            Param::MmPerCountRight => "mm_per_count_right",
            Param::CountsPerWheelRev => "counts_per_wheel_rev",
            Param::DriverKind => "driver_kind",
            Param::LeftPin1 => "left_pin1",
            Param::LeftPin2 => "left_pin2",
            Param::LeftPin3 => "left_pin3",
            Param::RightPin1 => "right_pin1",
            Param::RightPin2 => "right_pin2",
            Param::RightPin3 => "right_pin3",
            Param::BrakeCoastMs => "brake_coast_ms",
            Param::BrakePulseMs => "brake_pulse_ms",
            Param::StopLeadMs => "stop_lead_ms",
            Param::StallProgressCounts => "stall_progress_counts",
            Param::WrongWayCounts => "wrong_way_counts",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_are_dense_and_round_trip() {
        for (i, p) in Param::ALL.iter().enumerate() {
            assert_eq!(p.id() as usize, i + 1);
            assert_eq!(Param::from_u8(p.id()), Some(*p));
        }
        assert_eq!(Param::from_u8(0), None);
        assert_eq!(Param::from_u8(32), None);
        assert_eq!(Param::from_u8(255), None);
    }

    #[test]
    fn range_edges_are_inclusive() {
        for p in Param::ALL {
            let r = p.range();
            assert_eq!(p.check(r.min), Ok(r.min), "{p:?} min");
            assert_eq!(p.check(r.max), Ok(r.max), "{p:?} max");
            let below = if r.min == 0.0 {
                -1.0e-6
            } else {
                r.min * (1.0 - 1.0e-6)
            };
            assert_eq!(p.check(below), Err(Status::OutOfRange), "{p:?} below");
            assert_eq!(
                p.check(r.max * (1.0 + 1.0e-6)),
                Err(Status::OutOfRange),
                "{p:?} above"
            );
        }
    }

    #[test]
    fn non_finite_values_are_refused() {
        for p in Param::ALL {
            for v in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
                assert_eq!(p.check(v), Err(Status::OutOfRange), "{p:?} {v}");
            }
        }
    }

    #[test]
    fn integer_parameters_refuse_fractions() {
        assert_eq!(Param::StallTimeoutMs.check(200.0), Ok(200.0));
        assert_eq!(Param::StallTimeoutMs.check(200.5), Err(Status::OutOfRange));
        assert_eq!(Param::StallDuty.check(100.0), Ok(100.0));
        assert_eq!(Param::StallDuty.check(99.9), Err(Status::OutOfRange));
        assert_eq!(Param::CorrLeft.check(1.0013), Ok(1.0013));
        assert_eq!(Param::LeftPin1.check(9.5), Err(Status::OutOfRange));
        assert_eq!(Param::DriverKind.check(1.0), Ok(1.0));
        assert_eq!(Param::BrakeCoastMs.check(20.5), Err(Status::OutOfRange));
        assert_eq!(Param::StopLeadMs.check(0.5), Err(Status::OutOfRange));
        assert_eq!(Param::WrongWayCounts.check(64.0), Ok(64.0));
        assert_eq!(
            Param::StallProgressCounts.check(2.5),
            Err(Status::OutOfRange)
        );
    }

    /// The stop timing and thresholds' factory values are the constants the
    /// robust firmware had compiled in: a robot told nothing runs as before.
    #[test]
    fn stop_timing_and_thresholds_default_to_the_thesis_constants() {
        let ids: [(Param, u8, f32); 5] = [
            (Param::BrakeCoastMs, 27, 20.0),
            (Param::BrakePulseMs, 28, 5.0),
            (Param::StopLeadMs, 29, 0.0),
            (Param::StallProgressCounts, 30, 3.0),
            (Param::WrongWayCounts, 31, 64.0),
        ];
        for (p, id, v) in ids {
            assert_eq!(p.id(), id, "{p:?}");
            assert_eq!(p.factory_default(), v, "{p:?}");
            assert!(p.range().integer, "{p:?}");
        }
    }

    #[test]
    fn factory_defaults_are_accepted() {
        for p in Param::ALL {
            assert_eq!(
                p.check(p.factory_default()),
                Ok(p.factory_default()),
                "{p:?}"
            );
        }
    }

    #[test]
    fn driver_kinds_round_trip() {
        for k in [
            DriverKind::TwoPwm,
            DriverKind::EnableTwoDir,
            DriverKind::PwmDir,
        ] {
            assert_eq!(DriverKind::from_u8(k as u8), Some(k));
        }
        assert_eq!(DriverKind::from_u8(3), None);
    }
}
