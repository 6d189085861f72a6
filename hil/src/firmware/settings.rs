//! The robot config's `[firmware]` table: the robust firmware's settings
//! for this robot (PID gains per wheel, speed set-points, the stall
//! watchdog's thresholds), by their protocol names, sent before each run
//! after the geometry (see [`super::params::plan`]) and before any
//! `--param`, so that a `--param` of the same name wins.
//!
//! The set-point may instead be a wheel ground speed, `setpoint_mm_s`
//! (both wheels), converted to the protocol's thesis "RPM" (wheel RPM / 6)
//! from each wheel's diameter. Either way it must stay below the wheel's
//! top speed on its motor model (full duty at the battery's voltage).
//!
//! Only what the firmware takes over the protocol and no other input of
//! the bench gives: the geometry comes from `[geometry]` and `[encoder]`,
//! the driver's wiring from the board, the leg from `--leg-mm`, the turn
//! angles from the test. Each value is checked against the firmware's own
//! range (`henrytwo_protocol::limits`) when the config is loaded.

use henrytwo_protocol::Param;
use plant_model::RobotConfig;

/// The parameters a `[firmware]` table may set, in the order they are sent.
pub const SETTABLE: [Param; 15] = [
    Param::KpLeft,
    Param::KiLeft,
    Param::KdLeft,
    Param::KpRight,
    Param::KiRight,
    Param::KdRight,
    Param::SetpointLeft,
    Param::SetpointRight,
    Param::StallTimeoutMs,
    Param::StallDuty,
    Param::BrakeCoastMs,
    Param::BrakePulseMs,
    Param::StopLeadMs,
    Param::StallProgressCounts,
    Param::WrongWayCounts,
];

/// The set-point as a wheel ground speed, mm/s, for both wheels.
pub const SETPOINT_MM_S: &str = "setpoint_mm_s";

/// Thesis "RPM" of a wheel of `diameter_mm` at `mm_s` on the ground.
pub fn thesis_rpm_of_mm_s(mm_s: f64, diameter_mm: f64) -> f64 {
    mm_s / (std::f64::consts::PI * diameter_mm) * 60.0 / 6.0
}

/// The set-point of wheel `i` (0 left, 1 right), thesis "RPM": the config's
/// `setpoint_left`/`setpoint_right`, else its `setpoint_mm_s`, else the
/// factory one.
pub fn setpoint_thesis_rpm(robot: &RobotConfig, i: usize) -> f64 {
    let (p, d) = if i == 0 {
        (Param::SetpointLeft, robot.geometry.wheel_diameter_left_mm)
    } else {
        (Param::SetpointRight, robot.geometry.wheel_diameter_right_mm)
    };
    if let Some(&v) = robot.firmware.get(p.name()) {
        return v;
    }
    if let Some(&v) = robot.firmware.get(SETPOINT_MM_S) {
        return thesis_rpm_of_mm_s(v, d);
    }
    p.factory_default() as f64
}

/// Wheel `i`'s top speed on its motor model, thesis "RPM": full duty at
/// the battery's voltage.
pub fn top_thesis_rpm(robot: &RobotConfig, i: usize) -> f64 {
    let m = if i == 0 {
        &robot.motor.left
    } else {
        &robot.motor.right
    };
    let plant_model::MotorModel::FirstOrder(m) = m;
    full_duty_thesis_rpm(m, robot.battery.voltage_v)
}

/// A first-order motor's steady speed at full duty on `volts`, thesis "RPM"
/// (the plant's `steady_speed` at duty 1, in the firmware's unit).
pub fn full_duty_thesis_rpm(m: &plant_model::FirstOrderMotor, volts: f64) -> f64 {
    m.gain_thesis_rpm * (1.0 - m.dead_band_duty) / (m.reference_duty - m.dead_band_duty) * volts
        / m.fit_voltage_v
}

/// A `[firmware]` key the firmware does not take from a robot config, or a
/// value outside its range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SettingsError {
    #[error("[firmware] {key}: {why}; a robot config sets {}", names())]
    Unknown { key: String, why: &'static str },
    #[error("[firmware] {key} = {value}: outside what the robust firmware accepts, {range}")]
    OutOfRange {
        key: &'static str,
        value: f64,
        range: String,
    },
    #[error(
        "[firmware] {key} = {value}: {side} wheel faster than its motor can turn it; \
         allowed {min} to {max:.1} {unit} (full duty at {volts} V on the motor model)"
    )]
    AboveMotor {
        key: &'static str,
        value: f64,
        side: &'static str,
        min: f64,
        max: f64,
        unit: &'static str,
        volts: f64,
    },
    #[error(
        "[firmware] {SETPOINT_MM_S} and {key} both set the {side} wheel's set-point; give one"
    )]
    Twice {
        key: &'static str,
        side: &'static str,
    },
}

fn names() -> String {
    let mut n: Vec<&str> = SETTABLE.map(|p| p.name()).to_vec();
    n.push(SETPOINT_MM_S);
    n.join(", ")
}

/// Why a parameter of the protocol is not a `[firmware]` key.
fn elsewhere(p: Param) -> &'static str {
    match p {
        Param::MmPerCountLeft
        | Param::MmPerCountRight
        | Param::CountsPerWheelRev
        | Param::WheelbaseMm => "the bench tells the firmware this from [geometry] and [encoder]",
        Param::LegLengthMm => "the leg is the test's, given with --leg-mm",
        Param::TurnUmbmarkDeg | Param::TurnTriangleDeg => {
            "the turn angle is the test's, which the bench judges the run by"
        }
        Param::CorrLeft | Param::CorrRight => {
            "the correction factors are calibration's (hil calibrate), given with --param"
        }
        _ => "the bench tells the firmware its driver's wiring from the board",
    }
}

/// `robot`'s `[firmware]` settings as parameters in [`SETTABLE`]'s order,
/// each checked against the firmware's range.
pub fn of(robot: &RobotConfig) -> Result<Vec<(Param, f32)>, SettingsError> {
    for key in robot.firmware.keys() {
        if key == SETPOINT_MM_S {
            continue;
        }
        if let Some(p) = Param::ALL.into_iter().find(|p| p.name() == key) {
            if !SETTABLE.contains(&p) {
                return Err(SettingsError::Unknown {
                    key: key.clone(),
                    why: elsewhere(p),
                });
            }
        } else {
            return Err(SettingsError::Unknown {
                key: key.clone(),
                why: "no setting of the robust firmware",
            });
        }
    }
    let mut given: Vec<(Param, f64)> = SETTABLE
        .into_iter()
        .filter_map(|p| robot.firmware.get(p.name()).map(|&v| (p, v)))
        .collect();
    if let Some(&mm_s) = robot.firmware.get(SETPOINT_MM_S) {
        for (i, p, side) in [
            (0, Param::SetpointLeft, "left"),
            (1, Param::SetpointRight, "right"),
        ] {
            if robot.firmware.contains_key(p.name()) {
                return Err(SettingsError::Twice {
                    key: p.name(),
                    side,
                });
            }
            let d = if i == 0 {
                robot.geometry.wheel_diameter_left_mm
            } else {
                robot.geometry.wheel_diameter_right_mm
            };
            let top = top_thesis_rpm(robot, i);
            let rpm = thesis_rpm_of_mm_s(mm_s, d);
            let lowest = p.range().min as f64;
            if !(rpm >= lowest && rpm <= top) {
                let per = std::f64::consts::PI * d * 6.0 / 60.0;
                return Err(SettingsError::AboveMotor {
                    key: SETPOINT_MM_S,
                    value: mm_s,
                    side,
                    min: (lowest * per * 10.0).ceil() / 10.0,
                    max: top * per,
                    unit: "mm/s",
                    volts: robot.battery.voltage_v,
                });
            }
            given.push((p, rpm));
        }
        given.sort_by_key(|(p, _)| SETTABLE.iter().position(|q| q == p));
    }
    for (i, p, side) in [
        (0, Param::SetpointLeft, "left"),
        (1, Param::SetpointRight, "right"),
    ] {
        if let Some(&v) = robot.firmware.get(p.name()) {
            let top = top_thesis_rpm(robot, i);
            if v.is_finite() && v > top && p.check(v as f32).is_ok() {
                return Err(SettingsError::AboveMotor {
                    key: p.name(),
                    value: v,
                    side,
                    min: p.range().min as f64,
                    max: top,
                    unit: "thesis RPM",
                    volts: robot.battery.voltage_v,
                });
            }
        }
    }
    given
        .into_iter()
        .map(|(p, v)| {
            let r = p.range();
            p.check(v as f32)
                .ok()
                .filter(|_| v.is_finite())
                .map(|sent| (p, sent))
                .ok_or_else(|| SettingsError::OutOfRange {
                    key: p.name(),
                    value: v,
                    range: format!(
                        "{} to {}{}",
                        r.min,
                        r.max,
                        if r.integer { ", whole numbers" } else { "" }
                    ),
                })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn robot(pairs: &[(&str, f64)]) -> RobotConfig {
        RobotConfig {
            firmware: pairs.iter().map(|&(k, v)| (k.to_string(), v)).collect(),
            ..Default::default()
        }
    }

    #[test]
    fn settings_are_sent_in_their_order() {
        let r = robot(&[("stall_duty", 120.0), ("kp_left", 1.0), ("kp_right", 1.5)]);
        assert_eq!(
            of(&r),
            Ok(vec![
                (Param::KpLeft, 1.0),
                (Param::KpRight, 1.5),
                (Param::StallDuty, 120.0)
            ])
        );
        assert_eq!(of(&RobotConfig::default()), Ok(vec![]));
    }

    #[test]
    fn a_value_outside_the_firmware_range_names_key_and_range() {
        let e = of(&robot(&[("kp_left", 101.0)])).unwrap_err();
        assert_eq!(
            e.to_string(),
            "[firmware] kp_left = 101: outside what the robust firmware accepts, 0 to 100"
        );
        let e = of(&robot(&[("stall_duty", 10.5)])).unwrap_err();
        assert!(e.to_string().ends_with("1 to 255, whole numbers"), "{e}");
        assert!(of(&robot(&[("brake_pulse_ms", 201.0)])).is_err());
        assert!(of(&robot(&[("stop_lead_ms", 150.0)])).is_ok());
    }

    /// The set-point's ceiling is the motor's top speed, not the thesis' 40.
    #[test]
    fn the_setpoint_is_capped_by_the_motor() {
        let r = RobotConfig::default();
        let top = top_thesis_rpm(&r, 0).min(top_thesis_rpm(&r, 1));
        assert!(of(&robot(&[("setpoint_left", top - 0.1)])).is_ok());
        let e = of(&robot(&[("setpoint_left", top + 0.1)])).unwrap_err();
        assert!(
            e.to_string().starts_with("[firmware] setpoint_left = "),
            "{e}"
        );
        assert!(e.to_string().contains("faster than its motor"), "{e}");
        // A fast robot's set-point beyond the thesis' 40 is taken.
        let mut fast = robot(&[("setpoint_left", 60.0)]);
        fast.battery.voltage_v *= 3.0;
        assert!(of(&fast).is_ok());
    }

    /// `setpoint_mm_s` is both wheels' set-point from their diameters.
    #[test]
    fn a_setpoint_in_mm_s_is_converted_from_the_wheel_diameter() {
        let r = robot(&[("setpoint_mm_s", 24.0)]);
        let sent = of(&r).unwrap();
        // 24 mm/s on a 32 mm wheel: 14.32 wheel RPM, 2.387 thesis RPM.
        let expected = (24.0 / (std::f64::consts::PI * 32.0) * 10.0) as f32;
        assert_eq!(
            sent,
            vec![
                (Param::SetpointLeft, expected),
                (Param::SetpointRight, expected)
            ]
        );
        assert!((setpoint_thesis_rpm(&r, 0) - 2.387).abs() < 1e-3);
        let e = of(&robot(&[("setpoint_mm_s", 1000.0)])).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("[firmware] setpoint_mm_s = 1000: left wheel faster"),
            "{e}"
        );
        assert!(of(&robot(&[("setpoint_mm_s", 24.0), ("setpoint_right", 14.0)])).is_err());
    }

    #[test]
    fn keys_the_bench_gives_otherwise_are_refused_with_why() {
        let e = of(&robot(&[("wheelbase_mm", 150.0)])).unwrap_err();
        assert!(e.to_string().contains("[geometry]"), "{e}");
        let e = of(&robot(&[("kp_lefft", 1.0)])).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("[firmware] kp_lefft: no setting of the robust firmware; a robot config sets kp_left, ki_left"),
            "{e}"
        );
    }
}
