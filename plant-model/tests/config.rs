//! The robot config: the nominal fixture is the default robot, and every kind of mistake in a
//! config file is refused with an error that names the key.

mod common;

use plant_model::{Error, RobotConfig};
use rstest::rstest;

fn fixture_text() -> String {
    std::fs::read_to_string(common::fixture("robots/henrytwo-ideal.toml")).unwrap()
}

/// `fixtures/robots/henrytwo-ideal.toml` loads, validates and equals `RobotConfig::default()`.
#[test]
fn ideal_fixture_is_the_default_robot() {
    let loaded = RobotConfig::load(common::fixture("robots/henrytwo-ideal.toml")).unwrap();
    assert_eq!(loaded, RobotConfig::default());
}

/// The optional keys default as documented: coast = tau, brake = tau / 3, encoders forward.
#[test]
fn optional_keys_take_their_documented_defaults() {
    let config = RobotConfig::default();
    let plant_model::MotorModel::FirstOrder(left) = &config.motor.left;
    assert_eq!(left.coast_tau().0, 0.055);
    assert_eq!(left.brake_tau().0, 0.055 / 3.0);
    let text = fixture_text().replacen("# brake_tau_s = 0.018333", "brake_tau_s = 0.01", 1);
    let config = RobotConfig::from_toml_str(&text).unwrap();
    let plant_model::MotorModel::FirstOrder(left) = &config.motor.left;
    assert_eq!(left.brake_tau().0, 0.01);
    assert!(!config.encoder.reversed_left && !config.encoder.reversed_right);
}

/// Which error a one-line change of the fixture gives, and that the message names the key.
#[derive(Debug)]
enum Expect {
    Parse,
    NotFinite,
    DutyOutOfRange,
    DeadBand,
    OutOfRange,
    Conflict,
    Unphysical,
}

#[rstest]
#[case::unknown_key(
    "wheelbase_mm = 130.0",
    "wheelbase_mm = 130.0\nwheel_radius_mm = 16.0",
    Expect::Parse,
    "wheel_radius_mm"
)]
#[case::unknown_key_in_motor(
    "tau_s = 0.0685",
    "tau_s = 0.0685\ntau_ms = 68.5",
    Expect::Parse,
    "tau_ms"
)]
#[case::unknown_section("[battery]", "[batery]", Expect::Parse, "batery")]
#[case::unknown_model(
    "model = \"first_order\"",
    "model = \"second_order\"",
    Expect::Parse,
    "second_order"
)]
#[case::missing_key("wheelbase_mm = 130.0", "", Expect::Parse, "wheelbase_mm")]
#[case::wrong_type("voltage_v = 7.4", "voltage_v = \"7.4\"", Expect::Parse, "voltage_v")]
#[case::negative_length(
    "wheelbase_mm = 130.0",
    "wheelbase_mm = -130.0",
    Expect::Unphysical,
    "geometry.wheelbase_mm"
)]
#[case::zero_diameter(
    "wheel_diameter_right_mm = 32.0",
    "wheel_diameter_right_mm = 0.0",
    Expect::Unphysical,
    "geometry.wheel_diameter_right_mm"
)]
#[case::nan_length(
    "wheel_diameter_left_mm = 32.0",
    "wheel_diameter_left_mm = nan",
    Expect::Unphysical,
    "geometry.wheel_diameter_left_mm"
)]
#[case::infinite_tau("tau_s = 0.055", "tau_s = inf", Expect::Unphysical, "motor.left.tau_s")]
#[case::negative_tau(
    "tau_s = 0.0685",
    "tau_s = -0.0685",
    Expect::Unphysical,
    "motor.right.tau_s"
)]
#[case::zero_edges(
    "a_edges_per_motor_rev = 6",
    "a_edges_per_motor_rev = 0",
    Expect::Unphysical,
    "encoder.a_edges_per_motor_rev"
)]
#[case::zero_battery(
    "voltage_v = 7.4",
    "voltage_v = 0.0",
    Expect::Unphysical,
    "battery.voltage_v"
)]
#[case::duty_above_one(
    "dead_band_duty = 0.5068",
    "dead_band_duty = 1.5",
    Expect::DutyOutOfRange,
    "motor.right.dead_band_duty"
)]
#[case::negative_duty(
    "dead_band_duty = 0.5796",
    "dead_band_duty = -0.1",
    Expect::DutyOutOfRange,
    "motor.left.dead_band_duty"
)]
#[case::dead_band_above_reference(
    "dead_band_duty = 0.5796",
    "dead_band_duty = 0.9",
    Expect::DeadBand,
    "motor.left.dead_band_duty"
)]
#[case::negative_brake_tau(
    "# brake_tau_s = 0.018333",
    "brake_tau_s = -1.0",
    Expect::Unphysical,
    "motor.left.brake_tau_s"
)]
#[case::battery_megavolt(
    "voltage_v = 7.4",
    "voltage_v = 1e6",
    Expect::Unphysical,
    "battery.voltage_v"
)]
#[case::battery_1e300("voltage_v = 7.4", "voltage_v = 1e300", Expect::Unphysical, "1e300")]
#[case::gear_micro(
    "gear_ratio = 100.37",
    "gear_ratio = 1e-6",
    Expect::Unphysical,
    "encoder.gear_ratio"
)]
#[case::gear_giga(
    "gear_ratio = 100.37",
    "gear_ratio = 1e9",
    Expect::Unphysical,
    "give 1 to 1000"
)]
#[case::wheelbase_nanometre(
    "wheelbase_mm = 130.0",
    "wheelbase_mm = 1e-9",
    Expect::Unphysical,
    "give 20 to 2000 mm"
)]
#[case::tau_picosecond(
    "tau_s = 0.055",
    "tau_s = 1e-12",
    Expect::Unphysical,
    "motor.left.tau_s = 1e-12: give 1e-5 to 10 s"
)]
#[case::nan_fit_voltage(
    "fit_voltage_v = 7.4",
    "fit_voltage_v = nan",
    Expect::Unphysical,
    "motor.left.fit_voltage_v = NaN: give 1 to 60 V"
)]
#[case::inf_gain(
    "gain_thesis_rpm = 25.0",
    "gain_thesis_rpm = inf",
    Expect::Unphysical,
    "motor.right.gain_thesis_rpm = inf"
)]
#[case::edges_beyond_any_encoder(
    "a_edges_per_motor_rev = 6",
    "a_edges_per_motor_rev = 4000000000",
    Expect::Unphysical,
    "give 1 to 10000"
)]
fn bad_config_is_refused_naming_the_key(
    #[case] find: &str,
    #[case] replace: &str,
    #[case] expect: Expect,
    #[case] key: &str,
) {
    let original = fixture_text();
    assert!(original.contains(find), "fixture has `{find}`");
    let text = original.replacen(find, replace, 1);
    let err = RobotConfig::from_toml_str(&text).unwrap_err();
    let matches = match expect {
        Expect::Parse => matches!(err, Error::ParseConfig(_)),
        Expect::NotFinite => matches!(err, Error::NotFinite { .. }),
        Expect::DutyOutOfRange => matches!(err, Error::DutyOutOfRange { .. }),
        Expect::DeadBand => matches!(err, Error::DeadBandNotBelowReference { .. }),
        Expect::Unphysical => matches!(err, Error::Unphysical { .. }),
        _ => false,
    };
    assert!(matches, "expected {expect:?}, got {err:?}");
    let message = err.to_string();
    assert!(message.contains(key), "message names `{key}`: {message}");
}

/// Every effect table parses, validates and round-trips through TOML; an empty `effects`
/// serialises to nothing, so the ideal robot's file has no `[effects]` at all.
#[test]
fn every_effect_round_trips() {
    let text = format!("{}\n{}", fixture_text(), common::ALL_EFFECTS);
    let config = RobotConfig::from_toml_str(&text).unwrap();
    assert_eq!(
        config.effects.enabled(),
        plant_model::Effects::NAMES.to_vec()
    );
    let again = RobotConfig::from_toml_str(&toml::to_string(&config).unwrap()).unwrap();
    assert_eq!(again, config);
    assert!(!toml::to_string(&RobotConfig::default())
        .unwrap()
        .contains("effects"));
}

/// Mistakes in effect tables are refused with an error that names the key.
#[rstest]
#[case::unknown_effect(
    "[effects.turn_slip]\nfraction = 0.02",
    "[effects.turn_slipp]\nfraction = 0.02",
    Expect::Parse,
    "turn_slipp"
)]
#[case::key_without_unit("left_tau_s = 0.12", "left_tau = 0.12", Expect::Parse, "left_tau")]
#[case::missing_key("right_tau_s = 0.15\n", "", Expect::Parse, "right_tau_s")]
#[case::negative_length(
    "stretch_mm = 25.0",
    "stretch_mm = -25.0",
    Expect::Unphysical,
    "effects.floor_noise.stretch_mm"
)]
#[case::negative_sigma(
    "heading_deg_per_sqrt_m = 0.5",
    "heading_deg_per_sqrt_m = -0.5",
    Expect::Unphysical,
    "effects.floor_noise.heading_deg_per_sqrt_m"
)]
#[case::percentage_for_ratio(
    "right_over_left_ratio = 1.02",
    "right_over_left_ratio = 102.0",
    Expect::OutOfRange,
    "effects.wheel_diameter_ratio.right_over_left_ratio"
)]
#[case::fraction_above_one(
    "fraction = 0.02",
    "fraction = 1.5",
    Expect::OutOfRange,
    "effects.turn_slip.fraction"
)]
#[case::empty_above_full(
    "open_circuit_empty_v = 6.6",
    "open_circuit_empty_v = 9.0",
    Expect::OutOfRange,
    "effects.battery_sag.open_circuit_empty_v"
)]
#[case::nan_toe(
    "left_deg = 1.0",
    "left_deg = nan",
    Expect::NotFinite,
    "effects.toe.left_deg"
)]
#[case::glitch_wider_than_half_a_state(
    "width_motor_deg = 0.5",
    "width_motor_deg = 20.0",
    Expect::OutOfRange,
    "effects.encoder_glitches.width_motor_deg"
)]
#[case::coast_set_twice(
    "# coast_tau_s = 0.055",
    "coast_tau_s = 0.055",
    Expect::Conflict,
    "effects.coast.left_tau_s"
)]
#[case::coast_picosecond(
    "left_tau_s = 0.12",
    "left_tau_s = 1e-12",
    Expect::Unphysical,
    "effects.coast.left_tau_s = 1e-12: give 1e-5 to 10 s"
)]
#[case::sag_megavolt(
    "open_circuit_full_v = 8.4",
    "open_circuit_full_v = 1e6",
    Expect::Unphysical,
    "effects.battery_sag.open_circuit_full_v"
)]
#[case::castor_huge_force(
    "force_n = 0.2",
    "force_n = 1e300",
    Expect::Unphysical,
    "effects.castor_drag.force_n"
)]
#[case::backlash_past_a_quarter_turn(
    "right_wheel_deg = 1.5",
    "right_wheel_deg = 120.0",
    Expect::OutOfRange,
    "effects.backlash.right_wheel_deg"
)]
#[case::dead_band_above_full_duty(
    "extra_left_duty = 0.02",
    "extra_left_duty = 1.2",
    Expect::OutOfRange,
    "effects.dead_band.extra_left_duty"
)]
#[case::gain_percentage_for_ratio(
    "left_gain_ratio = 0.98",
    "left_gain_ratio = 98.0",
    Expect::OutOfRange,
    "effects.motor_gain_asymmetry.left_gain_ratio"
)]
#[case::straight_slip_negative(
    "left_fraction = 0.01",
    "left_fraction = -0.01",
    Expect::OutOfRange,
    "effects.straight_slip.left_fraction"
)]
#[case::missed_counts_above_all(
    "left_fraction = 0.001",
    "left_fraction = 1.001",
    Expect::OutOfRange,
    "effects.encoder_missed_counts.left_fraction"
)]
fn bad_effect_is_refused_naming_the_key(
    #[case] find: &str,
    #[case] replace: &str,
    #[case] expect: Expect,
    #[case] key: &str,
) {
    let original = format!("{}\n{}", fixture_text(), common::ALL_EFFECTS);
    assert!(original.contains(find), "config has `{find}`");
    let text = original.replacen(find, replace, 1);
    let err = RobotConfig::from_toml_str(&text).unwrap_err();
    let matches = match expect {
        Expect::Parse => matches!(err, Error::ParseConfig(_)),
        Expect::NotFinite => matches!(err, Error::NotFinite { .. }),
        Expect::OutOfRange => matches!(err, Error::OutOfRange { .. }),
        Expect::Conflict => matches!(err, Error::Conflict { .. }),
        Expect::Unphysical => matches!(err, Error::Unphysical { .. }),
        _ => false,
    };
    assert!(matches, "expected {expect:?}, got {err:?}");
    let message = err.to_string();
    assert!(message.contains(key), "message names `{key}`: {message}");
}

/// A config file's error names the file, the key, the value and the range, on one line.
#[test]
fn a_file_error_names_the_file_the_key_and_the_range() {
    let dir = std::env::temp_dir().join(format!("plant-config-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("x.toml");
    std::fs::write(
        &path,
        fixture_text().replacen("tau_s = 0.055", "tau_s = 1e-12", 1),
    )
    .unwrap();
    let message = RobotConfig::load(&path).unwrap_err().to_string();
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(
        message.starts_with(&format!(
            "{}: motor.left.tau_s = 1e-12: give 1e-5 to 10 s",
            path.display()
        )),
        "{message}"
    );
    assert_eq!(message.lines().count(), 1, "{message}");
}

/// Every robot of fixtures/robots/ is inside the ranges.
#[test]
fn every_fixture_robot_is_in_range() {
    let dir = common::fixture("robots");
    let mut n = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            RobotConfig::load(&path).unwrap_or_else(|e| panic!("{e}"));
            n += 1;
        }
    }
    assert!(n >= 6, "{n} robots");
}
