//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::PathBuf;

pub mod thesis;

use plant_model::{Duty, RobotConfig};

/// A file under the repository's `fixtures/` folder.
pub fn fixture(relative: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join("fixtures")
        .join(relative)
}

/// A duty from a fraction known to be valid.
pub fn duty(fraction: f64) -> Duty {
    Duty::new(fraction).expect("test duty in [0, 1]")
}

/// The nominal robot with the right motor on both sides, so both wheels behave identically.
pub fn symmetric_config() -> RobotConfig {
    let mut config = RobotConfig::default();
    config.motor.left = config.motor.right.clone();
    config
}

/// One table per effect, every key set (the optional ones too): appended to the ideal
/// robot's file it switches every effect on.
pub const ALL_EFFECTS: &str = r#"
[effects.wheel_diameter_ratio]
right_over_left_ratio = 1.02
[effects.wheelbase_ratio]
actual_over_nominal_ratio = 0.97
[effects.distance_scale]
odometry_over_actual_ratio = 1.01
[effects.dead_band]
extra_left_duty = 0.02
extra_right_duty = 0.0
[effects.motor_gain_asymmetry]
left_gain_ratio = 0.98
right_gain_ratio = 1.0
[effects.coast]
left_tau_s = 0.12
right_tau_s = 0.15
[effects.turn_slip]
fraction = 0.02
[effects.straight_slip]
left_fraction = 0.01
right_fraction = 0.0
[effects.floor_noise]
heading_deg_per_sqrt_m = 0.5
lateral_mm_per_sqrt_m = 2.0
turn_heading_deg_per_sqrt_m = 3.0
stretch_mm = 25.0
[effects.castor_drag]
force_n = 0.2
lateral_offset_mm = 5.0
wheel_stall_torque_nm = 0.11
[effects.encoder_missed_counts]
left_fraction = 0.001
right_fraction = 0.0
[effects.encoder_glitches]
left_fraction = 0.01
right_fraction = 0.01
width_motor_deg = 0.5
[effects.battery_sag]
open_circuit_full_v = 8.4
open_circuit_empty_v = 6.6
capacity_mah = 1000.0
initial_charge_fraction = 0.8
internal_resistance_ohm = 0.2
motor_resistance_ohm = 10.0
idle_current_a = 0.15
update_interval_s = 0.05
[effects.backlash]
left_wheel_deg = 1.0
right_wheel_deg = 1.5
[effects.toe]
left_deg = 1.0
right_deg = -0.5
"#;

/// The ideal robot with every effect of [`ALL_EFFECTS`] on.
pub fn all_effects_config() -> RobotConfig {
    let text = std::fs::read_to_string(fixture("robots/henrytwo-ideal.toml")).unwrap();
    RobotConfig::from_toml_str(&format!("{text}\n{ALL_EFFECTS}")).unwrap()
}
