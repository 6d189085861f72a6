//! Reading a scenario file and checking every value before anything runs:
//! the first problem is one error line naming the value, where it is and
//! what is allowed.

use std::path::Path;

use super::{Scenario, ScenarioError};

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
pub(super) fn check_time(what: &str, value: f64, open: bool) -> Result<(), String> {
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

impl Scenario {
    /// Read and check a scenario file.
    pub fn load(path: &Path) -> Result<Self, ScenarioError> {
        let text = input_file::read_text(path).map_err(|source| ScenarioError::Read {
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
        if s.faults.is_empty() && s.expect.is_empty() {
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
        for (i, e) in s.expect.iter().enumerate() {
            e.validate(s.faults.len())
                .map_err(|message| ScenarioError::Expect {
                    path: path.to_owned(),
                    index: i + 1,
                    message,
                })?;
        }
        let field = |message: String| ScenarioError::Field {
            path: path.to_owned(),
            message,
        };
        if let Some(v) = s
            .leg_mm
            .filter(|v| !(v.is_finite() && *v > 0.0 && *v <= 100_000.0))
        {
            return Err(field(format!(
                "leg_mm = {v}: give a length above 0 and up to 100000 mm"
            )));
        }
        if let Some(v) = s.limit_s {
            check_time("limit_s", v, true).map_err(field)?;
        }
        if let Some(f) = s
            .firmware
            .as_deref()
            .filter(|f| !["robust", "thesis"].contains(f))
        {
            return Err(field(format!(
                "firmware = {f:?}: give \"robust\" or \"thesis\" (another ELF: hil test --elf FILE)"
            )));
        }
        Ok(s)
    }
}
