//! One robot's calibration session, as the operator typed it: the end points
//! of each round, the straight-line measurement for Es, the parameters the
//! robot ran with, and what was sent to it afterwards.
//!
//! Fields are kept as typed (text), so that a half-typed "-1" survives a
//! closed tab; [`evaluate`] parses and validates them field by field and
//! hands complete rounds to the `calib` crate. The file is rewritten
//! atomically on every change ([`save`]).

use std::path::{Path, PathBuf};

use calib::{Endpoint, PartialEndpoint, Solution};

use crate::runs::experiment::Test;
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Runs per direction in a fresh round (UMBmark asks for five, and so does
/// the Triangular Path for its line and its triangle).
pub const RUNS_PER_DIRECTION: usize = 5;
/// End errors farther than this from the start are taken as a unit slip.
const MAX_ERROR_CM: f64 = 500.0;

#[derive(Debug, Error)]
pub enum SessionError {
    #[error("cannot read the session {path}: {source}")]
    Read {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("the session {path} is not a session file ({source}); move it away to start afresh")]
    Parse {
        path: PathBuf,
        source: serde_json::Error,
    },
    #[error("cannot save the session {path}: {source}; check the folder is writable")]
    Write {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("the CSV: {0}")]
    Csv(#[from] calib::Error),
    #[error("the CSV holds {method} experiments {list}: give the one to import")]
    WhichExperiment { method: &'static str, list: String },
    #[error(
        "round {round} has end points from tests with {was_mm} mm legs: run its tests with {was_mm} mm legs, \
         or clear its end points first (one side per round)"
    )]
    LegChanged { round: usize, was_mm: f64 },
}

/// One end point as typed, centimetres.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct PointText {
    pub x: String,
    pub y: String,
}

/// The robot's odometry parameters during a round.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Params {
    pub c_left: f64,
    pub c_right: f64,
    pub wheelbase_mm: f64,
}

/// The test a round's end points come from.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// Five CW and five CCW squares (Borenstein & Feng). Session files
    /// written before the Triangular Path was offered hold only these.
    #[default]
    Umbmark,
    /// Five straight lines, then five counter-clockwise triangles (Ruan, Li
    /// & Zhu), as the thesis ran it.
    Triangle,
}

impl Method {
    fn name(self) -> &'static str {
        match self {
            Method::Umbmark => "UMBmark",
            Method::Triangle => "Triangular Path",
        }
    }

    /// Whether `test`'s end point is one of this method's runs (a line in a
    /// UMBmark round measures Es, with its own length).
    pub fn runs_of(self, test: Test) -> bool {
        match self {
            Method::Umbmark => matches!(test, Test::UmbmarkCw | Test::UmbmarkCcw),
            Method::Triangle => matches!(test, Test::Line | Test::Triangle),
        }
    }
}

fn empty_runs() -> Vec<PointText> {
    vec![PointText::default(); RUNS_PER_DIRECTION]
}

/// One round: runs with `params`, then (maybe) a correction sent.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RoundEntry {
    pub params: Params,
    #[serde(default)]
    pub method: Method,
    pub cw: Vec<PointText>,
    pub ccw: Vec<PointText>,
    /// Triangular Path: the straight lines and the triangles. Older files
    /// have neither: they get empty rows to type into.
    #[serde(default = "empty_runs")]
    pub line: Vec<PointText>,
    #[serde(default = "empty_runs")]
    pub triangle: Vec<PointText>,
    /// The straight line for Es: commanded and measured length, cm (both
    /// empty when not measured).
    #[serde(default)]
    pub line_commanded_cm: String,
    #[serde(default)]
    pub line_measured_cm: String,
    /// The parameters read back from the robot after sending this round's
    /// correction.
    #[serde(default)]
    pub applied: Option<Params>,
    /// The leg length (mm) the station's tests of this round ran with,
    /// recorded when the first of them started: the side of Borenstein's
    /// (or Ruan's) formulas. None for end points from elsewhere (typed, a
    /// CSV), and in files from before it was recorded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub leg_mm: Option<f64>,
}

impl RoundEntry {
    pub fn new(params: Params) -> Self {
        Self {
            params,
            method: Method::default(),
            cw: empty_runs(),
            ccw: empty_runs(),
            line: empty_runs(),
            triangle: empty_runs(),
            line_commanded_cm: String::new(),
            line_measured_cm: String::new(),
            applied: None,
            leg_mm: None,
        }
    }

    /// Whether any end point of the round's method is typed.
    fn has_points(&self) -> bool {
        let groups = match self.method {
            Method::Umbmark => [&self.cw, &self.ccw],
            Method::Triangle => [&self.line, &self.triangle],
        };
        groups
            .iter()
            .flat_map(|g| g.iter())
            .any(|p| !p.x.trim().is_empty() || !p.y.trim().is_empty())
    }
}

/// Legs this close (mm) are the same leg (the firmware keeps an f32; a side
/// is typed with a few decimals).
pub(crate) const SAME_LEG_MM: f64 = 0.05;

/// `test` is about to start with `leg_mm` legs: when it gives the last
/// round's end points, the round records the leg and the side follows it
/// (true: the session changed). Refused when the round already has end
/// points from tests with another leg: one round, one side.
pub fn record_leg(session: &mut Session, test: Test, leg_mm: f64) -> Result<bool, SessionError> {
    let k = session.rounds.len().saturating_sub(1);
    let Some(round) = session.rounds.get_mut(k) else {
        return Ok(false);
    };
    if !round.method.runs_of(test) {
        return Ok(false);
    }
    match round.leg_mm {
        Some(was) if (was - leg_mm).abs() <= SAME_LEG_MM => return Ok(false),
        Some(was) if round.has_points() => {
            return Err(SessionError::LegChanged {
                round: k,
                was_mm: was,
            })
        }
        _ => {}
    }
    round.leg_mm = Some(leg_mm);
    session.side_cm = format!("{}", leg_mm / 10.0);
    Ok(true)
}

/// Everything entered for one robot.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Session {
    /// Which robot (the session file's name).
    pub robot: String,
    /// Side of the square (or of the line and the triangle), cm, as typed.
    pub side_cm: String,
    /// First-order formulas or the exact solution of the same model, for
    /// every round (older files: first order, as they were computed).
    #[serde(default)]
    pub solution: Solution,
    pub rounds: Vec<RoundEntry>,
}

impl Session {
    pub fn new(robot: &str, params: Params) -> Self {
        Self {
            robot: robot.into(),
            side_cm: "200".into(),
            solution: Solution::default(),
            rounds: vec![RoundEntry::new(params)],
        }
    }
}

/// A file name for `robot`: letters, digits, '-' and '_' only.
pub fn file_name(robot: &str) -> String {
    let mut s: String = robot
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '-'
            }
        })
        .collect();
    s = s.trim_matches('-').to_string();
    if s.is_empty() {
        s = "robot".into();
    }
    format!("{s}.json")
}

/// The session in `path`, if there is one.
pub fn load(path: &Path) -> Result<Option<Session>, SessionError> {
    match input_file::read_text(path) {
        Ok(text) => serde_json::from_str(&text)
            .map(Some)
            .map_err(|source| SessionError::Parse {
                path: path.into(),
                source,
            }),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(source) => Err(SessionError::Read {
            path: path.into(),
            source,
        }),
    }
}

/// Write `session` to `path` atomically (a crash leaves the old file or the
/// new one, never half of one).
pub fn save(path: &Path, session: &Session) -> Result<(), SessionError> {
    let write = |source| SessionError::Write {
        path: path.into(),
        source,
    };
    let text =
        serde_json::to_string_pretty(session).map_err(|e| write(std::io::Error::other(e)))?;
    crate::output::write_atomic(path, text.as_bytes()).map_err(write)
}

mod evaluate;

pub use evaluate::{evaluate, Correction, Evaluation, RoundEval, TableRow};

/// Replace the end points of `round` with experiment `experiment` of a
/// table in the round's method's layout: UMBmark
/// (`experiment,direction,run,x_cm,y_cm`) or Triangular Path
/// (`experiment,test,run,x_cm,y_cm`, the triangles' y may be empty). `None`
/// takes the table's only experiment.
pub fn import_csv(
    session: &mut Session,
    round: usize,
    text: &str,
    experiment: Option<u32>,
) -> Result<(), SessionError> {
    let method = session
        .rounds
        .get(round)
        .map(|r| r.method)
        .unwrap_or_default();
    let experiment = match experiment {
        Some(e) => e,
        None => {
            let all = match method {
                Method::Umbmark => calib::csv::umbmark_experiments(text)?,
                Method::Triangle => calib::csv::triangle_experiments(text)?,
            };
            match all.as_slice() {
                [one] => *one,
                _ => {
                    return Err(SessionError::WhichExperiment {
                        method: method.name(),
                        list: all
                            .iter()
                            .map(u32::to_string)
                            .collect::<Vec<_>>()
                            .join(", "),
                    })
                }
            }
        }
    };
    let text_of = |points: Vec<PartialEndpoint>| {
        points
            .into_iter()
            .map(|p| PointText {
                x: p.x_cm.to_string(),
                y: p.y_cm.map(|y| y.to_string()).unwrap_or_default(),
            })
            .collect()
    };
    let partial = |points: &[Endpoint]| points.iter().map(|&p| p.into()).collect();
    let Some(r) = session.rounds.get_mut(round) else {
        return Ok(());
    };
    // The table's points are not the station's tests: their side is the
    // one typed.
    r.leg_mm = None;
    match method {
        Method::Umbmark => {
            let opts = calib::csv::CsvOptions::default();
            let runs = calib::csv::read_umbmark_csv(text, experiment, &opts)?;
            r.cw = text_of(partial(runs.cw()));
            r.ccw = text_of(partial(runs.ccw()));
        }
        Method::Triangle => {
            // As `hil calibrate` reads the thesis' table: one experiment
            // there lost its triangles' y.
            let opts = calib::csv::CsvOptions {
                triangle_y_optional: true,
                ..Default::default()
            };
            let exp = calib::csv::read_triangle_csv(text, experiment, &opts)?;
            r.line = text_of(partial(exp.line.runs()));
            r.triangle = text_of(exp.triangle.runs().to_vec());
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests;
