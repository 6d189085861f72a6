//! The checks a config section runs on its values, each failing with an [`Error`] that names
//! the key (`section.key`) and says what to write instead.
//!
//! A leaf under the config and the parts it configures: [`crate::config`] runs them on the
//! robot's geometry, the motors and the effects on their own sections, so none of those
//! depends on another for them.

use crate::Error;

/// `value` must be finite and greater than zero.
pub(crate) fn check_positive(key: &str, value: f64, meaning: &'static str) -> Result<(), Error> {
    check_finite(key, value)?;
    if value > 0.0 {
        Ok(())
    } else {
        Err(Error::NotPositive {
            key: key.to_owned(),
            value,
            meaning,
        })
    }
}

/// `value` must be finite and in `[0, 1]`.
pub(crate) fn check_duty(key: &str, value: f64) -> Result<(), Error> {
    check_finite(key, value)?;
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
    check_finite(key, value)?;
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

/// `value` must be finite and not negative.
pub(crate) fn check_non_negative(
    key: &str,
    value: f64,
    meaning: &'static str,
) -> Result<(), Error> {
    check_between(
        key,
        value,
        (0.0, f64::MAX),
        "it must not be negative",
        meaning,
    )
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

fn check_finite(key: &str, value: f64) -> Result<(), Error> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(Error::NotFinite {
            key: key.to_owned(),
            value,
        })
    }
}
