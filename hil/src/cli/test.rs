//! `hil test FILE...`: the user's own firmware tests. Each scenario file is
//! one test case: its faults injected, its `[[expect]]`s judged on the run
//! (`hil::runs::scenario::eval`); one line per case, a JUnit XML and a JSON report
//! for CI, and for each failed case its VCD and last state saved for triage.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use hil::board::Board;
use hil::runs::experiment::{run_test_observed, Test, TestName, TestOptions, TestRun};
use hil::runs::scenario::eval::{judge, Context as EvalContext, LastState, Outcome, Watch};
use hil::runs::scenario::Scenario;
use plant_model::RobotConfig;
use rayon::prelude::*;
use serde::Serialize;

use super::args::{parse_leg, parse_seconds, Build, Jobs, Json, Target};

#[derive(clap::Args)]
pub struct TestCmd {
    /// Scenario files with [[expect]]s (TOML or JSON), one test case each.
    #[arg(required = true, value_name = "FILE")]
    files: Vec<PathBuf>,
    /// Run this build instead of the file's `firmware` (default robust).
    #[arg(long, value_enum)]
    firmware: Option<Build>,
    /// Run this ELF instead of the file's build.
    #[arg(long, value_name = "FILE")]
    elf: Option<PathBuf>,
    /// Test description (docs/reference/test-description.md) of a firmware
    /// that knows nothing of the bench: each case's test starts and ends as
    /// it says, on its `elf` unless --elf is given. Checked before anything runs.
    #[arg(long = "tests", value_name = "FILE", value_parser = super::args::parse_description)]
    description: Option<std::sync::Arc<hil::firmware::description::Description>>,
    /// Robot config TOML (default: fixtures/robots/henrytwo.toml).
    #[arg(long, value_name = "FILE")]
    robot: Option<PathBuf>,
    /// Board TOML (default: Henrytwo's). Checked before anything runs.
    #[arg(long, value_name = "FILE", value_parser = super::board::parse_board)]
    board: Option<Board>,
    /// The plant's seed instead of the file's `seed` (default 0).
    #[arg(long)]
    seed: Option<u64>,
    /// Leg length instead of the file's `leg_mm` (default 2000).
    #[arg(long, value_parser = parse_leg, allow_negative_numbers = true)]
    leg_mm: Option<f64>,
    /// A firmware parameter to set over the protocol before each case, after
    /// the robot's geometry and its config's [firmware] settings: NAME=VALUE
    /// (e.g. kp_left=1.5); repeat for more. Checked before anything runs.
    #[arg(long = "param", value_name = "NAME=VALUE", value_parser = super::args::parse_param)]
    params: Vec<(hil::firmware::link::Param, f32)>,
    /// Robot seconds without progress after which a busy firmware is
    /// reported hung (its expectations are still judged on what it did).
    #[arg(long, value_name = "S", default_value_t = hil::bench::hang::DEFAULT_HANG_AFTER_S, value_parser = parse_seconds)]
    hang_after: f64,
    #[command(flatten)]
    jobs: Jobs,
    /// Write a JUnit XML report here.
    #[arg(long, value_name = "FILE")]
    junit: Option<PathBuf>,
    /// Save each failed case's VCD and last state here (default: beside
    /// the JUnit file, in JUNIT-STEM-artifacts/).
    #[arg(long, value_name = "DIR")]
    artifacts: Option<PathBuf>,
    #[command(flatten)]
    json: Json,
}

/// One case, checked and ready to run.
struct Prepared {
    file: PathBuf,
    name: String,
    scenario: Scenario,
    robot: RobotConfig,
    firmware: hil::firmware::elf::Firmware,
    test: TestName,
    opts: TestOptions,
    watch: Watch,
}

/// What `hil test` reports of one case.
#[derive(Debug, Serialize)]
pub struct CaseReport {
    pub case: String,
    pub file: PathBuf,
    pub firmware: String,
    pub seed: u64,
    pub test: TestName,
    pub pass: bool,
    /// `pass`, `fail`, or `incomplete` (the bench stopped the run).
    pub verdict: &'static str,
    /// One line: the first failed expectation (which, when, what was seen).
    pub message: String,
    pub robot_time_s: f64,
    pub expectations: Vec<Outcome>,
    /// Files saved for triage, on a failure.
    pub artifacts: Vec<PathBuf>,
    /// What the firmware sent on each USART (empty when the bench stopped
    /// the run before it ended).
    pub uarts: Vec<hil::runs::experiment::UartOutput>,
    /// Wall-clock seconds the case took (the JUnit `time`); not in the
    /// JSON, which stays the same from run to run.
    #[serde(skip)]
    pub wall_time_s: f64,
}

impl TestCmd {
    pub fn run(self) -> Result<()> {
        // Everything checked before anything runs: exit 2 on a bad file.
        if let Some(path) = &self.junit {
            super::check_output("--junit", path)?;
        }
        if let Some(dir) = &self.artifacts {
            super::check_output_dir("--artifacts", dir)?;
        }
        let cases = self
            .files
            .iter()
            .map(|f| self.prepare(f))
            .collect::<Result<Vec<_>>>()?;
        let artifacts = self.artifacts.clone().or_else(|| {
            self.junit.as_ref().map(|j| {
                let stem = j
                    .file_stem()
                    .map_or("junit".into(), |s| s.to_string_lossy());
                j.with_file_name(format!("{stem}-artifacts"))
            })
        });
        let slugs = slugs(&cases);
        let board = self.board.unwrap_or_default();
        let pool = self.jobs.pool(cases.len())?;
        let reports = pool.install(|| {
            cases
                .into_par_iter()
                .zip(slugs)
                .map(|(c, slug)| run_case(c, &board, artifacts.as_deref(), &slug))
                .collect::<Result<Vec<_>>>()
        })?;
        self.json.emit(&reports, || render(&reports))?;
        if let Some(path) = &self.junit {
            let xml = junit(&reports, path);
            super::write_output(path, xml.as_bytes())?;
        }
        let failed = reports.iter().filter(|r| r.verdict == "fail").count();
        let incomplete = reports.iter().filter(|r| r.verdict == "incomplete").count();
        if failed > 0 {
            anyhow::bail!("{failed} of {} test case(s) failed", reports.len());
        }
        if let Some(first) = reports.iter().find(|r| r.verdict == "incomplete") {
            return Err(super::Incomplete(format!(
                "{incomplete} of {} test case(s) did not complete ({}: {})",
                reports.len(),
                first.case,
                first.message
            ))
            .into());
        }
        Ok(())
    }

    fn prepare(&self, file: &Path) -> Result<Prepared> {
        let scenario = Scenario::load(file).map_err(super::bad_input)?;
        if scenario.expect.is_empty() {
            return Err(super::bad_input(anyhow::anyhow!(
                "the scenario {} has no [[expect]]: hil test has nothing to judge (hil run --scenario runs it)",
                file.display()
            )));
        }
        let build = self.firmware.unwrap_or(match scenario.firmware.as_deref() {
            Some("thesis") => Build::Thesis,
            _ => Build::Robust,
        });
        let seed = self.seed.or(scenario.seed).unwrap_or(0);
        let target = Target {
            no_skip: false,
            firmware: build,
            elf: self.elf.clone(),
            description: self.description.clone(),
            robot: self.robot.clone(),
            board: self.board,
            mcu: None,
            seed,
            keep_firmware_params: false,
            params: self.params.clone(),
        };
        let (robot, firmware) = target.load()?;
        let bench = target.bench();
        super::check_scenario_wiring(file, &scenario, &bench.board)?;
        let watch = Watch::new(&scenario, &firmware, bench.clock).map_err(|e| {
            super::bad_input(anyhow::anyhow!("the scenario {}, {e}", file.display()))
        })?;
        let test = scenario.test.clone().unwrap_or(Test::Line.into());
        let asked = self.leg_mm.or(scenario.leg_mm);
        let leg_mm = match &self.description {
            // The test must be one the description starts: said now, not
            // as a bench error in the middle of the cases.
            Some(d) => {
                d.start(test.clone()).map_err(|e| {
                    super::bad_input(anyhow::anyhow!("the scenario {}: {e}", file.display()))
                })?;
                d.leg_mm(asked, super::args::DEFAULT_LEG_MM)
                    .map_err(super::bad_input)?
            }
            None => asked.unwrap_or(super::args::DEFAULT_LEG_MM),
        };
        let opts = TestOptions {
            leg_mm,
            bench,
            limit_s: scenario.limit_s,
            // The VCD of a failed case needs the pins' detail.
            record: true,
            faults: scenario.scheduled(),
            framed: scenario.framed,
            params: target.params.clone(),
            hang_after_s: Some(self.hang_after),
            description: self.description.clone(),
            ..Default::default()
        };
        let name = scenario.name.clone().unwrap_or_else(|| stem(file));
        Ok(Prepared {
            file: file.to_owned(),
            name,
            scenario,
            robot,
            firmware,
            test,
            opts,
            watch,
        })
    }
}

fn stem(file: &Path) -> String {
    file.file_stem()
        .map_or_else(|| "scenario".into(), |s| s.to_string_lossy().into_owned())
}

/// A file name for each case's artifacts: its file's stem, numbered when
/// two cases share one.
fn slugs(cases: &[Prepared]) -> Vec<String> {
    let stems: Vec<String> = cases.iter().map(|c| stem(&c.file)).collect();
    stems
        .iter()
        .enumerate()
        .map(|(i, s)| {
            if stems.iter().filter(|t| *t == s).count() > 1 {
                format!("{s}-{}", i + 1)
            } else {
                s.clone()
            }
        })
        .collect()
}

fn run_case(
    c: Prepared,
    board: &Board,
    artifacts: Option<&Path>,
    slug: &str,
) -> Result<CaseReport> {
    let firmware_name = match &c.opts.description {
        Some(d) => d.firmware_name(&c.firmware),
        None => c.firmware.name(),
    };
    let seed = c.opts.bench.seed;
    let clock = c.opts.bench.clock;
    // Wall time around the run, for the JUnit report only.
    let started = std::time::Instant::now();
    let outcome = run_test_observed(
        c.firmware,
        &c.robot,
        c.test.clone(),
        &c.opts,
        Some(Box::new(c.watch)),
    );
    let wall_time_s = started.elapsed().as_secs_f64();
    let base = CaseReport {
        case: c.name.clone(),
        file: c.file.clone(),
        firmware: firmware_name,
        seed,
        test: c.test,
        pass: false,
        verdict: "incomplete",
        message: String::new(),
        robot_time_s: 0.0,
        expectations: Vec::new(),
        artifacts: Vec::new(),
        uarts: Vec::new(),
        wall_time_s,
    };
    let (run, observer) = match outcome {
        Ok(r) => r,
        Err(e) => {
            return Ok(CaseReport {
                message: format!("the bench stopped the run: {e}"),
                ..base
            })
        }
    };
    let watch = observer
        .and_then(|o| o.into_any().downcast::<Watch>().ok())
        .context("the run lost its watch")?;
    let outcomes = judge(
        &c.scenario,
        &watch,
        &EvalContext {
            run: &run,
            board,
            clock,
        },
    );
    let mut failures: Vec<String> = outcomes
        .iter()
        .filter(|o| !o.pass)
        .map(|o| o.message.clone())
        .collect();
    for i in &run.faults_never_fired {
        failures.push(format!(
            "fault {} never fired in {:.3} s of robot time: nothing was tested",
            i + 1,
            run.robot_time_s
        ));
    }
    // A run the bench stopped as hung did not finish what its expectations
    // are about: it is no pass, whatever held before the hang.
    // Nor did a run that fragmented (more legs or turns than its test's
    // shape, without a fault to cause it) or drove other than its described
    // shape: it did not drive the test.
    let hung = match (&run.hang, &run.off_shape) {
        (Some(_), _) => Some(format!(
            "the bench stopped the run: {}",
            run.finding.as_deref().unwrap_or("hung")
        )),
        (None, Some(why)) if !run.completed => Some(why.clone()),
        _ => None,
    };
    let pass = failures.is_empty() && hung.is_none();
    let verdict = match (&hung, pass) {
        (Some(_), _) => "incomplete",
        (None, true) => "pass",
        (None, false) => "fail",
    };
    let message = hung
        .clone()
        .or_else(|| failures.first().cloned())
        .unwrap_or_default();
    let mut report = CaseReport {
        pass,
        verdict,
        message,
        robot_time_s: run.robot_time_s,
        expectations: outcomes,
        uarts: run.uarts.clone(),
        ..base
    };
    if !pass {
        if let Some(dir) = artifacts {
            report.artifacts = save_artifacts(dir, slug, &run, watch.last_state(), board)?;
        }
    }
    Ok(report)
}

/// The VCD of `run`, its GTKWave save file and its last state, as
/// `DIR/SLUG.vcd`, `DIR/SLUG.gtkw` and `DIR/SLUG.state.json`: what a
/// failure is triaged with.
pub(super) fn save_artifacts(
    dir: &Path,
    slug: &str,
    run: &TestRun,
    last: &LastState,
    board: &Board,
) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    // The trace with its GTKWave save file, as `hil run --vcd` writes them.
    // A folder the bench made: the trace is a regular file, with its save file.
    let mut written = super::run::write_vcd(
        &dir.join(format!("{slug}.vcd")),
        hil::output::Kind::Replace,
        run,
        false,
        board,
    )?;
    let state = dir.join(format!("{slug}.state.json"));
    let json = serde_json::json!({
        "test": run.test,
        "firmware": run.firmware,
        "seed": run.seed,
        "completed": run.completed,
        "finding": run.finding,
        "last": last,
    });
    super::write_output(&state, serde_json::to_string_pretty(&json)?.as_bytes())?;
    written.push(state);
    Ok(written)
}

/// One line a case, then the count.
fn render(reports: &[CaseReport]) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    for r in reports {
        let head = match r.verdict {
            "pass" => "pass",
            "fail" => "FAIL",
            _ => "INCOMPLETE",
        };
        let _ = write!(
            s,
            "{head:<5} {} ({}, {:.1} s robot)",
            r.case,
            r.file.display(),
            r.robot_time_s
        );
        if !r.pass {
            let _ = write!(s, ": {}", r.message);
        }
        s.push('\n');
        for a in &r.artifacts {
            let _ = writeln!(s, "      saved {}", a.display());
        }
    }
    let count = |v: &str| reports.iter().filter(|r| r.verdict == v).count();
    let _ = write!(s, "{} passed, {} failed", count("pass"), count("fail"));
    match count("incomplete") {
        0 => s.push('\n'),
        n => {
            let _ = writeln!(s, ", {n} incomplete");
        }
    }
    s
}

/// The JUnit report at `path`: a suite per case's file (the properties of
/// every command, then its file and test), its one test case.
fn junit(reports: &[CaseReport], path: &Path) -> String {
    let suites: Vec<hil::output::junit::Suite> = reports
        .iter()
        .map(|r| {
            let details: Vec<String> = r
                .expectations
                .iter()
                .map(|o| format!("{} {}", if o.pass { "pass" } else { "FAIL" }, o.message))
                .collect();
            hil::output::junit::Suite {
                name: format!("hil test {}", r.file.display()),
                properties: hil::output::junit::run_properties(
                    "test",
                    &r.firmware,
                    r.seed,
                    r.robot_time_s,
                )
                .into_iter()
                .chain([
                    ("test".into(), r.test.name().into()),
                    ("file".into(), r.file.display().to_string()),
                ])
                .collect(),
                cases: vec![hil::output::junit::Case {
                    name: r.case.clone(),
                    classname: format!("hil.test.{}", stem(&r.file)),
                    time_s: r.wall_time_s,
                    failure: (!r.pass).then(|| hil::output::junit::Failure {
                        message: r.message.clone(),
                        kind: r.verdict.into(),
                        text: details.join("\n"),
                    }),
                    skipped: None,
                    // What the firmware printed, as the text report shows it.
                    system_out: (!r.uarts.is_empty())
                        .then(|| hil::runs::experiment::uarts::render(&r.uarts, "")),
                    attachments: r
                        .artifacts
                        .iter()
                        .map(|a| hil::output::junit::relative_to_report(path, a))
                        .collect(),
                }],
            }
        })
        .collect();
    hil::output::junit::render("hil test", &suites)
}
