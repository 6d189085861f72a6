//! The experiments over many runs: `hil umbmark`, `hil triangle`, `hil merge`
//! and `hil calibrate`.

use std::path::PathBuf;

use anyhow::{Context, Result};
use hil::bench::BenchOptions;
use hil::firmware::elf::Firmware;
use hil::output::OutputDir;
use hil::runs::odometry::{execute, IndexedRun, Plan, RunSet, RunSpec, Shard};
use hil::runs::report::{json_with_pace, Pace, PaceFields};
use plant_model::RobotConfig;

use super::args::{Common, Correction, FrameArg, Jobs, Json, Leg, MethodArg, OutDir, Solve};

#[derive(clap::Args)]
#[command(mut_arg("leg_mm", |a| a.help("Side of the square in millimetres")))]
#[command(mut_arg("out", |a| a.help("Output folder for partial results, reports and plots")))]
pub struct Umbmark {
    #[command(flatten)]
    leg: Leg,
    #[command(flatten)]
    correction: Correction,
    /// Run only shard K of N (K/N) and write its partial result to --out.
    #[arg(long, value_name = "K/N")]
    shard: Option<Shard>,
    #[command(flatten)]
    out: OutDir,
    #[command(flatten)]
    jobs: Jobs,
    #[command(flatten)]
    common: Common,
}

impl Umbmark {
    pub fn run(self) -> Result<()> {
        let Umbmark {
            leg,
            correction,
            shard,
            out,
            jobs,
            common,
        } = self;
        common.refuse_trace("umbmark")?;
        let (robot, firmware, plan) = setup(&common, leg)?;
        // The folder is claimed before anything runs: another writer, or a
        // folder that cannot be replaced, is refused now, not after the runs.
        let shard_dir = out.out.clone().unwrap_or_else(|| PathBuf::from("."));
        let (claim, _shared) = match (shard, &out.out) {
            (Some(_), _) => (None, Some(hil::output::share(&shard_dir)?)),
            (None, Some(dir)) => (
                Some(OutputDir::claim(dir, hil::runs::odometry::UMBMARK_FILES)?),
                None,
            ),
            (None, None) => (None, None),
        };
        if let Some(s) = shard {
            // The partial result's file, checked before the runs.
            super::check_output("--out", &hil::runs::odometry::partial_path(&shard_dir, s))?;
        }
        let specs = match shard {
            Some(s) => plan.shard(s),
            None => plan.runs(),
        };
        let pool = jobs.pool(specs.len())?;
        let clock = common.print.wall_clock();
        let runs = pool.install(|| {
            execute_with_progress(&firmware, &robot, &plan, &specs, common.target.bench())
        })?;
        let wall_s = clock.stop();
        let partial = RunSet {
            kind: if shard.is_some() {
                "umbmark-partial".into()
            } else {
                "umbmark".into()
            },
            plan,
            shard,
            runs,
        };
        if let Some(s) = shard {
            let path = hil::runs::odometry::partial_path(&shard_dir, s);
            super::write_output(&path, serde_json::to_string_pretty(&partial)?.as_bytes())?;
            eprintln!("wrote {} ({} runs)", path.display(), partial.runs.len());
            return Ok(());
        }
        let report = hil::runs::odometry::report(
            &partial,
            correction
                .firmware_wheelbase_mm
                .unwrap_or(partial.plan.believed().wheelbase_mm),
            correction.solve.solution(),
        )?;
        if let Some(claim) = claim {
            hil::runs::odometry::write_set(claim.staging(), &partial, &report)?;
            for f in claim.commit()? {
                eprintln!("wrote {}", f.display());
            }
        }
        let pace = Pace::of(report.robot_time_s, wall_s);
        if common.print.json.json {
            let v = json_with_pace(&report, pace, PaceFields::RtfAndWall)?;
            println!("{}", serde_json::to_string_pretty(&v)?);
        } else {
            print!("{}", report.render());
            if let Some(p) = pace {
                println!(
                    "  wall time {:.2} s on {} threads: {:.0}x real time",
                    p.wall_s,
                    pool.current_num_threads(),
                    p.rtf()
                );
            }
        }
        incomplete(&partial)
    }
}

#[derive(clap::Args)]
#[command(mut_arg("leg_mm", |a| a.help("Length of the line and side of the triangle, mm")))]
pub struct Triangle {
    #[command(flatten)]
    leg: Leg,
    #[command(flatten)]
    correction: Correction,
    #[command(flatten)]
    out: OutDir,
    #[command(flatten)]
    common: Common,
}

impl Triangle {
    pub fn run(self) -> Result<()> {
        let Triangle {
            leg,
            correction,
            out,
            common,
        } = self;
        common.refuse_trace("triangle")?;
        let (robot, firmware, plan) = setup(&common, leg)?;
        // Claimed before anything runs (see `Umbmark::run`).
        let claim = match &out.out {
            Some(dir) => Some(OutputDir::claim(dir, hil::runs::odometry::TRIANGLE_FILES)?),
            None => None,
        };
        let plan = plan.triangle();
        let clock = common.print.wall_clock();
        let runs = execute_with_progress(
            &firmware,
            &robot,
            &plan,
            &plan.runs(),
            common.target.bench(),
        )?;
        let wall_s = clock.stop();
        let full = RunSet {
            kind: "triangle".into(),
            plan,
            shard: None,
            runs,
        };
        let report = hil::runs::odometry::triangle_report(
            &full,
            correction
                .firmware_wheelbase_mm
                .unwrap_or(full.plan.believed().wheelbase_mm),
            correction.solve.solution(),
        )?;
        if let Some(claim) = claim {
            hil::runs::odometry::write_triangle_set(claim.staging(), &full, &report)?;
            for f in claim.commit()? {
                eprintln!("wrote {}", f.display());
            }
        }
        if common.print.json.json {
            let pace = Pace::of(report.robot_time_s, wall_s);
            let v = json_with_pace(&report, pace, PaceFields::Rtf)?;
            println!("{}", serde_json::to_string_pretty(&v)?);
        } else {
            print!("{}", report.render());
        }
        incomplete(&full)
    }
}

#[derive(clap::Args)]
pub struct Merge {
    /// Partial result files (JSON).
    #[arg(required = true)]
    parts: Vec<PathBuf>,
    #[command(flatten)]
    correction: Correction,
    #[command(flatten)]
    json: Json,
}

impl Merge {
    pub fn run(self) -> Result<()> {
        let mut partials = Vec::new();
        for p in &self.parts {
            let text = input_file::read_text(p)
                .with_context(|| format!("reading {}", p.display()))
                .map_err(super::bad_input)?;
            let kind = serde_json::from_str::<serde_json::Value>(&text)
                .ok()
                .and_then(|v| v["kind"].as_str().map(str::to_owned));
            if kind.as_deref() == Some(hil::runs::gap_bench::PARTIAL_KIND) {
                return Err(super::BadInput(format!(
                    "{} is a partial result of `hil gap --bench --shard`: merge it with `hil gap --merge`",
                    p.display()
                ))
                .into());
            }
            let part: RunSet = serde_json::from_str(&text)
                .with_context(|| {
                    format!(
                        "{} is not a partial result of `hil umbmark --shard`",
                        p.display()
                    )
                })
                .map_err(super::bad_input)?;
            part.check()
                .map_err(|e| super::BadInput(format!("{}: {e}", p.display())))?;
            if part.plan.experiment != hil::runs::odometry::Experiment::Umbmark {
                return Err(super::BadInput(format!(
                    "{}: kind = {:?}: hil merge combines the shards of hil umbmark \
                     (umbmark-partial)",
                    p.display(),
                    part.kind
                ))
                .into());
            }
            partials.push((p.display().to_string(), part));
        }
        // Parts that do not make one experiment are refused (exit 2), as
        // input that does not check: no order of them gives a result.
        let full = hil::runs::odometry::merge_named(partials).map_err(super::bad_input)?;
        let report = hil::runs::odometry::report(
            &full,
            self.correction
                .firmware_wheelbase_mm
                .unwrap_or(full.plan.believed().wheelbase_mm),
            self.correction.solve.solution(),
        )?;
        if self.json.json {
            // As `hil umbmark --json --deterministic` prints it, byte for
            // byte (a merge has no wall time of its own).
            let v = json_with_pace(&report, None, PaceFields::RtfAndWall)?;
            println!("{}", serde_json::to_string_pretty(&v)?);
        } else {
            print!("{}", report.render());
        }
        incomplete(&full)
    }
}

#[derive(clap::Args)]
#[command(mut_arg("leg_mm", |a| a.help("Side of the square for the rounds, mm")))]
pub struct Calibrate {
    /// End points in the layout of umbmark_endpoints.csv or triangular_endpoints.csv.
    #[arg(long, value_name = "FILE")]
    from_csv: Option<PathBuf>,
    /// With --from-csv: the experiment number in the table [default: 1].
    #[arg(long)]
    experiment: Option<u32>,
    /// The test (default: umbmark, or with --from-csv from the table's header).
    #[arg(long, value_enum)]
    method: Option<MethodArg>,
    /// The thesis GUI's formulas exactly as printed (its bugs included).
    #[arg(long)]
    thesis_compat: bool,
    /// The frame the end points are recorded in: default (x along the
    /// first leg, y to the left) or thesis-gui (x mirrored). Default:
    /// default, or in --thesis-compat the GUI's.
    #[arg(long, value_enum)]
    frame: Option<FrameArg>,
    /// With --from-csv: square side / line length, cm (above 0, up to
    /// 10000; default 200).
    #[arg(long, value_parser = parse_side_cm, allow_negative_numbers = true)]
    side_cm: Option<f64>,
    /// The wheelbase the robot's odometry used, mm (default with
    /// --from-csv: the --robot config's, else 130, or in --thesis-compat
    /// the thesis' value for the experiment).
    #[arg(long, value_parser = super::args::parse_wheelbase)]
    wheelbase_mm: Option<f64>,
    /// With --from-csv: runs per direction (UMBmark) or per test (Triangular
    /// Path) in the table.
    /// [default: 5]
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..=1000))]
    runs_per_group: Option<u16>,
    #[command(flatten)]
    solve: Solve,
    /// Correction rounds on the emulated robot (without --from-csv); with
    /// --until-cm, the most to run (0 to 100) [default: 2].
    #[arg(long, value_parser = clap::value_parser!(u16).range(0..=100))]
    rounds: Option<u16>,
    /// Stop the rounds once a round's systematic error (UMBmark's E_max, the
    /// triangle centroid's distance) is at most this many cm; exit 1 when no
    /// round reaches it.
    #[arg(long, value_parser = parse_until_cm)]
    until_cm: Option<f64>,
    #[command(flatten)]
    leg: Leg,
    #[command(flatten)]
    common: Common,
}

impl Calibrate {
    pub fn run(self) -> Result<()> {
        self.common.refuse_trace("calibrate")?;
        match &self.from_csv {
            Some(path) => self.measured(path),
            None => self.rounds(),
        }
    }

    /// Corrections from measured end points.
    fn measured(&self, path: &std::path::Path) -> Result<()> {
        // The options of calibration rounds, which --from-csv does not run.
        let given = [
            (self.until_cm.is_some(), "--until-cm"),
            (self.rounds.is_some(), "--rounds"),
            (self.leg.leg_mm.is_some(), "--leg-mm"),
        ];
        if let Some((_, option)) = given.iter().find(|(g, _)| *g) {
            return Err(super::BadInput(format!(
                "{option}: an option of calibration rounds on the emulated robot, which \
                 --from-csv does not run (its table's side is --side-cm)"
            ))
            .into());
        }
        let method = match self.method {
            None => hil::runs::calibrate::detect(path).map_err(super::bad_input)?,
            Some(m) => m.into(),
        };
        let opts = hil::runs::calibrate::FromCsv {
            experiment: self.experiment.unwrap_or(1),
            thesis_compat: self.thesis_compat,
            frame: self.frame.map(Into::into),
            side_cm: self.side_cm,
            wheelbase_mm: self.measured_wheelbase_mm()?,
            solution: self.solve.solution(),
            runs_per_group: self.runs_per_group.unwrap_or(5).into(),
        };
        let result = hil::runs::calibrate::from_csv(path, method, &opts)
            .with_context(|| format!("{}", path.display()))
            .map_err(super::bad_input)?;
        self.common.print.json.emit(&result, || result.render())
    }

    /// The wheelbase the measured robot's odometry used: --wheelbase-mm,
    /// else the nominal one of the robot config given with --robot (a robot
    /// other than Henrytwo is not computed with Henrytwo's 130 mm), else
    /// the default of [`hil::runs::calibrate::FromCsv::wheelbase_mm`].
    fn measured_wheelbase_mm(&self) -> Result<Option<f64>> {
        if self.wheelbase_mm.is_some() || self.common.target.robot.is_none() {
            return Ok(self.wheelbase_mm);
        }
        Ok(Some(self.common.target.robot()?.geometry.wheelbase_mm))
    }

    /// Calibration rounds on the emulated robot.
    fn rounds(&self) -> Result<()> {
        // The options of a measured table, which rounds do not read.
        let given = [
            (self.experiment.is_some(), "--experiment"),
            (self.runs_per_group.is_some(), "--runs-per-group"),
            (self.side_cm.is_some(), "--side-cm"),
            (self.thesis_compat, "--thesis-compat"),
            (self.frame.is_some(), "--frame"),
        ];
        if let Some((_, option)) = given.iter().find(|(g, _)| *g) {
            return Err(super::BadInput(format!(
                "{option}: an option of --from-csv (a measured table), which calibration \
                 rounds do not read (their square's side is --leg-mm)"
            ))
            .into());
        }
        if let Some(d) = &self.common.target.description {
            return Err(super::BadInput(format!(
                "{}: calibration rounds send each round's correction (cL, cR, wheelbase) over the protocol, which a firmware run from a test description does not speak; run hil umbmark --tests and build the correction into the firmware",
                d.path
            ))
            .into());
        }
        let (robot, firmware, plan) = setup(&self.common, self.leg)?;
        let mut plan = match self.method {
            None | Some(MethodArg::Umbmark) => plan,
            Some(MethodArg::Triangle) => plan.triangle(),
        };
        // Round 0 runs with the wheelbase asked for, as the later rounds do.
        let wheelbase_mm = self.wheelbase_mm.unwrap_or(plan.believed().wheelbase_mm);
        if self.wheelbase_mm.is_some() {
            plan.params.push((
                hil::firmware::link::Param::WheelbaseMm.id(),
                wheelbase_mm as f32,
            ));
        }
        let total = 2 * plan.runs_per_direction;
        let rounds = usize::from(self.rounds.unwrap_or(2));
        let bar = progress_bar((rounds + 1) * total, plan.leg_mm);
        let calibration = hil::runs::odometry::calibrate(
            &firmware,
            &robot,
            &plan,
            &hil::runs::odometry::RoundOptions {
                wheelbase_mm,
                rounds,
                until_cm: self.until_cm,
                // Rounds iterate on what the model says; the first-order
                // formulas misread errors of several degrees and the
                // rounds then wander instead of converging.
                solution: self.solve.solution_or(calib::Solution::Exact),
                bench: self.common.target.bench(),
            },
            &|attempt, n, _| {
                // A retried round runs more than `rounds + 1` experiments.
                let at = (attempt * total + n) as u64;
                if bar.length().is_some_and(|l| at > l) {
                    bar.set_length(at);
                }
                bar.set_position(at);
                bar.set_message(format!("experiment {}", attempt + 1));
            },
        )?;
        bar.finish_and_clear();
        let results = &calibration.rounds;
        let table = hil::runs::odometry::table10(results)?;
        if self.common.print.json.json {
            let v = serde_json::json!({
                "rounds": results,
                "rejected": calibration.rejected,
                "table10": table,
                "stop": calibration.stop,
                "best": calibration.best,
            });
            println!("{}", serde_json::to_string_pretty(&v)?);
        } else {
            for r in results {
                // The attempts at this round that raised the error, first.
                for t in calibration.rejected.iter().filter(|t| t.round == r.round) {
                    println!("{}", round_line(t, &results[t.round - 1]));
                }
                println!(
                    "{}",
                    round_line(r, r.round.checked_sub(1).map(|i| &results[i]))
                );
            }
            // The attempts of the round no step of which was kept.
            for t in calibration
                .rejected
                .iter()
                .filter(|t| t.round == results.len())
            {
                println!("{}", round_line(t, &results[t.round - 1]));
            }
            let rows: Vec<(&str, calib::Round)> =
                table.iter().map(|(n, r)| (n.as_str(), *r)).collect();
            print!(
                "{}",
                calib::round::format_table10(&rows, calib::round::TableStyle::Rounded)
            );
            println!("stopped: {}", calibration.stop.describe());
            if let Some(best) = calibration.best.map(|i| &results[i]) {
                println!(
                    "best: round {} (cL {:.5}, cR {:.5}, wheelbase {:.2} mm), error {:.2} cm",
                    best.round,
                    best.c_left,
                    best.c_right,
                    best.wheelbase_mm,
                    best.error_cm.unwrap_or(f64::NAN)
                );
            }
        }
        match calibration.stop {
            hil::runs::odometry::Stop::Incomplete { .. } => {
                Err(super::Incomplete(calibration.stop.describe()).into())
            }
            ref s if !s.done() => Err(anyhow::anyhow!("{}", s.describe())),
            _ => Ok(()),
        }
    }
}

/// A calibration round, one line: its parameters, the share of the last
/// kept round's correction they apply, its errors, and for an attempt that
/// raised the error beyond the floor noise, that it was not kept.
fn round_line<'a>(
    r: &hil::runs::odometry::CalibrationRound,
    kept: impl Into<Option<&'a hil::runs::odometry::CalibrationRound>>,
) -> String {
    let step = r.step.map_or(String::new(), |s| format!(", step {s}"));
    let mut line = format!(
        "round {}: cL {:.5}, cR {:.5}, wheelbase {:.2} mm{step} -> {}",
        r.round,
        r.c_left,
        r.c_right,
        r.wheelbase_mm,
        r.report.summary()
    );
    // Rounding noise of a robot with none is not printed as 0.00 cm.
    if let Some(noise) = r.noise_cm.filter(|n| *n >= 0.005) {
        line += &format!(" (floor noise {noise:.2} cm)");
    }
    if let Some(kept) = kept.into().filter(|k| r.rises_above(k)) {
        line += &format!(
            "; not kept: above round {}'s {:.2} cm by more than the floor noise",
            kept.round,
            kept.error_cm.unwrap_or(f64::NAN)
        );
    }
    line
}

/// `--side-cm`: the table's square side or line, as a leg of the bench's
/// tests is bounded (a 1e308 cm side printed a 309-digit length).
fn parse_side_cm(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 && v <= 10_000.0 => Ok(v),
        _ => Err(format!(
            "{s} is out of range: give a length above 0 and up to 10000 cm"
        )),
    }
}

/// A `--until-cm` error: positive and finite.
fn parse_until_cm(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 && v <= 10_000.0 => Ok(v),
        _ => Err(format!(
            "{s} is out of range: give an error above 0 and up to 10000 cm"
        )),
    }
}

/// Ok when every run of `set` completed, else the error that says how many
/// did not (exit code 3): a correction from them is no result.
fn incomplete(set: &hil::runs::odometry::RunSet) -> Result<()> {
    let n = set.runs.iter().filter(|r| !r.completed).count();
    if n == 0 {
        return Ok(());
    }
    Err(super::Incomplete(format!(
        "{n} of {} runs did not complete: the correction printed is not a result",
        set.runs.len()
    ))
    .into())
}

/// The robot and firmware `common` names, and the plan of a UMBmark on them.
fn setup(common: &Common, leg: Leg) -> Result<(RobotConfig, Firmware, Plan)> {
    let (robot, firmware) = common.target.load()?;
    let plan = Plan::new(
        common.leg_mm(leg)?,
        common.target.seed,
        &robot,
        &common.target.bench().board,
        &firmware,
        common.target.tell(),
    );
    if let Some(d) = &common.target.description {
        if !common.target.params.is_empty() {
            return Err(super::BadInput(format!(
                "{}: the firmware it describes has no protocol to set parameters with; drop --param",
                d.path
            ))
            .into());
        }
        return Ok((robot, firmware, plan.described(d.clone())));
    }
    // The user's parameters after the robot's: theirs win.
    let mut plan = plan;
    plan.params
        .extend(common.target.params.iter().map(|(p, v)| (p.id(), *v)));
    Ok((robot, firmware, plan))
}

/// Run `specs` of `plan` on `bench` (its board; each run's own seed) with
/// a progress bar of runs and robot time.
fn execute_with_progress(
    firmware: &Firmware,
    robot: &RobotConfig,
    plan: &Plan,
    specs: &[RunSpec],
    bench: BenchOptions,
) -> Result<Vec<IndexedRun>> {
    let bar = progress_bar(specs.len(), plan.leg_mm);
    let runs = execute(firmware, robot, plan, specs, bench, &|n, robot_s| {
        bar.set_position(n as u64);
        bar.set_message(format!("{robot_s:.0} s of robot time"));
    })?;
    bar.finish_and_clear();
    Ok(runs)
}

fn progress_bar(runs: usize, leg_mm: f64) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::new(runs as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template(&format!(
            "{{bar:30}} {{pos}}/{{len}} runs of a {:.0} mm square, {{msg}} [{{elapsed}}]",
            leg_mm
        ))
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar
}
