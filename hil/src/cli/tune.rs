//! `hil tune --robot FILE`: the robust firmware's PID gains for a robot,
//! derived and checked on the bench; `--write` puts them in the config.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

use super::args::{Build, Json, Target};

#[derive(clap::Args)]
pub struct Tune {
    /// Robot config TOML whose motor model and encoders the gains are derived from.
    #[arg(long, value_name = "FILE")]
    robot: PathBuf,
    /// Board TOML (default: Henrytwo's).
    #[arg(long, value_name = "FILE", value_parser = super::board::parse_board)]
    board: Option<hil::board::Board>,
    /// Length of the line the gains are checked on, mm.
    #[arg(long, default_value_t = 2000.0, value_parser = super::args::parse_leg, allow_negative_numbers = true)]
    length_mm: f64,
    /// Seed of the plant's random effects.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Write the gains into the config's [firmware] table (its comments and
    /// other keys kept) when every check passed.
    #[arg(long)]
    write: bool,
    #[command(flatten)]
    json: Json,
}

impl Tune {
    pub fn run(self) -> Result<()> {
        let target = Target {
            no_skip: false,
            firmware: Build::Robust,
            elf: None,
            description: None,
            robot: Some(self.robot.clone()),
            board: self.board,
            seed: self.seed,
            keep_firmware_params: false,
            params: Vec::new(),
            mcu: None,
        };
        let (robot, firmware) = target.load()?;
        if self.write {
            // The file is rewritten after the run: refuse now what could not be.
            super::check_output("--write", &self.robot)?;
        }
        let report = match hil::runs::tune::tune(firmware, &robot, target.bench(), self.length_mm) {
            Ok(r) => r,
            Err(hil::runs::tune::TuneRunError::Tune(e)) => {
                return Err(
                    super::BadInput(format!("robot config {}: {e}", self.robot.display())).into(),
                )
            }
            Err(hil::runs::tune::TuneRunError::Bench(e)) => {
                return Err(
                    super::Incomplete(format!("the check's line did not complete: {e}")).into(),
                )
            }
        };
        let passed = report.passed();
        self.json.emit(&report, || report.render())?;
        if !passed {
            let failed: Vec<&str> = report
                .checks
                .iter()
                .filter(|c| !c.pass)
                .map(|c| c.name.as_str())
                .collect();
            anyhow::bail!(
                "the derived gains failed {} check(s) on the bench: {}{}",
                failed.len(),
                failed.join(", "),
                if self.write { "; nothing written" } else { "" }
            );
        }
        if self.write {
            write_gains(&self.robot, &report.tuning.params())?;
            eprintln!(
                "note: wrote the gains into {} [firmware]",
                self.robot.display()
            );
        }
        Ok(())
    }
}

/// `params` into `path`'s `[firmware]` table, made when absent; every other
/// key, table and comment of the file kept as it was.
fn write_gains(path: &Path, params: &[(hil::firmware::link::Param, f32)]) -> Result<()> {
    let text =
        input_file::read_text(path).with_context(|| format!("reading {}", path.display()))?;
    let mut doc: toml_edit::DocumentMut = text
        .parse()
        .with_context(|| format!("parsing {}", path.display()))?;
    let table = doc
        .entry("firmware")
        .or_insert_with(|| toml_edit::Item::Table(toml_edit::Table::new()))
        .as_table_mut()
        .with_context(|| format!("{}: firmware is not a table", path.display()))?;
    for &(p, v) in params {
        // The f32 the firmware is sent, written as its shortest decimal.
        let v: f64 = v.to_string().parse().expect("an f32 prints as a number");
        table[p.name()] = toml_edit::value(v);
    }
    super::write_output(path, doc.to_string().as_bytes())
}
