//! Scenario files: faults for `hil run --scenario FILE` and `hil faults
//! --scenario FILE`, in TOML (or JSON, by the `.json` extension).
//!
//! ```toml
//! name = "left encoder off, then a slip"
//! test = "line"        # for `hil faults`; `hil run` takes the test it is given
//! leg_mm = 2000.0      # for `hil faults`
//! limit_s = 25.0       # for `hil faults`
//!
//! [[fault]]
//! trigger = { at = "time", s = 3.0 }
//! action = { action = "encoder", side = "left", fault = { kind = "dropout" } }
//!
//! [[fault]]
//! trigger = { at = "turn_start", n = 3 }
//! action = { action = "slip_burst", side = "left", slip = 0.3 }
//! duration_s = 1.5     # then the fault ends (or `undo` runs, when given)
//! ```
//!
//! Triggers: `time` (`s` since reset), `turn_start` / `leg_start` (`n`,
//! 1-based), `host_byte` (`n`-th byte from the host on the Bluetooth link).
//! Actions are [`crate::bench::Action`]'s, tagged by `action`: `encoder`,
//! `encoder_glitch`, `link`, `motor_disconnected`, `motor`, `slip_burst`,
//! `battery_volts`, `reset`, `host_send`. Every value is checked before
//! anything runs; times (`s`, `duration_s`, `limit_s`) are at most a day of
//! robot time ([`MAX_ROBOT_TIME_S`]), far beyond any run and far below the
//! 64-bit cycle counter, so no fault waits forever or wraps round. A fault
//! whose trigger the run never reaches is named in the run's warnings.

use std::path::{Path, PathBuf};

use serde::Deserialize;
use thiserror::Error;

use crate::bench::{Action, ScheduledFault, Trigger};
use crate::experiment::Test;
use crate::inject::{EncoderFault, LinkFault};

#[derive(Debug, Error)]
pub enum ScenarioError {
    #[error("cannot read the scenario {path}: {source}")]
    Read {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("the scenario {path} does not parse: {message} (the module docs of hil::scenario show the layout)")]
    Parse { path: PathBuf, message: String },
    #[error("the scenario {path}, fault {index}: {message}")]
    Invalid {
        path: PathBuf,
        /// 1-based, in file order.
        index: usize,
        message: String,
    },
    #[error("the scenario {path} has no [[fault]]: add at least one")]
    Empty { path: PathBuf },
    /// A top-level value (`leg_mm`, `limit_s`) out of its range.
    #[error("the scenario {path}: {message}")]
    Field { path: PathBuf, message: String },
}

/// A parser's message on one line: the TOML parser draws the line it quotes
/// and carets under it on lines of their own (`  |`, `2 | text`, `  ^`).
fn one_line(message: &str) -> String {
    message
        .lines()
        .map(str::trim)
        .filter(|l| !l.trim_start_matches(['|', '^', ' ']).is_empty())
        .filter(|l| !l.starts_with('|'))
        .collect::<Vec<_>>()
        .join(" ")
}

/// The longest robot time a scenario may name: one day.
pub const MAX_ROBOT_TIME_S: f64 = 86_400.0;

/// `what = value` when `value` is not a robot time in `low..=MAX_ROBOT_TIME_S`
/// (`low` itself excluded when `open`).
fn check_time(what: &str, value: f64, open: bool) -> Result<(), String> {
    let above = if open { value > 0.0 } else { value >= 0.0 };
    if value.is_finite() && above && value <= MAX_ROBOT_TIME_S {
        return Ok(());
    }
    let shown = if value.is_finite() && value.abs() >= 1e6 {
        format!("{value:e}")
    } else {
        format!("{value}")
    };
    let range = if open {
        format!("more than 0 and at most {MAX_ROBOT_TIME_S} s")
    } else {
        format!("0 to {MAX_ROBOT_TIME_S} s")
    };
    Err(format!(
        "{what} = {shown}: give {range} of robot time (one day)"
    ))
}

/// One fault of a scenario file.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FaultEntry {
    pub trigger: Trigger,
    pub action: Action,
    /// How long the fault lasts; without `undo`, the bench ends it with the
    /// action's healthy counterpart.
    #[serde(default)]
    pub duration_s: Option<f64>,
    #[serde(default)]
    pub undo: Option<Action>,
}

/// A scenario file.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    #[serde(default)]
    pub name: Option<String>,
    #[serde(default)]
    pub test: Option<Test>,
    #[serde(default)]
    pub leg_mm: Option<f64>,
    #[serde(default)]
    pub limit_s: Option<f64>,
    /// Start with a framed command instead of the raw selector byte.
    #[serde(default)]
    pub framed: bool,
    #[serde(rename = "fault")]
    pub faults: Vec<FaultEntry>,
}

impl Scenario {
    /// Read and check a scenario file.
    pub fn load(path: &Path) -> Result<Self, ScenarioError> {
        let text = std::fs::read_to_string(path).map_err(|source| ScenarioError::Read {
            path: path.to_owned(),
            source,
        })?;
        Self::parse(path, &text)
    }

    /// Parse and check scenario text (`path` names it in errors and picks
    /// the format: `.json` is JSON, anything else TOML).
    pub fn parse(path: &Path, text: &str) -> Result<Self, ScenarioError> {
        let parsed: Result<Scenario, String> = if path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("json"))
        {
            serde_json::from_str(text).map_err(|e| e.to_string())
        } else {
            toml::from_str(text).map_err(|e| e.to_string())
        };
        let s = parsed.map_err(|message| ScenarioError::Parse {
            path: path.to_owned(),
            message: one_line(&message),
        })?;
        if s.faults.is_empty() {
            return Err(ScenarioError::Empty {
                path: path.to_owned(),
            });
        }
        for (i, f) in s.faults.iter().enumerate() {
            f.validate().map_err(|message| ScenarioError::Invalid {
                path: path.to_owned(),
                index: i + 1,
                message,
            })?;
        }
        if let Some(v) = s
            .leg_mm
            .filter(|v| !(v.is_finite() && *v > 0.0 && *v <= 100_000.0))
        {
            return Err(ScenarioError::Field {
                path: path.to_owned(),
                message: format!("leg_mm = {v}: give a length above 0 and up to 100000 mm"),
            });
        }
        if let Some(v) = s.limit_s {
            check_time("limit_s", v, true).map_err(|message| ScenarioError::Field {
                path: path.to_owned(),
                message,
            })?;
        }
        Ok(s)
    }

    /// The faults, as the bench schedules them.
    pub fn scheduled(&self) -> Vec<ScheduledFault> {
        self.faults.iter().map(FaultEntry::scheduled).collect()
    }
}

impl FaultEntry {
    fn scheduled(&self) -> ScheduledFault {
        let undo = self.duration_s.map(|d| {
            let a = self
                .undo
                .clone()
                .or_else(|| healthy(&self.action))
                .expect("validated: a duration has an undo");
            (d, a)
        });
        ScheduledFault {
            trigger: self.trigger,
            action: self.action.clone(),
            undo,
        }
    }

    fn validate(&self) -> Result<(), String> {
        match self.trigger {
            Trigger::Time { s } => check_time("trigger.s", s, false)?,
            Trigger::TurnStart { n: 0 }
            | Trigger::LegStart { n: 0 }
            | Trigger::HostByte { n: 0 } => {
                return Err("trigger n = 0: events are counted from 1".into())
            }
            _ => {}
        }
        check_action(&self.action)?;
        if let Some(a) = &self.undo {
            check_action(a).map_err(|e| format!("undo: {e}"))?;
            if self.duration_s.is_none() {
                return Err("`undo` without `duration_s`: say how long the fault lasts".into());
            }
        }
        if let Some(d) = self.duration_s {
            check_time("duration_s", d, true)?;
            if self.undo.is_none() && healthy(&self.action).is_none() {
                return Err(format!(
                    "`{}` has no healthy state to return to: drop duration_s, or give `undo`",
                    self.action.name()
                ));
            }
        }
        Ok(())
    }
}

/// The action that ends `a`'s fault, when it has one.
fn healthy(a: &Action) -> Option<Action> {
    Some(match a {
        Action::Encoder { side, .. } => Action::Encoder {
            side: *side,
            fault: EncoderFault::Healthy,
        },
        Action::Link { .. } => Action::Link {
            fault: LinkFault::default(),
        },
        Action::MotorDisconnected { side, .. } => Action::MotorDisconnected {
            side: *side,
            disconnected: false,
        },
        Action::Motor { side, .. } => Action::Motor {
            side: *side,
            fault: plant_model::MotorFault::None,
        },
        Action::SlipBurst { side, .. } => Action::SlipBurst {
            side: *side,
            slip: 0.0,
        },
        Action::BatteryVolts { .. } => Action::BatteryVolts { volts: None },
        Action::Reset | Action::EncoderGlitch { .. } | Action::HostSend { .. } => return None,
    })
}

fn check_action(a: &Action) -> Result<(), String> {
    let unit = |what: &str, p: f64| {
        if (0.0..=1.0).contains(&p) {
            Ok(())
        } else {
            Err(format!("{what} = {p}: give a probability from 0 to 1"))
        }
    };
    match a {
        Action::Encoder {
            fault: EncoderFault::MissPairs { every },
            ..
        } if *every < 2 => Err(format!(
            "miss_pairs every = {every}: give 2 or more (every n-th edge and the next are lost)"
        )),
        Action::Link { fault } => {
            unit("link loss", fault.loss)?;
            unit("link corrupt", fault.corrupt)?;
            unit("link garbage", fault.garbage)
        }
        Action::Motor { fault, .. } => fault.validate().map_err(|e| e.to_string()),
        Action::SlipBurst { slip, .. } if !(0.0..1.0).contains(slip) => Err(format!(
            "slip = {slip}: give a fraction from 0 up to (not including) 1"
        )),
        Action::BatteryVolts { volts: Some(v) } if !(v.is_finite() && (0.0..=20.0).contains(v)) => {
            Err(format!("battery volts = {v}: give 0 to 20 V"))
        }
        Action::EncoderGlitch {
            pulses,
            width_us,
            period_us,
            ..
        } => {
            if !(1..=100_000).contains(pulses) {
                Err(format!("glitch pulses = {pulses}: give 1 to 100000"))
            } else if !(width_us.is_finite() && *width_us > 0.0) {
                Err(format!(
                    "glitch width_us = {width_us}: give a positive width"
                ))
            } else if !(period_us.is_finite() && *period_us <= 1e6) {
                Err(format!(
                    "glitch period_us = {period_us}: give at most 1000000 (one pulse a second)"
                ))
            } else if period_us <= width_us {
                Err(format!(
                    "glitch period_us = {period_us}: give more than width_us ({width_us})"
                ))
            } else {
                Ok(())
            }
        }
        Action::HostSend { bytes } if bytes.is_empty() => {
            Err("host_send with no bytes: give at least one".into())
        }
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
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
        assert_eq!(s.test, Some(Test::UmbmarkCw));
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
        assert_eq!(s.test, Some(Test::UmbmarkCw));
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
        let e = bad(
            "[[fault]]\ntrigger = { at = \"time\", s = -1.0 }\naction = { action = \"reset\" }\n",
        );
        assert!(
            e.contains("fault 1") && e.contains("trigger.s = -1: give 0 to 86400 s"),
            "{e}"
        );
        let e = bad("[[fault]]\ntrigger = { at = \"time\", s = 1.0 }\naction = { action = \"reset\" }\nduration_s = 1.0\n");
        assert!(e.contains("drop duration_s, or give `undo`"), "{e}");
        let e = bad("[[fault]]\ntrigger = { at = \"time\", s = 1.0 }\naction = { action = \"slip_burst\", side = \"left\", slip = 1.5 }\n");
        assert!(e.contains("slip = 1.5"), "{e}");
        let e =
            bad("[[fault]]\ntrigger = { at = \"sometime\" }\naction = { action = \"reset\" }\n");
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
}
