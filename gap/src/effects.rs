//! Effect names, parameter descriptions and parameter values.
//!
//! Parameters are identified by stable string names, the names of the plant's effects
//! library, so that a diagnosis made with one [`crate::Model`] (the kinematic one here, the
//! full bench later) talks about the same effects. Each model declares which of them it
//! implements ([`crate::Model::parameters`]), with unit, bounds and the value that means "no
//! effect", and which it cannot ([`crate::Model::unsupported`]).

use std::collections::BTreeMap;

use serde::Serialize;

/// Ed = D_R/D_L, the ratio of the wheel diameters.
pub const WHEEL_DIAMETER_RATIO: &str = "wheel_diameter_ratio";
/// Eb = b_actual/b_reference, the wheelbase error.
pub const WHEELBASE_RATIO: &str = "wheelbase_ratio";
/// Es = L_calc/L_actual, the linear scale error (mean wheel diameter).
pub const DISTANCE_SCALE: &str = "distance_scale";
/// A fraction of each spin turn lost to wheel slip.
pub const TURN_SLIP: &str = "turn_slip";
/// Wheel slip in straight legs.
pub const STRAIGHT_SLIP: &str = "straight_slip";
/// Rotation after the motors are cut at the end of a turn.
pub const COAST: &str = "coast";
/// Misalignment of the wheels against the axle (crab angle of straight legs).
pub const TOE: &str = "toe";
/// Random heading disturbances from the floor.
pub const FLOOR_NOISE: &str = "floor_noise";
/// Different motor gains left and right.
pub const MOTOR_GAIN_ASYMMETRY: &str = "motor_gain_asymmetry";
/// Duty below which a motor does not turn.
pub const DEAD_BAND: &str = "dead_band";
/// Battery voltage dropping under load and over a run.
pub const BATTERY_SAG: &str = "battery_sag";
/// Encoder edges the firmware does not count.
pub const ENCODER_MISSED_COUNTS: &str = "encoder_missed_counts";
/// Encoder edges that bounce.
pub const ENCODER_GLITCHES: &str = "encoder_glitches";
/// Drag of the castor wheel.
pub const CASTOR_DRAG: &str = "castor_drag";
/// Lost motion in the gearbox when a wheel reverses.
pub const BACKLASH: &str = "backlash";

/// Every effect name of the plant's effects library (`plant_model::effects`), in a fixed
/// order.
pub const ALL_EFFECTS: [&str; 15] = [
    WHEEL_DIAMETER_RATIO,
    WHEELBASE_RATIO,
    DISTANCE_SCALE,
    TURN_SLIP,
    STRAIGHT_SLIP,
    COAST,
    TOE,
    FLOOR_NOISE,
    MOTOR_GAIN_ASYMMETRY,
    DEAD_BAND,
    BATTERY_SAG,
    ENCODER_MISSED_COUNTS,
    ENCODER_GLITCHES,
    CASTOR_DRAG,
    BACKLASH,
];

/// Whether a parameter moves the mean of what is measured or only its spread.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ParamKind {
    /// Shifts the expected measurement (identified from centroids).
    Systematic,
    /// Random from run to run (identified from the scatter between runs).
    Stochastic,
}

/// One parameter a model implements.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ParamSpec {
    /// Stable name (one of [`ALL_EFFECTS`]).
    pub name: String,
    /// Short symbol for reports (`Ed`, `Eb`, ...).
    pub symbol: String,
    /// Unit of the value (`"1"` for a ratio or fraction).
    pub unit: String,
    /// Smallest accepted value.
    pub lower: f64,
    /// Largest accepted value.
    pub upper: f64,
    /// The value that means "no effect".
    pub neutral: f64,
    /// A typical noticeable size of the effect (|value − neutral|): the step scale of the
    /// fits, and the size the self-test injects (0.5 to 1.5 times this).
    pub scale: f64,
    /// Systematic or stochastic.
    pub kind: ParamKind,
    /// What the value means.
    pub description: String,
}

impl ParamSpec {
    /// One row of a model's parameter table.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        name: &str,
        symbol: &str,
        unit: &str,
        (lower, upper): (f64, f64),
        neutral: f64,
        scale: f64,
        kind: ParamKind,
        description: &str,
    ) -> Self {
        Self {
            name: name.to_owned(),
            symbol: symbol.to_owned(),
            unit: unit.to_owned(),
            lower,
            upper,
            neutral,
            scale,
            kind,
            description: description.to_owned(),
        }
    }

    /// Whether `v` lies within the bounds.
    pub fn contains(&self, v: f64) -> bool {
        v.is_finite() && v >= self.lower && v <= self.upper
    }

    /// Whether the effect can go either way from neutral.
    pub fn two_sided(&self) -> bool {
        self.lower < self.neutral && self.upper > self.neutral
    }

    /// Whether the effect is stochastic: it moves the spread between runs, not the
    /// centroids.
    pub fn stochastic(&self) -> bool {
        self.kind == ParamKind::Stochastic
    }
}

/// An effect of the library a model cannot represent, and why.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Unsupported {
    /// The effect's name.
    pub name: String,
    /// Why the model cannot represent it (and what could).
    pub reason: String,
}

/// Values of named effect parameters. A parameter not set has its neutral value.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct EffectParams(BTreeMap<String, f64>);

impl EffectParams {
    /// No effect at all.
    pub fn new() -> Self {
        Self::default()
    }

    /// With `name` set to `value`.
    pub fn with(mut self, name: &str, value: f64) -> Self {
        self.set(name, value);
        self
    }

    /// Sets `name` to `value`.
    pub fn set(&mut self, name: &str, value: f64) {
        self.0.insert(name.to_owned(), value);
    }

    /// The value of `name`, if set.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.0.get(name).copied()
    }

    /// The value of `name`, or `neutral` when it is not set.
    pub fn get_or(&self, name: &str, neutral: f64) -> f64 {
        self.get(name).unwrap_or(neutral)
    }

    /// The names and values set.
    pub fn iter(&self) -> impl Iterator<Item = (&str, f64)> {
        self.0.iter().map(|(k, v)| (k.as_str(), *v))
    }

    /// Whether nothing is set.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}
