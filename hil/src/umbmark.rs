//! The reduced UMBmark on the emulated robot, as the thesis ran it on the floor:
//! five runs clockwise and five counter-clockwise around a square of side L,
//! each from a fresh firmware reset with its own seed, end errors measured by
//! the plant as a person with a tape would, then Borenstein's correction.
//!
//! Runs are independent, so they run in parallel (rayon) and in any order,
//! and a plan can be split into shards that run on different machines:
//! [`Plan::runs`] fixes every run's index and seed up front, so a merge of
//! shards is exactly what one machine would have produced.

use std::path::PathBuf;

use calib::{Direction, Endpoint, UmbmarkParams, UmbmarkResult, UmbmarkRuns};
use plant_model::RobotConfig;
use rayon::prelude::*;
use thiserror::Error;

use crate::bench::{BenchError, BenchOptions};
use crate::elf::Firmware;
use crate::experiment::{run_test, Test, TestOptions, TestRun};

#[derive(Debug, Error)]
pub enum UmbmarkError {
    #[error(transparent)]
    Bench(#[from] BenchError),
    #[error("shard {0}: give it as K/N with 1 <= K <= N, e.g. 2/4")]
    BadShard(String),
    #[error("partial results do not belong together: {0}")]
    Mismatch(String),
    #[error("runs {missing:?} are missing: merge the partial results of every shard")]
    Missing { missing: Vec<usize> },
    #[error("calibration: {0}")]
    Calib(#[from] calib::Error),
}

/// Which experiment a plan runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Experiment {
    /// UMBmark: CW squares, then CCW squares.
    #[default]
    Umbmark,
    /// Triangular Path: straight lines, then counter-clockwise triangles.
    Triangle,
}

impl Experiment {
    /// The `kind` of its partial results.
    pub fn kind(self) -> &'static str {
        match self {
            Experiment::Umbmark => "umbmark",
            Experiment::Triangle => "triangle",
        }
    }
}

/// What to run. Everything that changes a result is in here.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Plan {
    #[serde(default)]
    pub experiment: Experiment,
    pub leg_mm: f64,
    pub runs_per_direction: usize,
    /// Run `i` uses seed `seed + i`.
    pub seed: u64,
    /// The robot config, by content (a file name would not pin it).
    pub robot: String,
    /// The firmware, by name and content hash.
    pub firmware: String,
    pub firmware_hash: String,
    /// Firmware parameters set over the protocol before each run: (id, value)
    /// (see protocol/README.md: 1 cL, 2 cR, 3 wheelbase mm, ...).
    #[serde(default)]
    pub params: Vec<(u8, f32)>,
}

/// One run of a plan: its index, direction and seed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct RunSpec {
    pub index: usize,
    pub test: Test,
    pub seed: u64,
}

/// K of N, 1-based: runs whose index i has i % N == K - 1.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Shard {
    pub k: usize,
    pub n: usize,
}

impl std::str::FromStr for Shard {
    type Err = UmbmarkError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let bad = || UmbmarkError::BadShard(s.into());
        let (k, n) = s.split_once('/').ok_or_else(bad)?;
        let k: usize = k.trim().parse().map_err(|_| bad())?;
        let n: usize = n.trim().parse().map_err(|_| bad())?;
        if n == 0 || k == 0 || k > n {
            return Err(bad());
        }
        Ok(Shard { k, n })
    }
}

impl Plan {
    pub fn new(leg_mm: f64, seed: u64, robot: &RobotConfig, firmware: &Firmware) -> Self {
        let name = firmware.name();
        Self {
            experiment: Experiment::Umbmark,
            leg_mm,
            runs_per_direction: 5,
            seed,
            robot: toml::to_string(robot).unwrap_or_default(),
            firmware: name,
            firmware_hash: firmware.content_hash(),
            params: Vec::new(),
        }
    }

    /// The same plan for the Triangular Path.
    pub fn triangle(mut self) -> Self {
        self.experiment = Experiment::Triangle;
        self
    }

    /// Every run: the first group (CW, or the lines), then the second.
    pub fn runs(&self) -> Vec<RunSpec> {
        let n = self.runs_per_direction;
        let (first, second) = match self.experiment {
            Experiment::Umbmark => (Test::UmbmarkCw, Test::UmbmarkCcw),
            Experiment::Triangle => (Test::Line, Test::Triangle),
        };
        (0..2 * n)
            .map(|i| RunSpec {
                index: i,
                test: if i < n { first } else { second },
                seed: self.seed.wrapping_add(i as u64),
            })
            .collect()
    }

    pub fn shard(&self, shard: Shard) -> Vec<RunSpec> {
        self.runs()
            .into_iter()
            .filter(|r| r.index % shard.n == shard.k - 1)
            .collect()
    }
}

/// Runs of a plan (all of them, or one shard's), each with its index.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct Partial {
    pub kind: String,
    pub plan: Plan,
    pub shard: Option<Shard>,
    pub runs: Vec<IndexedRun>,
}

#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
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
                params: plan
                    .params
                    .iter()
                    .filter_map(|&(id, v)| crate::link::Param::from_u8(id).map(|p| (p, v)))
                    .collect(),
                hang_after_s: None,
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

/// Combine partial results into the full set, checking they belong together.
pub fn merge(parts: Vec<Partial>) -> Result<Partial, UmbmarkError> {
    let mut iter = parts.into_iter();
    let first = iter
        .next()
        .ok_or_else(|| UmbmarkError::Mismatch("no partial results given".into()))?;
    let plan = first.plan.clone();
    let mut runs = first.runs;
    for p in iter {
        if p.plan != plan {
            return Err(UmbmarkError::Mismatch(
                "they come from different plans (leg, seed, robot or firmware differ)".into(),
            ));
        }
        runs.extend(p.runs);
    }
    runs.sort_by_key(|r| r.spec.index);
    runs.dedup_by_key(|r| r.spec.index);
    let expected = plan.runs();
    let missing: Vec<usize> = expected
        .iter()
        .filter(|s| !runs.iter().any(|r| r.spec == **s))
        .map(|s| s.index)
        .collect();
    if !missing.is_empty() {
        return Err(UmbmarkError::Missing { missing });
    }
    Ok(Partial {
        kind: "umbmark".into(),
        plan,
        shard: None,
        runs,
    })
}

/// The experiment's result: the runs' end errors and Borenstein's correction.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Report {
    pub plan: Plan,
    pub runs: Vec<RunRow>,
    #[serde(flatten)]
    pub result: UmbmarkResult,
    pub robot_time_s: f64,
}

#[derive(Debug, Clone, serde::Serialize)]
pub struct RunRow {
    pub run: usize,
    pub direction: &'static str,
    pub seed: u64,
    pub completed: bool,
    pub x_cm: f64,
    pub y_cm: f64,
}

/// The table rows of a complete set of runs: the first group (CW, or the
/// lines) named `names[0]`, the second `names[1]`.
fn run_rows(full: &Partial, names: [&'static str; 2]) -> Vec<RunRow> {
    let n = full.plan.runs_per_direction;
    full.runs
        .iter()
        .map(|r| RunRow {
            run: r.spec.index % n + 1,
            direction: names[usize::from(r.spec.index >= n)],
            seed: r.spec.seed,
            completed: r.completed,
            x_cm: r.x_cm,
            y_cm: r.y_cm,
        })
        .collect()
}

/// Borenstein's correction from a complete set of runs.
pub fn report(
    full: &Partial,
    wheelbase_mm: f64,
    solution: calib::Solution,
) -> Result<Report, UmbmarkError> {
    let n = full.plan.runs_per_direction;
    let point = |r: &IndexedRun| Endpoint::new(r.x_cm, r.y_cm);
    let cw: Vec<Endpoint> = full
        .runs
        .iter()
        .filter(|r| r.spec.index < n)
        .map(point)
        .collect();
    let ccw: Vec<Endpoint> = full
        .runs
        .iter()
        .filter(|r| r.spec.index >= n)
        .map(point)
        .collect();
    let runs = UmbmarkRuns::new(cw, ccw)?;
    let params = UmbmarkParams {
        side_cm: full.plan.leg_mm / 10.0,
        wheelbase_mm,
        solution,
        ..UmbmarkParams::default()
    };
    let result = calib::umbmark_correction(&runs, &params);
    Ok(Report {
        plan: full.plan.clone(),
        runs: run_rows(full, [Direction::Cw.as_str(), Direction::Ccw.as_str()]),
        result,
        robot_time_s: full.runs.iter().map(|r| r.robot_time_s).sum(),
    })
}

impl Report {
    /// The thesis-style table and the correction.
    pub fn render(&self) -> String {
        use std::fmt::Write;
        let r = &self.result;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "Reduced UMBmark, L = {:.0} mm, {} runs per direction ({}, seeds {}..)",
            self.plan.leg_mm, self.plan.runs_per_direction, self.plan.firmware, self.plan.seed
        );
        let _ = writeln!(
            s,
            "  end errors (cm; x along the first leg, y to the left):"
        );
        let _ = writeln!(s, "    run |     CW x     CW y |    CCW x    CCW y");
        let n = self.plan.runs_per_direction;
        for i in 0..n {
            let cw = &self.runs[i];
            let ccw = &self.runs[n + i];
            let _ = writeln!(
                s,
                "    {:>3} | {:8.2} {:8.2} | {:8.2} {:8.2}{}",
                i + 1,
                cw.x_cm,
                cw.y_cm,
                ccw.x_cm,
                ccw.y_cm,
                if cw.completed && ccw.completed {
                    ""
                } else {
                    "  (incomplete run)"
                }
            );
        }
        let _ = writeln!(
            s,
            "    c.g.| {:8.2} {:8.2} | {:8.2} {:8.2}",
            r.centroid_cw.x_cm, r.centroid_cw.y_cm, r.centroid_ccw.x_cm, r.centroid_ccw.y_cm
        );
        let _ = writeln!(
            s,
            "  r_cg CW {:.2} cm, r_cg CCW {:.2} cm, E_max,syst {:.2} cm",
            r.r_cg_cw_cm, r.r_cg_ccw_cm, r.e_max_cm
        );
        let _ = writeln!(
            s,
            "  alpha {:+.4} deg (from y {:+.4}), beta {:+.4} deg (from y {:+.4})",
            r.alpha_deg, r.alpha_y_deg, r.beta_deg, r.beta_y_deg
        );
        let _ = writeln!(
            s,
            "  R {}, Ed {:.5}, Eb {:.5}",
            r.radius_cm
                .map_or("infinite".to_string(), |v| format!("{v:.1} cm")),
            r.ed,
            r.eb
        );
        let _ = writeln!(
            s,
            "  correction: cL {:.5}, cR {:.5}, wheelbase {:.2} mm (was {:.2} mm)",
            r.cl, r.cr, r.wheelbase_mm, r.wheelbase_nominal_mm
        );
        for w in &r.warnings {
            let _ = writeln!(s, "  warning: {w}");
        }
        let _ = writeln!(s, "  robot time {:.1} s in all", self.robot_time_s);
        s
    }
}

/// Write the report, its Markdown rendering and the plots into `dir`; each
/// file appears whole or not at all.
pub fn write_outputs(
    dir: &std::path::Path,
    full: &Partial,
    report: &Report,
) -> anyhow::Result<Vec<PathBuf>> {
    use crate::output::write_atomic;
    std::fs::create_dir_all(dir)?;
    let tmp = dir.join(format!(".tmp-{}", std::process::id()));
    std::fs::create_dir_all(&tmp)?;
    let n = full.plan.runs_per_direction;
    let point = |r: &IndexedRun| Endpoint::new(r.x_cm, r.y_cm);
    let runs = UmbmarkRuns::new(
        full.runs
            .iter()
            .filter(|r| r.spec.index < n)
            .map(point)
            .collect(),
        full.runs
            .iter()
            .filter(|r| r.spec.index >= n)
            .map(point)
            .collect(),
    )?;
    calib::plot_umbmark(
        &report.result,
        &runs,
        tmp.join("umbmark.svg"),
        tmp.join("umbmark.png"),
    )?;
    let labels: Vec<String> = full
        .runs
        .iter()
        .map(|r| {
            if r.spec.index < n {
                "clockwise".into()
            } else {
                "counter-clockwise".into()
            }
        })
        .collect();
    let paths: Vec<calib::plot::Path2d> = full
        .runs
        .iter()
        .zip(&labels)
        .map(|(r, l)| calib::plot::Path2d {
            label: l,
            points: &r.path_cm,
            group: usize::from(r.spec.index >= n),
        })
        .collect();
    calib::plot::plot_trajectories(
        &format!("UMBmark trajectories, L = {:.0} mm", full.plan.leg_mm),
        &paths,
        tmp.join("trajectories.svg"),
        tmp.join("trajectories.png"),
    )?;
    let mut written = Vec::new();
    for f in [
        "umbmark.svg",
        "umbmark.png",
        "trajectories.svg",
        "trajectories.png",
    ] {
        let to = dir.join(f);
        std::fs::rename(tmp.join(f), &to)?;
        written.push(to);
    }
    let _ = std::fs::remove_dir_all(&tmp);
    let json = dir.join("report.json");
    write_atomic(&json, serde_json::to_string_pretty(report)?.as_bytes())?;
    written.push(json);
    let md = dir.join("report.md");
    write_atomic(&md, report.markdown().as_bytes())?;
    written.push(md);
    Ok(written)
}

impl Report {
    /// The report as Markdown, with the plots next to it.
    pub fn markdown(&self) -> String {
        format!(
            "# Reduced UMBmark on the emulated robot\n\n\
             Firmware `{}` ({}), L = {:.0} mm, seeds from {}.\n\n\
             ```text\n{}```\n\n\
             ![end errors](umbmark.svg)\n\n![trajectories](trajectories.svg)\n",
            self.plan.firmware,
            self.plan.firmware_hash,
            self.plan.leg_mm,
            self.plan.seed,
            self.render()
        )
    }
}

/// The Triangular Path's result: the runs' end errors and the correction.
#[derive(Debug, Clone, serde::Serialize)]
pub struct TriangleReport {
    pub plan: Plan,
    pub runs: Vec<RunRow>,
    #[serde(flatten)]
    pub result: calib::TriangleResult,
    pub robot_time_s: f64,
}

fn triangle_runs(full: &Partial) -> Result<(calib::LineRuns, calib::TriangleRuns), UmbmarkError> {
    let n = full.plan.runs_per_direction;
    let point = |r: &IndexedRun| Endpoint::new(r.x_cm, r.y_cm);
    let line = calib::LineRuns::new(
        full.runs
            .iter()
            .filter(|r| r.spec.index < n)
            .map(point)
            .collect(),
    )?;
    let tri = calib::TriangleRuns::complete(
        full.runs
            .iter()
            .filter(|r| r.spec.index >= n)
            .map(point)
            .collect(),
    )?;
    Ok((line, tri))
}

/// The Triangular Path correction from a complete set of runs.
pub fn triangle_report(
    full: &Partial,
    wheelbase_mm: f64,
    solution: calib::Solution,
) -> Result<TriangleReport, UmbmarkError> {
    let (line, tri) = triangle_runs(full)?;
    let params = calib::TriangleParams {
        side_cm: full.plan.leg_mm / 10.0,
        wheelbase_mm,
        // The bench drives the lines and the triangles with the same
        // parameters: the triangles' legs bend as the lines do.
        line_correction_applied: false,
        solution,
        ..calib::TriangleParams::default()
    };
    let result = calib::triangle_correction(&line, &tri, &params);
    Ok(TriangleReport {
        plan: full.plan.clone(),
        runs: run_rows(full, ["line", "triangle"]),
        result,
        robot_time_s: full.runs.iter().map(|r| r.robot_time_s).sum(),
    })
}

impl TriangleReport {
    pub fn render(&self) -> String {
        use std::fmt::Write;
        let r = &self.result;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "Triangular Path, L = {:.0} mm, {} lines and {} counter-clockwise triangles ({}, seeds {}..)",
            self.plan.leg_mm, self.plan.runs_per_direction, self.plan.runs_per_direction, self.plan.firmware, self.plan.seed
        );
        let _ = writeln!(
            s,
            "  end errors (cm; x along the first leg, y to the left; the line's against its end):"
        );
        let _ = writeln!(s, "    run |   line x   line y |  trian x  trian y");
        let n = self.plan.runs_per_direction;
        for i in 0..n {
            let (a, b) = (&self.runs[i], &self.runs[n + i]);
            let _ = writeln!(
                s,
                "    {:>3} | {:8.2} {:8.2} | {:8.2} {:8.2}",
                i + 1,
                a.x_cm,
                a.y_cm,
                b.x_cm,
                b.y_cm
            );
        }
        let _ = writeln!(
            s,
            "  line centroid ({:.2}, {:.2}) cm -> beta {:.4} deg, Ed {:.5}, cL {:.5}, cR {:.5}",
            r.line_centroid.x_cm, r.line_centroid.y_cm, r.beta_deg, r.ed, r.cl, r.cr
        );
        let _ = writeln!(
            s,
            "  triangle centroid ({:.2}, {}) cm -> 120-degree turn error {:.4} deg, Eb {:.5}, wheelbase {:.2} mm",
            r.triangle_centroid.x_cm,
            r.triangle_centroid.y_cm.map_or("?".into(), |y| format!("{y:.2}")),
            r.alpha_deg,
            r.eb,
            r.wheelbase_mm
        );
        let _ = writeln!(s, "  robot time {:.1} s in all", self.robot_time_s);
        s
    }
}

/// Write the triangle report and its plot into `dir`.
pub fn write_triangle_outputs(
    dir: &std::path::Path,
    full: &Partial,
    report: &TriangleReport,
) -> anyhow::Result<Vec<PathBuf>> {
    use crate::output::write_atomic;
    std::fs::create_dir_all(dir)?;
    let (line, tri) = triangle_runs(full)?;
    let tmp = dir.join(format!(".tmp-{}", std::process::id()));
    std::fs::create_dir_all(&tmp)?;
    calib::plot_triangle(
        &report.result,
        &line,
        &tri,
        tmp.join("triangle.svg"),
        tmp.join("triangle.png"),
    )?;
    let mut written = Vec::new();
    for f in ["triangle.svg", "triangle.png"] {
        std::fs::rename(tmp.join(f), dir.join(f))?;
        written.push(dir.join(f));
    }
    let _ = std::fs::remove_dir_all(&tmp);
    let json = dir.join("triangle.json");
    write_atomic(&json, serde_json::to_string_pretty(report)?.as_bytes())?;
    written.push(json);
    Ok(written)
}

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

/// Calibrate the emulated robot: run the plan's experiment (UMBmark or
/// Triangular Path), send the correction (cL, cR, wheelbase) over the
/// protocol, run again, `rounds` corrections in all. The corrections compose:
/// each round's Ed and Eb are measured against the parameters the firmware
/// already used.
pub fn calibrate(
    firmware: &Firmware,
    robot: &RobotConfig,
    base: &Plan,
    wheelbase_mm: f64,
    rounds: usize,
    solution: calib::Solution,
    progress: &(dyn Fn(usize, usize, f64) + Sync),
) -> Result<Vec<CalibrationRound>, UmbmarkError> {
    let (mut cl, mut cr, mut b) = (1.0f64, 1.0f64, wheelbase_mm);
    let mut out = Vec::new();
    for round in 0..=rounds {
        let mut plan = base.clone();
        if round > 0 {
            plan.params = vec![(1, cl as f32), (2, cr as f32), (3, b as f32)];
        }
        let runs = execute(
            firmware,
            robot,
            &plan,
            &plan.runs(),
            BenchOptions::default(),
            &|n, t| progress(round, n, t),
        )?;
        let full = Partial {
            kind: plan.experiment.kind().into(),
            plan: plan.clone(),
            shard: None,
            runs,
        };
        let rep = match plan.experiment {
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
pub fn table10(rounds: &[CalibrationRound]) -> Result<Vec<(String, calib::Round)>, UmbmarkError> {
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
                    return Err(UmbmarkError::Mismatch(
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

/// Where a plan's partial result goes by default.
pub fn partial_path(dir: &std::path::Path, shard: Shard) -> PathBuf {
    dir.join(format!("umbmark-shard-{}-of-{}.json", shard.k, shard.n))
}
