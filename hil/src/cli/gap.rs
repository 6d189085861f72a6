//! `hil gap`: the sim-to-real gap of real data, or the diagnosis' self-test.

use std::path::PathBuf;

use anyhow::{Context, Result};
use gap::selftest::{render_cases_with, CaseColumns};
use gap::SplitRule;
use plant_model::RobotConfig;

use super::args::Json;

#[derive(clap::Args)]
pub struct Gap {
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
    #[command(flatten)]
    json: Json,
    #[arg(long, default_value_t = 0)]
    seed: u64,
}

impl Gap {
    pub fn run(self) -> Result<()> {
        let kinematic = gap::KinematicModel;
        if self.self_test {
            let cases = gap::self_test(&kinematic, self.seed);
            return self
                .json
                .emit(&cases, || render_cases_with(&cases, CaseColumns::Measures));
        }
        if self.real.is_empty() {
            anyhow::bail!("give --real DIR (manifests of real data, e.g. fixtures/real/thesis) or --self-test");
        }
        let mut manifests = Vec::new();
        for r in &self.real {
            if r.is_dir() {
                manifests.extend(gap::load_dir(r)?);
            } else {
                manifests.push(gap::LoadedManifest::load(r)?);
            }
        }
        if let Some(m) = &self.model {
            let cfg = RobotConfig::load(m).with_context(|| format!("model {}", m.display()))?;
            let reference = gap::manifest::reference_from_config(&cfg);
            for lm in &mut manifests {
                lm.reference = Some(reference);
            }
        }
        let rule = if self.train.is_empty() {
            SplitRule::thesis_default(&manifests)
        } else {
            SplitRule::TrainOnExperiments(self.train.clone())
        };
        let d = gap::diagnose_manifests(
            &kinematic,
            &manifests,
            &rule,
            &gap::DiagnoseOptions::default(),
        )?;
        if let Some(path) = &self.markdown {
            let svg_path = path.with_extension("svg");
            let svg = gap::plot_svg(&d)?;
            hil::output::write_atomic(&svg_path, svg.as_bytes())?;
            let name = svg_path
                .file_name()
                .map(|n| n.to_string_lossy().into_owned());
            hil::output::write_atomic(path, gap::render_markdown(&d, name.as_deref()).as_bytes())?;
            eprintln!("wrote {} and {}", path.display(), svg_path.display());
        }
        self.json.emit(&d, || gap::render_text(&d))
    }
}
