//! The argument groups several commands share, each parsed and checked once.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::ValueEnum;
use hil::bench::BenchOptions;
use hil::board::{Board, Mcu};
use hil::firmware::elf::Firmware;
use hil::runs::experiment::TestOptions;
use plant_model::RobotConfig;

/// A `clap::ValueEnum` for a library enum whose crate knows nothing of clap:
/// the same variants, kebab-case on the command line, converted with `From`.
macro_rules! value_enum {
    ($(#[$doc:meta])* $name:ident => $target:path { $($variant:ident),+ $(,)? }) => {
        $(#[$doc])*
        #[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
        pub enum $name {
            $($variant),+
        }

        impl From<$name> for $target {
            fn from(v: $name) -> Self {
                match v {
                    $($name::$variant => <$target>::$variant),+
                }
            }
        }
    };
}

value_enum! {
    /// `--method`: which calibration test.
    MethodArg => hil::runs::calibrate::Method { Umbmark, Triangle }
}

value_enum! {
    /// `--frame`: the frame end points are recorded in.
    FrameArg => calib::Frame { Default, ThesisGui }
}

value_enum! {
    /// `--side`: which motor.
    SideArg => plant_model::Side { Left, Right }
}

/// `--firmware`: which build of firmware/target to run.
#[derive(ValueEnum, Clone, Copy, PartialEq, Eq)]
pub enum Build {
    Robust,
    Thesis,
}

/// What to run: the firmware, the robot, its board and the plant's seed.
#[derive(clap::Args, Clone)]
pub struct Target {
    /// Which firmware build to run.
    #[arg(long, value_enum, default_value_t = Build::Robust)]
    pub firmware: Build,
    /// Firmware ELF to run instead of the build in firmware/target.
    #[arg(long, value_name = "FILE")]
    pub elf: Option<PathBuf>,
    /// Test description (TOML, docs/reference/test-description.md) of a firmware
    /// that knows nothing of the bench (an Arduino sketch, your own C or
    /// Rust): how it is ready, how each test starts and ends, its variable
    /// names. Runs its `elf` unless --elf is given. Checked before anything runs.
    #[arg(long = "tests", value_name = "FILE", value_parser = parse_description)]
    pub description: Option<std::sync::Arc<hil::firmware::description::Description>>,
    /// Robot config TOML (default: fixtures/robots/henrytwo.toml, the best
    /// estimate of the thesis robot).
    #[arg(long, value_name = "FILE")]
    pub robot: Option<PathBuf>,
    /// Board TOML: which MCU pin each part is on, the motor driver, the
    /// links' USARTs (default: Henrytwo's, fixtures/boards/henrytwo.toml,
    /// built in). Checked before anything runs.
    #[arg(long, value_name = "FILE", value_parser = super::board::parse_board)]
    pub board: Option<Board>,
    /// The MCU the ELF is built for, over what the ELF says (its device
    /// note, `.mmcu` section or architecture): atmega2560, atmega328p or
    /// atmega32u4. It must be the board's (`mcu` in the board file).
    #[arg(long, value_name = "NAME", value_parser = parse_mcu)]
    pub mcu: Option<Mcu>,
    /// Seed of the plant's random effects (an experiment's runs each use a
    /// seed mixed from it and the run's index).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Run every iteration of the firmware's polling loops: no fast-forward
    /// over repeats the bench proves change nothing (the results are the
    /// same to the bit; only slower).
    #[arg(long)]
    pub no_skip: bool,
    /// Do not tell the firmware the robot's geometry (distance per count,
    /// counts per wheel turn, wheelbase) before each run: it keeps its own
    /// (factory) values, and the report warns where they are not the robot's.
    #[arg(long)]
    pub keep_firmware_params: bool,
    /// A firmware parameter to set over the protocol before each run, after
    /// the robot's geometry: NAME=VALUE with a name of protocol/README.md
    /// (e.g. kp_left=1.5); repeat for more. Checked against the firmware's
    /// range before anything runs.
    #[arg(long = "param", value_name = "NAME=VALUE", value_parser = parse_param)]
    pub params: Vec<(hil::firmware::link::Param, f32)>,
}

/// The `[firmware]` settings of the robot config at `path`, checked against
/// the firmware's ranges before anything runs: one error line naming the
/// file, the key and the range (exit 2).
pub fn check_firmware_settings(path: &std::path::Path, robot: &RobotConfig) -> Result<()> {
    hil::firmware::settings::of(robot)
        .map(drop)
        .map_err(|e| super::BadInput(format!("robot config {}: {e}", path.display())).into())
}

/// `--tests FILE`: a test description, read and checked.
pub fn parse_description(
    s: &str,
) -> Result<std::sync::Arc<hil::firmware::description::Description>, String> {
    hil::firmware::description::Description::load(s)
        .map(std::sync::Arc::new)
        .map_err(|e| e.to_string())
}

/// `NAME=VALUE` of `--param`: a protocol parameter's name and a value in its
/// range.
pub fn parse_param(s: &str) -> Result<(hil::firmware::link::Param, f32), String> {
    use hil::firmware::link::Param;
    let names = || {
        Param::ALL
            .iter()
            .map(|p| p.name())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let (name, value) = s
        .split_once('=')
        .ok_or_else(|| format!("{s:?}: give NAME=VALUE, NAME one of {}", names()))?;
    let p = Param::ALL
        .into_iter()
        .find(|p| p.name() == name.trim())
        .ok_or_else(|| format!("{name:?} is no firmware parameter; one of {}", names()))?;
    if p == Param::LegLengthMm {
        // The bench judges a run by the leg it asked for: a leg set behind
        // its back would be reported against the other length.
        return Err(format!(
            "{name}: the leg is set with --leg-mm (hil line: --length-mm), which the bench \
             also judges the run by; give it there"
        ));
    }
    let r = p.range();
    let v: f32 = value
        .trim()
        .parse()
        .map_err(|_| format!("{name}: {value:?} is not a number"))?;
    p.check(v).map_err(|_| {
        format!(
            "{name} = {value}: outside what the firmware accepts, {} to {}{}",
            r.min,
            r.max,
            if r.integer { ", whole numbers" } else { "" }
        )
    })?;
    Ok((p, v))
}

impl Target {
    /// Whether runs tell the firmware the robot's geometry.
    pub fn tell(&self) -> hil::firmware::params::Tell {
        if self.keep_firmware_params {
            hil::firmware::params::Tell::Keep
        } else {
            hil::firmware::params::Tell::Robot
        }
    }

    /// The robot config asked for, else the best estimate of the thesis
    /// robot, else the ideal one.
    pub fn robot(&self) -> Result<RobotConfig> {
        // The loader's errors name the file.
        let robot = RobotConfig::load(self.robot_path()).map_err(super::bad_input)?;
        check_firmware_settings(&self.robot_path(), &robot)?;
        // The robust build is told the robot's geometry before each run, and refuses
        // what lies outside its limits: refuse such a robot here, before anything runs.
        let told = self.firmware == Build::Robust
            && self.elf.is_none()
            && self.description.is_none()
            && !self.keep_firmware_params;
        let beyond = hil::firmware::params::beyond_firmware_limits(&robot);
        if told && !beyond.is_empty() {
            return Err(super::BadInput(format!(
                "{}: the robust firmware would refuse this robot's {}",
                self.robot_path().display(),
                beyond.join(", ")
            ))
            .into());
        }
        Ok(robot)
    }

    /// The path of the robot config [`Target::robot`] reads.
    pub fn robot_path(&self) -> PathBuf {
        self.robot.clone().unwrap_or_else(|| {
            let best = hil::paths::robot_config(hil::paths::REFERENCE_ROBOT);
            if best.exists() {
                best
            } else {
                hil::paths::robot_config("henrytwo-ideal")
            }
        })
    }

    /// The ELF of `--elf`, else the one the test description names, else
    /// of the `--firmware` build.
    pub fn firmware(&self) -> Result<Firmware> {
        let described = self.description.as_ref().and_then(|d| d.elf.clone());
        let path = match self.elf.as_ref().or(described.as_ref()) {
            Some(path) => path.clone(),
            None => {
                let build = self.firmware.to_possible_value().context("no such build")?;
                hil::paths::firmware_elf(build.get_name())
            }
        };
        let firmware = Firmware::load(&path).map_err(super::bad_input)?;
        self.check_mcu(&firmware)?;
        // A bench build (it takes parameters: the robust one) reads its
        // encoders on fixed pins: a board with them elsewhere would run and
        // count nothing. Refused here, before the run.
        if self.description.is_none() && hil::firmware::params::takes_params(&firmware) {
            if let Some(why) = self.board.and_then(|b| b.firmware_encoder_mismatch()) {
                return Err(super::BadInput(format!("--board: {why}")).into());
            }
        }
        if let Some(d) = &self.description {
            // The names the description gives must be in this ELF: checked
            // now, not when the run reaches them.
            d.resolve(&firmware).map_err(super::bad_input)?;
            let board = self.board.map_or(Mcu::default(), |b| b.mcu);
            d.check_usb(board).map_err(super::BadInput)?;
            if let Some(name) = d.control_function(&firmware) {
                name.map_err(super::bad_input)?;
            }
            if let Some((p, _)) = self.params.first() {
                return Err(super::BadInput(format!(
                    "--param {}: {}: the firmware it describes has no protocol to set parameters \
                     with; drop --param",
                    p.name(),
                    d.path
                ))
                .into());
            }
        }
        Ok(firmware)
    }

    /// The ELF's MCU (`--mcu` over what the ELF says; the board's when it
    /// says nothing) is the board's, and the ELF's architecture is its.
    fn check_mcu(&self, firmware: &Firmware) -> Result<()> {
        let board = self.board.map_or(Mcu::default(), |b| b.mcu);
        let (mcu, from) = match (self.mcu, firmware.mcu) {
            (Some(m), _) => (m, "--mcu"),
            (None, Some(m)) => (m, "the ELF"),
            (None, None) => (board, "the board"),
        };
        if mcu != board {
            return Err(super::BadInput(format!(
                "{}: built for the {mcu} ({from} says), the board is an {board}'s (mcu in the \
                 board file; absent: atmega2560): give a board for the {mcu}, or --mcu {board}",
                firmware.path.display()
            ))
            .into());
        }
        let chip = mcu.chip();
        if firmware.arch != chip.arch {
            return Err(super::BadInput(format!(
                "{}: its architecture (e_flags) is not the {mcu}'s {}: rebuild it for the {mcu}",
                firmware.path.display(),
                chip.arch_name
            ))
            .into());
        }
        Ok(())
    }

    /// The robot and the firmware, read in that order.
    pub fn load(&self) -> Result<(RobotConfig, Firmware)> {
        let robot = self.robot()?;
        Ok((robot, self.firmware()?))
    }

    /// Bench options with this seed and board.
    pub fn bench(&self) -> BenchOptions {
        BenchOptions {
            seed: self.seed,
            board: self.board.unwrap_or_default(),
            skip: !self.no_skip,
            ..Default::default()
        }
    }
}

/// `--mcu NAME`: a described MCU.
fn parse_mcu(s: &str) -> Result<Mcu, String> {
    Mcu::named(s).ok_or_else(|| format!("no MCU {s:?} is described; give one of {}", Mcu::names()))
}

/// `--json` alone, for commands without host timing.
#[derive(clap::Args, Clone, Copy)]
pub struct Json {
    /// Print one JSON object instead of the text summary.
    #[arg(long)]
    pub json: bool,
}

impl Json {
    /// Print `value` as JSON, or its text rendering for people.
    pub fn emit<T: serde::Serialize>(self, value: &T, text: impl FnOnce() -> String) -> Result<()> {
        if self.json {
            println!("{}", serde_json::to_string_pretty(value)?);
        } else {
            print!("{}", text());
        }
        Ok(())
    }
}

/// What a simulation prints: JSON or text, with or without host timing.
#[derive(clap::Args, Clone, Copy)]
pub struct Print {
    #[command(flatten)]
    pub json: Json,
    /// Leave host timing (wall time, real-time factor) out of the output,
    /// so that two runs print byte-identical results.
    #[arg(long)]
    pub deterministic: bool,
}

impl Print {
    /// A wall clock started now, which reads nothing under `--deterministic`.
    pub fn wall_clock(self) -> hil::runs::report::WallClock {
        hil::runs::report::WallClock::start(!self.deterministic)
    }
}

/// The VCD trace of a run.
#[derive(clap::Args, Clone)]
pub struct Trace {
    /// Write a VCD trace (encoder lines, bridge inputs, UART bytes, plant
    /// pose) for GTKWave or Surfer.
    #[arg(long, value_name = "FILE")]
    pub vcd: Option<PathBuf>,
    /// In the VCD, write the 31 kHz PWM waveforms edge by edge (large).
    #[arg(long, requires = "vcd")]
    pub vcd_pwm: bool,
}

/// The options every simulation takes.
#[derive(clap::Args, Clone)]
pub struct Common {
    #[command(flatten)]
    pub target: Target,
    #[command(flatten)]
    pub print: Print,
    #[command(flatten)]
    pub trace: Trace,
}

impl Common {
    /// For a command that writes no trace: `--vcd` refused (exit 2), not
    /// dropped without a file or a word.
    pub fn refuse_trace(&self, command: &str) -> Result<()> {
        if self.trace.vcd.is_some() {
            return Err(super::bad_input(anyhow::anyhow!(
                "--vcd traces one run: use hil run TEST ... --vcd FILE (hil {command} writes no trace)"
            )));
        }
        Ok(())
    }

    /// For a command that starts no run itself (its client does): `--tests`,
    /// `--param` and `--keep-firmware-params`, which shape how the bench starts
    /// each run and what it tells the firmware before it, refused (exit 2), not
    /// dropped.
    pub fn refuse_run_params(&self, command: &str) -> Result<()> {
        let t = &self.target;
        let option = if t.description.is_some() {
            "--tests"
        } else if !t.params.is_empty() {
            "--param"
        } else if t.keep_firmware_params {
            "--keep-firmware-params"
        } else {
            return Ok(());
        };
        Err(super::bad_input(anyhow::anyhow!(
            "{option}: hil {command} starts no run of its own (its client selects the tests and \
             sets the parameters over the link); the commands that run tests take it (hil run, \
             hil umbmark, ...)"
        )))
    }

    /// For a command that prints no result: `--json` (and `--deterministic`,
    /// which only shapes results) refused, not dropped.
    pub fn refuse_result_format(&self, command: &str, what: &str) -> Result<()> {
        let print = self.print;
        if let Some(option) = [
            (print.json.json, "--json"),
            (print.deterministic, "--deterministic"),
        ]
        .into_iter()
        .find_map(|(given, name)| given.then_some(name))
        {
            return Err(super::bad_input(anyhow::anyhow!(
                "{option}: hil {command} prints no result to format ({what}); the commands that \
                 run tests take it (hil run, hil umbmark, ...)"
            )));
        }
        Ok(())
    }

    /// A test run as these options ask for it, with legs of `leg_mm`.
    pub fn test_options(&self, leg_mm: f64) -> TestOptions {
        TestOptions {
            leg_mm,
            bench: self.target.bench(),
            record: self.trace.vcd.is_some(),
            tell: self.target.tell(),
            params: self.target.params.clone(),
            description: self.target.description.clone(),
            ..Default::default()
        }
    }

    /// The leg length `leg` asks for, as the test description allows it.
    pub fn leg_mm(&self, leg: Leg) -> Result<f64> {
        match &self.target.description {
            Some(d) => Ok(d.leg_mm(leg.leg_mm, DEFAULT_LEG_MM)?),
            None => Ok(leg.leg_mm.unwrap_or(DEFAULT_LEG_MM)),
        }
    }
}

/// The leg of the thesis' tests: 2 m.
pub const DEFAULT_LEG_MM: f64 = 2000.0;

/// The leg of a test: the side of the square or triangle, the line's length.
#[derive(clap::Args, Clone, Copy)]
pub struct Leg {
    /// Leg length in millimetres [default: 2000, or a described firmware's own].
    #[arg(long, value_parser = parse_leg, allow_negative_numbers = true)]
    pub leg_mm: Option<f64>,
}

/// How the error model is solved.
#[derive(clap::Args, Clone, Copy)]
pub struct Solve {
    /// Solve the error model exactly instead of with the published
    /// first-order formulas (better when turns miss by degrees; the default
    /// of calibration rounds).
    #[arg(long, conflicts_with = "first_order")]
    pub exact: bool,
    /// The published first-order formulas (Borenstein & Feng; Ruan, Li &
    /// Zhu), also in calibration rounds.
    #[arg(long)]
    pub first_order: bool,
}

impl Solve {
    /// The solution `--exact` or `--first-order` selects, else `default`.
    pub fn solution_or(self, default: calib::Solution) -> calib::Solution {
        if self.exact {
            calib::Solution::Exact
        } else if self.first_order {
            calib::Solution::FirstOrder
        } else {
            default
        }
    }

    /// The solution selected, the published formulas by default.
    pub fn solution(self) -> calib::Solution {
        self.solution_or(calib::Solution::FirstOrder)
    }
}

/// How end errors become a correction: the wheelbase of the firmware's
/// odometry, which the correction scales, and how the model is solved.
#[derive(clap::Args, Clone, Copy)]
pub struct Correction {
    /// The wheelbase the firmware's odometry uses, mm (the thesis' `b`;
    /// default: the one the runs told it, the robot's, or the firmware's own).
    #[arg(long, value_parser = parse_wheelbase)]
    pub firmware_wheelbase_mm: Option<f64>,
    #[command(flatten)]
    pub solve: Solve,
}

/// Where result files go.
#[derive(clap::Args, Clone)]
pub struct OutDir {
    /// Output folder for the report and the plot.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

/// A length in millimetres: positive, finite, at most 100 m.
pub fn parse_length(s: &str) -> Result<f64, String> {
    let v: f64 = s
        .parse()
        .map_err(|_| format!("{s:?} is not a number of millimetres"))?;
    if !v.is_finite() || v <= 0.0 || v > 100_000.0 {
        return Err(format!(
            "{s} mm is out of range: give a length above 0 and up to 100000 mm"
        ));
    }
    Ok(v)
}

/// A leg of the firmware's tests, mm: a length within what the firmware
/// accepts (`leg_length_mm`), so no run is started that it would refuse.
pub fn parse_leg(s: &str) -> Result<f64, String> {
    let v = parse_length(s)?;
    let p = hil::firmware::link::Param::LegLengthMm;
    let r = p.range();
    p.check(v as f32).map_err(|_| {
        format!(
            "{s} mm is out of range: the firmware's legs are {} to {} mm",
            r.min, r.max
        )
    })?;
    Ok(v)
}

/// A wheelbase in millimetres, in the robot config's range
/// (`plant_model::check::WHEELBASE_MM`, 20 to 2000 mm):
/// 0 or nan would print a correction of 0 mm or NaN.
pub fn parse_wheelbase(s: &str) -> Result<f64, String> {
    let v: f64 = s
        .parse()
        .map_err(|_| format!("{s:?} is not a number of millimetres"))?;
    // The robot config's own range: one definition, in the plant.
    let range = plant_model::check::WHEELBASE_MM;
    if !range.contains(v) {
        return Err(format!(
            "{s} mm is out of range: a wheelbase is {} to {} {}",
            range.low, range.high, range.unit
        ));
    }
    Ok(v)
}

/// A robot time in seconds: positive and finite.
pub fn parse_seconds(s: &str) -> Result<f64, String> {
    let v: f64 = s
        .parse()
        .map_err(|_| format!("{s:?} is not a number of seconds"))?;
    if !v.is_finite() || v <= 0.0 {
        return Err(format!("{s} s is out of range: give a positive robot time"));
    }
    Ok(v)
}

/// `--jobs`: parallel runs, at least 1. Any larger count is taken and
/// capped by [`threads`]: threads past the work or the cores only cost.
#[derive(clap::Args, Clone, Copy)]
pub struct Jobs {
    /// Parallel runs (default: all cores; capped at the runs to make and
    /// at the machine's cores, with a note).
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
    pub jobs: Option<u64>,
}

impl Jobs {
    /// The worker threads for `work` runs: `--jobs`, else the machine's
    /// cores, at most one per run and per core. A count given and capped
    /// is said on stderr, so that `--jobs 100000` is not taken for 100 000
    /// threads (one per job made 4000 threads and ran six times slower).
    pub fn threads(self, work: usize) -> usize {
        cap_jobs(self.jobs, Some(work))
    }

    /// A pool of [`Jobs::threads`] workers for `work` runs.
    pub fn pool(self, work: usize) -> anyhow::Result<rayon::ThreadPool> {
        rayon::ThreadPoolBuilder::new()
            .num_threads(self.threads(work))
            .build()
            .context("starting the worker threads")
    }
}

/// `given` parallel jobs (default: all cores) capped at the machine's cores
/// and, when known, at the `work` to share out; a count given and capped
/// is said on stderr.
pub fn cap_jobs(given: Option<u64>, work: Option<usize>) -> usize {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let cap = work.map_or(cores, |w| cores.min(w)).max(1);
    match given {
        Some(j) if j > cap as u64 => {
            let runs = work.map_or(String::new(), |w| format!("{w} run(s) to make, "));
            eprintln!("note: --jobs {j} capped at {cap} ({runs}{cores} core(s) on this machine)");
            cap
        }
        Some(j) => j as usize,
        None => cap,
    }
}
