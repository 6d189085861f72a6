//! The [`Model`] trait: what a simulator must answer for the diagnosis, and the experiment
//! description it answers for.
//!
//! The trait knows nothing of any simulator: an experiment is the test the firmware ran, with
//! the firmware's parameters, plus the physical reference the effect parameters are relative
//! to; the answer is what would have been measured. The kinematic model
//! ([`crate::KinematicModel`]) implements it here; the full bench will implement it in its
//! own crate.

use henrytwo_protocol::Test;
use serde::{Deserialize, Serialize};

use crate::effects::{EffectParams, ParamSpec, Unsupported, ALL_EFFECTS};
use crate::series::Telemetry;

/// The test a run executed: one of the firmware's tests ([`Test`], the protocol's, the one
/// definition firmware and hosts share), or the Triangular Path driven clockwise, which a real
/// robot's table may hold but the firmware has no selector for. Coordinates of the answer:
/// [`calib::Frame::Default`] (origin at the start, x along the first leg, y to the left).
///
/// Written in manifests and reports by its snake_case name ([`TestKind::as_str`]); the kinds
/// have associated constants named as the tests are, usable in patterns (`TestKind::Line`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum TestKind {
    /// A test the firmware runs: the UMBmark squares (4 × (leg, spin by the UMBmark angle),
    /// right or left), the line (one straight leg, the end error measured from the commanded
    /// end (L, 0)), the counter-clockwise triangle (3 × (leg, spin left by the triangle
    /// angle)).
    Firmware(Test),
    /// Triangle, clockwise: 3 × (leg, spin right by the triangle angle).
    TriangleCw,
}

#[allow(non_upper_case_globals)]
impl TestKind {
    /// UMBmark square, clockwise.
    pub const UmbmarkCw: TestKind = TestKind::Firmware(Test::UmbmarkCw);
    /// UMBmark square, counter-clockwise.
    pub const UmbmarkCcw: TestKind = TestKind::Firmware(Test::UmbmarkCcw);
    /// One straight leg.
    pub const Line: TestKind = TestKind::Firmware(Test::Line);
    /// Triangle, counter-clockwise: the firmware's triangle.
    pub const TriangleCcw: TestKind = TestKind::Firmware(Test::Triangle);
}

impl TestKind {
    /// Every test kind.
    pub const ALL: [TestKind; 5] = [
        TestKind::UmbmarkCw,
        TestKind::UmbmarkCcw,
        TestKind::Line,
        TestKind::TriangleCcw,
        TestKind::TriangleCw,
    ];

    /// The snake_case name used in manifests and reports.
    pub const fn as_str(self) -> &'static str {
        match self {
            TestKind::Firmware(Test::UmbmarkCw) => "umbmark_cw",
            TestKind::Firmware(Test::UmbmarkCcw) => "umbmark_ccw",
            TestKind::Firmware(Test::Line) => "line",
            TestKind::Firmware(Test::Triangle) => "triangle_ccw",
            TestKind::TriangleCw => "triangle_cw",
        }
    }

    /// The names of [`TestKind::ALL`], in order.
    const NAMES: [&'static str; 5] = {
        let mut names = [""; 5];
        let mut i = 0;
        while i < names.len() {
            names[i] = TestKind::ALL[i].as_str();
            i += 1;
        }
        names
    };

    /// The path driven: the firmware's test, or for the clockwise triangle the firmware's
    /// triangle it mirrors.
    fn path(self) -> Test {
        match self {
            TestKind::Firmware(t) => t,
            TestKind::TriangleCw => Test::Triangle,
        }
    }

    /// Number of legs (each followed by a turn, except for the line).
    pub fn legs(self) -> usize {
        self.path().legs()
    }

    /// +1 for left (counter-clockwise) turns, −1 for right turns, 0 without turns.
    pub fn turn_sign(self) -> f64 {
        match self {
            TestKind::TriangleCw => -1.0,
            TestKind::Firmware(t) if t.turns() == 0 => 0.0,
            TestKind::Firmware(t) => t.turn_deg().signum(),
        }
    }

    /// The commanded turn of each corner for `firmware`, degrees (0 for the line).
    pub fn turn_deg(self, firmware: &Firmware) -> f64 {
        match self.path() {
            Test::UmbmarkCw | Test::UmbmarkCcw => firmware.turn_umbmark_deg,
            Test::Triangle => firmware.turn_triangle_deg,
            Test::Line => 0.0,
        }
    }
}

impl std::fmt::Display for TestKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

impl Serialize for TestKind {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.as_str())
    }
}

impl<'de> Deserialize<'de> for TestKind {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Name;
        impl serde::de::Visitor<'_> for Name {
            type Value = TestKind;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                write!(f, "a test name: {}", TestKind::NAMES.join(", "))
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<TestKind, E> {
                TestKind::ALL
                    .into_iter()
                    .find(|k| k.as_str() == v)
                    .ok_or_else(|| E::unknown_variant(v, &TestKind::NAMES))
            }
        }
        d.deserialize_str(Name)
    }
}

/// How the firmware drives a straight leg, which decides what cL and cR do there.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StraightLegs {
    /// Each wheel's count rate is held at its own set-point (a speed PID per wheel, as in the
    /// thesis firmware and the bench's): the count ratio of a leg is set-point left / right;
    /// cL and cR only weigh the stop rule `(cL nL + cR nR)/2 · mm_per_count ≥ L` and the spin
    /// targets. Correction factors then cannot straighten a leg.
    #[default]
    SpeedSetpoints,
    /// The firmware keeps the *corrected* wheel distances equal (`cL nL = cR nR`, Borenstein's
    /// intent) and stops when they reach L: cL and cR set the count ratio of a leg.
    CorrectedOdometry,
}

/// The firmware parameters in force during a run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Firmware {
    /// Left wheel's distance-per-count correction factor cL.
    pub c_left: f64,
    /// Right wheel's distance-per-count correction factor cR.
    pub c_right: f64,
    /// Wheelbase the firmware computes spin targets with, mm.
    pub wheelbase_mm: f64,
    /// Distance per encoder count the firmware assumes (before cL, cR), mm.
    pub mm_per_count: f64,
    /// Commanded leg length, mm.
    pub leg_mm: f64,
    /// UMBmark corner angle, degrees.
    pub turn_umbmark_deg: f64,
    /// Triangle corner angle, degrees.
    pub turn_triangle_deg: f64,
    /// Left wheel speed set-point (any unit proportional to count rate; only the ratio to the
    /// right one matters kinematically). `None`: both wheels alike.
    pub setpoint_left: Option<f64>,
    /// Right wheel speed set-point, same unit.
    pub setpoint_right: Option<f64>,
    /// How straight legs are driven.
    pub straight_legs: StraightLegs,
}

impl Firmware {
    /// A firmware with no corrections for a robot with `reference` geometry.
    pub fn nominal(reference: &Reference, leg_mm: f64) -> Self {
        Firmware {
            c_left: 1.0,
            c_right: 1.0,
            wheelbase_mm: reference.wheelbase_mm,
            mm_per_count: reference.mm_per_count,
            leg_mm,
            turn_umbmark_deg: 90.0,
            turn_triangle_deg: 120.0,
            setpoint_left: None,
            setpoint_right: None,
            straight_legs: StraightLegs::default(),
        }
    }

    /// Count-rate ratio left/right of the set-points (1 when not given).
    pub fn setpoint_ratio(&self) -> f64 {
        match (self.setpoint_left, self.setpoint_right) {
            (Some(l), Some(r)) if l > 0.0 && r > 0.0 => l / r,
            _ => 1.0,
        }
    }
}

/// The physical reference the effect parameters are relative to: the robot as designed.
/// `wheelbase_ratio` = actual wheelbase / `wheelbase_mm`; the mean wheel's actual distance per
/// count is `mm_per_count / distance_scale`. It does not change between experiments of one
/// robot (the firmware's values may).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Reference {
    /// Reference wheelbase, mm.
    pub wheelbase_mm: f64,
    /// Reference distance per encoder count of the mean wheel, mm.
    pub mm_per_count: f64,
}

/// What was run: the input of [`Model::predict`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Experiment {
    /// The test.
    pub test: TestKind,
    /// Firmware parameters in force.
    pub firmware: Firmware,
    /// The robot's physical reference.
    pub reference: Reference,
    /// Number of runs to predict.
    pub runs: usize,
    /// Seed of the run-to-run randomness (run `i` uses its own stream derived from it).
    pub seed: u64,
}

/// The end of one run in [`calib::Frame::Default`]: end position minus start (the line:
/// minus the commanded end), and the heading error (end heading minus the commanded one,
/// wrapped to ±π).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RunEndpoint {
    /// x error, cm.
    pub x_cm: f64,
    /// y error, cm.
    pub y_cm: f64,
    /// Heading error, rad (counter-clockwise positive).
    pub theta_rad: f64,
}

/// Why a model could not answer.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelError {
    /// A parameter name the model does not implement.
    #[error("model `{model}` has no parameter `{name}` (it implements: {known})")]
    UnknownParameter {
        /// The model.
        model: String,
        /// The name asked for.
        name: String,
        /// The names it implements.
        known: String,
    },
    /// A parameter outside its bounds.
    #[error("parameter `{name}` = {value} is outside [{lower}, {upper}]")]
    OutOfBounds {
        /// The parameter.
        name: String,
        /// Its value.
        value: f64,
        /// Lower bound.
        lower: f64,
        /// Upper bound.
        upper: f64,
    },
    /// The model cannot predict this kind of measurement.
    #[error("model `{model}` cannot predict {what}")]
    Unsupported {
        /// The model.
        model: String,
        /// What was asked.
        what: String,
    },
    /// The experiment description is not usable.
    #[error("invalid experiment: {0}")]
    InvalidExperiment(String),
}

/// A simulator as the diagnosis sees it.
pub trait Model: Send + Sync {
    /// A short name for reports.
    fn name(&self) -> String;

    /// The effect parameters it implements (names from [`crate::effects::ALL_EFFECTS`]).
    fn parameters(&self) -> Vec<ParamSpec>;

    /// The library's effects it cannot represent, with the reason. The default lists every
    /// library effect missing from [`Model::parameters`] without a reason of its own.
    fn unsupported(&self) -> Vec<Unsupported> {
        let mine: Vec<String> = self.parameters().into_iter().map(|p| p.name).collect();
        ALL_EFFECTS
            .iter()
            .filter(|e| !mine.iter().any(|m| m == *e))
            .map(|e| Unsupported {
                name: (*e).to_owned(),
                reason: "not implemented by this model".to_owned(),
            })
            .collect()
    }

    /// The end of each of `experiment.runs` runs with the effects `params` (unset ones
    /// neutral). Deterministic for a given seed.
    fn predict(
        &self,
        params: &EffectParams,
        experiment: &Experiment,
    ) -> Result<Vec<RunEndpoint>, ModelError>;

    /// The telemetry of one run (wheel speeds and PWM per control period), when the model
    /// has motor dynamics. The default: [`ModelError::Unsupported`].
    fn predict_series(
        &self,
        _params: &EffectParams,
        _experiment: &Experiment,
    ) -> Result<Telemetry, ModelError> {
        Err(ModelError::Unsupported {
            model: self.name(),
            what: "time series (it has no motor dynamics)".to_owned(),
        })
    }
}

/// The parameter `name` among a model's `specs`, or the error that names the ones it has.
pub(crate) fn known_spec<'a>(
    model: &str,
    specs: &'a [ParamSpec],
    name: &str,
) -> Result<&'a ParamSpec, ModelError> {
    specs
        .iter()
        .find(|s| s.name == name)
        .ok_or_else(|| ModelError::UnknownParameter {
            model: model.to_owned(),
            name: name.to_owned(),
            known: specs
                .iter()
                .map(|s| s.name.as_str())
                .collect::<Vec<_>>()
                .join(", "),
        })
}

/// Checks `params` against `specs`: every name known, every value in bounds.
pub fn check_params(
    model: &str,
    specs: &[ParamSpec],
    params: &EffectParams,
) -> Result<(), ModelError> {
    for (name, value) in params.iter() {
        let spec = known_spec(model, specs, name)?;
        if !spec.contains(value) {
            return Err(ModelError::OutOfBounds {
                name: name.to_owned(),
                value,
                lower: spec.lower,
                upper: spec.upper,
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Manifests and reports name the kinds in snake_case, the clockwise triangle included;
    /// the shapes are the firmware's tests', mirrored for that triangle; groups sort in the
    /// order of [`TestKind::ALL`].
    #[test]
    fn each_kind_keeps_its_name_shape_and_order() {
        let table = [
            (TestKind::UmbmarkCw, "umbmark_cw", 4, -1.0),
            (TestKind::UmbmarkCcw, "umbmark_ccw", 4, 1.0),
            (TestKind::Line, "line", 1, 0.0),
            (TestKind::TriangleCcw, "triangle_ccw", 3, 1.0),
            (TestKind::TriangleCw, "triangle_cw", 3, -1.0),
        ];
        for (i, (kind, name, legs, sign)) in table.into_iter().enumerate() {
            assert_eq!(kind, TestKind::ALL[i]);
            assert_eq!(kind.to_string(), name);
            assert_eq!(serde_json::to_string(&kind).unwrap(), format!("\"{name}\""));
            let back: TestKind = serde_json::from_str(&format!("\"{name}\"")).unwrap();
            assert_eq!(back, kind);
            assert_eq!((kind.legs(), kind.turn_sign()), (legs, sign), "{name}");
        }
        assert!(TestKind::ALL.windows(2).all(|w| w[0] < w[1]));
        let err = serde_json::from_str::<TestKind>("\"triangle\"").unwrap_err();
        assert!(
            err.to_string().contains("unknown variant `triangle`"),
            "{err}"
        );
    }
}
