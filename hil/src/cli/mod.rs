//! The `hil` command line: one module per family of commands, each command an
//! argument struct with its `run`; the groups several share are in [`args`].

use std::path::Path;
use std::process::ExitCode;

use anyhow::Result;
use clap::{Parser, Subcommand};

mod args;
mod bench;
mod board;
mod experiments;
mod faults;
mod gap;
mod run;
mod station;
mod timing;
mod tune;

// The user's own firmware tests.
mod golden;
mod test;

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

#[derive(Subcommand)]
enum Command {
    /// The reduced UMBmark: 5 runs clockwise, 5 counter-clockwise, and the correction.
    Umbmark(experiments::Umbmark),
    /// Measure the firmware's timing cycle-exactly over a run and check it
    /// against the budgets; fails when one is exceeded.
    Timing(timing::Timing),
    /// Identify a motor from a step-response CSV (the thesis' layout):
    /// 63.2 % fit, first order plus dead time, Ziegler-Nichols, ZOH model,
    /// and which thesis figures it reproduces or contradicts.
    Identify(bench::Identify),
    /// Odometry corrections from measured end points (a real robot's, or the
    /// thesis' tables), or calibration rounds on the emulated robot.
    Calibrate(experiments::Calibrate),
    /// Measure the bench's speed: real-time factors of the bench, raw simavr
    /// on the same ELF, and the thesis build; the bench's overhead.
    Bench(bench::Bench),
    /// Inject each fault of the library into the robust and the thesis
    /// builds; check the robust build's reaction against the expectation.
    Faults(faults::Faults),
    /// The Triangular Path test: 5 straight lines, 5 counter-clockwise
    /// triangles, and the correction (Ed from the lines, Eb from the turns).
    Triangle(experiments::Triangle),
    /// Fuzz the robust firmware's UART parser in the emulator with seeded
    /// invalid frames: no hang, no reset, no state change allowed.
    Fuzz(bench::Fuzz),
    /// Sim-to-real gap: where the real data and the model disagree, which
    /// effect explains it, how far it shrinks on held-out data.
    Gap(gap::Gap),
    /// Combine the partial results of `hil umbmark --shard` into the full result.
    Merge(experiments::Merge),
    /// Run one of the firmware's tests and report each leg and turn.
    Run(run::Run),
    /// Run the straight-line test (command byte 4) and summarise it.
    Line(run::Line),
    /// Run the emulated robot paced to real time (or N x real time) and
    /// expose its Bluetooth UART (USART1) as a pseudo-terminal, for any
    /// serial client.
    Serve(station::Serve),
    /// The operator's station: a web page on 127.0.0.1 to pick a robot
    /// (emulated or on a serial port), run tests, watch telemetry, enter end
    /// points and send the correction.
    Ui(station::Ui),
    /// PID gains for a robot from its motor model and encoders
    /// (Ziegler-Nichols, as the thesis derived Henrytwo's), checked on the
    /// bench; --write puts them in the config's [firmware] table.
    Tune(tune::Tune),
    /// Board descriptions (which MCU pin each part of the robot is on):
    /// `hil board check FILE`.
    Board(board::BoardCmd),

    /// Run scenario files with expectations as test cases (one each): one
    /// line per case, pass or FAIL with what was seen; --junit FILE for CI,
    /// each failed case's VCD and last state saved for triage.
    Test(test::TestCmd),

    /// Golden runs: `hil golden record TEST --out FILE.json` writes a run's
    /// quantities once; `hil golden check FILE.json` compares a later run
    /// to them within tolerances and prints what moved.
    Golden(golden::GoldenCmd),
}

impl Command {
    fn run(self) -> Result<()> {
        match self {
            Command::Umbmark(c) => c.run(),
            Command::Timing(c) => c.run(),
            Command::Identify(c) => c.run(),
            Command::Calibrate(c) => c.run(),
            Command::Bench(c) => c.run(),
            Command::Faults(c) => c.run(),
            Command::Triangle(c) => c.run(),
            Command::Fuzz(c) => c.run(),
            Command::Gap(c) => c.run(),
            Command::Merge(c) => c.run(),
            Command::Run(c) => c.run(),
            Command::Line(c) => c.run(),
            Command::Serve(c) => c.run(),
            Command::Ui(c) => c.run(),
            Command::Board(c) => c.run(),
            Command::Tune(c) => c.run(),

            Command::Test(c) => c.run(),
            Command::Golden(c) => c.run(),
        }
    }
}

/// A command whose runs did not all complete: what it printed is marked so,
/// and the exit code says it (3).
#[derive(Debug)]
pub struct Incomplete(pub String);

impl std::fmt::Display for Incomplete {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Incomplete {}

/// Input refused before anything ran: a robot config, scenario, ELF or CSV
/// that does not check, an option the command does not take. The exit code
/// says it (2), as for a bad argument; the message is one line.
#[derive(Debug)]
pub struct BadInput(pub String);

impl std::fmt::Display for BadInput {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for BadInput {}

/// A scenario's faults checked against the board's wiring before anything
/// runs (exit 2, naming the file and the fault).
pub fn check_scenario_wiring(
    path: &Path,
    scenario: &hil::runs::scenario::Scenario,
    board: &hil::board::Board,
) -> Result<()> {
    scenario
        .check_wiring(board)
        .map_err(|e| BadInput(format!("{}: {e}", path.display())).into())
}

/// `e` (with its causes, on one line) as a [`BadInput`].
pub fn bad_input(e: impl Into<anyhow::Error>) -> anyhow::Error {
    BadInput(one_line(&e.into())).into()
}

/// `FLAG PATH` checked before anything runs (see [`hil::output::check_file`]):
/// a folder, a symbolic link or a path below no writable folder refused
/// (exit 2) now, rather than after a long run whose result would be lost.
pub fn check_output(flag: &str, path: &std::path::Path) -> Result<hil::output::Kind> {
    hil::output::check_file(path).map_err(|e| bad_input(anyhow::anyhow!("{flag} {e}")))
}

/// `FLAG DIR`, a folder files are written into, checked as [`check_output`]
/// checks a file: absent (it is made) or a folder.
pub fn check_output_dir(flag: &str, dir: &std::path::Path) -> Result<()> {
    if dir.exists() && !dir.is_dir() {
        return Err(BadInput(format!("{flag} {}: it is not a folder", dir.display())).into());
    }
    check_output(flag, &dir.join(".hil-probe")).map(|_| ())
}

/// Write a result file at a path the user named (see [`check_output`]).
pub fn write_output(path: &std::path::Path, bytes: &[u8]) -> Result<()> {
    use anyhow::Context;
    hil::output::write_file(path, bytes).with_context(|| format!("writing {}", path.display()))
}

/// Parse the command line and run it. One exit code rule for every command
/// (docs/reference/exit-codes.md): 0 done; 1 the command ran and its check
/// failed (a reaction not as expected, a budget exceeded, a quantity moved);
/// 2 bad arguments or input refused before anything ran; 3 a run did not
/// complete (hung, stopped by the bench, not finished); 4 the output is
/// locked by another writer (nothing ran). Every error is one line on stderr.
pub fn main() -> ExitCode {
    log_if_asked();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return usage_error(&e),
    };
    match cli.command.run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", one_line(&e));
            if e.downcast_ref::<Incomplete>().is_some() {
                ExitCode::from(3)
            } else if e.downcast_ref::<BadInput>().is_some() {
                ExitCode::from(2)
            } else if let Some(o) = e.downcast_ref::<hil::output::OutputError>() {
                match o {
                    hil::output::OutputError::Busy { .. } => ExitCode::from(4),
                    o if o.is_bad_folder() => ExitCode::from(2),
                    _ => ExitCode::FAILURE,
                }
            } else {
                ExitCode::FAILURE
            }
        }
    }
}

/// The bench's own log on stderr when `RUST_LOG` asks for it
/// (`RUST_LOG=hil=debug`): spans per run and phase, and what the bench
/// decided (a segment, a fault applied, a hang) at robot time (`t_s`). No
/// wall-clock stamps: two runs of one config log the same lines. Without
/// `RUST_LOG` no subscriber is installed and every event is skipped at its
/// call site.
fn log_if_asked() {
    let Ok(filter) = tracing_subscriber::EnvFilter::try_from_default_env() else {
        return;
    };
    tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_writer(std::io::stderr)
        .without_time()
        .init();
}

/// Help and version go to stdout as clap writes them; a usage error is one
/// line: what is wrong and, for a value outside a fixed set, the set.
/// `--help` says the rest.
fn usage_error(e: &clap::Error) -> ExitCode {
    use clap::error::{ContextKind, ContextValue, ErrorKind};
    if matches!(
        e.kind(),
        ErrorKind::DisplayHelp
            | ErrorKind::DisplayVersion
            | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
    ) {
        let _ = e.print();
        return ExitCode::SUCCESS;
    }
    let text = e.render().to_string();
    let first = text.lines().next().unwrap_or("error: bad arguments");
    let valid = match (e.kind(), e.get(ContextKind::ValidValue)) {
        (ErrorKind::InvalidValue, Some(ContextValue::Strings(values))) => {
            format!(": use {}", values.join(", "))
        }
        // clap names the missing arguments on the lines below the first.
        (ErrorKind::MissingRequiredArgument, _) => match e.get(ContextKind::InvalidArg) {
            Some(ContextValue::Strings(args)) => format!(" {}", args.join(", ")),
            _ => String::new(),
        },
        _ => String::new(),
    };
    eprintln!("{first}{valid} (see `hil --help`)");
    ExitCode::from(2)
}

/// `e` and its causes on one line, as `{e:#}` prints them, but a cause whose
/// text the line already holds is left out: the library's errors name their
/// cause in their own message (`cannot read the scenario F: No such file`),
/// and the chain would print it a second time.
fn one_line(e: &anyhow::Error) -> String {
    let mut line = String::new();
    for cause in e.chain() {
        let text = cause.to_string();
        if line.is_empty() {
            line = text;
        } else if !line.contains(&text) {
            line.push_str(": ");
            line.push_str(&text);
        }
    }
    line
}

#[cfg(test)]
mod tests {
    use super::one_line;

    /// A cause the message already names is said once; a new one is added.
    #[test]
    fn an_error_line_names_each_cause_once() {
        let io = || std::io::Error::new(std::io::ErrorKind::NotFound, "No such file");
        #[derive(Debug, thiserror::Error)]
        #[error("cannot read F: {source}")]
        struct Named {
            source: std::io::Error,
        }
        let e = anyhow::Error::new(Named { source: io() });
        assert_eq!(one_line(&e), "cannot read F: No such file");
        let e = anyhow::Error::new(io()).context("reading F");
        assert_eq!(one_line(&e), "reading F: No such file");
    }
}
