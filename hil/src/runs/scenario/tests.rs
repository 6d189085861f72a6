//! The loader's checks: the documented layout, the fixtures, one error line per mistake.

use std::path::Path;

use super::*;
use crate::bench::{Action, Trigger};
use crate::runs::experiment::Test;
use plant_model::Side;

const EXAMPLE: &str = r#"
name = "example"
test = "umbmark-cw"

[[fault]]
trigger = { at = "time", s = 3.0 }
action = { action = "encoder", side = "left", fault = { kind = "dropout" } }

[[fault]]
trigger = { at = "turn_start", n = 3 }
action = { action = "slip_burst", side = "left", slip = 0.3 }
duration_s = 1.5

[[fault]]
trigger = { at = "host_byte", n = 2 }
action = { action = "link", fault = { loss = 1.0 } }
duration_s = 0.0005
"#;

#[test]
fn the_documented_layout_parses_and_durations_get_their_undo() {
    let s = Scenario::parse(Path::new("x.toml"), EXAMPLE).unwrap();
    assert_eq!(s.test, Some(Test::UmbmarkCw.into()));
    let f = s.scheduled();
    assert_eq!(f.len(), 3);
    assert_eq!(f[0].undo, None);
    assert_eq!(
        f[1].undo,
        Some((
            1.5,
            Action::SlipBurst {
                side: Side::Left,
                slip: 0.0
            }
        ))
    );
    assert_eq!(f[2].trigger, Trigger::HostByte { n: 2 });
}

#[test]
fn the_example_fixture_parses() {
    let path = crate::paths::workspace_root().join("fixtures/scenarios/dropout-then-slip.toml");
    let s = Scenario::load(&path).unwrap();
    assert_eq!(s.test, Some(Test::UmbmarkCw.into()));
    assert_eq!(s.scheduled().len(), 3);
}

#[test]
fn json_parses_too() {
    let text = r#"{"fault": [{"trigger": {"at": "leg_start", "n": 2},
        "action": {"action": "reset"}}]}"#;
    let s = Scenario::parse(Path::new("x.json"), text).unwrap();
    assert_eq!(s.scheduled()[0].action, Action::Reset);
}

#[test]
fn errors_name_the_fault_and_what_to_do() {
    let bad = |t: &str| {
        Scenario::parse(Path::new("s.toml"), t)
            .unwrap_err()
            .to_string()
    };
    let e =
        bad("[[fault]]\ntrigger = { at = \"time\", s = -1.0 }\naction = { action = \"reset\" }\n");
    assert!(
        e.contains("fault 1") && e.contains("trigger.s = -1: give 0 to 86400 s"),
        "{e}"
    );
    let e = bad("[[fault]]\ntrigger = { at = \"time\", s = 1.0 }\naction = { action = \"reset\" }\nduration_s = 1.0\n");
    assert!(e.contains("drop duration_s, or give `undo`"), "{e}");
    let e = bad("[[fault]]\ntrigger = { at = \"time\", s = 1.0 }\naction = { action = \"slip_burst\", side = \"left\", slip = 1.5 }\n");
    assert!(e.contains("slip = 1.5"), "{e}");
    let e = bad("[[fault]]\ntrigger = { at = \"sometime\" }\naction = { action = \"reset\" }\n");
    assert!(e.contains("does not parse"), "{e}");
    let e = bad("name = \"nothing\"\nfault = []\n");
    assert!(e.contains("no [[fault]]"), "{e}");
}

/// Random scenario files, absurd numbers included (nan, inf, negative,
/// past a day, past the 64-bit cycle counter), are either loaded with
/// every number finite or refused with one error line; never a panic.
mod fuzz {
    use super::*;
    use proptest::prelude::*;

    fn number() -> impl Strategy<Value = String> {
        prop_oneof![
            3 => (0.0f64..20.0).prop_map(|v| format!("{v:.3}")),
            1 => prop::sample::select(vec![
                "nan", "inf", "-inf", "-1.0", "0.0", "86400.0", "86400.5", "1.2e12", "1e300",
                "\"3\"", "3",
            ])
            .prop_map(str::to_owned),
        ]
    }

    fn count() -> impl Strategy<Value = String> {
        prop::sample::select(vec!["1", "3", "0", "-1", "1000000000", "1.5", "\"x\""])
            .prop_map(str::to_owned)
    }

    fn fault() -> impl Strategy<Value = String> {
        let trigger = prop_oneof![
            number().prop_map(|s| format!("{{ at = \"time\", s = {s} }}")),
            (
                prop::sample::select(vec!["turn_start", "leg_start", "host_byte", "noon"]),
                count()
            )
                .prop_map(|(at, n)| format!("{{ at = \"{at}\", n = {n} }}")),
        ];
        let action = prop_oneof![
            Just(
                "{ action = \"encoder\", side = \"left\", fault = { kind = \"dropout\" } }"
                    .to_owned()
            ),
            number().prop_map(|v| format!(
                "{{ action = \"slip_burst\", side = \"right\", slip = {v} }}"
            )),
            number().prop_map(|v| format!("{{ action = \"link\", fault = {{ loss = {v} }} }}")),
            Just("{ action = \"reset\" }".to_owned()),
            Just("{ action = \"explode\" }".to_owned()),
        ];
        let duration = prop_oneof![
            Just(String::new()),
            number().prop_map(|d| format!("duration_s = {d}\n")),
        ];
        (trigger, action, duration)
            .prop_map(|(t, a, d)| format!("[[fault]]\ntrigger = {t}\naction = {a}\n{d}"))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]

        #[test]
        fn scenario_files_load_or_are_refused(faults in prop::collection::vec(fault(), 0..4)) {
            let text = format!("name = \"fuzz\"\n{}", faults.join("\n"));
            match Scenario::parse(std::path::Path::new("fuzz.toml"), &text) {
                Ok(s) => {
                    let shown = format!("{s:?}");
                    prop_assert!(!shown.contains("NaN") && !shown.contains("inf"), "{shown}");
                }
                Err(e) => {
                    let e = e.to_string();
                    prop_assert!(!e.is_empty() && !e.contains('\n'), "{e}");
                }
            }
        }
    }
}
