//! `hil timing`: the firmware's control loop timed cycle-exactly against its budgets.

use std::path::PathBuf;

use anyhow::{Context, Result};
use hil::bench::BenchOptions;
use hil::firmware::description::Description;
use hil::runs::experiment::{run_test_observed, Test, TestName};
use hil::runs::timing::{Budgets, TimingProbe};

use super::args::{Common, Leg};

#[derive(clap::Args)]
pub struct Timing {
    /// The test to run while measuring [default: line; with --tests, the
    /// description's one test, or its line].
    #[arg(long)]
    test: Option<TestName>,
    #[command(flatten)]
    leg: Leg,
    /// Budgets (TOML; default: fixtures/timing-budgets.toml).
    #[arg(long, value_name = "FILE")]
    budgets: Option<PathBuf>,
    /// The control function to time [default: the test description's
    /// `symbols.control` (none: no control tick timed), else the bench's
    /// builds' ht_control_tick].
    #[arg(long)]
    function: Option<String>,
    #[command(flatten)]
    common: Common,
}

impl Timing {
    pub fn run(self) -> Result<()> {
        let Timing {
            test,
            leg,
            budgets,
            function,
            common,
        } = self;
        let budgets_path = budgets
            .unwrap_or_else(|| hil::paths::workspace_root().join("fixtures/timing-budgets.toml"));
        let budgets = Budgets::load(&budgets_path).map_err(super::bad_input)?;
        let description = common.target.description.as_deref();
        let test = pick_test(description, test, Test::Line).map_err(super::bad_input)?;
        let (robot, firmware) = common.target.load()?;
        let described = common
            .target
            .description
            .as_ref()
            .and_then(|d| d.control_function(&firmware))
            .transpose()
            .map_err(super::bad_input)?;
        // A described firmware has a control function only if its
        // description names one.
        let function = function
            .or(described)
            .or_else(|| description.is_none().then(|| "ht_control_tick".into()));
        let clock = BenchOptions::default().clock;
        let period = budgets
            .tick_period_us
            .map_or(0, |us| clock.cycles_in(plant_model::Seconds(us * 1e-6)));
        let opts = common.test_options(common.leg_mm(leg)?);
        budgets
            .check_for(
                &budgets_path.display().to_string(),
                function.as_deref(),
                opts.bench.board.mcu.chip(),
            )
            .map_err(super::bad_input)?;
        let probe = TimingProbe::new(&firmware, function.as_deref(), period, &opts.bench.board)
            .map_err(|e| {
                super::bad_input(match function.as_deref() {
                    Some(f) => anyhow::anyhow!("--function {f:?}: {e}"),
                    None => anyhow::anyhow!("{e}"),
                })
            })?;
        let (run, observer) = run_test_observed(
            firmware.clone(),
            &robot,
            test.clone(),
            &opts,
            Some(Box::new(probe)),
        )?;
        let probe = observer
            .and_then(|o| o.into_any().downcast::<TimingProbe>().ok())
            .context("the timing probe was lost")?;
        let report = probe.report(&firmware, clock.hz(), &run.segment_starts());
        let rows = report.check(&budgets);
        let failed: Vec<String> = rows
            .iter()
            .filter(|r| !r.pass)
            .map(|r| match r.measured {
                Some(_) => r.what.clone(),
                None => format!("{}: not measured", r.what),
            })
            .collect();
        if common.print.json.json {
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
        if !run.completed {
            // Budgets judged on part of a run are no verdict on the firmware.
            return Err(super::Incomplete(format!(
                "the {} run did not complete ({}): its timing is of part of a run",
                test.name(),
                run.finding.as_deref().unwrap_or("no reason found")
            ))
            .into());
        }
        if !failed.is_empty() {
            anyhow::bail!(
                "{} timing budget(s) exceeded or not measured: {} (budgets in {})",
                failed.len(),
                failed.join("; "),
                budgets_path.display()
            );
        }
        Ok(())
    }
}

/// The test a command runs: `asked`; else, with a description, its one
/// test, or `fallback` when it describes that; else `fallback`. A test the
/// description lacks, or a choice it leaves open, is refused.
pub(super) fn pick_test(
    description: Option<&Description>,
    asked: Option<TestName>,
    fallback: Test,
) -> Result<TestName> {
    let Some(d) = description else {
        let test = asked.unwrap_or(fallback.into());
        if test.thesis().is_none() {
            anyhow::bail!(
                "--test {test}: the bench's own builds run umbmark-cw, umbmark-ccw, line and \
                 triangle; a test of your firmware's own runs with its description (--tests FILE)"
            );
        }
        return Ok(test);
    };
    if let Some(test) = asked {
        d.test(test.clone())?;
        return Ok(test);
    }
    let names: Vec<&TestName> = d.tests.keys().collect();
    match names[..] {
        [only] => Ok(only.clone()),
        _ if d.tests.contains_key(&fallback.into()) => Ok(fallback.into()),
        _ => anyhow::bail!(
            "--test: {} describes {} tests ({}); name the one to run",
            d.path,
            names.len(),
            names
                .iter()
                .map(|t| t.name())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}
