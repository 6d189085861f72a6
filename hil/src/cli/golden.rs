//! `hil golden record` and `hil golden check`: a run's quantities written
//! once, later runs compared to them within tolerances (see
//! [`hil::runs::golden`]).
//!
//! A check makes the run again with what the golden file recorded (ELF,
//! robot, board, seed, parameters, scenario), each overridable on the
//! command line: `--elf new.elf` is the usual comparison.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::ValueEnum;
use hil::bench::{BenchOptions, Observer};
use hil::firmware::link::Param;
use hil::runs::experiment::{run_test_observed, TestName, TestOptions, TestRun};
use hil::runs::golden::{Golden, InForce, Quantity, Tolerances, CONTROL_FUNCTION};
use hil::runs::timing::TimingProbe;

use super::args::{parse_param, Build, Json, Leg, Target, DEFAULT_LEG_MM};

/// Golden runs: record one, check later runs against it.
#[derive(clap::Args)]
pub struct GoldenCmd {
    #[command(subcommand)]
    command: GoldenCommand,
}

#[derive(clap::Subcommand)]
enum GoldenCommand {
    /// Run a test once and write its quantities (each leg's end point,
    /// heading change and mean duty per side, each turn's angle, the control
    /// loop's cycles), what was in force and the tolerances to FILE.json.
    Record(Record),
    /// Run the golden file's test again (as recorded, but for the options
    /// given) and compare: a table of what moved; exit 0 when every
    /// quantity is within its tolerance, 1 when one moved, 2 for a golden
    /// file that cannot be used.
    Check(Check),
}

impl GoldenCmd {
    pub fn run(self) -> Result<()> {
        match self.command {
            GoldenCommand::Record(c) => c.run(),
            GoldenCommand::Check(c) => c.run(),
        }
    }
}

#[derive(clap::Args)]
struct Record {
    /// umbmark-cw, umbmark-ccw, line or triangle; with --tests, a test the
    /// description names.
    test: TestName,
    #[command(flatten)]
    leg: Leg,
    /// The golden file to write (JSON).
    #[arg(long, value_name = "FILE.json")]
    out: PathBuf,
    #[command(flatten)]
    run: RunArgs,
    #[command(flatten)]
    tol: TolArgs,
    #[command(flatten)]
    json: Json,
}

#[derive(clap::Args)]
struct Check {
    /// The golden file (from `hil golden record`).
    #[arg(value_name = "FILE.json")]
    file: PathBuf,
    /// The test this check is meant to compare (refused, exit 2, when the
    /// golden run is of another) [default: the golden file's].
    #[arg(long)]
    test: Option<TestName>,
    /// Legs of this length (refused, exit 2, when the golden run's are
    /// not) [default: the golden file's].
    #[arg(long, value_parser = super::args::parse_leg, allow_negative_numbers = true)]
    leg_mm: Option<f64>,
    #[command(flatten)]
    run: RunArgs,
    #[command(flatten)]
    tol: TolArgs,
    #[command(flatten)]
    json: Json,
}

/// What a golden run is made with; a check's defaults are the golden
/// file's, a record's the other commands' ones.
#[derive(clap::Args)]
struct RunArgs {
    /// Which firmware build to run [default: robust; check: as recorded].
    #[arg(long, value_enum)]
    firmware: Option<Build>,
    /// Firmware ELF to run instead of a build [check: as recorded].
    #[arg(long, value_name = "FILE")]
    elf: Option<PathBuf>,
    /// Robot config TOML [default: fixtures/robots/henrytwo.toml; check:
    /// as recorded].
    #[arg(long, value_name = "FILE")]
    robot: Option<PathBuf>,
    /// Board TOML [default: Henrytwo's, built in; check: as recorded].
    #[arg(long, value_name = "FILE")]
    board: Option<PathBuf>,
    /// Seed of the plant's random effects [default: 0; check: as recorded].
    #[arg(long)]
    seed: Option<u64>,
    /// A firmware parameter to set before the start, NAME=VALUE; repeat
    /// for more [check: as recorded, replaced as a whole when given].
    #[arg(long = "param", value_name = "NAME=VALUE", value_parser = parse_param)]
    params: Vec<(Param, f32)>,
    /// Do not tell the firmware the robot's geometry [check: as recorded,
    /// or given].
    #[arg(long)]
    keep_firmware_params: bool,
    /// Inject the faults of a scenario file [check: as recorded].
    #[arg(long, value_name = "FILE")]
    scenario: Option<PathBuf>,
    /// Test description of a firmware that knows nothing of the bench
    /// (docs/reference/test-description.md): its tests by their names, its
    /// `elf` unless --elf is given [check: as recorded].
    #[arg(long = "tests", value_name = "FILE")]
    tests: Option<PathBuf>,
}

/// Tolerances: a record's are stored in the file, a check's override the
/// file's.
#[derive(clap::Args)]
struct TolArgs {
    /// Tolerance of positions, mm [default: 5, or the golden file's].
    #[arg(long, value_name = "MM", value_parser = parse_tolerance)]
    tol_leg_mm: Option<f64>,
    /// Tolerance of angles, degrees [default: 1, or the golden file's].
    #[arg(long, value_name = "DEG", value_parser = parse_tolerance)]
    tol_turn_deg: Option<f64>,
    /// Tolerance of mean PWM duties (full duty is 1) [default: 0.02, or the
    /// golden file's].
    #[arg(long, value_name = "D", value_parser = parse_tolerance)]
    tol_duty: Option<f64>,
    /// Tolerance of the control loop's cycle figures [default: 200, or the
    /// golden file's].
    #[arg(long, value_name = "N", value_parser = parse_tolerance)]
    tol_cycles: Option<f64>,
}

impl TolArgs {
    /// `base` with the tolerances given here.
    fn over(&self, base: Tolerances) -> Tolerances {
        Tolerances {
            leg_mm: self.tol_leg_mm.unwrap_or(base.leg_mm),
            turn_deg: self.tol_turn_deg.unwrap_or(base.turn_deg),
            duty: self.tol_duty.unwrap_or(base.duty),
            cycles: self.tol_cycles.unwrap_or(base.cycles),
        }
    }
}

/// A tolerance: a finite number of at least 0.
fn parse_tolerance(s: &str) -> Result<f64, String> {
    let v: f64 = s.parse().map_err(|_| format!("{s:?} is not a number"))?;
    if !(v.is_finite() && v >= 0.0) {
        return Err(format!(
            "{s} is out of range: give a tolerance of at least 0"
        ));
    }
    Ok(v)
}

/// A run's conditions, resolved: the target to load and the scenario.
struct Conditions {
    target: Target,
    /// The board's file (the target holds it decoded), for what is in force.
    board: Option<PathBuf>,
    scenario: Option<PathBuf>,
    /// The test description's file (the target holds it decoded).
    tests: Option<PathBuf>,
}

impl RunArgs {
    /// These options over `recorded` (a check's) or over the defaults.
    fn resolve(&self, recorded: Option<&InForce>) -> Result<Conditions> {
        let path = |s: &String| from_golden(s);
        // A build given replaces a recorded ELF, as an ELF given does.
        let elf = self.elf.clone().or_else(|| {
            self.firmware
                .is_none()
                .then(|| recorded.and_then(|r| r.elf.as_ref().map(path)))
                .flatten()
        });
        let tests = self
            .tests
            .clone()
            .or_else(|| recorded.and_then(|r| r.tests.as_ref().map(path)));
        let description = tests
            .as_ref()
            .map(|p| super::args::parse_description(&p.display().to_string()))
            .transpose()
            .map_err(|e| super::bad_input(anyhow::anyhow!("{e}")))?;
        let firmware = match (self.firmware, recorded) {
            (Some(b), _) => b,
            // A described firmware's name is its own, no build's.
            (None, Some(r)) if r.elf.is_none() && description.is_none() => {
                Build::from_str(&r.firmware, false).map_err(|_| {
                    super::bad_input(anyhow::anyhow!(
                        "firmware {:?} of the golden file is no build: robust or thesis",
                        r.firmware
                    ))
                })?
            }
            _ => Build::Robust,
        };
        let board_path = self
            .board
            .clone()
            .or_else(|| recorded.and_then(|r| r.board.as_ref().map(path)));
        let board = match &board_path {
            Some(p) => Some(
                super::board::parse_board(&p.display().to_string())
                    .map_err(|e| super::bad_input(anyhow::anyhow!("{e}")))?,
            ),
            None => None,
        };
        let params = if !self.params.is_empty() {
            self.params.clone()
        } else {
            recorded
                .map(|r| r.params.iter().map(|p| parse_param(p)).collect())
                .transpose()
                .map_err(|e| super::bad_input(anyhow::anyhow!("golden file: --param {e}")))?
                .unwrap_or_default()
        };
        let mut target = Target {
            no_skip: false,
            firmware,
            elf,
            description,
            robot: self
                .robot
                .clone()
                .or_else(|| recorded.map(|r| path(&r.robot))),
            board,
            mcu: None,
            seed: self.seed.or(recorded.map(|r| r.seed)).unwrap_or(0),
            keep_firmware_params: self.keep_firmware_params
                || recorded.is_some_and(|r| r.keep_firmware_params),
            params,
        };
        // Recorded as the path the run read, so that a check reads the same.
        target.robot = Some(target.robot_path());
        let scenario = self
            .scenario
            .clone()
            .or_else(|| recorded.and_then(|r| r.scenario.as_ref().map(path)));
        Ok(Conditions {
            target,
            board: board_path,
            scenario,
            tests,
        })
    }
}

/// `path` as a golden file records it: relative to the repository when it
/// is inside (a golden file committed there checks in any checkout and from
/// any folder), else absolute.
fn for_golden(path: &Path) -> String {
    let abs = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    let abs = abs.canonicalize().unwrap_or(abs);
    let root = hil::paths::workspace_root();
    let root = root.canonicalize().unwrap_or(root);
    match abs.strip_prefix(&root) {
        Ok(inside) => inside.display().to_string(),
        Err(_) => abs.display().to_string(),
    }
}

/// A path a golden file recorded, as [`for_golden`] wrote it.
fn from_golden(recorded: &str) -> PathBuf {
    let p = PathBuf::from(recorded);
    if p.is_relative() {
        hil::paths::workspace_root().join(p)
    } else {
        p
    }
}

/// A golden run's measurement: the run, what was in force, the quantities.
struct Measured {
    run: TestRun,
    in_force: InForce,
    quantities: Vec<Quantity>,
}

/// Run `test` with legs of `leg_mm` under `c`, timing the control function
/// when the firmware has it.
fn measure(c: &Conditions, test: TestName, leg_mm: f64) -> Result<Measured> {
    let target = &c.target;
    let (robot, firmware) = target.load()?;
    let robot_path = target.robot_path();
    let robot_bytes = input_file::read_bytes(&robot_path)
        .with_context(|| format!("reading {}", robot_path.display()))?;
    let mut opts = TestOptions {
        leg_mm,
        bench: target.bench(),
        tell: target.tell(),
        params: target.params.clone(),
        description: target.description.clone(),
        ..Default::default()
    };
    if let Some(path) = &c.scenario {
        let s = hil::runs::scenario::Scenario::load(path).map_err(super::bad_input)?;
        super::check_scenario_wiring(path, &s, &opts.bench.board)?;
        opts.faults = s.scheduled();
        opts.framed = s.framed;
    }
    let clock = BenchOptions::default().clock;
    // The nominal period only sets the probe's jitter figure, unused here.
    let period = clock.cycles_in(plant_model::Seconds(15e-3));
    // A described firmware's control function is the one it names, if any.
    let control = match &target.description {
        Some(d) => d
            .control_function(&firmware)
            .transpose()
            .map_err(super::bad_input)?,
        None => Some(CONTROL_FUNCTION.to_string()),
    };
    let probe = control
        .and_then(|f| TimingProbe::new(&firmware, Some(&f), period, &opts.bench.board).ok())
        .map(|p| Box::new(p) as Box<dyn Observer>);
    let (run, observer) = run_test_observed(firmware.clone(), &robot, test, &opts, probe)?;
    let report = observer
        .and_then(|o| o.into_any().downcast::<TimingProbe>().ok())
        .map(|p| p.report(&firmware, clock.hz(), &run.segment_starts()));
    let quantities = hil::runs::golden::measure(&run, report.as_ref(), clock);
    let shown = |p: &Path| for_golden(p);
    let in_force = InForce {
        firmware: match (&target.description, &target.elf) {
            (Some(d), _) => d.firmware_name(&firmware),
            (None, Some(_)) => firmware.name(),
            (None, None) => Build::to_possible_value(&target.firmware)
                .map(|v| v.get_name().to_string())
                .unwrap_or_default(),
        },
        elf: target.elf.as_deref().map(shown),
        elf_hash: firmware.content_hash(),
        robot: shown(&robot_path),
        robot_hash: hil::runs::golden::bytes_hash(&robot_bytes),
        board: c.board.as_deref().map(shown),
        seed: target.seed,
        params: target
            .params
            .iter()
            .map(|(p, v)| format!("{}={v}", p.name()))
            .collect(),
        keep_firmware_params: target.keep_firmware_params,
        scenario: c.scenario.as_deref().map(shown),
        tests: c.tests.as_deref().map(shown),
    };
    Ok(Measured {
        run,
        in_force,
        quantities,
    })
}

impl Record {
    fn run(self) -> Result<()> {
        super::check_output("--out", &self.out)?;
        let c = self.run.resolve(None)?;
        // A described firmware's leg is its own (or refused when asked of
        // one that fixes it), as hil run takes it.
        let leg_mm = match &c.target.description {
            Some(d) => d
                .leg_mm(self.leg.leg_mm, DEFAULT_LEG_MM)
                .map_err(super::bad_input)?,
            None => self.leg.leg_mm.unwrap_or(DEFAULT_LEG_MM),
        };
        let m = measure(&c, self.test.clone(), leg_mm)?;
        if !m.run.completed {
            return Err(super::Incomplete(format!(
                "the {} run did not complete ({}): no golden file written",
                self.test.name(),
                m.run.finding.as_deref().unwrap_or("no reason found")
            ))
            .into());
        }
        let golden = Golden::new(
            self.test,
            leg_mm,
            m.in_force,
            self.tol.over(Tolerances::default()),
            m.quantities,
        );
        super::write_output(&self.out, golden.to_json().as_bytes())?;
        self.json.emit(&golden, || {
            format!(
                "golden run of {} (legs of {leg_mm} mm, {} ELF {}, seed {}): {} quantities written to {}\n",
                golden.test.name(),
                golden.recorded_with.firmware,
                golden.recorded_with.elf_hash,
                golden.recorded_with.seed,
                golden.quantities.len(),
                self.out.display()
            )
        })
    }
}

impl Check {
    fn run(self) -> Result<()> {
        let name = self.file.display().to_string();
        let golden = Golden::load(&self.file).map_err(super::bad_input)?;
        let test = self.test.clone().unwrap_or(golden.test.clone());
        let leg_mm = self.leg_mm.unwrap_or(golden.leg_mm);
        golden
            .check_same_test(&name, &test, leg_mm)
            .map_err(super::bad_input)?;
        let c = self.run.resolve(Some(&golden.recorded_with))?;
        let m = measure(&c, test.clone(), leg_mm)?;
        let tol = self.tol.over(golden.tolerances);
        let rows = hil::runs::golden::compare(&golden.quantities, &m.quantities, &tol);
        let in_force = hil::runs::golden::differences(&golden.recorded_with, &m.in_force);
        let moved: Vec<&str> = rows
            .iter()
            .filter(|r| !r.ok)
            .map(|r| r.quantity.as_str())
            .collect();
        if self.json.json {
            let v = serde_json::json!({
                "golden": name,
                "test": test.name(),
                "leg_mm": leg_mm,
                "completed": m.run.completed,
                "finding": m.run.finding,
                "in_force": m.in_force,
                "differences": in_force,
                "tolerances": tol,
                "rows": rows,
                "moved": moved,
            });
            println!("{}", serde_json::to_string_pretty(&v)?);
        } else {
            println!(
                "golden run {name}: {} with legs of {leg_mm} mm",
                test.name()
            );
            if !m.run.completed {
                println!(
                    "the run did not complete: {}",
                    m.run.finding.as_deref().unwrap_or("no reason found")
                );
            }
            print!("{}", hil::runs::golden::render(&rows, &in_force));
        }
        if !m.run.completed {
            // Quantities of part of a run are no comparison with a whole one.
            return Err(super::Incomplete(format!(
                "the {} run did not complete ({}): no comparison with the golden run {name}",
                test.name(),
                m.run.finding.as_deref().unwrap_or("no reason found")
            ))
            .into());
        }
        if !moved.is_empty() {
            anyhow::bail!(
                "{} of {} quantities moved from the golden run {name}: {}",
                moved.len(),
                rows.len(),
                moved.join(", ")
            );
        }
        Ok(())
    }
}
