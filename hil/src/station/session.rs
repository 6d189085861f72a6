//! One robot's calibration session, as the operator typed it: the end points
//! of each round, the straight-line measurement for Es, the parameters the
//! robot ran with, and what was sent to it afterwards.
//!
//! Fields are kept as typed (text), so that a half-typed "-1" survives a
//! closed tab; [`evaluate`] parses and validates them field by field and
//! hands complete rounds to the `calib` crate. The file is rewritten
//! atomically on every change ([`save`]).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use calib::{umbmark_correction, Endpoint, ScaleError, UmbmarkParams, UmbmarkResult, UmbmarkRuns};
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Runs per direction in a fresh round (UMBmark asks for five).
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
    #[error("the CSV holds UMBmark experiments {0}: give the one to import")]
    WhichExperiment(String),
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

/// One round: runs with `params`, then (maybe) a correction sent.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RoundEntry {
    pub params: Params,
    pub cw: Vec<PointText>,
    pub ccw: Vec<PointText>,
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
}

impl RoundEntry {
    pub fn new(params: Params) -> Self {
        Self {
            params,
            cw: vec![PointText::default(); RUNS_PER_DIRECTION],
            ccw: vec![PointText::default(); RUNS_PER_DIRECTION],
            line_commanded_cm: String::new(),
            line_measured_cm: String::new(),
            applied: None,
        }
    }
}

/// Everything entered for one robot.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Session {
    /// Which robot (the session file's name).
    pub robot: String,
    /// Side of the square, cm, as typed.
    pub side_cm: String,
    pub rounds: Vec<RoundEntry>,
}

impl Session {
    pub fn new(robot: &str, params: Params) -> Self {
        Self {
            robot: robot.into(),
            side_cm: "200".into(),
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
    match std::fs::read_to_string(path) {
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

/// What to send to the robot after a round.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Correction {
    /// The round's factors composed with the ones the robot ran with (and
    /// divided by Es when measured: the firmware has no separate scale).
    pub c_left: f64,
    pub c_right: f64,
    pub wheelbase_mm: f64,
    pub es: Option<f64>,
}

/// One round, evaluated.
#[derive(Debug, Clone, Serialize)]
pub struct RoundEval {
    /// Runs with both values typed and valid, per direction.
    pub complete_cw: usize,
    pub complete_ccw: usize,
    /// The calib crate's analysis, once every row is complete and valid.
    pub result: Option<UmbmarkResult>,
    pub send: Option<Correction>,
}

/// One row of the before/after table (round k against round 0).
#[derive(Debug, Clone, Serialize)]
pub struct TableRow {
    pub round: usize,
    #[serde(flatten)]
    pub row: calib::Round,
}

/// A session checked field by field.
#[derive(Debug, Clone, Serialize)]
pub struct Evaluation {
    /// Field id -> what is wrong with it. Ids: `side_cm`,
    /// `r{round}-{cw|ccw}-{run}-{x|y}` (run from 1),
    /// `r{round}-line_commanded_cm`, `r{round}-line_measured_cm`.
    pub errors: BTreeMap<String, String>,
    pub rounds: Vec<RoundEval>,
    pub table: Vec<TableRow>,
}

/// Parse a typed number: Ok(None) when empty.
fn number(text: &str) -> Result<Option<f64>, String> {
    let t = text.trim();
    if t.is_empty() {
        return Ok(None);
    }
    // A decimal comma, as many keyboards type it.
    let v: f64 = t
        .replace(',', ".")
        .parse()
        .map_err(|_| format!("{t:?} is not a number: type centimetres, e.g. -12.5"))?;
    if !v.is_finite() {
        return Err(format!("{t:?} is not a finite number"));
    }
    Ok(Some(v))
}

fn end_error(text: &str) -> Result<Option<f64>, String> {
    let v = number(text)?;
    if let Some(v) = v.filter(|v| v.abs() > MAX_ERROR_CM) {
        return Err(format!(
            "{v} cm is more than {MAX_ERROR_CM} cm from the start: end errors are in centimetres"
        ));
    }
    Ok(v)
}

fn positive(text: &str, what: &str) -> Result<Option<f64>, String> {
    match number(text)? {
        Some(v) if v <= 0.0 => Err(format!("{what} must be above 0")),
        v => Ok(v),
    }
}

/// Check every field and compute what can be computed.
pub fn evaluate(session: &Session) -> Evaluation {
    let mut errors = BTreeMap::new();
    let side = match positive(&session.side_cm, "the side") {
        Ok(Some(v)) => Some(v),
        Ok(None) => {
            errors.insert("side_cm".into(), "give the side of the square in cm".into());
            None
        }
        Err(e) => {
            errors.insert("side_cm".into(), e);
            None
        }
    };
    let mut rounds = Vec::new();
    for (k, round) in session.rounds.iter().enumerate() {
        let mut ok = true;
        let mut dirs: [Vec<Endpoint>; 2] = Default::default();
        for (d, (name, points)) in [("cw", &round.cw), ("ccw", &round.ccw)]
            .into_iter()
            .enumerate()
        {
            for (i, p) in points.iter().enumerate() {
                let id = |axis: &str| format!("r{k}-{name}-{}-{axis}", i + 1);
                let x = end_error(&p.x).map_err(|e| errors.insert(id("x"), e));
                let y = end_error(&p.y).map_err(|e| errors.insert(id("y"), e));
                match (x, y) {
                    (Ok(Some(x)), Ok(Some(y))) => dirs[d].push(Endpoint::new(x, y)),
                    (Ok(Some(_)), Ok(None)) => {
                        errors.insert(id("y"), "y is missing".into());
                        ok = false;
                    }
                    (Ok(None), Ok(Some(_))) => {
                        errors.insert(id("x"), "x is missing".into());
                        ok = false;
                    }
                    (Ok(None), Ok(None)) => ok = false,
                    _ => ok = false,
                }
            }
        }
        let commanded = positive(&round.line_commanded_cm, "the commanded length");
        let measured = positive(&round.line_measured_cm, "the measured length");
        let scale = match (commanded, measured) {
            (Ok(Some(c)), Ok(Some(m))) => Some(ScaleError {
                commanded_cm: c,
                measured_cm: m,
            }),
            (Ok(None), Ok(None)) => None,
            (c, m) => {
                for (field, r, other) in [
                    ("line_commanded_cm", c, "measured"),
                    ("line_measured_cm", m, "commanded"),
                ] {
                    let msg = match r {
                        Err(e) => e,
                        Ok(None) => format!("give this too, or clear the {other} length"),
                        Ok(Some(_)) => continue,
                    };
                    errors.insert(format!("r{k}-{field}"), msg);
                }
                ok = false;
                None
            }
        };
        let [cw, ccw] = dirs;
        let (complete_cw, complete_ccw) = (cw.len(), ccw.len());
        let result = match (ok, side) {
            (true, Some(side_cm)) => UmbmarkRuns::new(cw, ccw).ok().map(|runs| {
                let params = UmbmarkParams {
                    side_cm,
                    wheelbase_mm: round.params.wheelbase_mm,
                    scale,
                    ..UmbmarkParams::default()
                };
                umbmark_correction(&runs, &params)
            }),
            _ => None,
        };
        let send = result.as_ref().map(|r| {
            let scale = r.es.unwrap_or(1.0);
            Correction {
                c_left: round.params.c_left * r.cl / scale,
                c_right: round.params.c_right * r.cr / scale,
                wheelbase_mm: r.wheelbase_mm,
                es: r.es,
            }
        });
        rounds.push(RoundEval {
            complete_cw,
            complete_ccw,
            result,
            send,
        });
    }
    // Each round against the first, as the calib crate defines a round: the
    // wheelbase the first ran with, the one the later round measured.
    let table = match rounds.first() {
        Some(RoundEval {
            result: Some(r0), ..
        }) => rounds
            .iter()
            .enumerate()
            .skip(1)
            .filter_map(|(k, ev)| {
                ev.result.as_ref().map(|rk| TableRow {
                    round: k,
                    row: calib::improvement(r0, rk),
                })
            })
            .collect(),
        _ => Vec::new(),
    };
    Evaluation {
        errors,
        rounds,
        table,
    }
}

/// Replace the end points of `round` with experiment `experiment` of a
/// UMBmark table (`experiment,direction,run,x_cm,y_cm`); `None` takes the
/// table's only experiment.
pub fn import_csv(
    session: &mut Session,
    round: usize,
    text: &str,
    experiment: Option<u32>,
) -> Result<(), SessionError> {
    let experiment = match experiment {
        Some(e) => e,
        None => {
            let all = calib::csv::umbmark_experiments(text)?;
            match all.as_slice() {
                [one] => *one,
                _ => {
                    return Err(SessionError::WhichExperiment(
                        all.iter()
                            .map(u32::to_string)
                            .collect::<Vec<_>>()
                            .join(", "),
                    ))
                }
            }
        }
    };
    let runs = calib::csv::read_umbmark_csv(text, experiment, &calib::csv::CsvOptions::default())?;
    let text_of = |points: &[Endpoint]| {
        points
            .iter()
            .map(|p| PointText {
                x: p.x_cm.to_string(),
                y: p.y_cm.to_string(),
            })
            .collect()
    };
    if let Some(r) = session.rounds.get_mut(round) {
        r.cw = text_of(runs.cw());
        r.ccw = text_of(runs.ccw());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const NOMINAL: Params = Params {
        c_left: 1.0,
        c_right: 1.0,
        wheelbase_mm: 130.0,
    };

    fn filled() -> Session {
        let mut s = Session::new("test", NOMINAL);
        for (i, p) in s.rounds[0].cw.iter_mut().enumerate() {
            p.x = format!("{}", -10.0 - i as f64);
            p.y = format!("{}", -8.0 + 0.5 * i as f64);
        }
        for (i, p) in s.rounds[0].ccw.iter_mut().enumerate() {
            p.x = format!("{}", 4.0 + i as f64);
            p.y = format!("{}", -3.0 - 0.25 * i as f64);
        }
        s
    }

    #[test]
    fn a_complete_round_gives_the_libraries_correction() {
        let s = filled();
        let ev = evaluate(&s);
        assert!(ev.errors.is_empty(), "{:?}", ev.errors);
        let got = ev.rounds[0].result.as_ref().unwrap();
        let cw = (0..5)
            .map(|i| Endpoint::new(-10.0 - i as f64, -8.0 + 0.5 * i as f64))
            .collect();
        let ccw = (0..5)
            .map(|i| Endpoint::new(4.0 + i as f64, -3.0 - 0.25 * i as f64))
            .collect();
        let want = umbmark_correction(
            &UmbmarkRuns::new(cw, ccw).unwrap(),
            &UmbmarkParams {
                side_cm: 200.0,
                wheelbase_mm: 130.0,
                ..Default::default()
            },
        );
        assert_eq!(got, &want);
        let send = ev.rounds[0].send.unwrap();
        assert_eq!(send.c_left, want.cl);
        assert_eq!(send.wheelbase_mm, want.wheelbase_mm);
    }

    #[test]
    fn each_bad_field_is_named() {
        let mut s = filled();
        s.rounds[0].cw[2].x = "abc".into();
        s.rounds[0].ccw[4].y = "".into();
        s.rounds[0].line_commanded_cm = "200".into();
        s.side_cm = "-3".into();
        let ev = evaluate(&s);
        assert!(ev.errors["r0-cw-3-x"].contains("not a number"));
        assert!(ev.errors["r0-ccw-5-y"].contains("missing"));
        assert!(ev.errors["r0-line_measured_cm"].contains("give this too"));
        assert!(ev.errors["side_cm"].contains("above 0"));
        assert!(ev.rounds[0].result.is_none());
    }

    #[test]
    fn es_scales_both_factors_and_the_rounds_compose() {
        let mut s = filled();
        s.rounds[0].line_commanded_cm = "200".into();
        s.rounds[0].line_measured_cm = "196".into();
        let ev = evaluate(&s);
        let r = ev.rounds[0].result.as_ref().unwrap();
        let send = ev.rounds[0].send.unwrap();
        assert_eq!(r.es, Some(200.0 / 196.0));
        assert_eq!(send.c_left, r.cl / (200.0 / 196.0));
        // A second round run with the sent parameters composes with them.
        let applied = Params {
            c_left: send.c_left,
            c_right: send.c_right,
            wheelbase_mm: send.wheelbase_mm,
        };
        let mut next = filled().rounds.remove(0);
        next.params = applied;
        s.rounds.push(next);
        let ev = evaluate(&s);
        let r1 = ev.rounds[1].result.as_ref().unwrap();
        assert_eq!(ev.rounds[1].send.unwrap().c_left, applied.c_left * r1.cl);
        assert_eq!(ev.table.len(), 1);
        assert_eq!(ev.table[0].row, calib::improvement(r, r1));
    }

    #[test]
    fn csv_import_fills_the_round() {
        let mut s = Session::new("t", NOMINAL);
        let rows = |exp: u32| {
            (1..=5)
                .flat_map(|i| {
                    [
                        format!("{exp},cw,{i},-1.5,{i}\n"),
                        format!("{exp},ccw,{i},3,4.25\n"),
                    ]
                })
                .collect::<String>()
        };
        let text = format!("experiment,direction,run,x_cm,y_cm\n{}", rows(1));
        import_csv(&mut s, 0, &text, None).unwrap();
        assert_eq!(
            s.rounds[0].cw[1],
            PointText {
                x: "-1.5".into(),
                y: "2".into()
            }
        );
        assert_eq!(s.rounds[0].ccw.len(), 5);
        assert!(evaluate(&s).rounds[0].result.is_some());
        let two = format!("{text}{}", rows(2));
        let e = import_csv(&mut s, 0, &two, None).unwrap_err();
        assert!(e.to_string().contains("1, 2"), "{e}");
    }

    #[test]
    fn saved_sessions_load_back() {
        let dir = std::env::temp_dir().join(format!("station-session-{}", std::process::id()));
        let path = dir.join(file_name("emulated henrytwo/ideal"));
        assert!(path.ends_with("emulated-henrytwo-ideal.json"));
        let s = filled();
        save(&path, &s).unwrap();
        assert_eq!(load(&path).unwrap(), Some(s));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
