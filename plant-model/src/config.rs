//! The robot's parameters, read from TOML.
//!
//! Keys carry their unit in their name (`_mm`, `_s`, `_v`, `_duty` for a fraction of a PWM
//! period in `[0, 1]`, `_thesis_rpm`). Unknown keys are refused, so a typo cannot silently
//! leave a parameter at some other value; after parsing every number is checked (finite,
//! within the physical range of its key, duties in `[0, 1]`), so that a battery of 1e6 V or
//! a time constant of a picosecond is refused with the range instead of run. `fixtures/robots/henrytwo-ideal.toml` lists
//! every key with where its value comes from and equals [`RobotConfig::default`].
//!
//! ```toml
//! [geometry]
//! wheel_diameter_left_mm = 32.0
//! wheel_diameter_right_mm = 32.0
//! wheelbase_mm = 130.0
//!
//! [encoder]
//! gear_ratio = 100.37
//! a_edges_per_motor_rev = 6
//! reversed_left = false      # optional, default false
//! reversed_right = false     # optional, default false
//!
//! [battery]
//! voltage_v = 7.4
//!
//! [motor.left]               # and [motor.right]
//! model = "first_order"
//! gain_thesis_rpm = 22.0
//! reference_duty = 0.8235294117647058
//! dead_band_duty = 0.5796
//! tau_s = 0.055
//! fit_voltage_v = 7.4
//! # coast_tau_s = 0.055      # optional, default tau_s
//! # brake_tau_s = 0.0183     # optional, default tau_s / 3
//!
//! [effects.wheel_diameter_ratio]  # optional tables, one per effect: see crate::effects
//! right_over_left_ratio = 1.036
//!
//! [firmware]                 # optional: settings of the firmware that drives the robot
//! kp_left = 1.0
//! ```
//!
//! The `[firmware]` table is not the plant's: it holds numbers by name for the firmware that
//! drives this robot (its PID gains, set-points, thresholds), which the bench sends it before
//! a run. The plant keeps them as written; the bench checks the names and the ranges
//! against the firmware's (`hil::firmware::settings`).

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::check::{
    check_between, check_physical, A_EDGES_PER_MOTOR_REV, GEAR_RATIO, VOLTAGE_V, WHEELBASE_MM,
    WHEEL_DIAMETER_MM,
};
use crate::effects::Effects;
use crate::motor::{FirstOrderMotor, MotorModel};
use crate::side::{PerSide, Side};
use crate::Error;

/// Everything the plant needs to know about one robot.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotConfig {
    /// Wheels and wheelbase.
    pub geometry: Geometry,
    /// Gearbox and encoders.
    pub encoder: EncoderConfig,
    /// The battery.
    pub battery: BatteryConfig,
    /// One motor model per side (`[motor.left]`, `[motor.right]`).
    pub motor: PerSide<MotorModel>,
    /// The effects switched on (`[effects.<name>]` tables; none in the ideal robot). See
    /// [`crate::effects`].
    #[serde(default, skip_serializing_if = "Effects::is_empty")]
    pub effects: Effects,
    /// The `[firmware]` table: the firmware's settings for this robot, by name, as written
    /// (checked by the bench that sends them, not here; none in Henrytwo's config).
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub firmware: std::collections::BTreeMap<String, f64>,
}

/// Wheel sizes and wheelbase.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Geometry {
    /// Left wheel diameter, mm.
    pub wheel_diameter_left_mm: f64,
    /// Right wheel diameter, mm.
    pub wheel_diameter_right_mm: f64,
    /// Distance between the wheels' contact points, mm.
    pub wheelbase_mm: f64,
}

/// Gearbox and quadrature encoders (same on both sides).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EncoderConfig {
    /// Motor revolutions per wheel revolution.
    pub gear_ratio: f64,
    /// Edges on channel A per motor revolution (channel B has as many, in quadrature).
    pub a_edges_per_motor_rev: u32,
    /// The left encoder counts backwards when the wheel rolls forward (a wiring fault).
    #[serde(default)]
    pub reversed_left: bool,
    /// The right encoder counts backwards when the wheel rolls forward (a wiring fault).
    #[serde(default)]
    pub reversed_right: bool,
}

impl EncoderConfig {
    /// The `reversed_*` flag of `side`.
    pub fn reversed(&self, side: Side) -> bool {
        match side {
            Side::Left => self.reversed_left,
            Side::Right => self.reversed_right,
        }
    }
}

/// The battery feeding both bridges.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BatteryConfig {
    /// Terminal voltage, volts (constant for now).
    pub voltage_v: f64,
}

impl Default for RobotConfig {
    /// The nominal Henrytwo of the thesis; identical to `fixtures/robots/henrytwo-ideal.toml`.
    fn default() -> Self {
        RobotConfig {
            geometry: Geometry {
                wheel_diameter_left_mm: 32.0,
                wheel_diameter_right_mm: 32.0,
                wheelbase_mm: 130.0,
            },
            encoder: EncoderConfig {
                gear_ratio: 100.37,
                a_edges_per_motor_rev: 6,
                reversed_left: false,
                reversed_right: false,
            },
            battery: BatteryConfig { voltage_v: 7.4 },
            motor: PerSide {
                left: MotorModel::FirstOrder(FirstOrderMotor::henrytwo_left()),
                right: MotorModel::FirstOrder(FirstOrderMotor::henrytwo_right()),
            },
            effects: Effects::default(),
            firmware: std::collections::BTreeMap::new(),
        }
    }
}

impl RobotConfig {
    /// Parses and validates a config from TOML text.
    pub fn from_toml_str(text: &str) -> Result<Self, Error> {
        let config: RobotConfig = toml::from_str(text)?;
        config.validate()?;
        Ok(config)
    }

    /// Reads, parses and validates a config file; an error in it names the file
    /// ([`Error::InFile`]).
    pub fn load(path: impl AsRef<Path>) -> Result<Self, Error> {
        let path = path.as_ref();
        let text = input_file::read_text(path).map_err(|source| Error::ReadConfig {
            path: path.to_path_buf(),
            source,
        })?;
        Self::from_toml_str(&text).map_err(|error| Error::InFile {
            path: path.to_path_buf(),
            error: Box::new(error),
        })
    }

    /// Checks every number: finite, within its physical range (documented beside the keys in
    /// `fixtures/robots/henrytwo-ideal.toml`), duties in `[0, 1]`.
    pub fn validate(&self) -> Result<(), Error> {
        let g = &self.geometry;
        check_physical(
            "geometry.wheel_diameter_left_mm",
            g.wheel_diameter_left_mm,
            WHEEL_DIAMETER_MM,
            "left wheel diameter",
        )?;
        check_physical(
            "geometry.wheel_diameter_right_mm",
            g.wheel_diameter_right_mm,
            WHEEL_DIAMETER_MM,
            "right wheel diameter",
        )?;
        check_physical(
            "geometry.wheelbase_mm",
            g.wheelbase_mm,
            WHEELBASE_MM,
            "distance between the wheels' contact points",
        )?;
        check_physical(
            "encoder.gear_ratio",
            self.encoder.gear_ratio,
            GEAR_RATIO,
            "motor revolutions per wheel revolution",
        )?;
        check_physical(
            "encoder.a_edges_per_motor_rev",
            f64::from(self.encoder.a_edges_per_motor_rev),
            A_EDGES_PER_MOTOR_REV,
            "channel-A edges per motor revolution",
        )?;
        check_physical(
            "battery.voltage_v",
            self.battery.voltage_v,
            VOLTAGE_V,
            "battery terminal voltage",
        )?;
        for side in Side::BOTH {
            self.motor
                .get(side)
                .validate(&format!("motor.{}", side.name()))?;
        }
        self.effects.validate()?;
        self.validate_effects_against_base()
    }

    /// The checks that need both an effect and the base config.
    fn validate_effects_against_base(&self) -> Result<(), Error> {
        if self.effects.coast.is_some() {
            for side in Side::BOTH {
                let MotorModel::FirstOrder(motor) = self.motor.get(side);
                if motor.coast_tau_s.is_some() {
                    return Err(Error::Conflict {
                        key: format!("motor.{}.coast_tau_s", side.name()),
                        other: format!("effects.coast.{}_tau_s", side.name()),
                        why: "both set the coast time constant; keep one (the effect when \
                              the coast is a departure from the nominal robot)",
                    });
                }
            }
        }
        if let Some(glitches) = &self.effects.encoder_glitches {
            let state_deg = 360.0 / (2.0 * f64::from(self.encoder.a_edges_per_motor_rev));
            check_between(
                "effects.encoder_glitches.width_motor_deg",
                glitches.width_motor_deg,
                (0.0, 0.5 * state_deg - 1e-9),
                "a glitch must be shorter than half a quadrature state (15 degrees of the \
                 motor shaft with 6 A edges per turn)",
                "width of a glitch, degrees of motor-shaft angle",
            )?;
        }
        Ok(())
    }

    /// Wheel diameter of `side`, mm.
    pub fn wheel_diameter_mm(&self, side: Side) -> f64 {
        match side {
            Side::Left => self.geometry.wheel_diameter_left_mm,
            Side::Right => self.geometry.wheel_diameter_right_mm,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The default passes its own validation and survives a TOML round trip unchanged.
    #[test]
    fn default_is_valid_and_round_trips() {
        let config = RobotConfig::default();
        config.validate().unwrap();
        let text = toml::to_string(&config).unwrap();
        assert_eq!(RobotConfig::from_toml_str(&text).unwrap(), config);
    }

    /// A missing file is reported with its path.
    #[test]
    fn missing_file_names_the_path() {
        let err = RobotConfig::load("no/such/robot.toml").unwrap_err();
        assert!(matches!(err, Error::ReadConfig { .. }));
        assert!(err.to_string().contains("no/such/robot.toml"), "{err}");
    }
}
