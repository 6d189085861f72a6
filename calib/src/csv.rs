//! Reading the end-point tables.
//!
//! Two layouts, as in the thesis data files: `#` comment lines anywhere, blank lines
//! ignored, one header row, then one row per run:
//!
//! ```text
//! experiment,direction,run,x_cm,y_cm      (UMBmark: direction = cw | ccw)
//! experiment,test,run,x_cm,y_cm           (Triangular Path: test = line | triangle)
//! ```
//!
//! The whole file is checked (every row must parse), then one experiment is selected and its
//! run counts are checked. Every value is required, with one declared exception: the y value
//! of *triangle* rows may be empty when [`CsvOptions::triangle_y_optional`] is set (the
//! thesis' triangle experiment 2 lost its y column in transcription); the reader then says so
//! in [`TriangleExperiment::notes`]. An end error larger than the test's leg
//! ([`CsvOptions::max_end_error_cm`]) is refused: no run ends farther off than its whole path.
//! Errors name the 1-based line number and the column.

use std::collections::BTreeMap;
use std::path::Path;

use crate::types::{Direction, Endpoint, LineRuns, PartialEndpoint, TriangleRuns, UmbmarkRuns};
use crate::Error;

/// Header of the UMBmark table.
pub const UMBMARK_HEADER: &str = "experiment,direction,run,x_cm,y_cm";
/// Header of the Triangular Path table.
pub const TRIANGLE_HEADER: &str = "experiment,test,run,x_cm,y_cm";

/// How strictly to read.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CsvOptions {
    /// Runs expected in each group (each direction, or the line and the triangle).
    pub runs_per_group: usize,
    /// Accept an empty `y_cm` in `triangle` rows (and only there).
    pub triangle_y_optional: bool,
    /// The largest `x_cm` or `y_cm` accepted, in either direction: the test's leg (a run
    /// cannot end farther off than its path is long). Default [`MAX_LEG_CM`].
    pub max_end_error_cm: f64,
}

/// The longest leg of a test, cm (100 m: the bench's longest too).
pub const MAX_LEG_CM: f64 = 10_000.0;

impl Default for CsvOptions {
    fn default() -> Self {
        Self {
            runs_per_group: 5,
            triangle_y_optional: false,
            max_end_error_cm: MAX_LEG_CM,
        }
    }
}

/// `value` (already a finite number) unless it is farther than `max_cm` from 0.
fn check_end_error(line: usize, column: &str, value: f64, max_cm: f64) -> Result<f64, Error> {
    if value.abs() <= max_cm {
        return Ok(value);
    }
    let shown = if value.abs() >= 1e6 {
        format!("{value:e}")
    } else {
        format!("{value}")
    };
    Err(Error::EndErrorTooLarge {
        line,
        column: column.into(),
        value: shown,
        max_cm,
    })
}

/// One experiment of a Triangular Path table.
#[derive(Debug, Clone, PartialEq)]
pub struct TriangleExperiment {
    /// The straight-line runs.
    pub line: LineRuns,
    /// The triangle runs.
    pub triangle: TriangleRuns,
    /// What the reader accepted that the caller should know (e.g. missing y values).
    pub notes: Vec<String>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Layout {
    Umbmark,
    Triangle,
}

impl Layout {
    fn header(self) -> &'static str {
        match self {
            Self::Umbmark => UMBMARK_HEADER,
            Self::Triangle => TRIANGLE_HEADER,
        }
    }

    fn groups(self) -> [&'static str; 2] {
        match self {
            Self::Umbmark => ["cw", "ccw"],
            Self::Triangle => ["line", "triangle"],
        }
    }
}

#[derive(Debug, Clone)]
struct Row {
    line: usize,
    experiment: u32,
    group: &'static str,
    run: u32,
    x: f64,
    y: Option<f64>,
}

struct Table {
    header_line: usize,
    rows: Vec<Row>,
}

fn parse_positive(line: usize, column: &str, value: &str) -> Result<u32, Error> {
    match value.parse::<u32>() {
        Ok(v) if v > 0 => Ok(v),
        _ => Err(Error::NotAnInteger {
            line,
            column: column.into(),
            value: value.into(),
        }),
    }
}

fn parse_number(line: usize, column: &str, value: &str, hint: &str) -> Result<f64, Error> {
    if value.is_empty() {
        return Err(Error::MissingValue {
            line,
            column: column.into(),
            hint: hint.into(),
        });
    }
    match value.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(Error::NotANumber {
            line,
            column: column.into(),
            value: value.into(),
        }),
    }
}

fn parse_table(text: &str, layout: Layout, opts: &CsvOptions) -> Result<Table, Error> {
    let expected = layout.header();
    let mut header_line = None;
    let mut rows: Vec<Row> = Vec::new();
    let mut seen: BTreeMap<(u32, &'static str, u32), usize> = BTreeMap::new();
    let mut last_line = 0;
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        last_line = line;
        let raw = if i == 0 {
            raw.trim_start_matches('\u{feff}')
        } else {
            raw
        };
        let content = raw.trim();
        if content.is_empty() || content.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = content.split(',').map(str::trim).collect();
        let Some(_) = header_line else {
            let found = fields.join(",");
            if !found.eq_ignore_ascii_case(expected) {
                return Err(Error::BadHeader {
                    line,
                    found: content.into(),
                    expected: expected.into(),
                });
            }
            header_line = Some(line);
            continue;
        };
        if fields.len() != 5 {
            return Err(Error::FieldCount {
                line,
                found: fields.len(),
                expected: 5,
                header: expected.into(),
            });
        }
        let experiment = parse_positive(line, "experiment", fields[0])?;
        let g = fields[1].to_ascii_lowercase();
        let group = match layout.groups().into_iter().find(|name| *name == g) {
            Some(name) => name,
            None => {
                return Err(match layout {
                    Layout::Umbmark => Error::UnknownDirection {
                        line,
                        value: fields[1].into(),
                    },
                    Layout::Triangle => Error::UnknownTest {
                        line,
                        value: fields[1].into(),
                    },
                })
            }
        };
        let run = parse_positive(line, "run", fields[2])?;
        let max = opts.max_end_error_cm;
        let x = check_end_error(
            line,
            "x_cm",
            parse_number(line, "x_cm", fields[3], "")?,
            max,
        )?;
        let y_optional = layout == Layout::Triangle && group == "triangle";
        let y = if fields[4].is_empty() && y_optional && opts.triangle_y_optional {
            None
        } else {
            let hint = if y_optional {
                "; if this table's triangle y values were never recorded, declare them optional \
                 with `CsvOptions::triangle_y_optional`"
            } else {
                ""
            };
            let y = parse_number(line, "y_cm", fields[4], hint)?;
            Some(check_end_error(line, "y_cm", y, max)?)
        };
        if let Some(&first_line) = seen.get(&(experiment, group, run)) {
            return Err(Error::DuplicateRun {
                line,
                first_line,
                experiment,
                group: group.into(),
                run,
            });
        }
        seen.insert((experiment, group, run), line);
        rows.push(Row {
            line,
            experiment,
            group,
            run,
            x,
            y,
        });
    }
    let header_line = header_line.ok_or_else(|| Error::MissingHeader {
        line: last_line + 1,
        expected: expected.into(),
    })?;
    Ok(Table { header_line, rows })
}

/// The rows of one experiment, grouped, each group sorted by run and checked for its count.
fn select<'a>(
    table: &'a Table,
    layout: Layout,
    experiment: u32,
    opts: &CsvOptions,
) -> Result<[Vec<&'a Row>; 2], Error> {
    let mine: Vec<&Row> = table
        .rows
        .iter()
        .filter(|r| r.experiment == experiment)
        .collect();
    if mine.is_empty() {
        let mut available: Vec<u32> = table.rows.iter().map(|r| r.experiment).collect();
        available.sort_unstable();
        available.dedup();
        let available = if available.is_empty() {
            "none".to_string()
        } else {
            available
                .iter()
                .map(u32::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        };
        return Err(Error::NoSuchExperiment {
            experiment,
            available,
        });
    }
    let groups = layout.groups().map(|g| {
        let mut rows: Vec<&Row> = mine.iter().copied().filter(|r| r.group == g).collect();
        rows.sort_by_key(|r| r.run);
        rows
    });
    for (g, rows) in layout.groups().iter().zip(&groups) {
        if rows.len() != opts.runs_per_group {
            let line = rows
                .iter()
                .map(|r| r.line)
                .max()
                .unwrap_or(table.header_line);
            return Err(Error::RunCount {
                line,
                experiment,
                group: g.to_string(),
                found: rows.len(),
                expected: opts.runs_per_group,
            });
        }
    }
    Ok(groups)
}

fn complete(rows: &[&Row]) -> Vec<Endpoint> {
    rows.iter()
        .map(|r| Endpoint::new(r.x, r.y.expect("y is required outside triangle rows")))
        .collect()
}

/// Parse a UMBmark table and return experiment `experiment`.
pub fn read_umbmark_csv(
    text: &str,
    experiment: u32,
    opts: &CsvOptions,
) -> Result<UmbmarkRuns, Error> {
    let table = parse_table(text, Layout::Umbmark, opts)?;
    let [cw, ccw] = select(&table, Layout::Umbmark, experiment, opts)?;
    UmbmarkRuns::new(complete(&cw), complete(&ccw))
}

/// Parse a Triangular Path table and return experiment `experiment`.
pub fn read_triangle_csv(
    text: &str,
    experiment: u32,
    opts: &CsvOptions,
) -> Result<TriangleExperiment, Error> {
    let table = parse_table(text, Layout::Triangle, opts)?;
    let [line, triangle] = select(&table, Layout::Triangle, experiment, opts)?;
    let missing: Vec<usize> = triangle
        .iter()
        .filter(|r| r.y.is_none())
        .map(|r| r.line)
        .collect();
    let mut notes = Vec::new();
    if !missing.is_empty() {
        notes.push(format!(
            "experiment {experiment}: y_cm is empty in {} of {} triangle rows (lines {}); accepted \
             because triangle y values were declared optional. The turn error uses x only; the \
             triangle's end error and the x/y check are unknown",
            missing.len(),
            triangle.len(),
            missing
                .iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    Ok(TriangleExperiment {
        line: LineRuns::new(complete(&line))?,
        triangle: TriangleRuns::new(
            triangle
                .iter()
                .map(|r| PartialEndpoint::new(r.x, r.y))
                .collect(),
        )?,
        notes,
    })
}

/// The experiment numbers in a UMBmark table (every row checked).
pub fn umbmark_experiments(text: &str) -> Result<Vec<u32>, Error> {
    experiments(text, Layout::Umbmark)
}

/// The experiment numbers in a Triangular Path table (every row checked; y may be missing).
pub fn triangle_experiments(text: &str) -> Result<Vec<u32>, Error> {
    experiments(text, Layout::Triangle)
}

fn experiments(text: &str, layout: Layout) -> Result<Vec<u32>, Error> {
    let opts = CsvOptions {
        triangle_y_optional: true,
        ..CsvOptions::default()
    };
    let table = parse_table(text, layout, &opts)?;
    let mut v: Vec<u32> = table.rows.iter().map(|r| r.experiment).collect();
    v.sort_unstable();
    v.dedup();
    Ok(v)
}

fn read(path: &Path) -> Result<String, Error> {
    input_file::read_text(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// [`read_umbmark_csv`] on a file.
pub fn read_umbmark_file(
    path: impl AsRef<Path>,
    experiment: u32,
    opts: &CsvOptions,
) -> Result<UmbmarkRuns, Error> {
    read_umbmark_csv(&read(path.as_ref())?, experiment, opts)
}

/// [`read_triangle_csv`] on a file.
pub fn read_triangle_file(
    path: impl AsRef<Path>,
    experiment: u32,
    opts: &CsvOptions,
) -> Result<TriangleExperiment, Error> {
    read_triangle_csv(&read(path.as_ref())?, experiment, opts)
}

/// Direction of a CSV group name, for callers that read the columns themselves.
pub fn parse_direction(s: &str) -> Option<Direction> {
    match s.trim().to_ascii_lowercase().as_str() {
        "cw" => Some(Direction::Cw),
        "ccw" => Some(Direction::Ccw),
        _ => None,
    }
}
