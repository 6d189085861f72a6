//! `hil faults`: the fault library (or a scenario's faults) against both builds.

use std::path::PathBuf;

use anyhow::Result;
use hil::firmware::elf::Firmware;
use hil::runs::faults::{FaultCase, FaultOptions, FaultRow, Verdict};
use rayon::prelude::*;

use super::args::{parse_seconds, Common};

#[derive(clap::Args)]
pub struct Faults {
    /// Run every fault of the library.
    #[arg(long)]
    all: bool,
    /// Run only these faults (names as listed by `hil faults --list`).
    #[arg(long = "fault", value_name = "NAME")]
    only: Vec<String>,
    /// List the faults and their expected reactions (of the library, or
    /// of --scenario's file); runs nothing, so it takes no selection.
    #[arg(long, conflicts_with_all = ["all", "only", "junit"])]
    list: bool,
    /// Run the faults of a scenario file (TOML or JSON) against both
    /// builds instead of the library (reported, not judged; a fault that
    /// never fires fails).
    #[arg(long, value_name = "FILE")]
    scenario: Option<PathBuf>,
    /// Robot seconds without progress after which a busy firmware is
    /// reported hung, with its PC and symbol.
    #[arg(long, value_name = "S", default_value_t = hil::bench::hang::DEFAULT_HANG_AFTER_S, value_parser = parse_seconds)]
    hang_after: f64,
    /// Also write the verdicts as JUnit XML to FILE (one test case per
    /// fault, its robust build's reaction judged; the thesis build's is
    /// reported in the case's output).
    #[arg(long, value_name = "FILE")]
    junit: Option<PathBuf>,
    #[command(flatten)]
    common: Common,
}

impl Faults {
    pub fn run(self) -> Result<()> {
        self.common.refuse_trace("faults")?;
        if let Some(path) = &self.junit {
            super::check_output("--junit", path)?;
        }
        let options = FaultOptions {
            seed: self.common.target.seed,
            board: self.common.target.bench().board,
            hang_after_s: self.hang_after,
            description: self.common.target.description.clone(),
        };
        let library = match &self.scenario {
            Some(path) => {
                let s = hil::runs::scenario::Scenario::load(path).map_err(super::bad_input)?;
                super::check_scenario_wiring(path, &s, &options.board)?;
                vec![hil::runs::faults::from_scenario(path, &s)
                    .map_err(|e| super::bad_input(anyhow::anyhow!(e)))?]
            }
            None => hil::runs::faults::library(),
        };
        if self.list {
            for f in &library {
                println!(
                    "{:<20} {}\n{:<20} expected: {}",
                    f.name, f.what, "", f.expected
                );
            }
            return Ok(());
        }
        let selected = self.select(library)?;
        let (robot, robust) = self.common.target.load()?;
        let thesis_path = hil::paths::firmware_elf("thesis");
        // The thesis build beside the firmware under test, for comparison;
        // not beside a described one (the description is of that firmware).
        let thesis = (thesis_path.exists() && self.common.target.description.is_none())
            .then(|| Firmware::load(&thesis_path))
            .transpose()?;
        // Each row with the wall-clock seconds it took (the JUnit `time`),
        // measured around the runs.
        let timed = selected
            .par_iter()
            .map(|case| {
                let started = std::time::Instant::now();
                hil::runs::faults::run_fault(case, &robust, thesis.as_ref(), &robot, &options)
                    .map(|row| (row, started.elapsed().as_secs_f64()))
            })
            .collect::<Result<Vec<_>, _>>()?;
        let (rows, wall_s): (Vec<FaultRow>, Vec<f64>) = timed.into_iter().unzip();
        self.common
            .print
            .json
            .emit(&rows, || hil::runs::faults::render(&rows))?;
        if let Some(path) = &self.junit {
            // A suite per fault, as `hil test` has a suite per case: the
            // robot time is a suite's property.
            let suites: Vec<_> = rows
                .iter()
                .zip(&wall_s)
                .map(|(row, wall_s)| hil::output::junit::Suite {
                    name: format!("hil faults {}", row.fault),
                    properties: hil::output::junit::run_properties(
                        "faults",
                        &row.firmware,
                        self.common.target.seed,
                        row.robust_observed.robot_time_s,
                    ),
                    cases: vec![junit_case(row, *wall_s)],
                })
                .collect();
            super::write_output(
                path,
                hil::output::junit::render("hil faults", &suites).as_bytes(),
            )?;
        }
        let count = |v: Verdict| rows.iter().filter(|r| r.verdict == v).count();
        let (failed, not_fired) = (count(Verdict::Fail), count(Verdict::NotFired));
        match (failed, not_fired) {
            (0, 0) => Ok(()),
            (f, 0) => anyhow::bail!("{f} fault reaction(s) not as expected"),
            (0, n) => {
                anyhow::bail!("{n} case(s) with a fault that never fired: nothing was tested")
            }
            (f, n) => anyhow::bail!(
                "{f} fault reaction(s) not as expected, {n} case(s) with a fault that never fired"
            ),
        }
    }

    /// The cases `--all`, `--fault` or `--scenario` ask for.
    fn select(&self, library: Vec<FaultCase>) -> Result<Vec<FaultCase>> {
        let only = &self.only;
        if let Some(unknown) = only.iter().find(|o| library.iter().all(|f| f.name != *o)) {
            return Err(super::BadInput(format!(
                "--fault {unknown:?}: no fault is called so; `hil faults --list` names them"
            ))
            .into());
        }
        let selected: Vec<_> = library
            .into_iter()
            .filter(|f| self.all || self.scenario.is_some() || only.iter().any(|o| o == f.name))
            .collect();
        if selected.is_empty() {
            return Err(super::BadInput(
                "no fault selected: give --all, --fault NAME (see --list) or --scenario FILE"
                    .into(),
            )
            .into());
        }
        Ok(selected)
    }
}

/// A fault's row as a JUnit case: failed when its verdict fails the command
/// (a reaction not as expected, a fault that never fired), skipped when it
/// was run against no expectation (a scenario's faults).
fn junit_case(row: &FaultRow, wall_s: f64) -> hil::output::junit::Case {
    let mut out = format!(
        "fault: {}\nexpected: {}\n{}: {}\nthesis: {}",
        row.what, row.expected, row.firmware, row.robust, row.thesis
    );
    // What the firmware under test printed, as `hil run` shows it.
    let uarts = &row.robust_observed.uarts;
    if !uarts.is_empty() {
        out.push('\n');
        out.push_str(hil::runs::experiment::uarts::render(uarts, "").trim_end());
    }
    hil::output::junit::Case {
        name: row.fault.clone(),
        classname: "hil.faults".into(),
        time_s: wall_s,
        failure: row.verdict.failed().then(|| hil::output::junit::Failure {
            message: format!("{}: {}", row.verdict.tag(), row.why),
            kind: match row.verdict {
                Verdict::NotFired => "not_fired",
                _ => "reaction",
            }
            .into(),
            text: out.clone(),
        }),
        skipped: (row.verdict == Verdict::NotJudged).then(|| row.why.clone()),
        system_out: Some(out),
        attachments: Vec::new(),
    }
}
