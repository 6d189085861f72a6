//! Random robot configs, absurd numbers included (nan, inf, huge, tiny, negative, zero), either
//! load into a config the plant runs with, or are refused with one error line; never a panic.

mod common;

use plant_model::{Duty, Robot, RobotConfig, Seconds, Side};
use proptest::prelude::*;

/// The ideal robot with every effect on: every numeric key of the config appears once.
fn base_text() -> String {
    let ideal = std::fs::read_to_string(common::fixture("robots/henrytwo-ideal.toml")).unwrap();
    format!("{ideal}\n{}", common::ALL_EFFECTS)
}

/// The lines of `text` that set a number: (line index, key, value, whether it is a whole
/// number).
fn numeric_lines(text: &str) -> Vec<(usize, String, f64, bool)> {
    text.lines()
        .enumerate()
        .filter_map(|(i, line)| {
            let (key, rest) = line.split_once(" = ")?;
            let key = key.trim();
            let value = rest.split('#').next()?.trim();
            value
                .parse::<f64>()
                .ok()
                .map(|v| (i, key.to_owned(), v, !value.contains(['.', 'e'])))
        })
        .collect()
}

/// A value for a key whose fixture value is `original`: ordinary ones around it (within a
/// factor of 2, so most stay in range), and the absurd ones.
fn value(original: f64, whole: bool) -> BoxedStrategy<String> {
    if whole {
        prop_oneof![
            (1u32..20).prop_map(|v| v.to_string()),
            Just("0".to_owned()),
            Just("10000".to_owned()),
            Just("10001".to_owned()),
            Just("4294967295".to_owned()),
            Just("4294967296".to_owned()),
            Just("-1".to_owned()),
            Just("6.5".to_owned()),
        ]
        .boxed()
    } else {
        prop_oneof![
            4 => (0.5f64..2.0).prop_map(move |f| format!("{:e}", original * f)),
            1 => (-3.0f64..3.0).prop_map(|e| format!("{:e}", 10f64.powf(e))),
            1 => (-3.0f64..3.0).prop_map(|e| format!("{:e}", -(10f64.powf(e)))),
            1 => prop_oneof![
                Just("nan"),
                Just("inf"),
                Just("-inf"),
                Just("1e300"),
                Just("-1e300"),
                Just("1e-300"),
                Just("0.0"),
                Just("-0.0"),
                Just("1e6"),
                Just("1e9"),
                Just("1e-6"),
                Just("1e-9"),
                Just("1e-12"),
            ]
            .prop_map(str::to_owned),
        ]
        .boxed()
    }
}

/// The base text with some numbers replaced.
fn config_text() -> impl Strategy<Value = String> {
    let text = base_text();
    let keys = numeric_lines(&text);
    let changes: Vec<_> = keys
        .iter()
        .map(|(_, _, original, whole)| proptest::option::weighted(0.05, value(*original, *whole)))
        .collect();
    changes.prop_map(move |values| {
        let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
        for ((i, key, _, _), v) in keys.iter().zip(values) {
            if let Some(v) = v {
                lines[*i] = format!("{key} = {v}");
            }
        }
        lines.join("\n")
    })
}

/// A short drive of the plant alone: forward, a spin, coasting, and encoder transitions
/// stepped one by one; every number it reports stays finite and time moves forward.
fn runs_on_its_own(config: &RobotConfig) {
    let mut robot = Robot::new(config, 7).expect("a config that validates builds a robot");
    let full = Duty::new(1.0).unwrap();
    for (left, right, until) in [
        ((full, Duty::OFF), (full, Duty::OFF), 0.3),
        ((full, Duty::OFF), (Duty::OFF, full), 0.5),
        ((Duty::OFF, Duty::OFF), (Duty::OFF, Duty::OFF), 0.8),
    ] {
        robot.set_bridge(Side::Left, left.0, left.1);
        robot.set_bridge(Side::Right, right.0, right.1);
        let now = robot.now();
        for _ in 0..50 {
            let Some(t) = robot.next_encoder_transition(Side::Left) else {
                break;
            };
            assert!(
                t.0 > now.0 && t.0.is_finite(),
                "transition at {t:?} after {now:?}"
            );
            if t.0 >= until {
                break;
            }
            robot.advance_to(t).unwrap();
        }
        robot.advance_to(Seconds(until)).unwrap();
        let pose = robot.pose();
        assert!(
            pose.x().0.is_finite() && pose.y().0.is_finite() && pose.theta().0.is_finite(),
            "{pose:?}"
        );
        for side in Side::BOTH {
            assert!(robot.wheel_speed(side).0.is_finite());
            assert!(robot.battery_voltage().0.is_finite());
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    #[test]
    fn a_config_loads_and_runs_or_is_refused_in_one_line(text in config_text()) {
        match RobotConfig::from_toml_str(&text) {
            Ok(config) => runs_on_its_own(&config),
            Err(e) => {
                let message = e.to_string();
                prop_assert_eq!(message.lines().count(), 1, "{}", message);
            }
        }
    }
}

/// The unchanged base loads and runs (the property's ordinary case).
#[test]
fn the_base_config_runs() {
    runs_on_its_own(&RobotConfig::from_toml_str(&base_text()).unwrap());
}

/// The corners of the ranges (every combination of the smallest and largest wheel, wheelbase,
/// gear ratio, encoder, voltage, gain and time constant) load and run: the ranges admit no
/// robot the plant cannot step.
#[test]
fn the_corners_of_the_ranges_run() {
    let corners: [(&str, [&str; 2]); 7] = [
        ("wheel_diameter_left_mm = 32.0", ["5.0", "500.0"]),
        ("wheelbase_mm = 130.0", ["20.0", "2000.0"]),
        ("gear_ratio = 100.37", ["1.0", "1000.0"]),
        ("a_edges_per_motor_rev = 6", ["1", "10000"]),
        ("voltage_v = 7.4", ["1.0", "60.0"]),
        ("gain_thesis_rpm = 22.0", ["0.1", "2000.0"]),
        ("tau_s = 0.055", ["1e-5", "10.0"]),
    ];
    // Without the effects: the glitch width is relative to the encoder's states.
    let base = std::fs::read_to_string(common::fixture("robots/henrytwo-ideal.toml")).unwrap();
    for bits in 0..1u32 << corners.len() {
        let mut text = base.clone();
        for (k, (find, values)) in corners.iter().enumerate() {
            let key = find.split(" = ").next().unwrap();
            let v = values[(bits >> k & 1) as usize];
            assert!(text.contains(find), "{find}");
            text = text.replacen(find, &format!("{key} = {v}"), 1);
        }
        let config = RobotConfig::from_toml_str(&text)
            .unwrap_or_else(|e| panic!("corner {bits:07b} refused: {e}"));
        runs_on_its_own(&config);
    }
}
