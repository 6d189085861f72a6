//! `hil`: the bench's command line.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use hil::bench::BenchOptions;
use hil::elf::Firmware;
use hil::experiment::{run_test, Test, TestOptions};
use hil::line::{run_line, LineOptions};
use plant_model::RobotConfig;

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
    /// Robot config TOML (default: fixtures/robots/henrytwo-ideal.toml).
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
    /// Run one of the firmware's tests and report each leg and turn.
    Run {
        /// umbmark-cw, umbmark-ccw, line or triangle.
        test: Test,
        /// Leg length in millimetres.
        #[arg(long, default_value_t = 2000.0, value_parser = parse_length, allow_negative_numbers = true)]
        leg_mm: f64,
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

fn load_robot(path: Option<&PathBuf>) -> Result<RobotConfig> {
    let path = path
        .cloned()
        .unwrap_or_else(|| hil::paths::robot_config("henrytwo-ideal"));
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
        Command::Run {
            test,
            leg_mm,
            common,
        } => {
            let robot = load_robot(common.robot.as_ref())?;
            let firmware = load_firmware(&common)?;
            let opts = TestOptions {
                leg_mm,
                bench: BenchOptions {
                    seed: common.seed,
                    ..Default::default()
                },
                limit_s: None,
            };
            let wall = Instant::now();
            let run = run_test(firmware, &robot, test, &opts)?;
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
