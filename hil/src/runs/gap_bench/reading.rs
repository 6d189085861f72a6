//! How a person reads a bench parameter's value: the search holds one signed number per
//! effect (positive on the left side, negative on the right, see `params.rs`), but a drag,
//! a dead band or a share of lost counts is never negative on a robot. The report gives
//! each value as its size, the side it is on in words and its unit, and a value the search
//! ended at an end of its range as that bound, not as a measurement.

use gap::effects::{
    CASTOR_DRAG, DEAD_BAND, ENCODER_GLITCHES, ENCODER_MISSED_COUNTS, MOTOR_GAIN_ASYMMETRY,
    STRAIGHT_SLIP, TOE, WHEEL_DIAMETER_RATIO,
};
use gap::ParamSpec;

use super::params::bench_parameters;

/// Effects whose sign says the side (left positive, right negative) and whose size is the
/// magnitude.
const SIDED: [&str; 7] = [
    STRAIGHT_SLIP,
    DEAD_BAND,
    ENCODER_MISSED_COUNTS,
    ENCODER_GLITCHES,
    CASTOR_DRAG,
    MOTOR_GAIN_ASYMMETRY,
    TOE,
];

/// A value within this share of its range from a non-neutral bound is at that bound: the
/// search's golden section steps toward a bound without reaching it, and the data ask for
/// at least the bound there, not for the value found.
pub const AT_BOUND_SHARE: f64 = 0.01;

/// Which end of its range a fitted value sits at.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Bound {
    Lower,
    Upper,
}

fn spec(effect: &str) -> Option<ParamSpec> {
    bench_parameters().into_iter().find(|s| s.name == effect)
}

/// The bound of its range `value` sits at, if any (see [`AT_BOUND_SHARE`]); a bound that
/// is the neutral value (no slip, no coast) is no limit of the search.
pub fn at_bound(effect: &str, value: f64) -> Option<Bound> {
    let s = spec(effect)?;
    let tol = AT_BOUND_SHARE * (s.upper - s.lower);
    if s.lower != s.neutral && value - s.lower <= tol {
        Some(Bound::Lower)
    } else if s.upper != s.neutral && s.upper - value <= tol {
        Some(Bound::Upper)
    } else {
        None
    }
}

/// The side `value` puts the effect on, in words (None: an effect of both sides, or none).
pub fn side(effect: &str, value: f64) -> Option<&'static str> {
    if effect == WHEEL_DIAMETER_RATIO {
        return (value != 1.0).then_some(if value < 1.0 {
            "right wheel smaller"
        } else {
            "right wheel larger"
        });
    }
    if !SIDED.contains(&effect) || value == 0.0 {
        return None;
    }
    Some(match (effect, value > 0.0) {
        (MOTOR_GAIN_ASYMMETRY, true) => "left motor stronger",
        (MOTOR_GAIN_ASYMMETRY, false) => "right motor stronger",
        (TOE, true) => "right wheel toed in",
        (TOE, false) => "left wheel toed in",
        (CASTOR_DRAG, true) => "castor left of centre",
        (CASTOR_DRAG, false) => "castor right of centre",
        (DEAD_BAND, true) => "left motor",
        (DEAD_BAND, false) => "right motor",
        (ENCODER_MISSED_COUNTS | ENCODER_GLITCHES, true) => "left encoder",
        (ENCODER_MISSED_COUNTS | ENCODER_GLITCHES, false) => "right encoder",
        (_, true) => "left wheel",
        (_, false) => "right wheel",
    })
}

/// The size a person reads: the magnitude of a sided effect, the value of any other.
pub fn magnitude(effect: &str, value: f64) -> f64 {
    if SIDED.contains(&effect) {
        value.abs()
    } else {
        value
    }
}

/// A unit as printed: nothing for a dimensionless ratio or share (the specs' `"1"`).
pub fn unit_shown(unit: &str) -> &str {
    if unit == "1" {
        ""
    } else {
        unit
    }
}

/// `value` of `effect` as the report prints it: `0.1252 duty (right motor)`, or at a bound
/// `≥ 3.0000 N (castor right of centre; at the end of its range)`. `uncertainty`, when
/// known, follows the size as `± u`.
pub fn shown(effect: &str, value: f64, unit: &str, uncertainty: Option<f64>) -> String {
    let m = magnitude(effect, value);
    let bound = at_bound(effect, value);
    // At the lower bound of a sided effect's signed range the magnitude is at its largest.
    let relation = match (bound, SIDED.contains(&effect)) {
        (None, _) => "",
        (Some(_), true) => "≥ ",
        (Some(Bound::Lower), false) => "≤ ",
        (Some(Bound::Upper), false) => "≥ ",
    };
    let unit = unit_shown(unit);
    let mut s = format!("{relation}{m:.4}");
    if let (None, Some(u)) = (bound, uncertainty) {
        s.push_str(&format!(" ± {u:.4}"));
    }
    if !unit.is_empty() {
        s.push(' ');
        s.push_str(unit);
    }
    let mut words: Vec<&str> = side(effect, value).into_iter().collect();
    if bound.is_some() {
        words.push("at the end of its range: the data ask for at least this");
    }
    if !words.is_empty() {
        s.push_str(&format!(" ({})", words.join("; ")));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use gap::effects::{BATTERY_SAG, COAST, WHEELBASE_RATIO};

    /// A right-side castor drag reads as a positive force on the right, never as a
    /// negative one; a dead band names its motor; dimensionless values print no "1"; a fit
    /// at the end of its range reads as that bound, with no uncertainty; a neutral bound
    /// (no coast) is no bound.
    #[test]
    fn values_read_as_sizes_with_their_side_and_bound() {
        let c = shown(CASTOR_DRAG, -2.7, "N", Some(0.2));
        assert_eq!(c, "2.7000 ± 0.2000 N (castor right of centre)");
        assert_eq!(
            shown(CASTOR_DRAG, -3.0, "N", Some(0.2)),
            "≥ 3.0000 N (castor right of centre; at the end of its range: the data ask for at \
             least this)"
        );
        assert_eq!(
            shown(DEAD_BAND, -0.1252, "duty", None),
            "0.1252 duty (right motor)"
        );
        assert_eq!(
            shown(WHEEL_DIAMETER_RATIO, 0.97, "1", None),
            "0.9700 (right wheel smaller)"
        );
        assert_eq!(shown(WHEELBASE_RATIO, 1.05, "1", None), "1.0500");
        assert_eq!(
            shown(WHEELBASE_RATIO, 0.8, "1", None),
            "≤ 0.8000 (at the end of its range: the data ask for at least this)"
        );
        assert_eq!(at_bound(COAST, 0.0), None);
        assert_eq!(at_bound(COAST, 0.299), Some(Bound::Upper));
        assert_eq!(at_bound(BATTERY_SAG, 19.0), None);
    }

    /// Every effect's range is one a robot can have: at either end it switches on a table
    /// the plant accepts, and no size a person reads is negative.
    #[test]
    fn every_range_is_physical_at_both_ends() {
        let nominal = plant_model::RobotConfig::default();
        for s in bench_parameters() {
            for v in [s.lower, s.upper] {
                let params = gap::EffectParams::new().with(&s.name, v);
                let c = super::super::apply(&nominal, &params)
                    .unwrap_or_else(|e| panic!("{} = {v}: {e}", s.name));
                c.effects
                    .validate()
                    .unwrap_or_else(|e| panic!("{} = {v}: {e}", s.name));
                plant_model::Robot::new(&c, 1).unwrap_or_else(|e| panic!("{} = {v}: {e}", s.name));
                assert!(magnitude(&s.name, v) >= 0.0, "{} = {v}", s.name);
            }
        }
    }
}
