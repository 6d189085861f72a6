//! Reading a step-response CSV in the layout of `fixtures/thesis-data/motor_step_*.csv`.
//!
//! ```text
//! # comments (the side is taken from an upper-case RIGHT or LEFT in them)
//! sample,time_s,pwm170_rpm,pwm190_rpm,pwm210_rpm,pwm230_rpm,pwm250_rpm,mean_rpm
//! 0,0.000,0,0,0,0,0,0
//! 1,0.015,0,2.21,4.42,5.53,8.84,4.2
//! ...
//! 127,1.905,14.36,17.69,23.19,30.93,38.71,24.976
//! ```
//!
//! - `sample` is the index of the 15 ms window, strictly increasing but not necessarily
//!   contiguous (the thesis printed rows 0-7 and 127-129 only); the first row must be sample 0,
//!   the moment the step is applied, with the motor at rest.
//! - `time_s` must equal `sample * T` for one sample period `T` (to the 1 ms the thesis
//!   prints); `T` is read from these two columns.
//! - `pwmNNN_rpm` columns (at least one) hold the response to a step from 0 to the 8-bit PWM
//!   compare value `NNN` (duty `NNN / 255`), in thesis "RPM".
//! - `mean_rpm` (optional) is the thesis' "PROM" column, the mean of the PWM columns; when it
//!   is present it must be that mean (to 0.001), when it is absent it is computed.

use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::side::Side;

/// Everything that can go wrong when reading a step response or identifying a model from it.
///
/// Messages about the file name the 1-based line of the file and say what was expected.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum IdentifyError {
    /// The file could not be read.
    #[error("cannot read step-response CSV `{path}`: {source}")]
    Read {
        /// The file asked for.
        path: PathBuf,
        /// Why it could not be read.
        #[source]
        source: std::io::Error,
    },

    /// Only comments and blank lines.
    #[error(
        "step-response CSV has no header line: after the `#` comments write \
         `sample,time_s,pwm170_rpm,...,mean_rpm`"
    )]
    NoHeader,

    /// A header column this reader does not know, a duplicate, or a missing required column.
    #[error("line {line}: header column `{column}`: {reason}")]
    Header {
        /// 1-based line number.
        line: usize,
        /// The column as written (empty when a required one is missing).
        column: String,
        /// What is wrong and what to write instead.
        reason: String,
    },

    /// A data row with more or fewer fields than the header.
    #[error("line {line}: {found} comma-separated fields, but the header has {expected}")]
    FieldCount {
        /// 1-based line number.
        line: usize,
        /// Fields in the header.
        expected: usize,
        /// Fields in this row.
        found: usize,
    },

    /// A field that is not a finite number (or, for `sample`, not a non-negative integer).
    #[error("line {line}: column `{column}` is `{text}`, which is not {expected}")]
    Number {
        /// 1-based line number.
        line: usize,
        /// The column's header name.
        column: String,
        /// The field as written.
        text: String,
        /// What it should be.
        expected: &'static str,
    },

    /// The first data row is not sample 0.
    #[error(
        "line {line}: the first data row is sample {sample}; it must be sample 0, the moment \
         the step is applied"
    )]
    NoSampleZero {
        /// 1-based line number.
        line: usize,
        /// The sample index found.
        sample: u64,
    },

    /// A sample index not greater than the one before it.
    #[error("line {line}: sample {sample} does not come after sample {previous}")]
    SampleOrder {
        /// 1-based line number.
        line: usize,
        /// This row's sample index.
        sample: u64,
        /// The previous row's sample index.
        previous: u64,
    },

    /// A time that is not `sample * T`.
    #[error(
        "line {line}: time_s = {time_s} but sample {sample} x T = {expected_s:.4} s \
         (T = {period_s:.6} s from all rows); the rows must lie on one sampling grid"
    )]
    TimeOffGrid {
        /// 1-based line number.
        line: usize,
        /// This row's sample index.
        sample: u64,
        /// This row's time.
        time_s: f64,
        /// `sample * T`.
        expected_s: f64,
        /// The sample period read from all rows.
        period_s: f64,
    },

    /// The `mean_rpm` column is not the mean of the PWM columns.
    #[error(
        "line {line}: mean_rpm = {given} but the mean of the PWM columns is {computed:.4}; \
         fix the row or drop the mean_rpm column (it is then computed)"
    )]
    MeanMismatch {
        /// 1-based line number.
        line: usize,
        /// The value in the file.
        given: f64,
        /// The mean of the PWM columns in that row.
        computed: f64,
    },

    /// Not enough rows to identify anything.
    #[error(
        "step-response CSV has {rows} data rows; at least {needed} are needed (the start of \
         the response and its steady level)"
    )]
    TooFewRows {
        /// Data rows read.
        rows: usize,
        /// Rows needed.
        needed: usize,
    },

    /// A fit could not be made (e.g. the response never rises, or the 63.2 % point of the
    /// mean curve falls in a gap of the samples).
    #[error("cannot identify column `{column}`: {reason}")]
    Fit {
        /// The column.
        column: String,
        /// Why.
        reason: String,
    },
}

/// Where a step-response CSV comes from.
///
/// `From<&str>` decides by content: a string with a line break is the CSV text itself (a valid
/// file always has a header and rows), anything else is a path.
#[derive(Debug, Clone, Copy)]
pub enum CsvSource<'a> {
    /// A file to read.
    Path(&'a Path),
    /// The CSV text.
    Text(&'a str),
}

impl<'a> From<&'a str> for CsvSource<'a> {
    fn from(s: &'a str) -> Self {
        if s.contains('\n') {
            CsvSource::Text(s)
        } else {
            CsvSource::Path(Path::new(s))
        }
    }
}

impl<'a> From<&'a String> for CsvSource<'a> {
    fn from(s: &'a String) -> Self {
        CsvSource::from(s.as_str())
    }
}

impl<'a> From<&'a Path> for CsvSource<'a> {
    fn from(p: &'a Path) -> Self {
        CsvSource::Path(p)
    }
}

impl<'a> From<&'a PathBuf> for CsvSource<'a> {
    fn from(p: &'a PathBuf) -> Self {
        CsvSource::Path(p.as_path())
    }
}

/// One response column: thesis "RPM" per sample.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Column {
    /// The header name (`pwm170_rpm`, `mean_rpm`).
    pub name: String,
    /// The 8-bit PWM compare value of the step (`None` for the mean column).
    pub pwm: Option<u16>,
    /// One value per row of [`StepData::samples`], thesis "RPM".
    pub values: Vec<f64>,
}

impl Column {
    /// The duty of the step, `pwm / 255` (`None` for the mean column).
    pub fn duty(&self) -> Option<f64> {
        self.pwm.map(|p| f64::from(p) / 255.0)
    }
}

/// A parsed step-response file.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StepData {
    /// The sample period `T`, s (0.015 for the thesis).
    pub sample_period_s: f64,
    /// Sample index of each row (not necessarily contiguous).
    pub samples: Vec<u64>,
    /// `samples[i] * T`, s.
    pub times_s: Vec<f64>,
    /// The PWM columns in file order.
    pub levels: Vec<Column>,
    /// The mean of the PWM columns (read from `mean_rpm` or computed).
    pub mean: Column,
    /// The side named by an upper-case `RIGHT` or `LEFT` in the comments, if exactly one is.
    pub side_in_comments: Option<Side>,
}

/// The 1-based line and content of each non-comment, non-blank line.
fn content_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'))
}

fn side_in_comments(text: &str) -> Option<Side> {
    let mut right = false;
    let mut left = false;
    for line in text.lines().map(str::trim).filter(|l| l.starts_with('#')) {
        for word in line.split(|c: char| !c.is_ascii_alphanumeric()) {
            right |= word == "RIGHT";
            left |= word == "LEFT";
        }
    }
    match (right, left) {
        (true, false) => Some(Side::Right),
        (false, true) => Some(Side::Left),
        _ => None,
    }
}

enum Role {
    Sample,
    Time,
    Pwm(u16),
    Mean,
}

fn header_role(line: usize, name: &str) -> Result<Role, IdentifyError> {
    let err = |reason: String| IdentifyError::Header {
        line,
        column: name.to_owned(),
        reason,
    };
    match name {
        "sample" => Ok(Role::Sample),
        "time_s" => Ok(Role::Time),
        "mean_rpm" => Ok(Role::Mean),
        _ => {
            let pwm =
                name.strip_prefix("pwm")
                    .and_then(|s| s.strip_suffix("_rpm"))
                    .ok_or_else(|| {
                        err("expected `sample`, `time_s`, `pwmNNN_rpm` (NNN the 8-bit PWM value of \
                         the step) or `mean_rpm`"
                        .to_owned())
                    })?;
            match pwm.parse::<u16>() {
                Ok(p) if (1..=255).contains(&p) => Ok(Role::Pwm(p)),
                _ => Err(err(format!(
                    "`{pwm}` is not a PWM compare value in 1..=255"
                ))),
            }
        }
    }
}

fn parse_number(line: usize, column: &str, text: &str) -> Result<f64, IdentifyError> {
    match text.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(IdentifyError::Number {
            line,
            column: column.to_owned(),
            text: text.to_owned(),
            expected: "a finite number",
        }),
    }
}

/// Rows needed: sample 0, two of the rise, one of the steady level.
const MIN_ROWS: usize = 4;

impl StepData {
    /// Reads a step response from a file or from text (see [`CsvSource`]).
    pub fn load<'a>(source: impl Into<CsvSource<'a>>) -> Result<StepData, IdentifyError> {
        match source.into() {
            CsvSource::Text(text) => StepData::parse(text),
            CsvSource::Path(path) => {
                let text = input_file::read_text(path).map_err(|source| IdentifyError::Read {
                    path: path.to_owned(),
                    source,
                })?;
                StepData::parse(&text)
            }
        }
    }

    /// Parses CSV text (module docs give the layout). A UTF-8 byte-order mark (as
    /// spreadsheet programs write) is skipped, as the end-point tables' reader does.
    pub fn parse(text: &str) -> Result<StepData, IdentifyError> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let mut lines = content_lines(text);
        let (header_line, header) = lines.next().ok_or(IdentifyError::NoHeader)?;
        let names: Vec<&str> = header.split(',').map(str::trim).collect();
        let mut sample_col = None;
        let mut time_col = None;
        let mut mean_col = None;
        let mut pwm_cols: Vec<(usize, u16)> = Vec::new();
        for (i, name) in names.iter().enumerate() {
            let duplicate = || IdentifyError::Header {
                line: header_line,
                column: (*name).to_owned(),
                reason: "appears twice".to_owned(),
            };
            match header_role(header_line, name)? {
                Role::Sample if sample_col.is_none() => sample_col = Some(i),
                Role::Time if time_col.is_none() => time_col = Some(i),
                Role::Mean if mean_col.is_none() => mean_col = Some(i),
                Role::Pwm(p) if pwm_cols.iter().all(|&(_, q)| q != p) => pwm_cols.push((i, p)),
                _ => return Err(duplicate()),
            }
        }
        let missing = |column: &str, reason: &str| IdentifyError::Header {
            line: header_line,
            column: column.to_owned(),
            reason: reason.to_owned(),
        };
        let sample_col = sample_col.ok_or_else(|| missing("sample", "missing"))?;
        let time_col = time_col.ok_or_else(|| missing("time_s", "missing"))?;
        if pwm_cols.is_empty() {
            return Err(missing(
                "pwmNNN_rpm",
                "no PWM column: at least one `pwmNNN_rpm` is needed",
            ));
        }

        let mut rows: Vec<(usize, u64, f64)> = Vec::new();
        let mut level_values: Vec<Vec<f64>> = vec![Vec::new(); pwm_cols.len()];
        let mut mean_values: Vec<f64> = Vec::new();
        for (line, row) in lines {
            let fields: Vec<&str> = row.split(',').map(str::trim).collect();
            if fields.len() != names.len() {
                return Err(IdentifyError::FieldCount {
                    line,
                    expected: names.len(),
                    found: fields.len(),
                });
            }
            let sample_text = fields[sample_col];
            let sample = sample_text
                .parse::<u64>()
                .map_err(|_| IdentifyError::Number {
                    line,
                    column: "sample".to_owned(),
                    text: sample_text.to_owned(),
                    expected: "a non-negative integer",
                })?;
            match rows.last() {
                None if sample != 0 => return Err(IdentifyError::NoSampleZero { line, sample }),
                Some(&(_, previous, _)) if sample <= previous => {
                    return Err(IdentifyError::SampleOrder {
                        line,
                        sample,
                        previous,
                    })
                }
                _ => {}
            }
            let time = parse_number(line, "time_s", fields[time_col])?;
            let mut sum = 0.0;
            for (k, &(col, _)) in pwm_cols.iter().enumerate() {
                let v = parse_number(line, names[col], fields[col])?;
                sum += v;
                level_values[k].push(v);
            }
            let computed = sum / pwm_cols.len() as f64;
            if let Some(col) = mean_col {
                let given = parse_number(line, names[col], fields[col])?;
                if (given - computed).abs() > 1e-3 + 1e-9 {
                    return Err(IdentifyError::MeanMismatch {
                        line,
                        given,
                        computed,
                    });
                }
                mean_values.push(given);
            } else {
                mean_values.push(computed);
            }
            rows.push((line, sample, time));
        }
        if rows.len() < MIN_ROWS {
            return Err(IdentifyError::TooFewRows {
                rows: rows.len(),
                needed: MIN_ROWS,
            });
        }

        // T by least squares through the origin over all rows, then every row must lie on the
        // grid to the precision the thesis prints (1 ms, so 0.5 ms of rounding).
        let (num, den) = rows.iter().fold((0.0, 0.0), |(n, d), &(_, s, t)| {
            let s = s as f64;
            (n + s * t, d + s * s)
        });
        let period = num / den;
        if !(period.is_finite() && period > 0.0) {
            return Err(missing(
                "time_s",
                "the times do not give a positive sample period",
            ));
        }
        for &(line, sample, time) in &rows {
            let expected = sample as f64 * period;
            if (time - expected).abs() > 5e-4 + 1e-9 {
                return Err(IdentifyError::TimeOffGrid {
                    line,
                    sample,
                    time_s: time,
                    expected_s: expected,
                    period_s: period,
                });
            }
        }
        // The thesis prints times to 1 ms; snap T to 0.1 ms when that is within rounding.
        let snapped = (period * 1e4).round() / 1e4;
        let period = if rows
            .iter()
            .all(|&(_, s, t)| (t - s as f64 * snapped).abs() <= 5e-4 + 1e-9)
        {
            snapped
        } else {
            period
        };

        let samples: Vec<u64> = rows.iter().map(|&(_, s, _)| s).collect();
        Ok(StepData {
            sample_period_s: period,
            times_s: samples.iter().map(|&s| s as f64 * period).collect(),
            samples,
            levels: pwm_cols
                .iter()
                .zip(level_values)
                .map(|(&(col, pwm), values)| Column {
                    name: names[col].to_owned(),
                    pwm: Some(pwm),
                    values,
                })
                .collect(),
            mean: Column {
                name: mean_col.map_or("mean_rpm", |c| names[c]).to_owned(),
                pwm: None,
                values: mean_values,
            },
            side_in_comments: side_in_comments(text),
        })
    }

    /// The mean PWM value of the step columns: the step the mean column answers (210 for the
    /// thesis' 170..250).
    pub fn mean_pwm(&self) -> f64 {
        self.levels
            .iter()
            .filter_map(|c| c.pwm)
            .map(f64::from)
            .sum::<f64>()
            / self.levels.len() as f64
    }

    /// Whether row `i` directly follows row `i - 1` (no missing samples between them).
    pub fn contiguous(&self, i: usize) -> bool {
        i > 0 && self.samples[i] == self.samples[i - 1] + 1
    }

    /// The rows used as the steady level: the last contiguous block, at most its last 10 %
    /// of all samples and at least the last 3 rows (rows 127-129 for the thesis).
    pub fn steady_rows(&self) -> std::ops::Range<usize> {
        let n = self.samples.len();
        let mut block_start = n - 1;
        while block_start > 0 && self.contiguous(block_start) {
            block_start -= 1;
        }
        let want = ((self.samples[n - 1] as f64 * 0.1).ceil() as usize).max(3);
        let first = block_start.max(n.saturating_sub(want));
        let first = first.min(n - 3).max(1);
        first..n
    }
}
