//! Single runs: `hil run` (one test, per leg and turn) and `hil line`.

use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use anyhow::{Context, Result};
use hil::bench::BenchOptions;
use hil::board::Board;
use hil::output::vcd::VcdWriter;
use hil::output::StreamedFile;
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
            super::check_scenario_wiring(path, &s, &opts.bench.board)?;
            opts.faults = s.scheduled();
            opts.framed = s.framed;
        }
        // The trace is written as the run makes it (see `StreamedVcd`).
        let vcd = match &common.trace.vcd {
            Some(path) => {
                let board = common.target.bench().board;
                let stream = StreamedVcd::create(path, common.trace.vcd_pwm, board)?;
                opts.tap = Some(stream.tap());
                Some(stream)
            }
            None => None,
        };
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
        drop(opts);
        if let (Some(stream), Some(kind)) = (vcd, vcd_kind) {
            let written = stream.finish(kind)?;
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

/// A trace written to its file as the run makes it: the bench gives the
/// writer every record as it is made (a [`hil::bench::Tap`]), so that the
/// run keeps no pin change and the writer only the last moments' changes;
/// the same bytes as [`write_vcd`] writes from a run's records.
struct StreamedVcd {
    path: PathBuf,
    board: Board,
    pwm_edges: bool,
    writer: Arc<Mutex<VcdWriter<BufWriter<StreamedFile>>>>,
}

impl StreamedVcd {
    fn create(path: &Path, pwm_edges: bool, board: Board) -> Result<Self> {
        let file =
            StreamedFile::create(path).with_context(|| format!("writing {}", path.display()))?;
        let clock_hz = BenchOptions::default().clock.hz();
        let writer = VcdWriter::new(BufWriter::new(file), clock_hz, &board, pwm_edges);
        Ok(Self {
            path: path.to_path_buf(),
            board,
            pwm_edges,
            writer: Arc::new(Mutex::new(writer)),
        })
    }

    fn tap(&self) -> hil::bench::SharedTap {
        hil::bench::SharedTap(self.writer.clone())
    }

    /// The rest of the trace written, the file in its place, and for a
    /// regular file its GTKWave save file beside it (see [`write_vcd`]):
    /// the paths written.
    fn finish(self, kind: hil::output::Kind) -> Result<Vec<PathBuf>> {
        let context = || format!("writing {}", self.path.display());
        let writer = Arc::try_unwrap(self.writer)
            .map_err(|_| anyhow::anyhow!("the trace is still in use by the bench"))?
            .into_inner()
            .unwrap_or_else(|p| p.into_inner());
        let end_cycle = writer.end_cycle();
        let file = writer.finish().with_context(context)?;
        file.into_inner()
            .map_err(|e| e.into_error())
            .with_context(context)?
            .commit()
            .with_context(context)?;
        if kind == hil::output::Kind::InPlace {
            return Ok(vec![self.path]);
        }
        let traced = hil::output::vcd::Traced {
            clock_hz: BenchOptions::default().clock.hz(),
            board: &self.board,
            pwm_edges: self.pwm_edges,
            end_cycle,
        };
        let save = self.path.with_extension("gtkw");
        super::write_output(
            &save,
            hil::output::vcd::gtkw_of(&gtkw_name(&self.path), &traced).as_bytes(),
        )?;
        Ok(vec![self.path, save])
    }
}

/// The trace's name in its save file: its bare file name.
fn gtkw_name(path: &Path) -> String {
    path.file_name()
        .map_or_else(|| "trace.vcd".into(), |n| n.to_string_lossy().into_owned())
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
    super::write_output(
        &save,
        hil::output::vcd::gtkw(&gtkw_name(path), &input).as_bytes(),
    )?;
    Ok(vec![path.to_path_buf(), save])
}
