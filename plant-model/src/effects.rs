//! The effects library: named departures from the nominal robot, each switched on by its own
//! table in the robot config (`[effects.<name>]`), each with physical parameters in
//! unit-suffixed keys, all off in the ideal robot (`fixtures/robots/henrytwo-ideal.toml`).
//!
//! The names are a contract: the gap-diagnosis crate names effects the same way.
//!
//! | name | symbol / what | keys (unit) | acts on |
//! |---|---|---|---|
//! | [`wheel_diameter_ratio`] | Ed = D_R / D_L, mean kept | `right_over_left_ratio` | ground |
//! | [`wheelbase_ratio`] | Eb = b_actual / b_nominal | `actual_over_nominal_ratio` | ground |
//! | [`distance_scale`] | Es = L_odometry / L_actual | `odometry_over_actual_ratio` | ground |
//! | [`dead_band`] | Coulomb friction beyond the fit | `extra_left_duty`, `extra_right_duty` | motor |
//! | [`motor_gain_asymmetry`] | per-motor gain | `left_gain_ratio`, `right_gain_ratio` | motor |
//! | [`coast`] | coasting time constant | `left_tau_s`, `right_tau_s` | motor |
//! | [`turn_slip`] | rotation the ground does not see | `fraction` | ground |
//! | [`straight_slip`] | travel the ground does not see | `left_fraction`, `right_fraction` | ground |
//! | [`floor_noise`] | random walk per metre | `heading_deg_per_sqrt_m`, `lateral_mm_per_sqrt_m`, `turn_heading_deg_per_sqrt_m`, `stretch_mm` | ground |
//! | [`castor_drag`] | drag at the castor | `force_n`, `lateral_offset_mm`, `wheel_stall_torque_nm` | motor |
//! | [`encoder_missed_counts`] | A pulses missing | `left_fraction`, `right_fraction` | encoder |
//! | [`encoder_glitches`] | edges that bounce | `left_fraction`, `right_fraction`, `width_motor_deg` | encoder |
//! | [`battery_sag`] | V = V_oc(SoC) - R_int I | `open_circuit_full_v`, `open_circuit_empty_v`, `capacity_mah`, `initial_charge_fraction`, `internal_resistance_ohm`, `motor_resistance_ohm`, `idle_current_a`, `update_interval_s` | motor |
//! | [`backlash`] | lost motion on reversal | `left_wheel_deg`, `right_wheel_deg` | ground |
//! | [`toe`] | wheel misalignment | `left_deg`, `right_deg` | ground |
//!
//! Each module documents its model, its keys and its signature (what it does to a straight
//! leg, a spin turn, a UMBmark), and has a unit test that shows it.
//!
//! # Keeping the plant exact
//!
//! The bench raises encoder edges at the times [`crate::Robot::next_encoder_transition`]
//! predicts and re-plans only after an input change or a transition, so no effect may change
//! the encoder's timing behind its back:
//!
//! - **ground** effects act only in the pose integration: the encoder measures the motor
//!   shaft, what the floor sees differs (wheel sizes, slip, noise, backlash, toe);
//! - **motor** effects change the closed-form wheel motion and are fixed for as long as the
//!   inputs are (a gain, a friction, a time constant), except the battery, whose voltage is
//!   piecewise constant and changes at the times [`crate::Robot::next_internal_change`]
//!   announces;
//! - **encoder** effects are functions of the shaft angle, so the levels stay a function of
//!   the wheel angle ([`crate::encoder`]).
//!
//! Random effects draw from seeded SplitMix64 streams (one per effect) per stretch of floor or per
//! encoder pulse, never per call, so the same seed gives the same run however the bench
//! steps the plant.

pub mod backlash;
pub mod battery_sag;
pub mod castor_drag;
pub mod coast;
pub mod dead_band;
pub mod distance_scale;
pub mod encoder_glitches;
pub mod encoder_missed_counts;
pub mod floor_noise;
pub mod motor_gain_asymmetry;
pub mod straight_slip;
pub mod toe;
pub mod turn_slip;
pub mod wheel_diameter_ratio;
pub mod wheelbase_ratio;

use serde::{Deserialize, Serialize};

pub use backlash::Backlash;
pub use battery_sag::BatterySag;
pub use castor_drag::CastorDrag;
pub use coast::Coast;
pub use dead_band::DeadBand;
pub use distance_scale::DistanceScale;
pub use encoder_glitches::EncoderGlitches;
pub use encoder_missed_counts::EncoderMissedCounts;
pub use floor_noise::FloorNoise;
pub use motor_gain_asymmetry::MotorGainAsymmetry;
pub use straight_slip::StraightSlip;
pub use toe::Toe;
pub use turn_slip::TurnSlip;
pub use wheel_diameter_ratio::WheelDiameterRatio;
pub use wheelbase_ratio::WheelbaseRatio;

use crate::Error;

/// The effects switched on, one optional table each (`[effects.<name>]`); absent means off.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Effects {
    /// Ed: unequal wheel diameters.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wheel_diameter_ratio: Option<WheelDiameterRatio>,
    /// Eb: the actual wheelbase differs from the nominal one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wheelbase_ratio: Option<WheelbaseRatio>,
    /// Es: both wheels' effective diameter scaled.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub distance_scale: Option<DistanceScale>,
    /// Dead band / Coulomb friction beyond the fitted motor model.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dead_band: Option<DeadBand>,
    /// Per-motor gain.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub motor_gain_asymmetry: Option<MotorGainAsymmetry>,
    /// Coasting after the motor is switched off.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coast: Option<Coast>,
    /// Wheel slip in turns.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub turn_slip: Option<TurnSlip>,
    /// Wheel slip in straight legs.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub straight_slip: Option<StraightSlip>,
    /// Floor irregularities: seeded heading and lateral noise per metre.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub floor_noise: Option<FloorNoise>,
    /// Drag at the castor.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub castor_drag: Option<CastorDrag>,
    /// Encoder pulses that never appear.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub encoder_missed_counts: Option<EncoderMissedCounts>,
    /// Encoder edges that bounce.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub encoder_glitches: Option<EncoderGlitches>,
    /// Battery voltage with state of charge and load.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub battery_sag: Option<BatterySag>,
    /// Gear backlash.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub backlash: Option<Backlash>,
    /// Wheel misalignment.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub toe: Option<Toe>,
}

impl Effects {
    /// Every effect name, in the order of the table above (the `[effects.<name>]` tables).
    pub const NAMES: [&'static str; 15] = [
        "wheel_diameter_ratio",
        "wheelbase_ratio",
        "distance_scale",
        "dead_band",
        "motor_gain_asymmetry",
        "coast",
        "turn_slip",
        "straight_slip",
        "floor_noise",
        "castor_drag",
        "encoder_missed_counts",
        "encoder_glitches",
        "battery_sag",
        "backlash",
        "toe",
    ];

    /// Whether no effect is switched on (the ideal robot).
    pub fn is_empty(&self) -> bool {
        self.enabled().is_empty()
    }

    /// The names of the effects switched on, in the order of [`Effects::NAMES`].
    pub fn enabled(&self) -> Vec<&'static str> {
        let on = [
            self.wheel_diameter_ratio.is_some(),
            self.wheelbase_ratio.is_some(),
            self.distance_scale.is_some(),
            self.dead_band.is_some(),
            self.motor_gain_asymmetry.is_some(),
            self.coast.is_some(),
            self.turn_slip.is_some(),
            self.straight_slip.is_some(),
            self.floor_noise.is_some(),
            self.castor_drag.is_some(),
            self.encoder_missed_counts.is_some(),
            self.encoder_glitches.is_some(),
            self.battery_sag.is_some(),
            self.backlash.is_some(),
            self.toe.is_some(),
        ];
        Self::NAMES
            .into_iter()
            .zip(on)
            .filter_map(|(name, on)| on.then_some(name))
            .collect()
    }

    /// Checks every effect's parameters; errors name the key as `effects.<name>.<key>`.
    pub fn validate(&self) -> Result<(), Error> {
        fn check<T>(
            effect: &Option<T>,
            name: &str,
            f: impl Fn(&T, &str) -> Result<(), Error>,
        ) -> Result<(), Error> {
            match effect {
                Some(e) => f(e, &format!("effects.{name}")),
                None => Ok(()),
            }
        }
        check(
            &self.wheel_diameter_ratio,
            "wheel_diameter_ratio",
            WheelDiameterRatio::validate,
        )?;
        check(
            &self.wheelbase_ratio,
            "wheelbase_ratio",
            WheelbaseRatio::validate,
        )?;
        check(
            &self.distance_scale,
            "distance_scale",
            DistanceScale::validate,
        )?;
        check(&self.dead_band, "dead_band", DeadBand::validate)?;
        check(
            &self.motor_gain_asymmetry,
            "motor_gain_asymmetry",
            MotorGainAsymmetry::validate,
        )?;
        check(&self.coast, "coast", Coast::validate)?;
        check(&self.turn_slip, "turn_slip", TurnSlip::validate)?;
        check(&self.straight_slip, "straight_slip", StraightSlip::validate)?;
        check(&self.floor_noise, "floor_noise", FloorNoise::validate)?;
        check(&self.castor_drag, "castor_drag", CastorDrag::validate)?;
        check(
            &self.encoder_missed_counts,
            "encoder_missed_counts",
            EncoderMissedCounts::validate,
        )?;
        check(
            &self.encoder_glitches,
            "encoder_glitches",
            EncoderGlitches::validate,
        )?;
        check(&self.battery_sag, "battery_sag", BatterySag::validate)?;
        check(&self.backlash, "backlash", Backlash::validate)?;
        check(&self.toe, "toe", Toe::validate)?;
        Ok(())
    }
}

/// `prefix.name`.
pub(crate) fn key(prefix: &str, name: &str) -> String {
    format!("{prefix}.{name}")
}

#[cfg(test)]
pub(crate) mod test_support {
    //! Driving the plant in the signature tests.

    use crate::side::Side;
    use crate::{units::Seconds, Duty};
    use crate::{Robot, RobotConfig};

    /// The nominal robot with the right motor on both sides (both wheels behave alike), with
    /// `set` applied to its config.
    pub fn symmetric(set: impl FnOnce(&mut RobotConfig)) -> RobotConfig {
        let mut config = RobotConfig::default();
        config.motor.left = config.motor.right.clone();
        set(&mut config);
        config
    }

    /// A signed drive: positive forward on `in1`, negative reverse on `in2`.
    pub fn signed(d: f64) -> (Duty, Duty) {
        let duty = Duty::new(d.abs()).expect("test duty in [-1, 1]");
        if d >= 0.0 {
            (duty, Duty::OFF)
        } else {
            (Duty::OFF, duty)
        }
    }

    /// Sets both bridges from signed drives.
    pub fn drive(robot: &mut Robot, left: f64, right: f64) {
        let (a, b) = signed(left);
        robot.set_bridge(Side::Left, a, b);
        let (a, b) = signed(right);
        robot.set_bridge(Side::Right, a, b);
    }

    /// Drives both wheels with `left`, `right` for `on` seconds, then lets them coast for
    /// `coast` seconds; returns the robot.
    pub fn run(
        config: &RobotConfig,
        seed: u64,
        left: f64,
        right: f64,
        on: f64,
        coast: f64,
    ) -> Robot {
        let mut robot = Robot::new(config, seed).expect("valid test config");
        drive(&mut robot, left, right);
        robot.advance_to(Seconds(on)).unwrap();
        drive(&mut robot, 0.0, 0.0);
        robot.advance_to(Seconds(on + coast)).unwrap();
        robot
    }
}
