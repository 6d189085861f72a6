//! The checks a config section runs on its values, each failing with an [`Error`] that names
//! the key (`section.key`) and says what to write instead.
//!
//! A leaf under the config and the parts it configures: [`crate::config`] runs them on the
//! robot's geometry, the motors and the effects on their own sections, so none of those
//! depends on another for them.

use crate::Error;

/// The physical range of a config number: what a real robot of this kind can have, wide enough
/// for every robot in `fixtures/robots/` and narrow enough that a typo (a value in the wrong
/// unit, a dropped decimal point, an exponent) is refused instead of run. The ranges are
/// documented beside the keys in `fixtures/robots/henrytwo-ideal.toml`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounds {
    /// The smallest value allowed.
    pub low: f64,
    /// The largest value allowed.
    pub high: f64,
    /// The unit the key is written in (empty for a plain number).
    pub unit: &'static str,
}

impl Bounds {
    /// Whether `value` is finite and within the range.
    pub fn contains(self, value: f64) -> bool {
        value.is_finite() && (self.low..=self.high).contains(&value)
    }

    /// "give 1e-5 to 10 s": the range in words, for an error message.
    pub fn give(self) -> String {
        let unit = if self.unit.is_empty() {
            String::new()
        } else {
            format!(" {}", self.unit)
        };
        format!("give {} to {}{unit}", number(self.low), number(self.high))
    }
}

/// A number as a person reads it: plain near 1, in exponent form when very large or small
/// (so that 1e300 is not three hundred digits).
pub fn number(v: f64) -> String {
    if v == 0.0 || !v.is_finite() || (1e-4..1e6).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// Wheel diameters, mm: from a micro robot's 5 mm to a 0.5 m wheel.
pub const WHEEL_DIAMETER_MM: Bounds = Bounds {
    low: 5.0,
    high: 500.0,
    unit: "mm",
};
/// Wheelbase, mm.
pub const WHEELBASE_MM: Bounds = Bounds {
    low: 20.0,
    high: 2000.0,
    unit: "mm",
};
/// Motor turns per wheel turn (1: direct drive).
pub const GEAR_RATIO: Bounds = Bounds {
    low: 1.0,
    high: 1000.0,
    unit: "",
};
/// Channel-A edges per motor turn.
pub const A_EDGES_PER_MOTOR_REV: Bounds = Bounds {
    low: 1.0,
    high: 10_000.0,
    unit: "",
};
/// Battery and fit voltages, V: one cell to a 60 V pack.
pub const VOLTAGE_V: Bounds = Bounds {
    low: 1.0,
    high: 60.0,
    unit: "V",
};
/// A motor's steady speed at its reference duty, thesis RPM (true wheel RPM / 6).
pub const GAIN_THESIS_RPM: Bounds = Bounds {
    low: 0.1,
    high: 2000.0,
    unit: "thesis RPM",
};
/// Mechanical and electrical time constants, s: 10 us (below one control tick of any MCU)
/// to 10 s.
pub const TIME_CONSTANT_S: Bounds = Bounds {
    low: 1e-5,
    high: 10.0,
    unit: "s",
};

/// `value` must be finite and within `bounds` (a physical range).
pub(crate) fn check_physical(
    key: &str,
    value: f64,
    bounds: Bounds,
    meaning: &'static str,
) -> Result<(), Error> {
    if bounds.contains(value) {
        Ok(())
    } else {
        Err(Error::Unphysical {
            key: key.to_owned(),
            value: number(value),
            allowed: bounds.give(),
            meaning,
        })
    }
}

/// `value` must be finite and in `[0, 1]`.
pub(crate) fn check_duty(key: &str, value: f64) -> Result<(), Error> {
    check_finite(key, value, "give a duty from 0 to 1")?;
    if (0.0..=1.0).contains(&value) {
        Ok(())
    } else {
        Err(Error::DutyOutOfRange {
            key: key.to_owned(),
            value,
        })
    }
}

/// `value` must be finite and in `[low, high]` (`allowed` says so in words).
pub(crate) fn check_between(
    key: &str,
    value: f64,
    (low, high): (f64, f64),
    allowed: &'static str,
    meaning: &'static str,
) -> Result<(), Error> {
    check_finite(key, value, allowed)?;
    if (low..=high).contains(&value) {
        Ok(())
    } else {
        Err(Error::OutOfRange {
            key: key.to_owned(),
            value,
            allowed,
            meaning,
        })
    }
}

/// `value` must be a fraction in `[0, 1)`.
pub(crate) fn check_fraction(key: &str, value: f64, meaning: &'static str) -> Result<(), Error> {
    check_between(
        key,
        value,
        (0.0, 1.0 - f64::EPSILON),
        "a fraction must lie in [0, 1)",
        meaning,
    )
}

/// `value` must be a ratio in `[0.5, 2]`: a factor near 1 (a few percent off at most on a
/// real robot); anything outside is a typo such as a percentage.
pub(crate) fn check_ratio(key: &str, value: f64, meaning: &'static str) -> Result<(), Error> {
    check_between(
        key,
        value,
        (0.5, 2.0),
        "a ratio must lie in [0.5, 2] (write 1.02 for 2 % more, not 2 or 102)",
        meaning,
    )
}

fn check_finite(key: &str, value: f64, allowed: &str) -> Result<(), Error> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(Error::NotFinite {
            key: key.to_owned(),
            value,
            allowed: allowed.to_owned(),
        })
    }
}
