//! Calibration rounds on the emulated robot: run an experiment, send its
//! correction to the firmware over the protocol, run again; and the rounds
//! in the layout of the thesis' Table 10.

use plant_model::RobotConfig;

use super::plan::{Experiment, Plan};
use super::runs::{execute, RunSet};
use super::triangle::{triangle_report, TriangleReport};
use super::umbmark::{report, Report};
use super::ExperimentError;
use crate::bench::BenchOptions;
use crate::firmware::elf::Firmware;
use crate::firmware::link::Param;

/// One calibration round: the firmware's parameters, the experiment run with
/// them, and the correction it yields.
#[derive(Debug, Clone, serde::Serialize)]
pub struct CalibrationRound {
    pub round: usize,
    pub c_left: f64,
    pub c_right: f64,
    pub wheelbase_mm: f64,
    /// The round's systematic error, cm: UMBmark's E_max,syst (the larger
    /// centroid distance), the Triangular Path's triangle centroid distance.
    pub error_cm: Option<f64>,
    pub report: RoundReport,
}

/// The experiment of a calibration round.
#[derive(Debug, Clone, serde::Serialize)]
#[serde(tag = "method", rename_all = "snake_case")]
pub enum RoundReport {
    Umbmark(Report),
    Triangle(TriangleReport),
}

impl RoundReport {
    /// The correction measured against the parameters of the round:
    /// (cL, cR, wheelbase in mm).
    pub fn correction(&self) -> (f64, f64, f64) {
        match self {
            RoundReport::Umbmark(r) => (r.result.cl, r.result.cr, r.result.wheelbase_mm),
            RoundReport::Triangle(r) => (r.result.cl, r.result.cr, r.result.wheelbase_mm),
        }
    }

    /// The systematic error the rounds drive down, cm (see
    /// [`CalibrationRound::error_cm`]); `None` for a triangle whose y is
    /// unknown.
    pub fn error_cm(&self) -> Option<f64> {
        match self {
            RoundReport::Umbmark(r) => Some(r.result.e_max_cm),
            RoundReport::Triangle(r) => r.result.triangle_r_cm,
        }
    }

    /// The round's errors, one line.
    pub fn summary(&self) -> String {
        match self {
            RoundReport::Umbmark(r) => format!(
                "r_cg CW {:.2} cm, CCW {:.2} cm, E_max {:.2} cm",
                r.result.r_cg_cw_cm, r.result.r_cg_ccw_cm, r.result.e_max_cm
            ),
            RoundReport::Triangle(r) => format!(
                "line centroid ({:.2}, {:.2}) cm, triangle centroid {} cm",
                r.result.line_centroid.x_cm,
                r.result.line_centroid.y_cm,
                r.result
                    .triangle_r_cm
                    .map_or("unknown".to_string(), |e| format!("{e:.2}"))
            ),
        }
    }

    /// The runs of the round that did not complete.
    fn incomplete(&self) -> usize {
        let rows = match self {
            RoundReport::Umbmark(r) => &r.runs,
            RoundReport::Triangle(r) => &r.runs,
        };
        rows.iter().filter(|r| !r.completed).count()
    }
}

/// How calibration rounds run.
#[derive(Debug, Clone, Copy)]
pub struct RoundOptions {
    /// The wheelbase the firmware's odometry uses in round 0, mm.
    pub wheelbase_mm: f64,
    /// Corrections after round 0, at most.
    pub rounds: usize,
    /// Stop once a round's systematic error ([`CalibrationRound::error_cm`])
    /// is at most this, cm.
    pub until_cm: Option<f64>,
    pub solution: calib::Solution,
    /// The bench (its board; each run its own seed).
    pub bench: BenchOptions,
}

/// Why the rounds stopped.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(tag = "reason", rename_all = "snake_case")]
pub enum Stop {
    /// Every round asked for ran (no `until_cm`).
    RoundsDone,
    /// A round's error reached `until_cm`.
    Reached { until_cm: f64 },
    /// Every round ran and none reached `until_cm`.
    NotReached { until_cm: f64 },
    /// Runs of the last round did not complete: its end points are no
    /// measurement, and no correction was made from them.
    Incomplete { runs: usize },
    /// The last round's correction lies outside what the firmware accepts:
    /// it was not sent (the firmware would have refused it and kept its
    /// value), and the rounds stopped.
    Refused {
        param: &'static str,
        value: f64,
        min: f64,
        max: f64,
    },
}

impl Stop {
    /// Whether the rounds did what was asked.
    pub fn done(&self) -> bool {
        matches!(self, Stop::RoundsDone | Stop::Reached { .. })
    }

    /// One line for people.
    pub fn describe(&self) -> String {
        match self {
            Stop::RoundsDone => "every round asked for ran".into(),
            Stop::Reached { until_cm } => format!("the error reached {until_cm} cm"),
            Stop::NotReached { until_cm } => {
                format!("no round's error reached {until_cm} cm; give more --rounds")
            }
            Stop::Incomplete { runs } => format!(
                "{runs} runs of the last round did not complete: it measured nothing, and no correction was made from it"
            ),
            Stop::Refused {
                param,
                value,
                min,
                max,
            } => format!(
                "the next correction sets {param} = {value:.5}, outside what the firmware accepts ({min} to {max}): not sent, rounds stopped"
            ),
        }
    }
}

/// Calibration rounds: each round, why they stopped, and the round whose
/// parameters gave the smallest error (the ones to keep).
#[derive(Debug, Clone, serde::Serialize)]
pub struct Calibration {
    pub rounds: Vec<CalibrationRound>,
    pub stop: Stop,
    /// Index into `rounds` of the smallest error; `None` when no round
    /// measured one.
    pub best: Option<usize>,
}

/// Calibrate the emulated robot: run the plan's experiment (UMBmark or
/// Triangular Path), send the correction (cL, cR, wheelbase) over the
/// protocol, run again, at most `rounds` corrections, stopping early at
/// `until_cm`. The corrections compose: each round's Ed and Eb are measured
/// against the parameters the firmware already used. A round whose runs did
/// not all complete, or a correction the firmware would refuse, stops the
/// rounds ([`Stop`]): nothing is reported as used that the firmware did not
/// use.
pub fn calibrate(
    firmware: &Firmware,
    robot: &RobotConfig,
    base: &Plan,
    options: &RoundOptions,
    progress: &(dyn Fn(usize, usize, f64) + Sync),
) -> Result<Calibration, ExperimentError> {
    let RoundOptions {
        wheelbase_mm,
        rounds,
        until_cm,
        solution,
        bench,
    } = *options;
    let (mut cl, mut cr, mut b) = (1.0f64, 1.0f64, wheelbase_mm);
    let mut out = Vec::new();
    let mut stop = match until_cm {
        Some(until_cm) => Stop::NotReached { until_cm },
        None => Stop::RoundsDone,
    };
    for round in 0..=rounds {
        let mut plan = base.clone();
        if round > 0 {
            // After the robot's geometry: the corrections win.
            plan.params
                .extend([(1, cl as f32), (2, cr as f32), (3, b as f32)]);
        }
        let runs = execute(firmware, robot, &plan, &plan.runs(), bench, &|n, t| {
            progress(round, n, t)
        })?;
        let full = RunSet::new(plan, None, runs);
        let rep = match full.plan.experiment {
            Experiment::Umbmark => RoundReport::Umbmark(report(&full, b, solution)?),
            Experiment::Triangle => RoundReport::Triangle(triangle_report(&full, b, solution)?),
        };
        let (dl, dr, next_b) = rep.correction();
        let incomplete = rep.incomplete();
        let error_cm = (incomplete == 0).then(|| rep.error_cm()).flatten();
        out.push(CalibrationRound {
            round,
            c_left: cl,
            c_right: cr,
            wheelbase_mm: b,
            error_cm,
            report: rep,
        });
        if incomplete > 0 {
            stop = Stop::Incomplete { runs: incomplete };
            break;
        }
        if let (Some(until_cm), Some(e)) = (until_cm, error_cm) {
            if e <= until_cm {
                stop = Stop::Reached { until_cm };
                break;
            }
        }
        if round == rounds {
            break;
        }
        (cl, cr, b) = (cl * dl, cr * dr, next_b);
        if let Some(refused) = refused(&[
            (Param::CorrLeft, cl),
            (Param::CorrRight, cr),
            (Param::WheelbaseMm, b),
        ]) {
            stop = refused;
            break;
        }
    }
    let best = out
        .iter()
        .enumerate()
        .filter_map(|(i, r)| r.error_cm.map(|e| (i, e)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(i, _)| i);
    Ok(Calibration {
        rounds: out,
        stop,
        best,
    })
}

/// The stop for the first of `values` the firmware would refuse, if any.
fn refused(values: &[(Param, f64)]) -> Option<Stop> {
    values.iter().find_map(|&(p, v)| {
        p.check(v as f32).is_err().then(|| {
            let r = p.range();
            Stop::Refused {
                param: p.name(),
                value: v,
                min: r.min.into(),
                max: r.max.into(),
            }
        })
    })
}

/// The rounds in the thesis' Table 10 layout: each round against the first
/// (UMBmark: the mean end error; Triangular Path: the triangle centroid's
/// distance).
pub fn table10(
    rounds: &[CalibrationRound],
) -> Result<Vec<(String, calib::Round)>, ExperimentError> {
    let Some(first) = rounds.first() else {
        return Ok(Vec::new());
    };
    rounds
        .iter()
        .skip(1)
        .map(|r| {
            let (name, mut round) = match (&first.report, &r.report) {
                (RoundReport::Umbmark(a), RoundReport::Umbmark(b)) => {
                    ("umbmark", calib::improvement(&a.result, &b.result))
                }
                (RoundReport::Triangle(a), RoundReport::Triangle(b)) => (
                    "triangle",
                    calib::round::triangle_improvement(&a.result, &b.result)?,
                ),
                _ => {
                    return Err(ExperimentError::Mismatch(
                        "the rounds ran different experiments".into(),
                    ))
                }
            };
            // The wheelbase "after" is the one the firmware used in that round.
            round.wheelbase_after_mm = r.wheelbase_mm;
            round.wheelbase_correction_pct =
                (r.wheelbase_mm - first.wheelbase_mm) / first.wheelbase_mm * 100.0;
            Ok((format!("{name} round {}", r.round), round))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_correction_outside_the_firmwares_range_stops_the_rounds() {
        // The first-order rounds sent wheelbases of 48, 18 and 6 mm;
        // the firmware kept 130 mm while the report printed them as used.
        let stop = refused(&[
            (Param::CorrLeft, 1.01),
            (Param::CorrRight, 0.99),
            (Param::WheelbaseMm, 6.53),
        ])
        .expect("6.53 mm is below the firmware's wheelbase range");
        let r = Param::WheelbaseMm.range();
        assert_eq!(
            stop,
            Stop::Refused {
                param: Param::WheelbaseMm.name(),
                value: 6.53,
                min: r.min.into(),
                max: r.max.into(),
            }
        );
        assert!(!stop.done());
        assert!(stop.describe().contains("not sent"), "{}", stop.describe());
        assert_eq!(
            refused(&[(Param::CorrLeft, 1.01), (Param::WheelbaseMm, 127.0)]),
            None
        );
        let c = Param::CorrLeft.range();
        assert!(matches!(
            refused(&[(Param::CorrLeft, f64::from(c.max) * 1.5)]),
            Some(Stop::Refused { param, .. }) if param == Param::CorrLeft.name()
        ));
    }

    #[test]
    fn only_finished_rounds_are_done() {
        assert!(Stop::RoundsDone.done());
        assert!(Stop::Reached { until_cm: 5.0 }.done());
        assert!(!Stop::NotReached { until_cm: 5.0 }.done());
        assert!(!Stop::Incomplete { runs: 2 }.done());
    }
}
