//! Physical quantities as small newtypes, so that a time cannot be passed where a length is
//! expected.
//!
//! Each quantity wraps an `f64` in the unit its name says (`Seconds`, `Millimetres`,
//! `Radians`, `RadPerSec`, `Volts`, `ThesisRpm`). Arithmetic is provided only where it keeps
//! the unit (sum and difference of two values, scaling by a plain number). The one checked
//! quantity, [`crate::Duty`], has a module of its own: its constructor can fail.

use std::f64::consts::PI;
use std::fmt;
use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub, SubAssign};

use serde::{Deserialize, Serialize};

macro_rules! quantity {
    ($(#[$meta:meta])* $name:ident, $unit:literal) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, PartialOrd, Default, Serialize, Deserialize)]
        #[serde(transparent)]
        pub struct $name(pub f64);

        impl $name {
            /// Zero of this quantity.
            pub const ZERO: Self = Self(0.0);

            /// The value as a plain number in this type's unit.
            pub const fn get(self) -> f64 {
                self.0
            }

            /// The magnitude, keeping the unit.
            pub fn abs(self) -> Self {
                Self(self.0.abs())
            }
        }

        impl Add for $name {
            type Output = Self;
            fn add(self, rhs: Self) -> Self {
                Self(self.0 + rhs.0)
            }
        }

        impl Sub for $name {
            type Output = Self;
            fn sub(self, rhs: Self) -> Self {
                Self(self.0 - rhs.0)
            }
        }

        impl AddAssign for $name {
            fn add_assign(&mut self, rhs: Self) {
                self.0 += rhs.0;
            }
        }

        impl SubAssign for $name {
            fn sub_assign(&mut self, rhs: Self) {
                self.0 -= rhs.0;
            }
        }

        impl Neg for $name {
            type Output = Self;
            fn neg(self) -> Self {
                Self(-self.0)
            }
        }

        impl Mul<f64> for $name {
            type Output = Self;
            fn mul(self, rhs: f64) -> Self {
                Self(self.0 * rhs)
            }
        }

        impl Div<f64> for $name {
            type Output = Self;
            fn div(self, rhs: f64) -> Self {
                Self(self.0 / rhs)
            }
        }

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                fmt::Display::fmt(&self.0, f)?;
                f.write_str(concat!(" ", $unit))
            }
        }
    };
}

quantity!(
    /// A time or a duration, in seconds. Plant time starts at 0 when a [`crate::Robot`] is made.
    Seconds,
    "s"
);
quantity!(
    /// A length, in millimetres.
    Millimetres,
    "mm"
);
quantity!(
    /// An angle, in radians. Wheel angles and headings are not wrapped: they accumulate.
    Radians,
    "rad"
);
quantity!(
    /// An angular speed, in radians per second.
    RadPerSec,
    "rad/s"
);
quantity!(
    /// An electric potential, in volts.
    Volts,
    "V"
);
quantity!(
    /// A wheel speed in the thesis' "RPM" unit, which is the wheel's true revolutions per
    /// minute divided by 6.
    ///
    /// The thesis firmware computes `(counts/s * 60 / 6) / 602.2`: it divides by the 6 A-channel
    /// counts per motor revolution a second time, after already dividing by the 602.2 counts
    /// per wheel turn. The step-response tables and the motor gains use this unit, so the plant
    /// keeps it for comparisons; internally speeds are [`RadPerSec`].
    ThesisRpm,
    "thesis RPM"
);

impl Radians {
    /// An angle given in degrees.
    pub fn from_degrees(deg: f64) -> Self {
        Self(deg.to_radians())
    }

    /// The angle in degrees, as a plain number (reports and tests speak
    /// degrees).
    pub fn to_degrees(self) -> f64 {
        self.0.to_degrees()
    }
}

impl Millimetres {
    /// The hypotenuse of a right triangle with legs `self` and `other`: a
    /// distance from its x and y.
    pub fn hypot(self, other: Self) -> Self {
        Self(self.0.hypot(other.0))
    }
}

/// True wheel RPM per thesis "RPM" (see [`ThesisRpm`]).
pub const TRUE_RPM_PER_THESIS_RPM: f64 = 6.0;

/// Radians per second per thesis "RPM": `6 * 2 pi / 60 = pi / 5`, about 0.628.
pub const RAD_PER_SEC_PER_THESIS_RPM: f64 = TRUE_RPM_PER_THESIS_RPM * 2.0 * PI / 60.0;

impl From<ThesisRpm> for RadPerSec {
    fn from(rpm: ThesisRpm) -> Self {
        RadPerSec(rpm.0 * RAD_PER_SEC_PER_THESIS_RPM)
    }
}

impl From<RadPerSec> for ThesisRpm {
    fn from(speed: RadPerSec) -> Self {
        ThesisRpm(speed.0 / RAD_PER_SEC_PER_THESIS_RPM)
    }
}

impl RadPerSec {
    /// The same speed in the thesis' "RPM" unit (true wheel RPM / 6).
    pub fn to_thesis_rpm(self) -> ThesisRpm {
        self.into()
    }
}

impl Div for Seconds {
    type Output = f64;
    fn div(self, rhs: Self) -> f64 {
        self.0 / rhs.0
    }
}

/// The instants a sampled reader can observe: `t_k = k / hz` for `k = 0, 1, ...` (a CPU's
/// clock cycles). The one rounding rule between such a reader and the plant's continuous
/// time: a search on the grid ([`crate::Robot::next_encoder_transition_on`]) answers with
/// the first instant at which the plant has changed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct TimeGrid {
    hz: u32,
}

impl TimeGrid {
    /// A grid of `hz` instants per second (`hz > 0`).
    pub const fn new(hz: u32) -> Self {
        assert!(hz > 0, "a time grid needs a positive rate");
        Self { hz }
    }

    pub const fn hz(self) -> u32 {
        self.hz
    }

    /// Instant `k`.
    pub fn time(self, k: u64) -> Seconds {
        Seconds(k as f64 / self.hz as f64)
    }

    /// The first instant at or after `t` (0 for `t <= 0`). Exact: `time(k) >= t` and
    /// `time(k - 1) < t`, whatever the rounding of `t * hz`; so `index_at_or_after(time(k))
    /// == k`.
    pub fn index_at_or_after(self, t: Seconds) -> u64 {
        let exact = t.0 * self.hz as f64;
        if exact.is_nan() || exact <= 0.0 {
            return 0;
        }
        let mut k = exact.ceil() as u64;
        // `t * hz` is rounded: a hair above an integer would skip an instant, a hair below
        // would precede `t`. Both are at most one instant off.
        while k > 0 && self.time(k - 1).0 >= t.0 {
            k -= 1;
        }
        while self.time(k).0 < t.0 {
            k += 1;
        }
        k
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// 14.47 thesis RPM is about 86.8 true wheel RPM (robot.toml's comment).
    #[test]
    fn thesis_rpm_is_true_rpm_over_six() {
        let speed = RadPerSec::from(ThesisRpm(14.47));
        let true_rpm = speed.0 * 60.0 / (2.0 * PI);
        assert_relative_eq!(true_rpm, 86.82, epsilon = 1e-9);
        assert_relative_eq!(speed.to_thesis_rpm().0, 14.47, epsilon = 1e-12);
    }

    /// A duration over a duration is a plain number (how many periods fit in a run).
    #[test]
    fn a_time_over_a_time_is_their_ratio() {
        assert_eq!(Seconds(0.375) / Seconds(0.015), 25.0);
        assert_eq!(Seconds(-0.3) / Seconds(0.6), -0.5);
    }

    /// The grid's first instant at or after a time is exact, on the instants themselves
    /// too (where `t * hz` rounds either way).
    #[test]
    fn time_grid_rounds_up_exactly() {
        let grid = TimeGrid::new(16_000_000);
        for k in (0..200_000u64).chain((0..200_000).map(|i| 12_000_000_000 + 7919 * i)) {
            let t = grid.time(k);
            assert_eq!(grid.index_at_or_after(t), k, "instant {k}");
            let after = Seconds(f64::from_bits(t.0.to_bits() + 1));
            assert_eq!(
                grid.index_at_or_after(after),
                k + 1,
                "just after instant {k}"
            );
        }
        assert_eq!(grid.index_at_or_after(Seconds(-1.0)), 0);
    }
}
