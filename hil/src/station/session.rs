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

use calib::{
    triangle_correction, umbmark_correction, Endpoint, LineRuns, PartialEndpoint, ScaleError,
    Solution, TriangleParams, TriangleResult, TriangleRuns, UmbmarkParams, UmbmarkResult,
    UmbmarkRuns,
};
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
        }
    }
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
    pub method: Method,
    /// Runs with every needed value typed and valid, per direction (UMBmark)
    /// or per test (Triangular Path).
    pub complete_cw: usize,
    pub complete_ccw: usize,
    pub complete_line: usize,
    pub complete_triangle: usize,
    /// The calib crate's UMBmark analysis, once every row is complete and
    /// valid (UMBmark rounds).
    pub result: Option<UmbmarkResult>,
    /// The calib crate's Triangular Path analysis (triangle rounds).
    pub triangle: Option<TriangleResult>,
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
    /// `r{round}-{cw|ccw|line|triangle}-{run}-{x|y}` (run from 1),
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
        // Only the runs of the round's method count (and are checked): the
        // other method's rows stay as typed, for a switch back.
        let groups: [(&str, &Vec<PointText>); 2] = match round.method {
            Method::Umbmark => [("cw", &round.cw), ("ccw", &round.ccw)],
            Method::Triangle => [("line", &round.line), ("triangle", &round.triangle)],
        };
        let mut dirs: [Vec<PartialEndpoint>; 2] = Default::default();
        for (d, (name, points)) in groups.into_iter().enumerate() {
            // The thesis lost the y of one experiment's triangles (the
            // library then works from x alone and says so): a triangle
            // column with no y at all is taken as not measured.
            let y_optional = name == "triangle" && points.iter().all(|p| p.y.trim().is_empty());
            for (i, p) in points.iter().enumerate() {
                let id = |axis: &str| format!("r{k}-{name}-{}-{axis}", i + 1);
                let x = end_error(&p.x).map_err(|e| errors.insert(id("x"), e));
                let y = end_error(&p.y).map_err(|e| errors.insert(id("y"), e));
                match (x, y) {
                    (Ok(Some(x)), Ok(y)) if y.is_some() || y_optional => {
                        dirs[d].push(PartialEndpoint::new(x, y))
                    }
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
        let [first, second] = dirs;
        let complete = |v: &[PartialEndpoint]| v.iter().filter_map(|p| p.complete()).collect();
        let (n_first, n_second) = (first.len(), second.len());
        let (mut result, mut triangle) = (None, None);
        if let (true, Some(side_cm)) = (ok, side) {
            match round.method {
                Method::Umbmark => {
                    result = UmbmarkRuns::new(complete(&first), complete(&second))
                        .ok()
                        .map(|runs| {
                            let params = UmbmarkParams {
                                side_cm,
                                wheelbase_mm: round.params.wheelbase_mm,
                                scale,
                                solution: session.solution,
                                ..UmbmarkParams::default()
                            };
                            umbmark_correction(&runs, &params)
                        })
                }
                Method::Triangle => {
                    let runs = LineRuns::new(complete(&first))
                        .and_then(|line| TriangleRuns::new(second.clone()).map(|tri| (line, tri)));
                    triangle = runs.ok().map(|(line, tri)| {
                        let params = TriangleParams {
                            side_cm,
                            wheelbase_mm: round.params.wheelbase_mm,
                            scale,
                            solution: session.solution,
                            // One round runs its lines and triangles with the
                            // same parameters (the page sends once, after
                            // both), so the triangles' legs still carry the
                            // line's curvature.
                            line_correction_applied: false,
                            ..TriangleParams::default()
                        };
                        triangle_correction(&line, &tri, &params)
                    })
                }
            }
        }
        let factors = result
            .as_ref()
            .map(|r| (r.cl, r.cr, r.wheelbase_mm, r.es))
            .or(triangle
                .as_ref()
                .map(|r| (r.cl, r.cr, r.wheelbase_mm, r.es)));
        let send = factors.map(|(cl, cr, wheelbase_mm, es)| {
            let scale = es.unwrap_or(1.0);
            Correction {
                c_left: round.params.c_left * cl / scale,
                c_right: round.params.c_right * cr / scale,
                wheelbase_mm,
                es,
            }
        });
        let umbmark = round.method == Method::Umbmark;
        let count = |on: bool, n: usize| if on { n } else { 0 };
        rounds.push(RoundEval {
            method: round.method,
            complete_cw: count(umbmark, n_first),
            complete_ccw: count(umbmark, n_second),
            complete_line: count(!umbmark, n_first),
            complete_triangle: count(!umbmark, n_second),
            result,
            triangle,
            send,
        });
    }
    // Each round against the first, as the calib crate defines a round: the
    // wheelbase the first ran with, the one the later round measured.
    // Only rounds of the first round's method compare with it (a triangle's
    // error is not a square's); a triangle without y has no error to compare.
    let table = match rounds.first() {
        Some(first) => rounds
            .iter()
            .enumerate()
            .skip(1)
            .filter_map(|(k, ev)| {
                let row = match (&first.result, &ev.result, &first.triangle, &ev.triangle) {
                    (Some(r0), Some(rk), _, _) => Some(calib::improvement(r0, rk)),
                    (_, _, Some(t0), Some(tk)) => calib::round::triangle_improvement(t0, tk).ok(),
                    _ => None,
                };
                row.map(|row| TableRow { round: k, row })
            })
            .collect(),
        None => Vec::new(),
    };
    Evaluation {
        errors,
        rounds,
        table,
    }
}

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

    const LINE: [(f64, f64); 5] = [(5.8, 1.0), (7.1, 1.9), (3.6, 1.8), (2.5, 1.5), (4.4, 1.8)];
    const TRIANGLE: [(f64, f64); 5] = [
        (3.3, 1.9),
        (-6.9, 13.2),
        (-8.8, 19.0),
        (-9.1, 22.0),
        (-6.5, 4.7),
    ];

    fn triangle_session(solution: Solution) -> Session {
        let mut s = Session::new("t", NOMINAL);
        s.solution = solution;
        let r = &mut s.rounds[0];
        r.method = Method::Triangle;
        for (rows, points) in [(&mut r.line, LINE), (&mut r.triangle, TRIANGLE)] {
            for (row, (x, y)) in rows.iter_mut().zip(points) {
                row.x = x.to_string();
                row.y = y.to_string();
            }
        }
        s
    }

    fn library_triangle(solution: Solution) -> TriangleResult {
        let line = LineRuns::new(LINE.iter().map(|&(x, y)| Endpoint::new(x, y)).collect());
        let tri =
            TriangleRuns::complete(TRIANGLE.iter().map(|&(x, y)| Endpoint::new(x, y)).collect());
        triangle_correction(
            &line.unwrap(),
            &tri.unwrap(),
            &TriangleParams {
                side_cm: 200.0,
                wheelbase_mm: 130.0,
                line_correction_applied: false,
                solution,
                ..Default::default()
            },
        )
    }

    #[test]
    fn ten_triangle_points_give_the_libraries_correction() {
        for solution in [Solution::FirstOrder, Solution::Exact] {
            let ev = evaluate(&triangle_session(solution));
            assert!(ev.errors.is_empty(), "{:?}", ev.errors);
            let round = &ev.rounds[0];
            assert!(round.result.is_none());
            assert_eq!((round.complete_line, round.complete_triangle), (5, 5));
            let got = round.triangle.as_ref().unwrap();
            let want = library_triangle(solution);
            assert_eq!(got, &want);
            assert_eq!(got.solution, solution);
            let send = round.send.unwrap();
            assert_eq!(send.c_left, want.cl);
            assert_eq!(send.c_right, want.cr);
            assert_eq!(send.wheelbase_mm, want.wheelbase_mm);
        }
        assert_ne!(
            library_triangle(Solution::Exact).eb,
            library_triangle(Solution::FirstOrder).eb
        );
    }

    #[test]
    fn triangle_fields_are_checked_and_the_y_column_may_be_unmeasured() {
        let mut s = triangle_session(Solution::FirstOrder);
        s.rounds[0].line[1].x = "7,1".into();
        s.rounds[0].triangle[3].y = "".into();
        s.rounds[0].line[4].y = "x".into();
        let ev = evaluate(&s);
        assert!(ev.errors["r0-triangle-4-y"].contains("missing"));
        assert!(ev.errors["r0-line-5-y"].contains("not a number"));
        assert!(!ev.errors.contains_key("r0-line-2-x"));
        assert!(ev.rounds[0].triangle.is_none());
        // No triangle y at all: x alone, as the library allows.
        let mut s = triangle_session(Solution::FirstOrder);
        for p in &mut s.rounds[0].triangle {
            p.y.clear();
        }
        let ev = evaluate(&s);
        assert!(ev.errors.is_empty(), "{:?}", ev.errors);
        let r = ev.rounds[0].triangle.as_ref().unwrap();
        assert_eq!(r.triangle_centroid.y_cm, None);
        assert!(ev.rounds[0].send.is_some());
    }

    #[test]
    fn triangle_csv_import_fills_the_round() {
        let mut s = Session::new("t", NOMINAL);
        s.rounds[0].method = Method::Triangle;
        let mut text = String::from("experiment,test,run,x_cm,y_cm\n");
        for (test, points) in [("line", LINE), ("triangle", TRIANGLE)] {
            for (i, (x, y)) in points.iter().enumerate() {
                text += &format!("1,{test},{},{x},{y}\n", i + 1);
                // Experiment 2 as the thesis' table has it: no triangle y.
                let y = if test == "line" {
                    y.to_string()
                } else {
                    String::new()
                };
                text += &format!("2,{test},{},{x},{y}\n", i + 1);
            }
        }
        let e = import_csv(&mut s, 0, &text, None).unwrap_err();
        assert!(
            e.to_string().contains("Triangular Path experiments 1, 2"),
            "{e}"
        );
        import_csv(&mut s, 0, &text, Some(1)).unwrap();
        assert_eq!(
            evaluate(&s).rounds[0].triangle,
            Some(library_triangle(Solution::FirstOrder))
        );
        import_csv(&mut s, 0, &text, Some(2)).unwrap();
        assert_eq!(s.rounds[0].triangle[2].y, "");
        let ev = evaluate(&s);
        assert!(ev.errors.is_empty(), "{:?}", ev.errors);
        assert!(ev.rounds[0].triangle.is_some());
        // The UMBmark rows were left alone.
        assert!(s.rounds[0].cw.iter().all(|p| p.x.is_empty()));
    }

    #[test]
    fn a_session_from_before_the_triangle_loads_as_umbmark() {
        let mut old = serde_json::to_value(filled()).unwrap();
        old.as_object_mut().unwrap().remove("solution");
        for key in ["method", "line", "triangle"] {
            old["rounds"][0].as_object_mut().unwrap().remove(key);
        }
        let s: Session = serde_json::from_value(old).unwrap();
        assert_eq!(s.rounds[0].method, Method::Umbmark);
        assert_eq!(s.solution, Solution::FirstOrder);
        assert_eq!(s.rounds[0].triangle.len(), RUNS_PER_DIRECTION);
        assert_eq!(s, filled());
    }
}
