//! `hil timing`: the firmware's control loop timed cycle-exactly against its budgets.

use std::path::PathBuf;

use anyhow::{Context, Result};
use hil::bench::BenchOptions;
use hil::runs::experiment::{run_test_observed, Test};
use hil::runs::timing::{Budgets, TimingProbe};

use super::args::{Common, Leg};

#[derive(clap::Args)]
pub struct Timing {
    /// The test to run while measuring.
    #[arg(long, default_value = "line")]
    test: Test,
    #[command(flatten)]
    leg: Leg,
    /// Budgets (TOML; default: fixtures/timing-budgets.toml).
    #[arg(long, value_name = "FILE")]
    budgets: Option<PathBuf>,
    /// The control function to time [default: the test description's
    /// `symbols.control`, else the bench's builds' ht_control_tick].
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
        let (robot, firmware) = common.target.load()?;
        let described = common
            .target
            .description
            .as_ref()
            .and_then(|d| d.control_function(&firmware))
            .transpose()
            .map_err(super::bad_input)?;
        let function = function
            .or(described)
            .unwrap_or_else(|| "ht_control_tick".into());
        let clock = BenchOptions::default().clock;
        let period = clock.cycles_in(plant_model::Seconds(budgets.tick_period_us * 1e-6));
        let opts = common.test_options(common.leg_mm(leg)?);
        // The probe names vectors and unwinds return addresses as the 2560
        // lays them out (3-byte PCs); another MCU's would be misread.
        let mcu = opts.bench.board.mcu;
        if mcu != hil::board::Mcu::Atmega2560 {
            return Err(super::bad_input(anyhow::anyhow!(
                "--board: hil timing measures the atmega2560 only (its vectors, its 3-byte return \
                 addresses); this board's MCU is the {mcu}"
            )));
        }
        let probe = TimingProbe::new(&firmware, &function, period, &opts.bench.board)
            .map_err(|e| super::bad_input(anyhow::anyhow!("--function {function:?}: {e}")))?;
        let (run, observer) =
            run_test_observed(firmware.clone(), &robot, test, &opts, Some(Box::new(probe)))?;
        let probe = observer
            .and_then(|o| o.into_any().downcast::<TimingProbe>().ok())
            .context("the timing probe was lost")?;
        let report = probe.report(&firmware, &function, clock.hz(), &run.segment_starts());
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
