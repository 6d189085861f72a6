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
use crate::elf::Firmware;

/// One calibration round: the firmware's parameters, the experiment run with
/// them, and the correction it yields.
#[derive(Debug, Clone, serde::Serialize)]
pub struct CalibrationRound {
    pub round: usize,
    pub c_left: f64,
    pub c_right: f64,
    pub wheelbase_mm: f64,
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
}

/// How calibration rounds run.
#[derive(Debug, Clone, Copy)]
pub struct RoundOptions {
    /// The wheelbase the firmware's odometry uses in round 0, mm.
    pub wheelbase_mm: f64,
    /// Corrections after round 0.
    pub rounds: usize,
    pub solution: calib::Solution,
    /// The bench (its board; each run its own seed).
    pub bench: BenchOptions,
}

/// Calibrate the emulated robot: run the plan's experiment (UMBmark or
/// Triangular Path), send the correction (cL, cR, wheelbase) over the
/// protocol, run again, `rounds` corrections in all. The corrections compose:
/// each round's Ed and Eb are measured against the parameters the firmware
/// already used.
pub fn calibrate(
    firmware: &Firmware,
    robot: &RobotConfig,
    base: &Plan,
    options: &RoundOptions,
    progress: &(dyn Fn(usize, usize, f64) + Sync),
) -> Result<Vec<CalibrationRound>, ExperimentError> {
    let RoundOptions {
        wheelbase_mm,
        rounds,
        solution,
        bench,
    } = *options;
    let (mut cl, mut cr, mut b) = (1.0f64, 1.0f64, wheelbase_mm);
    let mut out = Vec::new();
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
        out.push(CalibrationRound {
            round,
            c_left: cl,
            c_right: cr,
            wheelbase_mm: b,
            report: rep,
        });
        (cl, cr, b) = (cl * dl, cr * dr, next_b);
    }
    Ok(out)
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
