//! Golden runs: what one run of a test measured (each leg's end point and
//! heading change, each turn's angle, the mean PWM duty of each leg per
//! side, the control loop's cycle figures), written once to a JSON file with
//! the tolerances it is to be held to and what was in force (firmware ELF
//! and its hash, robot, board, seed, parameters); later runs are compared
//! to it quantity by quantity ([`compare`]) and what moved is named.
//!
//! A golden file belongs to one test with one leg length: a run of another
//! test is refused ([`Golden::check_same_test`]), since its quantities are
//! not the same ones. A different ELF is what a comparison is for: it is
//! reported, never refused.
//!
//! | file | part |
//! |---|---|
//! | `mod.rs` | the file ([`Golden`], [`InForce`], [`Tolerances`]), reading and checking it |
//! | `measure.rs` | a run's quantities ([`measure`]) |
//! | `compare.rs` | golden against now ([`compare`], [`Row`]) and the table of what moved |

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::runs::experiment::TestName;

mod compare;
mod measure;

pub use compare::{compare, differences, render, Difference, Row};
pub use measure::{measure, CONTROL_FUNCTION};

/// The file format's name and version, first in every golden file: a file
/// of another version is refused, not half-read.
pub const FORMAT: &str = "hil-golden/1";

/// A golden run: one test's quantities, as recorded.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Golden {
    /// [`FORMAT`].
    pub format: String,
    pub test: TestName,
    pub leg_mm: f64,
    /// What the run was made with.
    pub recorded_with: InForce,
    /// How far a later run may be from each quantity (overridable when
    /// checking).
    pub tolerances: Tolerances,
    pub quantities: Vec<Quantity>,
}

/// What a run was made with: enough to make it again, and to say what
/// differs between a golden run and a later one.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InForce {
    /// The build's name (`robust`, `thesis`), or the ELF's path as given.
    pub firmware: String,
    /// The ELF's path, when one was given instead of a build.
    pub elf: Option<String>,
    /// [`crate::firmware::elf::Firmware::content_hash`] of the ELF that ran.
    pub elf_hash: String,
    /// The robot config's path.
    pub robot: String,
    /// A hash of the robot config's bytes (a file changed under its name
    /// shows).
    pub robot_hash: String,
    /// The board TOML's path (None: Henrytwo's, built in).
    pub board: Option<String>,
    pub seed: u64,
    /// `--param NAME=VALUE`s sent before the start, in order.
    pub params: Vec<String>,
    /// The firmware kept its own geometry (`--keep-firmware-params`).
    pub keep_firmware_params: bool,
    /// The scenario file whose faults were injected.
    pub scenario: Option<String>,
    /// The test description the firmware ran by (`--tests FILE`; None: the
    /// bench's own build and its interface).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tests: Option<String>,
}

/// What a quantity is, and so which tolerance holds it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// A position, mm.
    LegMm,
    /// An angle, degrees.
    TurnDeg,
    /// A PWM duty (signed, -1 to 1).
    Duty,
    /// CPU cycles.
    Cycles,
}

/// One measured number of a run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Quantity {
    /// What it is, e.g. "leg 1 end x (mm)": unique within a file.
    pub name: String,
    pub kind: Kind,
    pub value: f64,
}

/// The largest difference from the golden value that is still the same
/// run, by kind.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Tolerances {
    pub leg_mm: f64,
    pub turn_deg: f64,
    pub duty: f64,
    pub cycles: f64,
}

impl Default for Tolerances {
    /// Half a centimetre, a degree, 2 % of full duty, 200 cycles (12.5 us
    /// at 16 MHz): beyond what a floor measurement or a rebuild that does
    /// not touch the control law moves; the bench itself is deterministic,
    /// so the same ELF, robot and seed give a difference of 0.
    fn default() -> Self {
        Self {
            leg_mm: 5.0,
            turn_deg: 1.0,
            duty: 0.02,
            cycles: 200.0,
        }
    }
}

impl Tolerances {
    /// The tolerance of a quantity of kind `kind`.
    pub fn of(&self, kind: Kind) -> f64 {
        match kind {
            Kind::LegMm => self.leg_mm,
            Kind::TurnDeg => self.turn_deg,
            Kind::Duty => self.duty,
            Kind::Cycles => self.cycles,
        }
    }

    /// The first tolerance that is not a finite number of at least 0.
    fn invalid(&self) -> Option<(&'static str, f64)> {
        [
            ("leg_mm", self.leg_mm),
            ("turn_deg", self.turn_deg),
            ("duty", self.duty),
            ("cycles", self.cycles),
        ]
        .into_iter()
        .find(|(_, v)| !(v.is_finite() && *v >= 0.0))
    }
}

/// A golden file that cannot be used: each message is one line naming the
/// file.
#[derive(Debug, thiserror::Error)]
pub enum GoldenError {
    // The causes are in the message, not chained: the CLI prints a chain
    // in full, and the line would say it twice.
    #[error("{path}: cannot read the golden file: {error}")]
    Read { path: String, error: std::io::Error },
    #[error("{path}: not a golden file: {error}")]
    Parse {
        path: String,
        error: serde_json::Error,
    },
    #[error("{path}: golden file format {found:?}; this bench reads {FORMAT:?}")]
    Format { path: String, found: String },
    #[error("{path}: {what}")]
    Invalid { path: String, what: String },
    #[error(
        "{path}: the golden run is of {} with legs of {golden_leg_mm} mm; a run of {} \
         with legs of {now_leg_mm} mm measures other quantities: record a golden run of it",
        golden.name(),
        now.name()
    )]
    OtherTest {
        path: String,
        golden: TestName,
        golden_leg_mm: f64,
        now: TestName,
        now_leg_mm: f64,
    },
}

impl Golden {
    /// A golden run of `test` with legs of `leg_mm`.
    pub fn new(
        test: TestName,
        leg_mm: f64,
        recorded_with: InForce,
        tolerances: Tolerances,
        quantities: Vec<Quantity>,
    ) -> Self {
        Self {
            format: FORMAT.into(),
            test,
            leg_mm,
            recorded_with,
            tolerances,
            quantities,
        }
    }

    /// Read and check a golden file.
    pub fn load(path: &Path) -> Result<Self, GoldenError> {
        let name = path.display().to_string();
        let text = input_file::read_text(path).map_err(|error| GoldenError::Read {
            path: name.clone(),
            error,
        })?;
        Self::parse(&name, &text)
    }

    /// A golden file's text, checked: its format, every number finite,
    /// tolerances at least 0, no quantity named twice.
    pub fn parse(path: &str, text: &str) -> Result<Self, GoldenError> {
        // A key given twice is refused: JSON readers keep the last one, so
        // a file edited by hand could compare a line with a triangle.
        input_file::json_unique_keys(text).map_err(|error| GoldenError::Parse {
            path: path.into(),
            error,
        })?;
        // The format first, so that a file of another version says so
        // rather than which field it lacks.
        let value: serde_json::Value =
            serde_json::from_str(text).map_err(|error| GoldenError::Parse {
                path: path.into(),
                error,
            })?;
        let format = value.get("format").and_then(|f| f.as_str());
        if format != Some(FORMAT) {
            return Err(GoldenError::Format {
                path: path.into(),
                found: format.unwrap_or("none").into(),
            });
        }
        let golden: Golden = serde_json::from_value(value).map_err(|error| GoldenError::Parse {
            path: path.into(),
            error,
        })?;
        let invalid = |what: String| GoldenError::Invalid {
            path: path.into(),
            what,
        };
        // The firmware's legs (protocol/README.md's leg_length_mm): a golden
        // run of another length was never recorded.
        if !(golden.leg_mm.is_finite() && (10.0..=5000.0).contains(&golden.leg_mm)) {
            return Err(invalid(format!(
                "leg_mm = {}: give 10 to 5000 mm (the firmware's legs)",
                golden.leg_mm
            )));
        }
        if let Some((name, v)) = golden.tolerances.invalid() {
            return Err(invalid(format!(
                "tolerances.{name} = {v}: give a number of at least 0"
            )));
        }
        let mut names = std::collections::BTreeSet::new();
        for q in &golden.quantities {
            if !q.value.is_finite() {
                return Err(invalid(format!("quantity {:?} is not a number", q.name)));
            }
            if !names.insert(q.name.as_str()) {
                return Err(invalid(format!("quantity {:?} is given twice", q.name)));
            }
        }
        if golden.quantities.is_empty() {
            return Err(invalid("no quantities: nothing to compare".into()));
        }
        Ok(golden)
    }

    /// The file's text (pretty JSON, one field a line: diffs read well).
    pub fn to_json(&self) -> String {
        let mut s = serde_json::to_string_pretty(self).expect("a golden run is plain data");
        s.push('\n');
        s
    }

    /// Refuse a run of another test or leg length than this golden run's
    /// (`path` names the golden file in the error).
    pub fn check_same_test(
        &self,
        path: &str,
        test: &TestName,
        leg_mm: f64,
    ) -> Result<(), GoldenError> {
        if *test == self.test && leg_mm == self.leg_mm {
            return Ok(());
        }
        Err(GoldenError::OtherTest {
            path: path.into(),
            golden: self.test.clone(),
            golden_leg_mm: self.leg_mm,
            now: test.clone(),
            now_leg_mm: leg_mm,
        })
    }
}

/// A hash of `bytes` (64-bit FNV-1a, hex): the same as the ELF's
/// [`crate::firmware::elf::Firmware::content_hash`] uses, for files that are not ELFs.
pub fn bytes_hash(bytes: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= *b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}

#[cfg(test)]
mod tests;
