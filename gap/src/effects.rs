//! Effect names, parameter descriptions and parameter values.
//!
//! Parameters are identified by stable string names, the names of the plant's effects
//! library, so that a diagnosis made with one [`crate::Model`] (the kinematic one here, the
//! full bench later) talks about the same effects. Each model declares which of them it
//! implements ([`crate::Model::parameters`]), with unit, bounds and the value that means "no
//! effect", and which it cannot ([`crate::Model::unsupported`]).

use std::collections::BTreeMap;

use serde::Serialize;

/// An effect of the plant's effects library (`plant_model::effects`): the one list of
/// them. Code that acts per effect matches on this enum, so an effect added here is a
/// compile error wherever it is not handled yet; names from files and command lines come
/// in through [`Effect::from_name`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Effect {
    /// Ed = D_R/D_L, the ratio of the wheel diameters.
    WheelDiameterRatio,
    /// Eb = b_actual/b_reference, the wheelbase error.
    WheelbaseRatio,
    /// Es = L_calc/L_actual, the linear scale error (mean wheel diameter).
    DistanceScale,
    /// A fraction of each spin turn lost to wheel slip.
    TurnSlip,
    /// Wheel slip in straight legs.
    StraightSlip,
    /// Rotation after the motors are cut at the end of a turn.
    Coast,
    /// Misalignment of the wheels against the axle (crab angle of straight legs).
    Toe,
    /// Random heading disturbances from the floor.
    FloorNoise,
    /// Different motor gains left and right.
    MotorGainAsymmetry,
    /// Duty below which a motor does not turn.
    DeadBand,
    /// Battery voltage dropping under load and over a run.
    BatterySag,
    /// Encoder edges the firmware does not count.
    EncoderMissedCounts,
    /// Encoder edges that bounce.
    EncoderGlitches,
    /// Drag of the castor wheel.
    CastorDrag,
    /// Lost motion in the gearbox when a wheel reverses.
    Backlash,
}

impl Effect {
    /// Every effect, in the library's fixed order.
    pub const ALL: [Effect; 15] = [
        Effect::WheelDiameterRatio,
        Effect::WheelbaseRatio,
        Effect::DistanceScale,
        Effect::TurnSlip,
        Effect::StraightSlip,
        Effect::Coast,
        Effect::Toe,
        Effect::FloorNoise,
        Effect::MotorGainAsymmetry,
        Effect::DeadBand,
        Effect::BatterySag,
        Effect::EncoderMissedCounts,
        Effect::EncoderGlitches,
        Effect::CastorDrag,
        Effect::Backlash,
    ];

    /// The stable name: the key of its `[effects.<name>]` table in a robot config, and
    /// the name reports and files use.
    pub const fn name(self) -> &'static str {
        match self {
            Effect::WheelDiameterRatio => "wheel_diameter_ratio",
            Effect::WheelbaseRatio => "wheelbase_ratio",
            Effect::DistanceScale => "distance_scale",
            Effect::TurnSlip => "turn_slip",
            Effect::StraightSlip => "straight_slip",
            Effect::Coast => "coast",
            Effect::Toe => "toe",
            Effect::FloorNoise => "floor_noise",
            Effect::MotorGainAsymmetry => "motor_gain_asymmetry",
            Effect::DeadBand => "dead_band",
            Effect::BatterySag => "battery_sag",
            Effect::EncoderMissedCounts => "encoder_missed_counts",
            Effect::EncoderGlitches => "encoder_glitches",
            Effect::CastorDrag => "castor_drag",
            Effect::Backlash => "backlash",
        }
    }

    /// The effect named `name`, if the library has one.
    pub fn from_name(name: &str) -> Option<Effect> {
        Effect::ALL.into_iter().find(|e| e.name() == name)
    }
}

impl std::fmt::Display for Effect {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Ed = D_R/D_L, the ratio of the wheel diameters.
pub const WHEEL_DIAMETER_RATIO: &str = Effect::WheelDiameterRatio.name();
/// Eb = b_actual/b_reference, the wheelbase error.
pub const WHEELBASE_RATIO: &str = Effect::WheelbaseRatio.name();
/// Es = L_calc/L_actual, the linear scale error (mean wheel diameter).
pub const DISTANCE_SCALE: &str = Effect::DistanceScale.name();
/// A fraction of each spin turn lost to wheel slip.
pub const TURN_SLIP: &str = Effect::TurnSlip.name();
/// Wheel slip in straight legs.
pub const STRAIGHT_SLIP: &str = Effect::StraightSlip.name();
/// Rotation after the motors are cut at the end of a turn.
pub const COAST: &str = Effect::Coast.name();
/// Misalignment of the wheels against the axle (crab angle of straight legs).
pub const TOE: &str = Effect::Toe.name();
/// Random heading disturbances from the floor.
pub const FLOOR_NOISE: &str = Effect::FloorNoise.name();
/// Different motor gains left and right.
pub const MOTOR_GAIN_ASYMMETRY: &str = Effect::MotorGainAsymmetry.name();
/// Duty below which a motor does not turn.
pub const DEAD_BAND: &str = Effect::DeadBand.name();
/// Battery voltage dropping under load and over a run.
pub const BATTERY_SAG: &str = Effect::BatterySag.name();
/// Encoder edges the firmware does not count.
pub const ENCODER_MISSED_COUNTS: &str = Effect::EncoderMissedCounts.name();
/// Encoder edges that bounce.
pub const ENCODER_GLITCHES: &str = Effect::EncoderGlitches.name();
/// Drag of the castor wheel.
pub const CASTOR_DRAG: &str = Effect::CastorDrag.name();
/// Lost motion in the gearbox when a wheel reverses.
pub const BACKLASH: &str = Effect::Backlash.name();

/// Every effect name of the plant's effects library (`plant_model::effects`), in a fixed
/// order: the names of [`Effect::ALL`].
pub const ALL_EFFECTS: [&str; 15] = {
    let mut names = [""; 15];
    let mut i = 0;
    while i < 15 {
        names[i] = Effect::ALL[i].name();
        i += 1;
    }
    names
};

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

#[cfg(test)]
mod tests {
    use super::*;

    /// Each effect has its own name, and its name brings it back: a file's name can only
    /// mean one effect, and no effect is out of reach of the files.
    #[test]
    fn every_effect_name_is_its_own_and_leads_back_to_it() {
        for (i, e) in Effect::ALL.into_iter().enumerate() {
            assert_eq!(Effect::from_name(e.name()), Some(e));
            assert_eq!(ALL_EFFECTS[i], e.name());
            assert_eq!(
                Effect::ALL.iter().filter(|o| o.name() == e.name()).count(),
                1,
                "{e}"
            );
        }
        assert_eq!(Effect::from_name("wheelbase"), None);
    }
}
