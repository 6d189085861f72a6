//! The bench-backed diagnosis' speed (`hil bench --diagnosis`): a dataset as the thesis
//! recorded one (UMBmark 5 CW + 5 CCW, 5 lines, 5 counter-clockwise triangles) made by the
//! bench with a hidden effect (as the self-test makes its data), then the whole diagnosis of
//! it with one job and with N, timed in one run: both wall times, bench runs per second and
//! their ratio, and whether the budget (15 minutes on 2 cores) held.
//!
//! Wall time is read from the host clock around whole diagnoses, never inside a simulation.
//! Every job count must give the same diagnosis (run `i`'s seed does not depend on it), or
//! the times would not compare: a difference is an error.

use std::time::Instant;

use gap::{EffectParams, GapError};
use serde::Serialize;

use super::selftest::{make_data, split_rule};
use super::{diagnose_bench, kinematic_shortlist, BenchDiagnosis, BenchModel, SelectOptions};

/// The budget of one diagnosis on 2 cores, s.
pub const BUDGET_S: f64 = 900.0;

/// What to time.
pub struct SpeedPlan<'a> {
    /// The nominal bench (its `jobs` is not used: each timing sets its own).
    pub bench: &'a BenchModel,
    /// The hidden effects of the data, with their values.
    pub hidden: &'a [(&'a str, f64)],
    pub leg_mm: f64,
    /// Runs of each of the four tests.
    pub runs_per_group: usize,
    pub seed: u64,
    /// The job counts to time besides 1 (the budget is judged on 2).
    pub jobs: Vec<usize>,
    pub opts: &'a SelectOptions,
    /// Told what is being timed.
    pub progress: &'a dyn Fn(&str),
}

/// One timed diagnosis.
#[derive(Debug, Clone, Serialize)]
pub struct Timed {
    pub jobs: usize,
    pub wall_s: f64,
    pub bench_runs: usize,
    pub runs_per_s: f64,
}

/// What one kind of fit cost in one diagnosis: how many were fitted, their bench runs,
/// and the wall time those runs take at the diagnosis' mean rate with 2 jobs (or with the
/// last job count timed, when 2 was not), s. The rate is the whole diagnosis' (no clock is
/// read inside it), so the times are the runs' share of the measured wall time.
#[derive(Debug, Clone, Serialize)]
pub struct FitCost {
    /// "single", "pair" or "triple".
    pub kind: &'static str,
    pub fits: usize,
    pub bench_runs: usize,
    pub wall_s: f64,
}

/// The costs of `d`'s fits by kind, their wall time at `runs_per_s`.
fn costs_of(d: &BenchDiagnosis, runs_per_s: f64) -> Vec<FitCost> {
    let wall = |runs: usize| runs as f64 / runs_per_s.max(1e-9);
    let joint = |k: usize| {
        let fits: Vec<_> = d.joint.iter().filter(|j| j.effects.len() == k).collect();
        (fits.len(), fits.iter().map(|j| j.bench_runs).sum::<usize>())
    };
    let singles = d.bench_runs.saturating_sub(d.joint_runs);
    let mut out = vec![FitCost {
        kind: "single",
        fits: d.candidates.len(),
        bench_runs: singles,
        wall_s: wall(singles),
    }];
    for (k, kind) in [(2, "pair"), (3, "triple")] {
        let (fits, bench_runs) = joint(k);
        out.push(FitCost {
            kind,
            fits,
            bench_runs,
            wall_s: wall(bench_runs),
        });
    }
    out
}

/// What `hil bench --diagnosis` prints.
#[derive(Debug, Clone, Serialize)]
pub struct DiagnosisSpeed {
    pub leg_mm: f64,
    pub runs_per_group: usize,
    /// The hidden effect and what the diagnosis chose.
    pub hidden: String,
    pub winner: Option<String>,
    pub candidates: usize,
    /// The chosen model's effects, the joint fits tried and the bench runs they took (of
    /// each timing's total).
    pub chosen: Vec<String>,
    pub joint_fits: usize,
    pub joint_runs: usize,
    /// The cost of each kind of fit: the single effects (with the nominal robot's runs),
    /// the pairs and the triples.
    pub costs: Vec<FitCost>,
    /// Bench runs of the data, and the wall time they took (with the job count timed last).
    pub data_runs: usize,
    pub data_wall_s: f64,
    /// Cores the machine offers.
    pub cores: usize,
    /// Job count 1 first, then the others.
    pub timed: Vec<Timed>,
    /// Wall time with one job over each other job count's, in `timed` order after the first.
    pub speedups: Vec<f64>,
    pub budget_s: f64,
    /// The wall time with 2 jobs, and whether it is within the budget.
    pub two_jobs_wall_s: Option<f64>,
    pub within_budget: Option<bool>,
}

/// Times the plan (see the module docs).
pub fn measure_diagnosis(plan: &SpeedPlan) -> Result<DiagnosisSpeed, GapError> {
    let mut jobs: Vec<usize> = vec![1];
    for &j in &plan.jobs {
        if !jobs.contains(&j.max(1)) {
            jobs.push(j.max(1));
        }
    }
    // Each timing starts with no answers kept: every run of it is run.
    let with_jobs = |n: usize| BenchModel {
        jobs: n,
        ..plan.bench.without_answers()
    };
    let mut hidden = EffectParams::new();
    for &(effect, value) in plan.hidden {
        hidden.set(effect, value);
    }
    let data_jobs = *jobs.last().expect("job 1 at least");
    (plan.progress)(&format!(
        "making the data: {} runs of each test, {data_jobs} jobs",
        plan.runs_per_group
    ));
    let clock = Instant::now();
    let data = make_data(
        &with_jobs(data_jobs),
        &hidden,
        super::SelfTestDesign::legs(plan.leg_mm),
        plan.seed,
        plan.runs_per_group,
    )?;
    let data_wall_s = clock.elapsed().as_secs_f64();
    let data_runs = data.groups().iter().map(|g| g.runs.len()).sum();
    let (train, held) = data.split(&split_rule())?;
    let shortlist = kinematic_shortlist(&train, &held, &gap::selftest::self_test_options())?;
    let mut timed = Vec::new();
    let mut first: Option<BenchDiagnosis> = None;
    for &n in &jobs {
        (plan.progress)(&format!("timing the diagnosis with {n} jobs"));
        let bench = with_jobs(n);
        let clock = Instant::now();
        let d = diagnose_bench(&bench, &shortlist, &train, &held, plan.opts, &|_| {})?;
        let wall_s = clock.elapsed().as_secs_f64();
        timed.push(Timed {
            jobs: n,
            wall_s,
            bench_runs: d.bench_runs,
            runs_per_s: d.bench_runs as f64 / wall_s.max(1e-9),
        });
        match &first {
            Some(f) if json(f) != json(&d) => {
                return Err(GapError::Fit(format!(
                    "the diagnosis with {n} jobs differs from the one with 1 job: the job \
                     count changed a result (a bug in the bench's pool)"
                )))
            }
            Some(_) => {}
            None => first = Some(d),
        }
    }
    let d = first.expect("one timing at least");
    let one = timed[0].wall_s;
    let two = timed.iter().find(|t| t.jobs == 2).map(|t| t.wall_s);
    let rate = timed
        .iter()
        .find(|t| t.jobs == 2)
        .or(timed.last())
        .map_or(0.0, |t| t.runs_per_s);
    Ok(DiagnosisSpeed {
        leg_mm: plan.leg_mm,
        runs_per_group: plan.runs_per_group,
        hidden: plan
            .hidden
            .iter()
            .map(|(e, v)| format!("{e} = {v}"))
            .collect::<Vec<_>>()
            .join(", "),
        winner: d.winner.clone().map(|(w, _)| w),
        candidates: d.candidates.len(),
        chosen: d.chosen.iter().map(|c| c.effect.clone()).collect(),
        joint_fits: d.joint.len(),
        joint_runs: d.joint_runs,
        costs: costs_of(&d, rate),
        data_runs,
        data_wall_s,
        cores: std::thread::available_parallelism().map_or(1, |n| n.get()),
        speedups: timed[1..]
            .iter()
            .map(|t| one / t.wall_s.max(1e-9))
            .collect(),
        timed,
        budget_s: BUDGET_S,
        two_jobs_wall_s: two,
        within_budget: two.map(|t| t <= BUDGET_S),
    })
}

fn json<T: Serialize>(v: &T) -> Option<serde_json::Value> {
    serde_json::to_value(v).ok()
}

impl DiagnosisSpeed {
    /// The report as text.
    pub fn render(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "speed of the bench-backed diagnosis: {} runs per test (UMBmark CW and CCW, line, \
             triangle), L = {:.0} mm, hidden {}; {} bench runs of data in {:.1} s",
            self.runs_per_group, self.leg_mm, self.hidden, self.data_runs, self.data_wall_s
        );
        let _ = writeln!(
            s,
            "  {} candidates, winner {}; this machine offers {} cores",
            self.candidates,
            self.winner.as_deref().unwrap_or("none"),
            self.cores
        );
        let total = self.timed.first().map_or(0, |t| t.bench_runs);
        let _ = writeln!(
            s,
            "  joint fits: {} tried, {} bench runs of the {total} ({:.0} %); chosen model: {}",
            self.joint_fits,
            self.joint_runs,
            100.0 * self.joint_runs as f64 / total.max(1) as f64,
            if self.chosen.is_empty() {
                "none".to_owned()
            } else {
                self.chosen.join(" + ")
            }
        );
        let _ = writeln!(
            s,
            "  {:<8} {:>5} {:>11} {:>14} {:>10}",
            "fits", "count", "bench runs", "runs per fit", "wall s"
        );
        for c in &self.costs {
            let _ = writeln!(
                s,
                "  {:<8} {:>5} {:>11} {:>14} {:>10.1}",
                c.kind,
                c.fits,
                c.bench_runs,
                if c.fits == 0 {
                    "-".to_owned()
                } else {
                    format!("{:.0}", c.bench_runs as f64 / c.fits as f64)
                },
                c.wall_s
            );
        }
        let _ = writeln!(
            s,
            "  (the single fits' runs include the nominal robot's; wall s: each kind's share \
             of the wall time with 2 jobs, at the diagnosis' mean rate)"
        );
        let _ = writeln!(
            s,
            "  {:<8} {:>10} {:>11} {:>10}",
            "jobs", "wall s", "bench runs", "runs/s"
        );
        for t in &self.timed {
            let _ = writeln!(
                s,
                "  {:<8} {:>10.1} {:>11} {:>10.2}",
                t.jobs, t.wall_s, t.bench_runs, t.runs_per_s
            );
        }
        for (t, r) in self.timed[1..].iter().zip(&self.speedups) {
            let _ = writeln!(
                s,
                "  speed-up with {} jobs: {r:.2}x (the wall time with 1 job over theirs)",
                t.jobs
            );
        }
        match (self.two_jobs_wall_s, self.within_budget) {
            (Some(t), Some(ok)) => {
                let _ = writeln!(
                    s,
                    "  budget {:.0} s on 2 cores: {} ({t:.1} s with 2 jobs{})",
                    self.budget_s,
                    if ok { "held" } else { "NOT held" },
                    if self.cores < 2 {
                        "; this machine has 1 core, so not a 2-core figure"
                    } else {
                        ""
                    }
                );
            }
            _ => {
                let _ = writeln!(s, "  budget on 2 cores: not judged (2 jobs not timed)");
            }
        }
        s
    }
}
