//! A session checked field by field: what is wrong with each typed value,
//! and the corrections of the rounds whose values are complete.

use std::collections::BTreeMap;

use calib::{
    triangle_correction, umbmark_correction, LineRuns, PartialEndpoint, ScaleError, TriangleParams,
    TriangleResult, TriangleRuns, UmbmarkParams, UmbmarkResult, UmbmarkRuns,
};
use serde::Serialize;

use super::{Method, PointText, Session, MAX_ERROR_CM, SAME_LEG_MM};

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
    let last = session.rounds.len().saturating_sub(1);
    for (k, round) in session.rounds.iter().enumerate() {
        let mut ok = true;
        // The side is the leg the round's tests ran with, when the station
        // ran them. The last round's correction is refused while the side
        // typed says otherwise (a 300 mm leg computed as 200 cm gives a
        // correction 6.7 times too small); earlier rounds were sent already.
        let side = match (round.leg_mm, side) {
            (Some(leg), Some(typed)) if k == last && (typed * 10.0 - leg).abs() > SAME_LEG_MM => {
                errors.insert(
                    "side_cm".into(),
                    format!(
                        "this round's tests ran with {leg} mm legs: the side is {} cm, not {typed}",
                        leg / 10.0
                    ),
                );
                None
            }
            (Some(leg), _) => Some(leg / 10.0),
            (None, side) => side,
        };
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
