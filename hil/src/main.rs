//! `hil`: the bench's command line.

#![deny(unsafe_code)]

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use hil::bench::BenchOptions;
use hil::elf::Firmware;
use hil::experiment::{run_test, run_test_observed, Test, TestOptions};
use hil::line::{run_line, LineOptions};
use hil::timing::{Budgets, TimingProbe};
use hil::umbmark::{execute, Partial, Plan, Shard};
use plant_model::RobotConfig;
use rayon::prelude::*;

mod station_cli;

#[derive(Parser)]
#[command(
    name = "hil",
    version,
    about = "Hardware-in-the-loop bench for the Henrytwo robot firmware"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(clap::Args, Clone)]
struct Common {
    /// Which firmware build to run.
    #[arg(long, value_enum, default_value_t = Build::Robust)]
    firmware: Build,
    /// Firmware ELF to run instead of the build in firmware/target.
    #[arg(long, value_name = "FILE")]
    elf: Option<PathBuf>,
    /// Robot config TOML (default: fixtures/robots/henrytwo.toml, the best
    /// estimate of the thesis robot).
    #[arg(long, value_name = "FILE")]
    robot: Option<PathBuf>,
    /// Seed of the plant's random effects.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Print one JSON object instead of the text summary.
    #[arg(long)]
    json: bool,
    /// Leave host timing (wall time, real-time factor) out of the output,
    /// so that two runs print byte-identical results.
    #[arg(long)]
    deterministic: bool,
    /// Write a VCD trace (encoder lines, bridge inputs, UART bytes, plant
    /// pose) for GTKWave or Surfer.
    #[arg(long, value_name = "FILE")]
    vcd: Option<PathBuf>,
    /// In the VCD, write the 31 kHz PWM waveforms edge by edge (large).
    #[arg(long)]
    vcd_pwm: bool,
}

impl Common {
    /// A test run as these options ask for it.
    fn test_options(&self, leg_mm: f64) -> TestOptions {
        TestOptions {
            leg_mm,
            bench: BenchOptions {
                seed: self.seed,
                ..Default::default()
            },
            record: self.vcd.is_some(),
            ..Default::default()
        }
    }
}

#[derive(clap::ValueEnum, Clone, Copy, PartialEq, Eq)]
enum Build {
    Robust,
    Thesis,
}

impl Build {
    fn name(self) -> &'static str {
        match self {
            Build::Robust => "robust",
            Build::Thesis => "thesis",
        }
    }
}

#[derive(Subcommand)]
enum Command {
    /// The reduced UMBmark: 5 runs clockwise, 5 counter-clockwise, and the correction.
    Umbmark {
        /// Side of the square in millimetres.
        #[arg(long, default_value_t = 2000.0, value_parser = parse_length, allow_negative_numbers = true)]
        leg_mm: f64,
        /// The wheelbase the firmware's odometry uses, mm (the thesis' `b`).
        #[arg(long, default_value_t = 130.0)]
        firmware_wheelbase_mm: f64,
        /// Solve the error model exactly instead of with the published
        /// first-order formulas (better when turns miss by degrees).
        #[arg(long)]
        exact: bool,
        /// Run only shard K of N (K/N) and write its partial result to --out.
        #[arg(long, value_name = "K/N")]
        shard: Option<Shard>,
        /// Output folder for partial results, reports and plots.
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        /// Parallel runs (default: all cores).
        #[arg(long)]
        jobs: Option<usize>,
        #[command(flatten)]
        common: Common,
    },
    /// Measure the firmware's timing cycle-exactly over a run and check it
    /// against the budgets; fails when one is exceeded.
    Timing {
        /// The test to run while measuring.
        #[arg(long, default_value = "line")]
        test: Test,
        /// Leg length in millimetres.
        #[arg(long, default_value_t = 2000.0, value_parser = parse_length, allow_negative_numbers = true)]
        leg_mm: f64,
        /// Budgets (TOML; default: fixtures/timing-budgets.toml).
        #[arg(long, value_name = "FILE")]
        budgets: Option<PathBuf>,
        /// The control function to time.
        #[arg(long, default_value = "ht_control_tick")]
        function: String,
        #[command(flatten)]
        common: Common,
    },
    /// Identify a motor from a step-response CSV (the thesis' layout):
    /// 63.2 % fit, first order plus dead time, Ziegler-Nichols, ZOH model,
    /// and which thesis figures it reproduces or contradicts.
    Identify {
        /// Step-response CSV (e.g. fixtures/thesis-data/motor_step_right.csv).
        csv: PathBuf,
        /// Which motor, when the file name does not say (left or right).
        #[arg(long)]
        side: Option<String>,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Odometry corrections from measured end points (a real robot's, or the
    /// thesis' tables), or calibration rounds on the emulated robot.
    Calibrate {
        /// End points in the layout of umbmark_endpoints.csv or triangular_endpoints.csv.
        #[arg(long, value_name = "FILE")]
        from_csv: Option<PathBuf>,
        /// The experiment number in the table.
        #[arg(long, default_value_t = 1)]
        experiment: u32,
        /// umbmark or triangle (default: from the table's header).
        #[arg(long)]
        method: Option<String>,
        /// The thesis GUI's formulas exactly as printed (its bugs included).
        #[arg(long)]
        thesis_compat: bool,
        /// The frame the end points are recorded in: default (x along the
        /// first leg, y to the left) or thesis-gui (x mirrored). Default:
        /// default, or in --thesis-compat the GUI's.
        #[arg(long)]
        frame: Option<String>,
        /// Square side / line length, cm (default 200).
        #[arg(long)]
        side_cm: Option<f64>,
        /// The wheelbase the robot's odometry used, mm.
        #[arg(long)]
        wheelbase_mm: Option<f64>,
        /// Solve the error model exactly instead of with the published
        /// first-order formulas (better when turns miss by degrees).
        #[arg(long)]
        exact: bool,
        /// Correction rounds on the emulated robot (without --from-csv).
        #[arg(long, default_value_t = 2)]
        rounds: usize,
        /// Side of the square for the rounds, mm.
        #[arg(long, default_value_t = 2000.0, value_parser = parse_length, allow_negative_numbers = true)]
        leg_mm: f64,
        #[command(flatten)]
        common: Common,
    },
    /// Measure the bench's speed: real-time factors of the bench, raw simavr
    /// on the same ELF, and the thesis build; the bench's overhead.
    Bench {
        /// The test to time.
        #[arg(long, default_value = "umbmark-cw")]
        test: Test,
        /// Leg length in millimetres.
        #[arg(long, default_value_t = 2000.0, value_parser = parse_length, allow_negative_numbers = true)]
        leg_mm: f64,
        /// Skip the thesis build's runs (the slowest: busy loops; timed on
        /// a square of legs of at most 500 mm).
        #[arg(long)]
        without_thesis: bool,
        /// Skip raw simavr with its own PWM timers (slow, and not what the
        /// bench is compared with).
        #[arg(long)]
        without_simavr_pwm: bool,
        /// Time each run this many times, interleaved; the fastest counts.
        #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..))]
        repeats: u32,
        #[command(flatten)]
        common: Common,
    },
    /// Inject each fault of the library into the robust and the thesis
    /// builds; check the robust build's reaction against the expectation.
    Faults {
        /// Run every fault of the library.
        #[arg(long)]
        all: bool,
        /// Run only these faults (names as listed by `hil faults --list`).
        #[arg(long = "fault", value_name = "NAME")]
        only: Vec<String>,
        /// List the faults and their expected reactions.
        #[arg(long)]
        list: bool,
        /// Run the faults of a scenario file (TOML or JSON) against both
        /// builds instead of the library (reported, not judged).
        #[arg(long, value_name = "FILE")]
        scenario: Option<PathBuf>,
        /// Robot seconds without progress after which a busy firmware is
        /// reported hung, with its PC and symbol.
        #[arg(long, value_name = "S", default_value_t = hil::hang::DEFAULT_HANG_AFTER_S, value_parser = parse_seconds)]
        hang_after: f64,
        #[command(flatten)]
        common: Common,
    },
    /// The Triangular Path test: 5 straight lines, 5 counter-clockwise
    /// triangles, and the correction (Ed from the lines, Eb from the turns).
    Triangle {
        /// Length of the line and side of the triangle, mm.
        #[arg(long, default_value_t = 2000.0, value_parser = parse_length, allow_negative_numbers = true)]
        leg_mm: f64,
        /// The wheelbase the firmware's odometry uses, mm.
        #[arg(long, default_value_t = 130.0)]
        firmware_wheelbase_mm: f64,
        /// Solve the error model exactly instead of with the published
        /// first-order formulas (better when turns miss by degrees).
        #[arg(long)]
        exact: bool,
        /// Output folder for the report and the plot.
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        #[command(flatten)]
        common: Common,
    },
    /// Fuzz the robust firmware's UART parser in the emulator with seeded
    /// invalid frames: no hang, no reset, no state change allowed.
    Fuzz {
        /// Number of invalid frames.
        #[arg(long, default_value_t = 100_000)]
        frames: usize,
        #[command(flatten)]
        common: Common,
    },
    /// Sim-to-real gap: where the real data and the model disagree, which
    /// effect explains it, how far it shrinks on held-out data.
    Gap {
        /// A folder of manifests (TOML) or manifest files: the real data
        /// (e.g. fixtures/real/thesis).
        #[arg(long, value_name = "DIR|FILE", num_args = 1..)]
        real: Vec<PathBuf>,
        /// The base model: a robot config whose geometry is the reference
        /// (default: each manifest's own robot_config).
        #[arg(long, value_name = "FILE")]
        model: Option<PathBuf>,
        /// Train on these experiments (manifest `experiment` names), hold out
        /// the rest (default: umbmark-1 when present, else the first by name).
        #[arg(long, value_delimiter = ',')]
        train: Vec<String>,
        /// Generate "real" data from the model with one hidden effect at a
        /// time and check the diagnosis finds it.
        #[arg(long)]
        self_test: bool,
        /// Write the report as Markdown (with an SVG plot next to it).
        #[arg(long, value_name = "FILE")]
        markdown: Option<PathBuf>,
        /// Print JSON.
        #[arg(long)]
        json: bool,
        #[arg(long, default_value_t = 0)]
        seed: u64,
    },
    /// Combine the partial results of `hil umbmark --shard` into the full result.
    Merge {
        /// Partial result files (JSON).
        #[arg(required = true)]
        parts: Vec<PathBuf>,
        /// The wheelbase the firmware's odometry uses, mm.
        #[arg(long, default_value_t = 130.0)]
        firmware_wheelbase_mm: f64,
        /// Solve the error model exactly instead of with the published
        /// first-order formulas (better when turns miss by degrees).
        #[arg(long)]
        exact: bool,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Run one of the firmware's tests and report each leg and turn.
    Run {
        /// umbmark-cw, umbmark-ccw, line or triangle.
        test: Test,
        /// Leg length in millimetres.
        #[arg(long, default_value_t = 2000.0, value_parser = parse_length, allow_negative_numbers = true)]
        leg_mm: f64,
        /// Inject the faults of a scenario file (TOML or JSON).
        #[arg(long, value_name = "FILE")]
        scenario: Option<PathBuf>,
        /// Stop and report a hang (PC and symbol) after this many robot
        /// seconds without progress while the firmware is busy in the test.
        #[arg(long, value_name = "S", value_parser = parse_seconds)]
        hang_after: Option<f64>,
        /// Serve gdb's remote protocol on 127.0.0.1:PORT, the run paused at
        /// reset until the debugger continues (`target remote :PORT`).
        #[arg(long, value_name = "PORT")]
        gdb: Option<u16>,
        #[command(flatten)]
        common: Common,
    },
    /// Run the straight-line test (command byte 4) and summarise it.
    Line {
        /// Length of the line in millimetres.
        #[arg(long, default_value_t = 2000.0, value_parser = parse_length, allow_negative_numbers = true)]
        length_mm: f64,
        /// Write the plant trace (10 ms samples) as CSV.
        #[arg(long, value_name = "FILE")]
        trace_csv: Option<PathBuf>,
        #[command(flatten)]
        common: Common,
    },
    /// Run the emulated robot paced to real time (or N x real time) and
    /// expose its Bluetooth UART (USART1) as a pseudo-terminal, for any
    /// serial client.
    Serve {
        /// Expose USART1 on a pseudo-terminal (its path is printed).
        #[arg(long, required = true)]
        pty: bool,
        /// Robot seconds per wall-clock second.
        #[arg(long, default_value_t = 1.0)]
        speed: f64,
        #[command(flatten)]
        common: Common,
    },
    /// The operator's station: a web page on 127.0.0.1 to pick a robot
    /// (emulated or on a serial port), run tests, watch telemetry, enter end
    /// points and send the correction.
    Ui {
        /// A serial port to offer first (a real robot, or `hil serve --pty`).
        #[arg(long, value_name = "DEVICE")]
        port: Option<String>,
        /// Baud rate of the serial port (the HC-05's is 9600).
        #[arg(long, default_value_t = 9600)]
        baud: u32,
        /// TCP port of the page on 127.0.0.1 (0: any free port).
        #[arg(long, default_value_t = 8317)]
        listen_port: u16,
        /// Folder of the session files, one per robot.
        #[arg(long, value_name = "DIR", default_value = "station-sessions")]
        sessions: PathBuf,
        #[command(flatten)]
        common: Common,
    },
}

fn parse_length(s: &str) -> Result<f64, String> {
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

fn parse_seconds(s: &str) -> Result<f64, String> {
    let v: f64 = s
        .parse()
        .map_err(|_| format!("{s:?} is not a number of seconds"))?;
    if !v.is_finite() || v <= 0.0 {
        return Err(format!("{s} s is out of range: give a positive robot time"));
    }
    Ok(v)
}

/// Print `value` as JSON, or its text rendering for people.
fn emit<T: serde::Serialize>(json: bool, value: &T, text: impl FnOnce() -> String) -> Result<()> {
    if json {
        println!("{}", serde_json::to_string_pretty(value)?);
    } else {
        print!("{}", text());
    }
    Ok(())
}

fn write_vcd(
    path: &std::path::Path,
    run: &hil::experiment::TestRun,
    pwm_edges: bool,
) -> Result<()> {
    let text = hil::vcd::render(&hil::vcd::VcdInput {
        clock_hz: BenchOptions::default().clock.hz(),
        edges: &run.edges,
        drive: &run.drive,
        uart: &run.uart,
        samples: &run.trace,
        pwm_edges,
    });
    hil::output::write_atomic(path, text.as_bytes())
        .with_context(|| format!("writing {}", path.display()))?;
    eprintln!("wrote {}", path.display());
    Ok(())
}

/// Run `specs` of `plan` with a progress bar of runs and robot time.
fn execute_with_progress(
    firmware: &Firmware,
    robot: &RobotConfig,
    plan: &Plan,
    specs: &[hil::umbmark::RunSpec],
) -> Result<Vec<hil::umbmark::IndexedRun>> {
    let bar = progress_bar(specs.len(), plan.leg_mm);
    let runs = execute(
        firmware,
        robot,
        plan,
        specs,
        BenchOptions::default(),
        &|n, robot_s| {
            bar.set_position(n as u64);
            bar.set_message(format!("{robot_s:.0} s of robot time"));
        },
    )?;
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

fn load_robot(path: Option<&PathBuf>) -> Result<RobotConfig> {
    let path = path.cloned().unwrap_or_else(|| {
        let best = hil::paths::robot_config("henrytwo");
        if best.exists() {
            best
        } else {
            hil::paths::robot_config("henrytwo-ideal")
        }
    });
    RobotConfig::load(&path).with_context(|| format!("robot config {}", path.display()))
}

fn load_firmware(common: &Common) -> Result<Firmware> {
    let path = common
        .elf
        .clone()
        .unwrap_or_else(|| hil::paths::firmware_elf(common.firmware.name()));
    Ok(Firmware::load(&path)?)
}

fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Umbmark {
            leg_mm,
            firmware_wheelbase_mm,
            exact,
            shard,
            out,
            jobs,
            common,
        } => {
            let robot = load_robot(common.robot.as_ref())?;
            let firmware = load_firmware(&common)?;
            let plan = Plan::new(leg_mm, common.seed, &robot, &firmware);
            let specs = match shard {
                Some(s) => plan.shard(s),
                None => plan.runs(),
            };
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(jobs.unwrap_or(0))
                .build()
                .context("starting the worker threads")?;
            let wall = Instant::now();
            let runs = pool.install(|| execute_with_progress(&firmware, &robot, &plan, &specs))?;
            let wall_s = wall.elapsed().as_secs_f64();
            let partial = Partial {
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
                let dir = out.unwrap_or_else(|| PathBuf::from("."));
                let path = hil::umbmark::partial_path(&dir, s);
                hil::output::write_atomic(
                    &path,
                    serde_json::to_string_pretty(&partial)?.as_bytes(),
                )?;
                eprintln!("wrote {} ({} runs)", path.display(), partial.runs.len());
                return Ok(());
            }
            let report = hil::umbmark::report(&partial, firmware_wheelbase_mm, solution(exact))?;
            if let Some(dir) = &out {
                for f in hil::umbmark::write_outputs(dir, &partial, &report)? {
                    eprintln!("wrote {}", f.display());
                }
            }
            let robot_s = report.robot_time_s;
            if common.json {
                let mut v = serde_json::to_value(&report)?;
                if !common.deterministic {
                    v["rtf"] = (robot_s / wall_s).into();
                    v["wall_s"] = wall_s.into();
                }
                println!("{}", serde_json::to_string_pretty(&v)?);
            } else {
                print!("{}", report.render());
                if !common.deterministic {
                    println!(
                        "  wall time {wall_s:.2} s on {} threads: {:.0}x real time",
                        pool.current_num_threads(),
                        robot_s / wall_s
                    );
                }
            }
        }
        Command::Timing {
            test,
            leg_mm,
            budgets,
            function,
            common,
        } => {
            let robot = load_robot(common.robot.as_ref())?;
            let firmware = load_firmware(&common)?;
            let budgets_path = budgets.unwrap_or_else(|| {
                hil::paths::workspace_root().join("fixtures/timing-budgets.toml")
            });
            let budgets = Budgets::load(&budgets_path)?;
            let clock = BenchOptions::default().clock;
            let period = clock.cycles_in(plant_model::Seconds(budgets.tick_period_us * 1e-6));
            let probe = TimingProbe::new(&firmware, &function, period)?;
            let opts = common.test_options(leg_mm);
            let (run, observer) =
                run_test_observed(firmware.clone(), &robot, test, &opts, Some(Box::new(probe)))?;
            let probe = observer
                .and_then(|o| o.into_any().downcast::<TimingProbe>().ok())
                .context("the timing probe was lost")?;
            let report = probe.report(&firmware, &function, clock.hz());
            let rows = report.check(&budgets);
            let failed: Vec<&str> = rows
                .iter()
                .filter(|r| !r.pass)
                .map(|r| r.what.as_str())
                .collect();
            if common.json {
                let v = serde_json::json!({
                    "test": test.name(),
                    "completed": run.completed,
                    "report": report,
                    "budgets": rows,
                    "pass": failed.is_empty(),
                });
                println!("{}", serde_json::to_string_pretty(&v)?);
            } else {
                println!(
                    "timing of {} over {} ({}):",
                    firmware.path.display(),
                    test.name(),
                    if run.completed {
                        "completed"
                    } else {
                        "did not complete"
                    }
                );
                print!("{}", report.render(&rows));
            }
            if !failed.is_empty() {
                anyhow::bail!(
                    "{} timing budget(s) exceeded: {} (budgets in {})",
                    failed.len(),
                    failed.join("; "),
                    budgets_path.display()
                );
            }
        }
        Command::Identify { csv, side, json } => {
            let side = match side.as_deref() {
                None => None,
                Some("left") => Some(plant_model::Side::Left),
                Some("right") => Some(plant_model::Side::Right),
                Some(other) => anyhow::bail!("--side {other}: give left or right"),
            };
            let id = plant_model::identify::identify_csv(csv.as_path(), side)
                .with_context(|| format!("identifying {}", csv.display()))?;
            emit(json, &id, || id.render())?;
        }
        Command::Calibrate {
            from_csv,
            experiment,
            method,
            thesis_compat,
            frame,
            side_cm,
            wheelbase_mm,
            rounds,
            leg_mm,
            exact,
            common,
        } => {
            let json = common.json;
            let Some(path) = from_csv else {
                let robot = load_robot(common.robot.as_ref())?;
                let firmware = load_firmware(&common)?;
                let plan = Plan::new(leg_mm, common.seed, &robot, &firmware);
                let plan = match method.as_deref() {
                    None | Some("umbmark") => plan,
                    Some("triangle") => plan.triangle(),
                    Some(m) => anyhow::bail!("--method {m}: use umbmark or triangle"),
                };
                let bar = progress_bar((rounds + 1) * 2 * plan.runs_per_direction, leg_mm);
                let total = 2 * plan.runs_per_direction;
                let results = hil::umbmark::calibrate(
                    &firmware,
                    &robot,
                    &plan,
                    wheelbase_mm.unwrap_or(130.0),
                    rounds,
                    solution(exact),
                    &|round, n, _| {
                        bar.set_position((round * total + n) as u64);
                        bar.set_message(format!("round {round}"));
                    },
                )?;
                bar.finish_and_clear();
                let table = hil::umbmark::table10(&results)?;
                if common.json {
                    let v = serde_json::json!({ "rounds": results, "table10": table });
                    println!("{}", serde_json::to_string_pretty(&v)?);
                } else {
                    for r in &results {
                        println!(
                            "round {}: cL {:.5}, cR {:.5}, wheelbase {:.2} mm -> {}",
                            r.round,
                            r.c_left,
                            r.c_right,
                            r.wheelbase_mm,
                            r.report.summary()
                        );
                    }
                    let rows: Vec<(&str, calib::Round)> =
                        table.iter().map(|(n, r)| (n.as_str(), *r)).collect();
                    print!(
                        "{}",
                        calib::round::format_table10(&rows, calib::round::TableStyle::Rounded)
                    );
                }
                return Ok(());
            };
            let method = match method.as_deref() {
                None => hil::calibrate::detect(&path)?,
                Some("umbmark") => hil::calibrate::Method::Umbmark,
                Some("triangle") => hil::calibrate::Method::Triangle,
                Some(m) => anyhow::bail!("--method {m}: use umbmark or triangle"),
            };
            let frame = match frame.as_deref() {
                None => None,
                Some("default") => Some(calib::Frame::Default),
                Some("thesis-gui") => Some(calib::Frame::ThesisGui),
                Some(f) => anyhow::bail!("--frame {f}: use default or thesis-gui"),
            };
            if let Some(l) = side_cm.filter(|l| !(l.is_finite() && *l > 0.0)) {
                anyhow::bail!("--side-cm {l}: give a positive length in centimetres");
            }
            let opts = hil::calibrate::FromCsv {
                experiment,
                thesis_compat,
                frame,
                side_cm,
                wheelbase_mm,
                solution: solution(exact),
            };
            let result = hil::calibrate::from_csv(&path, method, &opts)
                .with_context(|| format!("{}", path.display()))?;
            emit(json, &result, || result.render())?;
        }
        Command::Bench {
            test,
            leg_mm,
            without_thesis,
            without_simavr_pwm,
            repeats,
            common,
        } => {
            let repeats = repeats as usize;
            let robot = load_robot(common.robot.as_ref())?;
            let firmware = load_firmware(&common)?;
            let thesis_path = hil::paths::firmware_elf("thesis");
            let thesis = if !without_thesis && thesis_path.exists() {
                Some(Firmware::load(&thesis_path)?)
            } else {
                None
            };
            let spinner = indicatif::ProgressBar::new_spinner();
            spinner.enable_steady_tick(std::time::Duration::from_millis(200));
            let report = hil::perf::measure(&hil::perf::BenchPlan {
                robust: &firmware,
                thesis: thesis.as_ref(),
                robot: &robot,
                test,
                leg_mm,
                repeats,
                raw_with_pwm_timers: !without_simavr_pwm,
                progress: &|what: &str| spinner.set_message(what.to_string()),
            });
            spinner.finish_and_clear();
            let report = report?;
            emit(common.json, &report, || report.render())?;
        }
        Command::Faults {
            all,
            only,
            list,
            scenario,
            hang_after,
            common,
        } => {
            let options = hil::faults::FaultOptions {
                seed: common.seed,
                hang_after_s: hang_after,
            };
            let library = match &scenario {
                Some(path) => vec![hil::faults::from_scenario(
                    path,
                    &hil::scenario::Scenario::load(path)?,
                )],
                None => hil::faults::library(),
            };
            if list {
                for f in &library {
                    println!(
                        "{:<20} {}\n{:<20} expected: {}",
                        f.name, f.what, "", f.expected
                    );
                }
                return Ok(());
            }
            if let Some(unknown) = only.iter().find(|o| library.iter().all(|f| f.name != *o)) {
                anyhow::bail!("no fault is called {unknown:?}: `hil faults --list` names them");
            }
            let selected: Vec<_> = library
                .into_iter()
                .filter(|f| all || scenario.is_some() || only.iter().any(|o| o == f.name))
                .collect();
            if selected.is_empty() {
                anyhow::bail!(
                    "no fault selected: give --all, --fault NAME (see --list) or --scenario FILE"
                );
            }
            let robot = load_robot(common.robot.as_ref())?;
            let robust = load_firmware(&common)?;
            let thesis_path = hil::paths::firmware_elf("thesis");
            let thesis = thesis_path
                .exists()
                .then(|| Firmware::load(&thesis_path))
                .transpose()?;
            let rows = selected
                .par_iter()
                .map(|case| {
                    hil::faults::run_fault(case, &robust, thesis.as_ref(), &robot, &options)
                })
                .collect::<Result<Vec<_>, _>>()?;
            let failed = rows.iter().filter(|r| !r.pass).count();
            if common.json {
                println!("{}", serde_json::to_string_pretty(&rows)?);
            } else {
                print!("{}", hil::faults::render(&rows));
            }
            if failed > 0 {
                anyhow::bail!("{failed} fault reaction(s) not as expected");
            }
        }
        Command::Triangle {
            leg_mm,
            firmware_wheelbase_mm,
            exact,
            out,
            common,
        } => {
            let robot = load_robot(common.robot.as_ref())?;
            let firmware = load_firmware(&common)?;
            let plan = Plan::new(leg_mm, common.seed, &robot, &firmware).triangle();
            let specs = plan.runs();
            let wall = Instant::now();
            let runs = execute_with_progress(&firmware, &robot, &plan, &specs)?;
            let wall_s = wall.elapsed().as_secs_f64();
            let full = Partial {
                kind: "triangle".into(),
                plan,
                shard: None,
                runs,
            };
            let report =
                hil::umbmark::triangle_report(&full, firmware_wheelbase_mm, solution(exact))?;
            if let Some(dir) = &out {
                for f in hil::umbmark::write_triangle_outputs(dir, &full, &report)? {
                    eprintln!("wrote {}", f.display());
                }
            }
            if common.json {
                let mut v = serde_json::to_value(&report)?;
                if !common.deterministic {
                    v["rtf"] = (report.robot_time_s / wall_s).into();
                }
                println!("{}", serde_json::to_string_pretty(&v)?);
            } else {
                print!("{}", report.render());
            }
        }
        Command::Fuzz { frames, common } => {
            let robot = load_robot(common.robot.as_ref())?;
            let firmware = load_firmware(&common)?;
            let bar = indicatif::ProgressBar::new(frames as u64);
            let report = hil::fuzz::fuzz(firmware, &robot, frames, common.seed, &|n| {
                bar.set_position(n as u64)
            })?;
            bar.finish_and_clear();
            if common.json {
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
        }
        Command::Gap {
            real,
            model,
            train,
            self_test,
            markdown,
            json,
            seed,
        } => {
            let kinematic = gap::KinematicModel;
            if self_test {
                let cases = gap::self_test(&kinematic, seed);
                if json {
                    println!("{}", serde_json::to_string_pretty(&cases)?);
                } else {
                    println!(
                        "{:<26} {:>12} {:>6} {:>12} {:>9} {:>12} {:>12}",
                        "effect",
                        "injected",
                        "first",
                        "fitted",
                        "error %",
                        "gap before",
                        "gap after"
                    );
                    for c in &cases {
                        println!(
                            "{:<26} {:>12.5} {:>6} {:>12.5} {:>9.2} {:>12.3} {:>12.3}",
                            c.effect,
                            c.injected,
                            if c.ranked_first { "yes" } else { "NO" },
                            c.fitted,
                            c.value_error_pct,
                            c.heldout_gap_before,
                            c.heldout_gap_after
                        );
                    }
                }
                return Ok(());
            }
            if real.is_empty() {
                anyhow::bail!("give --real DIR (manifests of real data, e.g. fixtures/real/thesis) or --self-test");
            }
            let mut manifests = Vec::new();
            for r in &real {
                if r.is_dir() {
                    manifests.extend(gap::load_dir(r)?);
                } else {
                    manifests.push(gap::LoadedManifest::load(r)?);
                }
            }
            if let Some(m) = &model {
                let cfg = RobotConfig::load(m).with_context(|| format!("model {}", m.display()))?;
                let reference = gap::manifest::reference_from_config(&cfg);
                for lm in &mut manifests {
                    lm.reference = Some(reference);
                }
            }
            let train = if train.is_empty() {
                let mut names: Vec<String> = manifests
                    .iter()
                    .filter(|m| m.manifest.endpoints.is_some())
                    .map(|m| m.manifest.experiment.clone())
                    .collect();
                names.sort();
                // The thesis' own procedure: fit on UMBmark experiment 1,
                // predict the rest.
                match names.iter().find(|n| n.as_str() == "umbmark-1") {
                    Some(n) => vec![n.clone()],
                    None => names.into_iter().take(1).collect(),
                }
            } else {
                train
            };
            let d = gap::diagnose_manifests(
                &kinematic,
                &manifests,
                &gap::SplitRule::TrainOnExperiments(train),
                &gap::DiagnoseOptions::default(),
            )?;
            if let Some(path) = &markdown {
                let svg_path = path.with_extension("svg");
                let svg = gap::plot_svg(&d)?;
                hil::output::write_atomic(&svg_path, svg.as_bytes())?;
                let name = svg_path
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned());
                hil::output::write_atomic(
                    path,
                    gap::render_markdown(&d, name.as_deref()).as_bytes(),
                )?;
                eprintln!("wrote {} and {}", path.display(), svg_path.display());
            }
            if json {
                println!("{}", serde_json::to_string_pretty(&d)?);
            } else {
                print!("{}", gap::render_text(&d));
            }
        }
        Command::Merge {
            parts,
            firmware_wheelbase_mm,
            exact,
            json,
        } => {
            let mut partials = Vec::new();
            for p in &parts {
                let text = std::fs::read_to_string(p)
                    .with_context(|| format!("reading {}", p.display()))?;
                let part: Partial = serde_json::from_str(&text).with_context(|| {
                    format!(
                        "{} is not a partial result of `hil umbmark --shard`",
                        p.display()
                    )
                })?;
                partials.push(part);
            }
            let full = hil::umbmark::merge(partials)?;
            let report = hil::umbmark::report(&full, firmware_wheelbase_mm, solution(exact))?;
            emit(json, &report, || report.render())?;
        }
        Command::Run {
            test,
            leg_mm,
            scenario,
            hang_after,
            gdb,
            common,
        } => {
            let robot = load_robot(common.robot.as_ref())?;
            let firmware = load_firmware(&common)?;
            let mut opts = common.test_options(leg_mm);
            opts.hang_after_s = hang_after;
            if let Some(path) = &scenario {
                let s = hil::scenario::Scenario::load(path)?;
                opts.faults = s.scheduled();
                opts.framed = s.framed;
            }
            let wall = Instant::now();
            let run = match gdb {
                Some(port) => {
                    let server = hil::gdb::GdbServer::bind(port)?;
                    eprintln!(
                        "gdb: paused at reset; connect with avr-gdb {} -ex 'target remote {}'",
                        firmware.path.display(),
                        server.local_addr()?
                    );
                    match hil::experiment::run_test_debugged(firmware, &robot, test, &opts, server)?
                    {
                        Some(run) => run,
                        None => {
                            eprintln!("gdb: the debugger killed the run");
                            return Ok(());
                        }
                    }
                }
                None => run_test(firmware, &robot, test, &opts)?,
            };
            if let Some(path) = &common.vcd {
                write_vcd(path, &run, common.vcd_pwm)?;
            }
            let wall_s = wall.elapsed().as_secs_f64();
            if common.json {
                let mut v = serde_json::to_value(&run)?;
                if !common.deterministic {
                    v["rtf"] = (run.robot_time_s / wall_s).into();
                }
                println!("{}", serde_json::to_string_pretty(&v)?);
            } else {
                print!("{}", hil::report::render_run(&run));
                if !common.deterministic {
                    println!("  real-time x    {:.1}", run.robot_time_s / wall_s);
                }
            }
        }
        Command::Line {
            length_mm,
            trace_csv,
            common,
        } => {
            let robot = load_robot(common.robot.as_ref())?;
            let firmware = load_firmware(&common)?;
            let opts = LineOptions {
                length_mm,
                bench: BenchOptions {
                    seed: common.seed,
                    ..Default::default()
                },
            };
            let wall = Instant::now();
            let mut run = run_line(firmware, &robot, &opts)?;
            let wall_s = wall.elapsed().as_secs_f64();
            if !common.deterministic {
                run.summary.rtf = Some(run.summary.robot_time_s / wall_s);
            }
            if let Some(path) = trace_csv {
                let mut csv = String::from(
                    "t_s,x_mm,y_mm,theta_rad,left_edges,right_edges,left_duty,right_duty\n",
                );
                for s in &run.trace {
                    csv.push_str(&format!(
                        "{},{},{},{},{},{},{},{}\n",
                        s.t_s,
                        s.x_mm,
                        s.y_mm,
                        s.theta_rad,
                        s.left_edges,
                        s.right_edges,
                        s.left_duty,
                        s.right_duty
                    ));
                }
                std::fs::write(&path, csv)
                    .with_context(|| format!("writing the trace to {}", path.display()))?;
            }
            if common.json {
                println!("{}", serde_json::to_string_pretty(&run.summary)?);
            } else {
                print!("{}", run.summary.render());
            }
        }
        Command::Serve {
            pty: _,
            speed,
            common,
        } => {
            let robot = load_robot(common.robot.as_ref())?;
            let firmware = load_firmware(&common)?;
            station_cli::serve(firmware, &robot, common.seed, speed)?;
        }
        Command::Ui {
            port,
            baud,
            listen_port,
            sessions,
            common,
        } => {
            let firmware = load_firmware(&common)?;
            station_cli::ui(
                firmware,
                common.robot.clone(),
                port,
                baud,
                listen_port,
                sessions,
                common.seed,
            )?;
        }
    }
    Ok(())
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            use clap::error::ErrorKind;
            if matches!(
                e.kind(),
                ErrorKind::DisplayHelp
                    | ErrorKind::DisplayVersion
                    | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
            ) {
                let _ = e.print();
                return ExitCode::SUCCESS;
            }
            // One line: what is wrong. `--help` says the rest.
            let text = e.render().to_string();
            let first = text.lines().next().unwrap_or("error: bad arguments");
            eprintln!("{first} (see `hil --help`)");
            return ExitCode::from(2);
        }
    };
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

/// The error model's solution the `--exact` flag selects.
fn solution(exact: bool) -> calib::Solution {
    if exact {
        calib::Solution::Exact
    } else {
        calib::Solution::FirstOrder
    }
}
