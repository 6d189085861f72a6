//! Running a plan's runs, in parallel, and the set of runs they make: one
//! shard's or all of them, each with its index, and their table rows.

use calib::Endpoint;
use plant_model::RobotConfig;
use rayon::prelude::*;

use super::plan::{Plan, RunSpec, Shard};
use crate::bench::{BenchError, BenchOptions};
use crate::firmware::elf::Firmware;
use crate::runs::experiment::{run_test, TestOptions, TestRun};

/// Runs of a plan (all of them, or one shard's), each with its index: what
/// `hil umbmark --shard` writes and `hil merge` reads. A key this bench does
/// not write is refused: a typo in a hand-edited file is not read as absent.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunSet {
    /// The experiment's [`super::Experiment::kind`], `-partial` appended for
    /// a shard's runs.
    pub kind: String,
    pub plan: Plan,
    pub shard: Option<Shard>,
    pub runs: Vec<IndexedRun>,
}

#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IndexedRun {
    pub spec: RunSpec,
    pub completed: bool,
    pub finding: Option<String>,
    pub x_cm: f64,
    pub y_cm: f64,
    pub robot_time_s: f64,
    pub awake_fraction: f64,
    /// Per-leg and per-turn detail.
    pub detail: serde_json::Value,
    /// The path of the robot's centre (x, y in cm), from the plant's trace.
    #[serde(default)]
    pub path_cm: Vec<(f64, f64)>,
}

impl IndexedRun {
    fn from_run(spec: RunSpec, run: &TestRun) -> Self {
        let mut detail = serde_json::to_value(run).unwrap_or_default();
        if let Some(obj) = detail.as_object_mut() {
            for k in ["test", "seed", "completed", "finding", "x_cm", "y_cm"] {
                obj.remove(k);
            }
        }
        Self {
            spec,
            completed: run.completed,
            finding: run.finding.clone(),
            x_cm: run.x_cm,
            y_cm: run.y_cm,
            robot_time_s: run.robot_time_s,
            awake_fraction: run.awake_fraction,
            detail,
            path_cm: run
                .trace
                .iter()
                .step_by(5)
                .map(|s| (s.x_mm / 10.0, s.y_mm / 10.0))
                .collect(),
        }
    }

    /// The run's end error as a tape would give it.
    pub fn endpoint(&self) -> Endpoint {
        Endpoint::new(self.x_cm, self.y_cm)
    }
}

/// Execute `specs`, in parallel, in index order. `progress` is called after
/// each run with (runs done, robot seconds so far).
pub fn execute(
    firmware: &Firmware,
    robot: &RobotConfig,
    plan: &Plan,
    specs: &[RunSpec],
    bench: BenchOptions,
    progress: &(dyn Fn(usize, f64) + Sync),
) -> Result<Vec<IndexedRun>, BenchError> {
    let done = std::sync::atomic::AtomicUsize::new(0);
    let robot_s = std::sync::Mutex::new(0.0f64);
    let mut runs: Vec<IndexedRun> = specs
        .par_iter()
        .map(|spec| {
            let opts = TestOptions {
                leg_mm: plan.leg_mm,
                bench: BenchOptions {
                    seed: spec.seed,
                    ..bench
                },
                limit_s: None,
                record: false,
                faults: Vec::new(),
                framed: false,
                // The plan holds the robot's geometry already.
                params: plan.firmware_params(),
                hang_after_s: None,
                description: plan.description.clone(),
                tell: crate::firmware::params::Tell::Keep,
                start_delay_s: 0.0,
                tap: None,
            };
            let run = run_test(firmware.clone(), robot, spec.test, &opts)?;
            let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
            let total = {
                let mut t = robot_s.lock().expect("progress lock");
                *t += run.robot_time_s;
                *t
            };
            progress(n, total);
            Ok(IndexedRun::from_run(*spec, &run))
        })
        .collect::<Result<_, BenchError>>()?;
    runs.sort_by_key(|r| r.spec.index);
    Ok(runs)
}

/// One row of an experiment's table of runs.
#[derive(Debug, Clone, serde::Serialize)]
pub struct RunRow {
    pub run: usize,
    pub direction: &'static str,
    pub seed: u64,
    pub completed: bool,
    pub x_cm: f64,
    pub y_cm: f64,
}

impl RunSet {
    /// `runs` of `plan`, from one shard or (None) from all.
    pub fn new(plan: Plan, shard: Option<Shard>, runs: Vec<IndexedRun>) -> Self {
        let kind = plan.experiment.kind();
        Self {
            kind: match shard {
                Some(_) => format!("{kind}-partial"),
                None => kind.into(),
            },
            plan,
            shard,
            runs,
        }
    }

    /// Whether a set read from a file is one the bench could have written:
    /// its kind the plan's (with `-partial` for a shard's), every number
    /// within what a run can give. Without it, a kind tag edited from
    /// triangle to umbmark merged a triangle's runs as squares, and an end
    /// x of 1e308 went into the correction.
    pub fn check(&self) -> Result<(), String> {
        let kind = self.plan.experiment.kind();
        let expected = match self.shard {
            Some(_) => format!("{kind}-partial"),
            None => kind.to_string(),
        };
        if self.kind != expected {
            return Err(format!(
                "kind = {:?}: a {} of a {kind} plan is {expected:?}",
                self.kind,
                if self.shard.is_some() {
                    "shard's runs"
                } else {
                    "set of runs"
                }
            ));
        }
        let range = |field: String, v: f64, low: f64, high: f64, unit: &str| {
            if v.is_finite() && (low..=high).contains(&v) {
                Ok(())
            } else {
                Err(format!("{field} = {v}: give {low} to {high}{unit}"))
            }
        };
        range("plan.leg_mm".into(), self.plan.leg_mm, 10.0, 5000.0, " mm")?;
        for (i, r) in self.runs.iter().enumerate() {
            // The farthest a run ends: ten legs of the longest, in cm.
            for (name, v) in [("x_cm", r.x_cm), ("y_cm", r.y_cm)] {
                range(format!("runs[{i}].{name}"), v, -5000.0, 5000.0, " cm")?;
            }
            range(
                format!("runs[{i}].robot_time_s"),
                r.robot_time_s,
                0.0,
                86_400.0,
                " s",
            )?;
            range(
                format!("runs[{i}].awake_fraction"),
                r.awake_fraction,
                0.0,
                1.0,
                "",
            )?;
            for (k, (x, y)) in r.path_cm.iter().enumerate() {
                range(
                    format!("runs[{i}].path_cm[{k}].x"),
                    *x,
                    -5000.0,
                    5000.0,
                    " cm",
                )?;
                range(
                    format!("runs[{i}].path_cm[{k}].y"),
                    *y,
                    -5000.0,
                    5000.0,
                    " cm",
                )?;
            }
        }
        Ok(())
    }

    /// Whether a run is in the second group (CCW, or the triangles).
    fn in_second_group(&self, run: &IndexedRun) -> bool {
        run.spec.index >= self.plan.runs_per_direction
    }

    /// The end points of the first group (CW, or the lines) and of the
    /// second (CCW, or the triangles), in index order.
    pub fn endpoints(&self) -> (Vec<Endpoint>, Vec<Endpoint>) {
        let group = |second: bool| {
            self.runs
                .iter()
                .filter(|r| self.in_second_group(r) == second)
                .map(IndexedRun::endpoint)
                .collect()
        };
        (group(false), group(true))
    }

    /// The table rows of a complete set of runs: the first group named
    /// `names[0]`, the second `names[1]`.
    pub fn rows(&self, names: [&'static str; 2]) -> Vec<RunRow> {
        let n = self.plan.runs_per_direction;
        self.runs
            .iter()
            .map(|r| RunRow {
                run: r.spec.index % n + 1,
                direction: names[usize::from(self.in_second_group(r))],
                seed: r.spec.seed,
                completed: r.completed,
                x_cm: r.x_cm,
                y_cm: r.y_cm,
            })
            .collect()
    }

    /// The plan's warnings, then each distinct warning of the runs (e.g. a
    /// parameter the firmware refused) with how many runs gave it.
    pub fn warnings(&self) -> Vec<String> {
        let mut seen: Vec<(String, usize)> = Vec::new();
        for r in &self.runs {
            let Some(list) = r.detail.get("warnings").and_then(|w| w.as_array()) else {
                continue;
            };
            for w in list.iter().filter_map(|w| w.as_str()) {
                match seen.iter_mut().find(|(s, _)| s == w) {
                    Some((_, n)) => *n += 1,
                    None => seen.push((w.to_string(), 1)),
                }
            }
        }
        let plan = self.plan.warnings.iter().cloned();
        let runs = seen
            .into_iter()
            .filter(|(w, _)| !self.plan.warnings.contains(w))
            .map(|(w, n)| format!("{n} of {} runs: {w}", self.runs.len()));
        plan.chain(runs).collect()
    }

    /// Robot time of all runs, seconds.
    pub fn robot_time_s(&self) -> f64 {
        self.runs.iter().map(|r| r.robot_time_s).sum()
    }

    /// Each run's path with its group (0 first, 1 second), labelled
    /// `names[group]`, for a trajectory plot.
    pub fn paths<'a>(&'a self, names: [&'a str; 2]) -> Vec<calib::plot::Path2d<'a>> {
        self.runs
            .iter()
            .map(|r| {
                let group = usize::from(self.in_second_group(r));
                calib::plot::Path2d {
                    label: names[group],
                    points: &r.path_cm,
                    group,
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::runs::experiment::Test;
    use crate::runs::odometry::plan::Experiment;

    fn run(index: usize, warnings: &[&str]) -> IndexedRun {
        IndexedRun {
            spec: RunSpec {
                index,
                test: Test::UmbmarkCw,
                seed: index as u64,
            },
            completed: true,
            finding: None,
            x_cm: 0.0,
            y_cm: 0.0,
            robot_time_s: 1.0,
            awake_fraction: 0.0,
            detail: serde_json::json!({ "warnings": warnings }),
            path_cm: Vec::new(),
        }
    }

    /// A run's warning (a refused correction) reaches the report, counted
    /// once per distinct text; one the plan states already is not repeated.
    #[test]
    fn run_warnings_are_counted_once_each() {
        let plan = Plan {
            experiment: Experiment::Umbmark,
            leg_mm: 300.0,
            runs_per_direction: 2,
            seed: 0,
            robot: String::new(),
            firmware: "robust".into(),
            firmware_hash: String::new(),
            params: Vec::new(),
            warnings: vec!["plan".into()],
            description: None,
        };
        let set = RunSet::new(
            plan,
            None,
            vec![
                run(0, &["refused", "plan"]),
                run(1, &["refused"]),
                run(2, &[]),
                run(3, &["other"]),
            ],
        );
        assert_eq!(
            set.warnings(),
            vec!["plan", "2 of 4 runs: refused", "1 of 4 runs: other"]
        );
    }
}
