//! Run-time parameters: ids, units and the ranges the firmware accepts.
//!
//! Every value travels as an `f32` (IEEE 754, little-endian). A value is
//! accepted when it is finite, within `min..=max` (both inclusive) and, for
//! the parameters marked integer, a whole number. Anything else is refused
//! with [`Status::OutOfRange`] and changes nothing.

use crate::status::Status;

/// A run-time parameter of the robust firmware.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Hash)]
#[repr(u8)]
pub enum Param {
    /// Left wheel distance-per-count correction factor c_L (Borenstein):
    /// left distance = c_L * 0.1669339526 mm * counts. Dimensionless.
    CorrLeft = 1,
    /// Right wheel correction factor c_R. Dimensionless.
    CorrRight = 2,
    /// Wheelbase b in millimetres; sets the spin-turn targets: counts for an
    /// angle A = A * (b / 2) / (c_side * 0.1669339526 mm).
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
}

/// The values a parameter accepts.
#[derive(Clone, Copy, PartialEq, Debug)]
pub struct Range {
    /// Smallest value accepted.
    pub min: f32,
    /// Largest value accepted.
    pub max: f32,
    /// Only whole numbers are accepted.
    pub integer: bool,
}

const fn real(min: f32, max: f32) -> Range {
    Range {
        min,
        max,
        integer: false,
    }
}

const fn whole(min: f32, max: f32) -> Range {
    Range {
        min,
        max,
        integer: true,
    }
}

impl Param {
    /// Every parameter, in id order.
    pub const ALL: [Param; 16] = [
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

    /// The values the firmware accepts.
    pub const fn range(self) -> Range {
        match self {
            Param::CorrLeft | Param::CorrRight => real(0.5, 1.5),
            Param::WheelbaseMm => real(50.0, 500.0),
            Param::LegLengthMm => real(10.0, 5000.0),
            Param::TurnUmbmarkDeg | Param::TurnTriangleDeg => real(1.0, 360.0),
            Param::SetpointLeft | Param::SetpointRight => real(1.0, 40.0),
            Param::KpLeft | Param::KpRight => real(0.0, 100.0),
            Param::KiLeft | Param::KiRight => real(0.0, 1000.0),
            Param::KdLeft | Param::KdRight => real(0.0, 10.0),
            Param::StallTimeoutMs => whole(45.0, 5000.0),
            Param::StallDuty => whole(1.0, 255.0),
        }
    }

    /// `value` if the parameter accepts it, else [`Status::OutOfRange`].
    pub const fn check(self, value: f32) -> Result<f32, Status> {
        let r = self.range();
        // NaN fails both comparisons; infinities fail one.
        if !(value >= r.min && value <= r.max) {
            return Err(Status::OutOfRange);
        }
        // In range, |value| <= 5000, so the cast is exact for whole numbers.
        if r.integer && (value as i32) as f32 != value {
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
        assert_eq!(Param::from_u8(17), None);
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
    }
}
