//! Single runs: `hil run` (one test, per leg and turn) and `hil line`.

use std::path::{Path, PathBuf};

use anyhow::Result;
use hil::bench::BenchOptions;
use hil::board::Board;
use hil::runs::experiment::{run_test, Test, TestName, TestRun};
use hil::runs::line::{run_line, LineOptions};
use hil::runs::report::{json_with_pace, Pace, PaceFields};

use super::args::{parse_leg, parse_seconds, Common, Leg};

#[derive(clap::Args)]
pub struct Run {
    /// umbmark-cw, umbmark-ccw, line or triangle, or with --tests any test
    /// the description names.
    test: TestName,
    #[command(flatten)]
    leg: Leg,
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
}

impl Run {
    pub fn run(self) -> Result<()> {
        let Run {
            test,
            leg,
            scenario,
            hang_after,
            gdb,
            common,
        } = self;
        // The trace and its GTKWave save file, checked before the run.
        let vcd_kind = match &common.trace.vcd {
            Some(path) => {
                let kind = super::check_output("--vcd", path)?;
                if kind == hil::output::Kind::Replace {
                    super::check_output("--vcd", &path.with_extension("gtkw"))?;
                }
                Some(kind)
            }
            None => None,
        };
        // A test the description lacks, or a test of a firmware's own
        // without one, is refused before anything runs.
        match &common.target.description {
            Some(d) => drop(d.test(test.clone()).map_err(super::bad_input)?),
            None if test.thesis().is_none() => {
                return Err(super::bad_input(anyhow::anyhow!(
                    "test {test}: the bench's own builds run umbmark-cw, umbmark-ccw, line and \
                     triangle; a test of your firmware's own runs with its description (--tests FILE)"
                )))
            }
            None => {}
        }
        let (robot, firmware) = common.target.load()?;
        let mut opts = common.test_options(common.leg_mm(leg)?);
        opts.hang_after_s = hang_after;
        if let Some(path) = &scenario {
            let s = hil::runs::scenario::Scenario::load(path).map_err(super::bad_input)?;
            opts.faults = s.scheduled();
            opts.framed = s.framed;
        }
        let clock = common.print.wall_clock();
        let run = match gdb {
            Some(port) => {
                let server = hil::bench::gdb::GdbServer::bind(port)?;
                eprintln!(
                    "gdb: paused at reset; connect with avr-gdb {} -ex 'target remote {}'",
                    firmware.path.display(),
                    server.local_addr()?
                );
                match hil::runs::experiment::run_test_debugged(
                    firmware,
                    &robot,
                    test.clone(),
                    &opts,
                    server,
                ) {
                    Ok(run) => run,
                    // Not a run that passed: exit 3, as for any run that
                    // did not complete.
                    Err(hil::bench::gdb::GdbError::Ended(why)) => {
                        return Err(super::Incomplete(format!(
                            "the {} run did not complete: {why}",
                            test.name()
                        ))
                        .into())
                    }
                    Err(e) => return Err(e.into()),
                }
            }
            None => run_test(firmware, &robot, test, &opts)?,
        };
        if let (Some(path), Some(kind)) = (&common.trace.vcd, vcd_kind) {
            let written = write_vcd(
                path,
                kind,
                &run,
                common.trace.vcd_pwm,
                &common.target.bench().board,
            )?;
            let written: Vec<String> = written.iter().map(|p| p.display().to_string()).collect();
            eprintln!("wrote {}", written.join(" and "));
        }
        let pace = Pace::of(run.robot_time_s, clock.stop());
        if common.print.json.json {
            let v = json_with_pace(&run, pace, PaceFields::Rtf)?;
            println!("{}", serde_json::to_string_pretty(&v)?);
        } else {
            print!("{}", hil::runs::report::render_run(&run));
            if let Some(p) = pace {
                println!("  real-time x    {:.1}", p.rtf());
            }
        }
        if !run.completed {
            return Err(super::Incomplete(format!(
                "the {} run did not complete: {}",
                run.test.name(),
                run.finding.as_deref().unwrap_or("no reason found")
            ))
            .into());
        }
        Ok(())
    }
}

#[derive(clap::Args)]
pub struct Line {
    /// Length of the line in millimetres [default: 2000, or a described
    /// firmware's own leg].
    #[arg(long, value_parser = parse_leg, allow_negative_numbers = true)]
    length_mm: Option<f64>,
    /// Write the plant trace (10 ms samples) as CSV.
    #[arg(long, value_name = "FILE")]
    trace_csv: Option<PathBuf>,
    #[command(flatten)]
    common: Common,
}

impl Line {
    pub fn run(self) -> Result<()> {
        self.common.refuse_trace("line")?;
        let target = &self.common.target;
        if let Some(path) = &self.trace_csv {
            super::check_output("--trace-csv", path)?;
        }
        if target.description.is_some() {
            return self.run_described();
        }
        let (robot, firmware) = target.load()?;
        let opts = LineOptions {
            length_mm: self.length_mm.unwrap_or(super::args::DEFAULT_LEG_MM),
            bench: target.bench(),
            tell: target.tell(),
            params: target.params.clone(),
        };
        let clock = self.common.print.wall_clock();
        let mut run = run_line(firmware, &robot, &opts)?;
        run.summary.rtf = Pace::of(run.summary.robot_time_s, clock.stop()).map(|p| p.rtf());
        if let Some(path) = &self.trace_csv {
            super::write_output(path, hil::runs::report::trace_csv(&run.trace).as_bytes())?;
        }
        self.common
            .print
            .json
            .emit(&run.summary, || run.summary.render())
    }
}

impl Line {
    /// The description's `line` test, reported as `hil run line` reports it:
    /// the line summary reads the bench interface's variables (the cut-off
    /// counts, the firmware's own distance per count), which a described
    /// firmware does not have.
    fn run_described(&self) -> Result<()> {
        let common = &self.common;
        let leg_mm = common.leg_mm(Leg {
            leg_mm: self.length_mm,
        })?;
        if let Some(d) = &common.target.description {
            // Said before anything runs: not a bench error after the reset.
            d.start(Test::Line).map_err(super::bad_input)?;
        }
        let (robot, firmware) = common.target.load()?;
        let clock = common.print.wall_clock();
        let run = run_test(firmware, &robot, Test::Line, &common.test_options(leg_mm))?;
        if let Some(path) = &self.trace_csv {
            super::write_output(path, hil::runs::report::trace_csv(&run.trace).as_bytes())?;
        }
        let pace = Pace::of(run.robot_time_s, clock.stop());
        if common.print.json.json {
            let v = json_with_pace(&run, pace, PaceFields::Rtf)?;
            println!("{}", serde_json::to_string_pretty(&v)?);
        } else {
            print!("{}", hil::runs::report::render_run(&run));
        }
        if !run.completed {
            return Err(super::Incomplete(format!(
                "the line run did not complete: {}",
                run.finding.as_deref().unwrap_or("no reason found")
            ))
            .into());
        }
        Ok(())
    }
}

/// The trace of `run` at `path` and, for a regular file, its GTKWave save file
/// beside it (the same name, `.gtkw`), naming the trace by its file name so that
/// the pair opens wherever it is moved. A pipe or a device (`kind` in place) has
/// no folder of its own to put a save file beside. Returns the paths written.
pub(super) fn write_vcd(
    path: &Path,
    kind: hil::output::Kind,
    run: &TestRun,
    pwm_edges: bool,
    board: &Board,
) -> Result<Vec<PathBuf>> {
    let input = hil::output::vcd::VcdInput {
        clock_hz: BenchOptions::default().clock.hz(),
        board,
        edges: &run.edges,
        drive: &run.drive,
        uart_tx: &run.uart,
        uart_rx: &run.uart_rx,
        samples: &run.trace,
        pwm_edges,
    };
    super::write_output(path, hil::output::vcd::render(&input).as_bytes())?;
    if kind == hil::output::Kind::InPlace {
        return Ok(vec![path.to_path_buf()]);
    }
    let save = path.with_extension("gtkw");
    let name = path
        .file_name()
        .map_or_else(|| "trace.vcd".into(), |n| n.to_string_lossy());
    super::write_output(&save, hil::output::vcd::gtkw(&name, &input).as_bytes())?;
    Ok(vec![path.to_path_buf(), save])
}
