//! The duty of a PWM input: a fraction validated to lie in `[0, 1]`, so its field is private.
//!
//! Apart from the plain quantities of [`crate::units`] because its constructor returns the
//! crate's [`Error`], whose variants themselves carry quantities.

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::Error;

/// The fraction of a PWM period during which an input is high, in `[0, 1]`.
///
/// Construct it with [`Duty::new`] (checked) or [`Duty::from_pwm8`] (an 8-bit compare value
/// as the thesis firmware writes it with `analogWrite`: `compare / 255`).
#[derive(Debug, Clone, Copy, PartialEq, PartialOrd, Default, Serialize)]
#[serde(transparent)]
pub struct Duty(f64);

impl Duty {
    /// Always low.
    pub const OFF: Duty = Duty(0.0);
    /// Always high.
    pub const FULL: Duty = Duty(1.0);

    /// A duty from a fraction; an error unless the fraction is finite and in `[0, 1]`.
    pub fn new(fraction: f64) -> Result<Duty, Error> {
        if fraction.is_finite() && (0.0..=1.0).contains(&fraction) {
            Ok(Duty(fraction))
        } else {
            Err(Error::InvalidDuty { value: fraction })
        }
    }

    /// The duty of an 8-bit PWM output whose compare register holds `compare`, as the thesis
    /// firmware uses it (phase-correct 8-bit PWM, `analogWrite`): `compare / 255`.
    pub fn from_pwm8(compare: u8) -> Duty {
        Duty(f64::from(compare) / 255.0)
    }

    /// The fraction in `[0, 1]`.
    pub const fn get(self) -> f64 {
        self.0
    }
}

impl<'de> Deserialize<'de> for Duty {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let fraction = f64::deserialize(deserializer)?;
        Duty::new(fraction).map_err(serde::de::Error::custom)
    }
}

impl fmt::Display for Duty {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "duty {}", self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// Duties outside `[0, 1]` or not finite are refused; 8-bit compare values map to /255.
    #[test]
    fn duty_is_checked() {
        assert!(Duty::new(-0.01).is_err());
        assert!(Duty::new(1.01).is_err());
        assert!(Duty::new(f64::NAN).is_err());
        assert_eq!(Duty::new(1.0).unwrap(), Duty::FULL);
        assert_eq!(Duty::from_pwm8(255), Duty::FULL);
        assert_eq!(Duty::from_pwm8(0), Duty::OFF);
        assert_relative_eq!(Duty::from_pwm8(210).get(), 210.0 / 255.0);
    }
}
