//! The robot config's `[firmware]` table: the robust firmware's settings
//! for this robot (PID gains per wheel, speed set-points, the stall
//! watchdog's thresholds), by their protocol names, sent before each run
//! after the geometry (see [`super::params::plan`]) and before any
//! `--param`, so that a `--param` of the same name wins.
//!
//! Only what the firmware takes over the protocol and no other input of
//! the bench gives: the geometry comes from `[geometry]` and `[encoder]`,
//! the driver's wiring from the board, the leg from `--leg-mm`, the turn
//! angles from the test. Each value is checked against the firmware's own
//! range (`henrytwo_protocol::limits`) when the config is loaded.

use henrytwo_protocol::Param;
use plant_model::RobotConfig;

/// The parameters a `[firmware]` table may set, in the order they are sent.
pub const SETTABLE: [Param; 10] = [
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
];

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
}

fn names() -> String {
    SETTABLE.map(|p| p.name()).join(", ")
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
    SETTABLE
        .into_iter()
        .filter_map(|p| robot.firmware.get(p.name()).map(|&v| (p, v)))
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
        assert!(of(&robot(&[("setpoint_left", 41.0)])).is_err());
        assert!(of(&robot(&[("setpoint_left", 40.0)])).is_ok());
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
