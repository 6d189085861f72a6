//! The bench measuring itself and the firmware: `hil bench` (speed), `hil fuzz`
//! (the parser against invalid frames) and `hil identify` (a motor from its
//! step response).

use std::path::PathBuf;

use anyhow::{Context, Result};
use hil::firmware::elf::Firmware;
use hil::runs::experiment::{Test, TestName};

use super::args::{Common, Json, Leg, SideArg};

/// The thesis sketch's test description, timed beside the builds.
const SKETCH_TESTS: &str = "firmware/arduino/henrytwo-thesis/tests.toml";

#[derive(clap::Args)]
pub struct Bench {
    /// The test to time [default: umbmark-cw; with --tests, the
    /// description's one test, or its umbmark-cw]. With --tests, the
    /// firmware it describes is timed on its board (bench and raw simavr on
    /// the same ELF and inputs), alone: the thesis build and sketch are the
    /// robust build's references.
    #[arg(long)]
    test: Option<TestName>,
    #[command(flatten)]
    leg: Leg,
    /// Skip the thesis build's runs (the slowest: busy loops; timed on
    /// a square of legs of at most 500 mm).
    #[arg(long)]
    without_thesis: bool,
    /// Skip the thesis sketch (Annex A built with the Arduino core), run
    /// black-box from its test description.
    #[arg(long)]
    without_sketch: bool,
    /// Skip raw simavr with its own PWM timers (slow, and not what the
    /// bench is compared with).
    #[arg(long)]
    without_simavr_pwm: bool,
    /// Time each run this many times, interleaved; the fastest counts (1 to 100).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=100))]
    repeats: u32,
    /// Time the bench-backed diagnosis instead (`hil gap --bench`): a
    /// dataset of 5 runs of each test (UMBmark CW and CCW, line, triangle)
    /// made by the bench with a small right wheel and a wide wheelbase
    /// hidden together, diagnosed with 1 job and with --jobs; the bench
    /// runs and wall time of the single, pair and triple fits, and whether
    /// 15 minutes on 2 cores held. The nominal
    /// robot: --robot, else the ideal one of `hil gap --self-test --bench`.
    #[arg(long, conflicts_with_all = ["test", "without_thesis", "without_sketch",
          "without_simavr_pwm", "repeats"])]
    diagnosis: bool,
    /// With --diagnosis: the parallel bench runs to compare with 1 job
    /// (default: the machine's cores, at least 2; 2 to 256).
    #[arg(long, requires = "diagnosis",
          value_parser = clap::value_parser!(u16).range(2..=256))]
    jobs: Option<u16>,
    #[command(flatten)]
    common: Common,
}

impl Bench {
    pub fn run(self) -> Result<()> {
        self.common.refuse_trace("bench")?;
        let described = self.common.target.description.as_deref();
        if let (true, Some(d)) = (self.diagnosis, described) {
            return Err(super::BadInput(format!(
                "--tests {}: --diagnosis times the bench-backed diagnosis, which sets each run's \
                 robot over the bench protocol; a firmware run from a test description has none \
                 (hil bench --tests FILE times its runs against raw simavr)",
                d.path
            ))
            .into());
        }
        // Said before anything runs: not a bench error after the reset.
        let test = super::timing::pick_test(described, self.test.clone(), Test::UmbmarkCw)
            .map_err(super::bad_input)?;
        if let Some(d) = described {
            hil::runs::perf::replayable_start(d, &test).map_err(super::bad_input)?;
        }
        let (robot, firmware) = self.common.target.load()?;
        if self.diagnosis {
            return self.diagnosis(robot, firmware);
        }
        // The thesis build and sketch are timed beside the robust build, as
        // the project's own references; a described firmware is timed alone.
        let thesis_path = hil::paths::firmware_elf("thesis");
        let thesis = if !self.without_thesis && described.is_none() && thesis_path.exists() {
            Some(Firmware::load(&thesis_path)?)
        } else {
            None
        };
        let sketch_tests = hil::paths::workspace_root().join(SKETCH_TESTS);
        let sketch = match self.without_sketch || described.is_some() {
            true => None,
            false => {
                let d = hil::firmware::description::Description::load(&sketch_tests)?;
                match d.elf.clone().filter(|p| p.exists()) {
                    Some(elf) => Some((Firmware::load(&elf)?, d)),
                    None => None,
                }
            }
        };
        let spinner = indicatif::ProgressBar::new_spinner();
        spinner.enable_steady_tick(std::time::Duration::from_millis(200));
        let board = self.common.target.bench().board;
        let report = hil::runs::perf::measure(&hil::runs::perf::BenchPlan {
            robust: &firmware,
            described,
            board: &board,
            thesis: thesis.as_ref(),
            sketch: sketch.as_ref().map(|(f, d)| (f, d)),
            robot: &robot,
            test,
            leg_mm: self.common.leg_mm(self.leg)?,
            repeats: self.repeats as usize,
            raw_with_pwm_timers: !self.without_simavr_pwm,
            progress: &|what: &str| spinner.set_message(what.to_string()),
        });
        spinner.finish_and_clear();
        let report = report?;
        self.common.print.json.emit(&report, || report.render())
    }
}

impl Bench {
    /// `--diagnosis`: the bench-backed diagnosis timed with 1 job and with N (and with 2,
    /// the budget's, when N is more).
    fn diagnosis(&self, robot: plant_model::RobotConfig, firmware: Firmware) -> Result<()> {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        let n = self.jobs.map_or(cores.max(2), usize::from);
        let mut jobs = vec![n];
        if n > 2 {
            jobs.insert(0, 2);
        }
        // The default robot has floor noise and effects of its own: a nominal bench robot
        // is noiseless.
        let robot = match self.common.target.robot {
            Some(_) => robot,
            None => plant_model::RobotConfig::default(),
        };
        let bench = hil::runs::gap_bench::BenchModel::new(firmware, robot, 1);
        let spinner = indicatif::ProgressBar::new_spinner();
        spinner.enable_steady_tick(std::time::Duration::from_millis(200));
        let speed = hil::runs::gap_bench::measure_diagnosis(&hil::runs::gap_bench::SpeedPlan {
            bench: &bench,
            hidden: &hil::runs::gap_bench::TWO_EFFECT_CASES[0],
            leg_mm: self.common.leg_mm(self.leg)?,
            runs_per_group: hil::runs::gap_bench::RUNS_PER_GROUP,
            seed: self.common.target.seed,
            jobs,
            opts: &hil::runs::gap_bench::SelectOptions::default(),
            progress: &|what: &str| spinner.set_message(what.to_string()),
        });
        spinner.finish_and_clear();
        let speed = speed?;
        self.common.print.json.emit(&speed, || speed.render())
    }
}

/// The most frames `hil fuzz` sends: a hundred times the default.
const MAX_FRAMES: u64 = 10_000_000;

#[derive(clap::Args)]
pub struct Fuzz {
    /// Number of invalid frames (1 to 10000000).
    #[arg(long, default_value_t = 100_000,
          value_parser = clap::value_parser!(u64).range(1..=MAX_FRAMES))]
    frames: u64,
    #[command(flatten)]
    common: Common,
}

impl Fuzz {
    pub fn run(self) -> Result<()> {
        self.common.refuse_trace("fuzz")?;
        let target = &self.common.target;
        let (robot, firmware) = target.load()?;
        let frames = self.frames as usize;
        let bar = indicatif::ProgressBar::new(self.frames);
        let report = hil::runs::fuzz::fuzz(firmware, &robot, frames, target.seed, &|n| {
            bar.set_position(n as u64)
        })?;
        bar.finish_and_clear();
        if self.common.print.json.json {
            println!("{}", serde_json::to_string_pretty(&report)?);
        } else {
            println!(
                "{} invalid frames (seed {}) over {:.0} s of robot time: {} error replies, {} ok replies, {} resets, {}, state {}",
                report.frames,
                report.seed,
                report.robot_time_s,
                report.error_replies,
                report.ok_replies,
                report.resets,
                if report.hung { "HUNG" } else { "still answering" },
                if report.state_changed { "CHANGED" } else { "unchanged" }
            );
            for (m, n) in &report.by_mutation {
                println!("  {m:?}: {n}");
            }
        }
        if !report.passed() {
            anyhow::bail!("the firmware did not survive the fuzzing unchanged");
        }
        Ok(())
    }
}

#[derive(clap::Args)]
pub struct Identify {
    /// Step-response CSV (e.g. fixtures/thesis-data/motor_step_right.csv).
    csv: PathBuf,
    /// Which motor, when the file name does not say.
    #[arg(long, value_enum)]
    side: Option<SideArg>,
    #[command(flatten)]
    json: Json,
}

impl Identify {
    pub fn run(self) -> Result<()> {
        let id = plant_model::identify::identify_csv(&self.csv, self.side.map(Into::into))
            .with_context(|| format!("identifying {}", self.csv.display()))
            .map_err(super::bad_input)?;
        self.json.emit(&id, || id.render())
    }
}
