//! The crate's one error type.

use std::path::PathBuf;

/// Everything that can go wrong in this crate.
///
/// CSV errors name the 1-based line number of the input, say what is wrong and what to do
/// about it, so that the message can be shown to the person who typed the table.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The file could not be read.
    #[error("cannot read {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// What the operating system said.
        #[source]
        source: std::io::Error,
    },

    /// The input holds no header row (only comments and blank lines).
    #[error(
        "line {line}: no header row found; the first line that is not a `#` comment must be `{expected}`"
    )]
    MissingHeader {
        /// Line after the last line of the input.
        line: usize,
        /// The header this table needs.
        expected: String,
    },

    /// The header row does not name the expected columns.
    #[error("line {line}: header is `{found}`, expected `{expected}`; rename the columns (same order) or check that this is the right file")]
    BadHeader {
        /// Line of the header.
        line: usize,
        /// What was found.
        found: String,
        /// What was expected.
        expected: String,
    },

    /// A data row has the wrong number of fields.
    #[error("line {line}: {found} fields, expected {expected} ({header}); look for a missing or extra comma")]
    FieldCount {
        /// Line of the row.
        line: usize,
        /// Number of fields found.
        found: usize,
        /// Number of fields expected.
        expected: usize,
        /// The header, for reference.
        header: String,
    },

    /// A required value is empty.
    #[error("line {line}: `{column}` is empty; fill in the measured value{hint}")]
    MissingValue {
        /// Line of the row.
        line: usize,
        /// Column name.
        column: String,
        /// Extra advice (may be empty).
        hint: String,
    },

    /// A value that must be a finite number is not one.
    #[error("line {line}: `{column}` is `{value}`, which is not a finite number; write a decimal number with a dot, e.g. `-28.6`")]
    NotANumber {
        /// Line of the row.
        line: usize,
        /// Column name.
        column: String,
        /// The text found.
        value: String,
    },

    /// A value that must be a positive integer (experiment, run) is not one.
    #[error("line {line}: `{column}` is `{value}`, expected a positive whole number such as `1`")]
    NotAnInteger {
        /// Line of the row.
        line: usize,
        /// Column name.
        column: String,
        /// The text found.
        value: String,
    },

    /// The direction column holds something other than `cw` / `ccw`.
    #[error("line {line}: unknown direction `{value}`; use `cw` (clockwise) or `ccw` (counter-clockwise)")]
    UnknownDirection {
        /// Line of the row.
        line: usize,
        /// The text found.
        value: String,
    },

    /// The test column holds something other than `line` / `triangle`.
    #[error("line {line}: unknown test `{value}`; use `line` (straight-line runs) or `triangle`")]
    UnknownTest {
        /// Line of the row.
        line: usize,
        /// The text found.
        value: String,
    },

    /// The same run number appears twice in one group.
    #[error("line {line}: run {run} of experiment {experiment}, {group} already appeared on line {first_line}; renumber or delete the duplicate")]
    DuplicateRun {
        /// Line of the duplicate.
        line: usize,
        /// Line where the run first appeared.
        first_line: usize,
        /// Experiment number.
        experiment: u32,
        /// `cw`, `ccw`, `line` or `triangle`.
        group: String,
        /// Run number.
        run: u32,
    },

    /// A group (direction or test) of the selected experiment has the wrong number of runs.
    #[error("line {line}: experiment {experiment}, {group} has {found} runs, expected {expected}; add the missing runs or remove the extra ones, or expect {found} runs per group")]
    RunCount {
        /// Last line of that group (the header line if the group is empty).
        line: usize,
        /// Experiment number.
        experiment: u32,
        /// `cw`, `ccw`, `line` or `triangle`.
        group: String,
        /// Runs found.
        found: usize,
        /// Runs expected.
        expected: usize,
    },

    /// An end error farther from the target than the test's whole path is long: a value
    /// in the wrong unit (mm for cm), a lost decimal point, a typo such as `1e308`.
    #[error("line {line}: `{column}` is {value} cm, more than the leg of the test ({max_cm} cm): an end error cannot be larger than the path; check the unit (centimetres) and the decimal point")]
    EndErrorTooLarge {
        /// Line of the row.
        line: usize,
        /// Column name.
        column: String,
        /// The value read, as written in the message.
        value: String,
        /// The largest end error accepted, cm.
        max_cm: f64,
    },

    /// The selected experiment has no rows.
    #[error("experiment {experiment} has no rows; experiments in the file: {available}")]
    NoSuchExperiment {
        /// Experiment asked for.
        experiment: u32,
        /// Experiments present, comma-separated.
        available: String,
    },

    /// Runs handed to a constructor are unusable (empty, or not finite numbers).
    #[error("invalid runs: {0}")]
    InvalidRuns(String),

    /// A quantity needs data that the runs do not hold (e.g. the triangle's y values).
    #[error("missing data: {0}")]
    MissingData(String),

    /// Drawing a plot failed.
    #[error("plot {path}: {message}")]
    Plot {
        /// The file being drawn.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
}
