//! Calibration rounds on the emulated robot: run an experiment, send its
//! correction to the firmware over the protocol, run again; and the rounds
//! in the layout of the thesis' Table 10.
//!
//! Each round's correction is line-searched: the whole correction is tried
//! first, and a round whose systematic error rises above the last kept
//! round's by more than the floor noise ([`RoundReport::noise_cm`]) is not
//! kept; the correction is tried again at half and a quarter of its size
//! ([`STEPS`]). Near what the error model can represent a whole correction
//! overshoots (turns' whole counts, turns that end differently CW and CCW),
//! and the rounds went up and down; kept rounds now never rise beyond the
//! noise, and every attempt not kept is reported.

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
    /// The share of the last kept round's correction these parameters
    /// apply (one of [`STEPS`]); `None` in round 0.
    pub step: Option<f64>,
    /// The round's systematic error, cm: UMBmark's E_max,syst (the larger
    /// centroid distance), the Triangular Path's triangle centroid distance.
    pub error_cm: Option<f64>,
    /// The floor noise of `error_cm`, cm ([`RoundReport::noise_cm`]).
    pub noise_cm: Option<f64>,
    pub report: RoundReport,
}

impl CalibrationRound {
    /// Whether this round's error is above `kept`'s by more than the noise
    /// of the two (the standard error of their difference): a correction
    /// that made things worse. A round with no error (incomplete, or a
    /// triangle whose y is unknown) is no evidence either way.
    pub fn rises_above(&self, kept: &CalibrationRound) -> bool {
        match (self.error_cm, kept.error_cm) {
            (Some(e), Some(k)) => {
                let n = self
                    .noise_cm
                    .unwrap_or(0.0)
                    .hypot(kept.noise_cm.unwrap_or(0.0));
                e - k > n
            }
            _ => false,
        }
    }
}

/// The shares of a round's correction tried, in order: the whole of it,
/// then half and a quarter (on a log scale: cL^s, cR^s, (b'/b)^s). A step
/// that does not raise the error is kept; when none of them does, the
/// rounds stop ([`Stop::NoDescent`]).
pub const STEPS: [f64; 3] = [1.0, 0.5, 0.25];

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

    /// The floor noise of [`RoundReport::error_cm`], cm: the standard error
    /// of the measured centroid's distance from the start (the scatter of
    /// the runs' end points along that direction, over √n). The runs differ
    /// only by what the plant draws from each run's seed (floor noise, a
    /// robot's random effects); a robot without any has none, and any rise
    /// counts. `None` when the round measured no error.
    pub fn noise_cm(&self) -> Option<f64> {
        self.error_cm()?;
        let (rows, group) = match self {
            RoundReport::Umbmark(r) => {
                let cw = r.result.r_cg_cw_cm >= r.result.r_cg_ccw_cm;
                (&r.runs, if cw { "cw" } else { "ccw" })
            }
            RoundReport::Triangle(r) => (&r.runs, "triangle"),
        };
        let points: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.direction == group)
            .map(|r| (r.x_cm, r.y_cm))
            .collect();
        Some(radial_standard_error(&points))
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
    /// Every step of the next round's correction ([`STEPS`]) raised the
    /// error above the last kept round's by more than the floor noise: the
    /// error is at what the error model can correct, and the rounds kept
    /// the last round. Done unless `until_cm` was asked for.
    NoDescent { round: usize, until_cm: Option<f64> },
}

impl Stop {
    /// Whether the rounds did what was asked.
    pub fn done(&self) -> bool {
        matches!(
            self,
            Stop::RoundsDone | Stop::Reached { .. } | Stop::NoDescent { until_cm: None, .. }
        )
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
            Stop::NoDescent { round, until_cm } => {
                let steps: Vec<String> = STEPS.iter().map(|s| s.to_string()).collect();
                let mut d = format!(
                    "round {round} raised the error beyond the floor noise at every step of its correction tried ({}): the rounds kept round {}",
                    steps.join(", "),
                    round - 1
                );
                if let Some(until_cm) = until_cm {
                    d += &format!(", whose error is above {until_cm} cm");
                }
                d
            }
        }
    }
}

/// Calibration rounds: each round kept, the attempts not kept, why they
/// stopped, and the round whose parameters gave the smallest error (the
/// ones to keep).
#[derive(Debug, Clone, serde::Serialize)]
pub struct Calibration {
    /// The rounds kept, round 0 first: none raises the error above the one
    /// before by more than the floor noise.
    pub rounds: Vec<CalibrationRound>,
    /// The attempts that raised the error and were tried again at a smaller
    /// step ([`STEPS`]), in the order they ran.
    pub rejected: Vec<CalibrationRound>,
    pub stop: Stop,
    /// Index into `rounds` of the smallest error; `None` when no round
    /// measured one.
    pub best: Option<usize>,
}

/// Calibrate the emulated robot: run the plan's experiment (UMBmark or
/// Triangular Path), send the correction (cL, cR, wheelbase) over the
/// protocol, run again, at most `rounds` corrections, stopping early at
/// `until_cm`. The corrections compose: each round's Ed and Eb are measured
/// against the parameters the firmware already used. Each correction is
/// line-searched ([`STEPS`]): a round whose error rises beyond the floor
/// noise is not kept ([`Calibration::rejected`]) and the correction is tried
/// again smaller. A round whose runs did not all complete, a correction the
/// firmware would refuse, or a correction no step of which lowers the
/// error stops the rounds ([`Stop`]): nothing is reported as used that the
/// firmware did not use.
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
    // Each attempt is its own progress "round", so that a retried round's
    // runs move the bar on.
    let attempts = std::sync::atomic::AtomicUsize::new(0);
    let measure = |round: usize, step: Option<f64>, (cl, cr, b): (f64, f64, f64)| {
        let attempt = attempts.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let mut plan = base.clone();
        if round > 0 {
            // After the robot's geometry: the corrections win.
            plan.params
                .extend([(1, cl as f32), (2, cr as f32), (3, b as f32)]);
        }
        let runs = execute(firmware, robot, &plan, &plan.runs(), bench, &|n, t| {
            progress(attempt, n, t)
        })?;
        let full = RunSet::new(plan, None, runs);
        let rep = match full.plan.experiment {
            Experiment::Umbmark => RoundReport::Umbmark(report(&full, b, solution)?),
            Experiment::Triangle => RoundReport::Triangle(triangle_report(&full, b, solution)?),
        };
        let complete = rep.incomplete() == 0;
        Ok::<_, ExperimentError>(CalibrationRound {
            round,
            c_left: cl,
            c_right: cr,
            wheelbase_mm: b,
            step,
            error_cm: complete.then(|| rep.error_cm()).flatten(),
            noise_cm: complete.then(|| rep.noise_cm()).flatten(),
            report: rep,
        })
    };
    let mut out = Vec::new();
    let mut rejected = Vec::new();
    let mut stop = match until_cm {
        Some(until_cm) => Stop::NotReached { until_cm },
        None => Stop::RoundsDone,
    };
    let mut next = Some(measure(0, None, (1.0, 1.0, wheelbase_mm))?);
    'rounds: while let Some(kept) = next.take() {
        let incomplete = kept.report.incomplete();
        let error_cm = kept.error_cm;
        out.push(kept);
        let kept = &out[out.len() - 1];
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
        if kept.round == rounds {
            break;
        }
        let (dl, dr, next_b) = kept.report.correction();
        for step in STEPS {
            let (cl, cr, b) = (
                kept.c_left * dl.powf(step),
                kept.c_right * dr.powf(step),
                kept.wheelbase_mm * (next_b / kept.wheelbase_mm).powf(step),
            );
            if let Some(refused) = refused(&[
                (Param::CorrLeft, cl),
                (Param::CorrRight, cr),
                (Param::WheelbaseMm, b),
            ]) {
                stop = refused;
                break 'rounds;
            }
            let tried = measure(kept.round + 1, Some(step), (cl, cr, b))?;
            if tried.rises_above(kept) {
                rejected.push(tried);
            } else {
                next = Some(tried);
                continue 'rounds;
            }
        }
        stop = Stop::NoDescent {
            round: kept.round + 1,
            until_cm,
        };
    }
    let best = out
        .iter()
        .enumerate()
        .filter_map(|(i, r)| r.error_cm.map(|e| (i, e)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(i, _)| i);
    Ok(Calibration {
        rounds: out,
        rejected,
        stop,
        best,
    })
}

/// The standard error of the distance from the origin of the centroid of
/// `points`: their scatter along the centroid's direction, over √n (0 for
/// fewer than two points, which show no scatter).
fn radial_standard_error(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    if points.len() < 2 {
        return 0.0;
    }
    let (cx, cy) = points
        .iter()
        .fold((0.0, 0.0), |(x, y), p| (x + p.0 / n, y + p.1 / n));
    let r = cx.hypot(cy);
    // At the origin every direction is the centroid's: take the scatter's
    // larger axis through the 2-D spread.
    let along = |p: &(f64, f64)| {
        if r > 0.0 {
            ((p.0 - cx) * cx + (p.1 - cy) * cy) / r
        } else {
            (p.0 - cx).hypot(p.1 - cy)
        }
    };
    let var = points.iter().map(|p| along(p).powi(2)).sum::<f64>() / (n - 1.0);
    (var / n).sqrt()
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
        // No step lowering the error is the end of what rounds can do,
        // unless an error was asked for that the kept round does not reach.
        let floor = |until_cm| Stop::NoDescent { round: 3, until_cm };
        assert!(floor(None).done());
        assert!(!floor(Some(2.0)).done());
        assert!(floor(None).describe().contains("kept round 2"));
        assert!(floor(Some(2.0)).describe().contains("above 2 cm"));
    }

    #[test]
    fn the_floor_noise_is_the_centroids_radial_standard_error() {
        // End points scattered only across the centroid's direction (x):
        // its distance does not move, whatever the scatter.
        assert_eq!(radial_standard_error(&[(10.0, -1.0), (10.0, 1.0)]), 0.0);
        // Along it: ±1 cm about 10 cm, sample sd √2, over √2 runs.
        let e = radial_standard_error(&[(9.0, 0.0), (11.0, 0.0)]);
        assert!((e - 1.0).abs() < 1e-12, "{e}");
        // At an angle, the same scatter along the direction.
        let u = std::f64::consts::FRAC_1_SQRT_2;
        let e = radial_standard_error(&[(9.0 * u, 9.0 * u), (11.0 * u, 11.0 * u)]);
        assert!((e - 1.0).abs() < 1e-12, "{e}");
        // One run shows no scatter.
        assert_eq!(radial_standard_error(&[(3.0, 4.0)]), 0.0);
    }
}
