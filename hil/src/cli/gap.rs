//! `hil gap`: the sim-to-real gap of real data, or the diagnosis' self-test; with `--bench`,
//! the bench itself is the model (see `hil::runs::gap_bench`).

use std::path::PathBuf;

use anyhow::{Context, Result};
use gap::selftest::{render_cases_with, CaseColumns};
use gap::SplitRule;
use hil::firmware::elf::Firmware;
use hil::runs::gap_bench::{
    BenchModel, SelectOptions, SelfTestDesign, CENTROID_RUNS, DEFAULT_CASES, GRID_POINTS,
    REFINE_STEPS,
};
use hil::runs::odometry::Shard;
use plant_model::RobotConfig;

use super::args::{Build, Json};

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
    /// The bench as the model: the kinematic diagnosis shortlists, the
    /// real firmware on the plant (the nominal robot: --model, or the
    /// manifests' robot_config) fits, cross-validates and predicts the
    /// held-out data.
    #[arg(long)]
    bench: bool,
    /// With --bench: parallel bench runs (1 to 256; default: the machine's
    /// cores). The answer is the same for any count.
    #[arg(long, requires = "bench",
          value_parser = clap::value_parser!(u16).range(1..=256))]
    jobs: Option<u16>,
    /// With --bench: how many of the kinematic diagnosis' best effects the
    /// bench fits, besides every effect the kinematic model cannot represent
    /// (0 to 7; 7, the default, is every effect of the library).
    #[arg(long, requires = "bench", default_value_t = 7,
          value_parser = clap::value_parser!(u8).range(0..=7))]
    shortlist: u8,
    /// With --bench: most effects the chosen model may hold (1 to 3): 1 fits
    /// single effects only, 2 adds joint fits of pairs, 3 a third effect.
    #[arg(long, requires = "bench", default_value_t = 3,
          value_parser = clap::value_parser!(u8).range(1..=3))]
    max_effects: u8,
    /// With --bench --self-test: how many hidden effects to try, in a fixed
    /// order (1 to 14: every effect of the library but the floor noise).
    #[arg(long, requires = "bench", default_value_t = 2,
          value_parser = clap::value_parser!(u8).range(1..=DEFAULT_CASES.len() as i64))]
    cases: u8,
    /// With --bench --self-test: hidden effects to try instead of the fixed
    /// cases, each as NAME=VALUE (a bench parameter within its range).
    #[arg(
        long,
        requires = "bench",
        value_name = "NAME=VALUE",
        value_delimiter = ','
    )]
    hidden: Vec<String>,
    /// With --bench --self-test: make the "real" data with this robot config
    /// (same geometry as the nominal robot) instead of the nominal robot;
    /// without --hidden, one case that hides nothing else. A robot whose
    /// differences no candidate holds passes when the report takes no effect.
    #[arg(long, requires = "self_test", requires = "bench", value_name = "FILE")]
    real_robot: Option<PathBuf>,
    /// With --bench --self-test: leg of every test, mm (100 to 5000).
    #[arg(long, requires = "bench", default_value_t = 300,
          value_parser = clap::value_parser!(u16).range(100..=5000))]
    leg_mm: u16,
    /// With --bench --self-test: record a shuttle too and train on it
    /// (UMBmark counter-clockwise with 180° corners): turns of a second
    /// angle, which tell a coast from a wheelbase.
    #[arg(long, requires = "self_test", requires = "bench")]
    shuttle: bool,
    /// With --bench: points of each candidate's search grid over its range
    /// (3 to 15). Fewer points and --refine steps cost fewer bench runs and
    /// find values only as finely: a first look, or a check that shards merge.
    #[arg(long, requires = "bench", default_value_t = GRID_POINTS as u8,
          value_parser = clap::value_parser!(u8).range(3..=15))]
    grid: u8,
    /// With --bench: golden-section steps of each fit after its grid (0 to
    /// 12); each cross-validation fold refits with at most 2.
    #[arg(long, requires = "bench", default_value_t = REFINE_STEPS as u8,
          value_parser = clap::value_parser!(u8).range(0..=12))]
    refine: u8,
    /// With --bench: bench runs each predicted centroid is the mean of, each
    /// from its own start phase within the control period (1 to 9). Fewer
    /// cost fewer runs and leave the firmware's discrete decisions (the count
    /// a leg stops on) in the prediction: a first look, or a check that
    /// shards merge.
    #[arg(long, requires = "bench", default_value_t = CENTROID_RUNS as u8,
          value_parser = clap::value_parser!(u8).range(1..=9))]
    centroid_runs: u8,
    /// With --bench: leave the training groups' telemetry out of the
    /// diagnosis (end points only, as without telemetry).
    #[arg(long, requires = "bench")]
    no_series: bool,
    /// With --bench: which firmware build to run.
    #[arg(long, requires = "bench", value_enum, default_value_t = Build::Robust)]
    firmware: Build,
    /// With --bench: board TOML of the robot (default: Henrytwo's). Checked
    /// before anything runs.
    #[arg(long, requires = "bench", value_name = "FILE", value_parser = super::board::parse_board)]
    board: Option<hil::board::Board>,
    /// With --bench: a firmware parameter to set before each run, after the
    /// robot config's [firmware] settings and the experiment's own
    /// (NAME=VALUE, e.g. kp_left=1.5); repeat for more.
    #[arg(long = "param", requires = "bench", value_name = "NAME=VALUE",
          value_parser = super::args::parse_param)]
    params: Vec<(hil::firmware::link::Param, f32)>,
    /// With --bench: firmware ELF to run instead of the build in firmware/target.
    #[arg(long, requires = "bench", value_name = "FILE")]
    elf: Option<PathBuf>,
    /// With --bench: fit only the candidates of shard K of N (K/N, dealt
    /// round robin over the candidate list) and write the partial result
    /// to --out, for `hil gap --merge`.
    #[arg(long, requires = "bench", requires = "out", conflicts_with_all = ["self_test", "json"],
          value_name = "K/N")]
    shard: Option<Shard>,
    /// With --shard: the folder the partial result goes in
    /// (gap-bench-shard-K-of-N.json).
    #[arg(long, requires = "shard", value_name = "DIR")]
    out: Option<PathBuf>,
    /// Merge the partial results of `hil gap --bench --shard` (every shard
    /// of one plan) and print the report one machine prints.
    #[arg(long, value_name = "FILE", num_args = 1..,
          conflicts_with_all = ["real", "self_test", "bench", "model", "train", "markdown"])]
    merge: Vec<PathBuf>,
    #[command(flatten)]
    json: Json,
    #[arg(long, default_value_t = 0)]
    seed: u64,
}

impl Gap {
    pub fn run(self) -> Result<()> {
        let kinematic = gap::KinematicModel;
        if !self.merge.is_empty() {
            return self.merge_shards();
        }
        if self.self_test && self.bench {
            return self.bench_self_test();
        }
        if self.self_test {
            let cases = gap::self_test(&kinematic, self.seed);
            self.json
                .emit(&cases, || render_cases_with(&cases, CaseColumns::Measures))?;
            let failed = cases.iter().filter(|c| c.identifiable && !c.passed());
            return cases_failed(failed.map(|c| c.effect.as_str()), cases.len());
        }
        if self.real.is_empty() {
            return Err(super::BadInput(
                "give --real DIR (manifests of real data, e.g. fixtures/real/thesis) or --self-test"
                    .into(),
            )
            .into());
        }
        // The report's files, checked before the diagnosis.
        if let Some(path) = &self.markdown {
            if super::check_output("--markdown", path)? == hil::output::Kind::Replace {
                super::check_output("--markdown", &path.with_extension("svg"))?;
            }
        }
        if let (Some(shard), Some(dir)) = (self.shard, &self.out) {
            super::check_output("--out", &hil::runs::gap_bench::partial_path(dir, shard))?;
        }
        let mut manifests = self.manifests()?;
        if let Some(m) = &self.model {
            let cfg = RobotConfig::load(m)
                .with_context(|| format!("--model {}", m.display()))
                .map_err(super::bad_input)?;
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
        if self.bench {
            return self.bench_real(&manifests, &rule);
        }
        let d = gap::diagnose_manifests(
            &kinematic,
            &manifests,
            &rule,
            &gap::DiagnoseOptions::default(),
        )?;
        if let Some(path) = &self.markdown {
            if hil::output::check_file(path).ok() == Some(hil::output::Kind::InPlace) {
                // A pipe or a device has no folder to put the plot beside.
                super::write_output(path, gap::render_markdown(&d, None).as_bytes())?;
                eprintln!("wrote {}", path.display());
            } else {
                let svg_path = path.with_extension("svg");
                let svg = gap::plot_svg(&d)?;
                super::write_output(&svg_path, svg.as_bytes())?;
                let name = svg_path
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned());
                let text = gap::render_markdown(&d, name.as_deref());
                super::write_output(path, text.as_bytes())?;
                eprintln!("wrote {} and {}", path.display(), svg_path.display());
            }
        }
        self.json.emit(&d, || gap::render_text(&d))
    }

    /// The manifests of `--real`: each a folder of them or a manifest file.
    /// A path that is neither, a folder without one, or a manifest that does
    /// not check is refused (exit 2) naming it, before any diagnosis.
    fn manifests(&self) -> Result<Vec<gap::LoadedManifest>> {
        let mut manifests = Vec::new();
        for r in &self.real {
            if r.is_dir() {
                let found = gap::load_dir(r).map_err(super::bad_input)?;
                if found.is_empty() {
                    return Err(super::BadInput(format!(
                        "--real {}: the folder holds no manifest (*.toml); give a folder of \
                         manifests, e.g. fixtures/real/thesis",
                        r.display()
                    ))
                    .into());
                }
                manifests.extend(found);
            } else if r.exists() {
                manifests.push(gap::LoadedManifest::load(r).map_err(super::bad_input)?);
            } else {
                return Err(super::BadInput(format!(
                    "--real {}: no such folder or file",
                    r.display()
                ))
                .into());
            }
        }
        Ok(manifests)
    }

    /// The ELF of `--elf`, else of the `--firmware` build.
    fn firmware(&self) -> Result<Firmware> {
        use clap::ValueEnum;
        let path = match &self.elf {
            Some(p) => p.clone(),
            None => {
                let build = self.firmware.to_possible_value().context("no such build")?;
                hil::paths::firmware_elf(build.get_name())
            }
        };
        Firmware::load(&path).map_err(super::bad_input)
    }

    /// `--jobs`, or the machine's cores; at most the cores.
    fn jobs(&self) -> usize {
        super::args::cap_jobs(self.jobs.map(u64::from), None)
    }

    fn select_options(&self) -> SelectOptions {
        let default = SelectOptions::default();
        SelectOptions {
            shortlist: self.shortlist.into(),
            series: !self.no_series,
            max_effects: self.max_effects.into(),
            grid: self.grid.into(),
            refine: self.refine.into(),
            fold_refine: default.fold_refine.min(self.refine.into()),
            fit: gap::FitOptions {
                centroid_runs: self.centroid_runs.into(),
                ..default.fit.clone()
            },
            ..default
        }
    }

    /// The nominal robot of the bench: `--model`, else the robot config every manifest
    /// names (they must name the same robot).
    fn nominal(&self, manifests: &[gap::LoadedManifest]) -> Result<RobotConfig> {
        if let Some(m) = &self.model {
            let cfg = RobotConfig::load(m)
                .with_context(|| format!("model {}", m.display()))
                .map_err(super::bad_input)?;
            super::args::check_firmware_settings(m, &cfg)?;
            return Ok(cfg);
        }
        let mut found: Option<(RobotConfig, PathBuf)> = None;
        for lm in manifests.iter().filter(|m| m.manifest.endpoints.is_some()) {
            let path = lm.resolve(&lm.manifest.robot_config);
            let cfg = RobotConfig::load(&path)
                .with_context(|| {
                    format!(
                        "{}: robot_config {} is not a plant configuration the bench can run \
                         (give --model FILE)",
                        lm.path.display(),
                        path.display()
                    )
                })
                .map_err(super::bad_input)?;
            match &found {
                Some((c, first)) if *c != cfg => {
                    return Err(super::bad_input(anyhow::anyhow!(
                        "{} and {} are different robots: the bench runs one nominal robot \
                         (give --model FILE)",
                        first.display(),
                        path.display()
                    )))
                }
                Some(_) => {}
                None => {
                    super::args::check_firmware_settings(&path, &cfg)?;
                    found = Some((cfg, path))
                }
            }
        }
        found
            .map(|(c, _)| c)
            .ok_or_else(|| super::bad_input(anyhow::anyhow!("no manifest with end points")))
    }

    /// The bench as the model: the firmware on `nominal`, on `--board`, with `--param`.
    fn bench_model(&self, nominal: RobotConfig) -> Result<BenchModel> {
        let firmware = self.firmware()?;
        if hil::firmware::params::takes_params(&firmware) {
            if let Some(why) = self.board.and_then(|b| b.firmware_encoder_mismatch()) {
                return Err(super::BadInput(format!("--board: {why}")).into());
            }
        }
        Ok(BenchModel::new(firmware, nominal, self.jobs())
            .on_board(self.board.unwrap_or_default())
            .with_params(self.params.clone()))
    }

    fn bench_real(&self, manifests: &[gap::LoadedManifest], rule: &SplitRule) -> Result<()> {
        let nominal = self.nominal(manifests)?;
        let bench = self.bench_model(nominal)?;
        let with_endpoints: Vec<_> = manifests
            .iter()
            .filter(|m| m.manifest.endpoints.is_some())
            .cloned()
            .collect();
        let (mut data, _) = gap::load_dataset(&with_endpoints)?;
        for note in gap::attach_telemetry(&mut data, manifests)? {
            eprintln!("note: {note}");
        }
        let (train, held) = data.split(rule)?;
        eprintln!("kinematic diagnosis (the shortlist)...");
        let shortlist = hil::runs::gap_bench::kinematic_shortlist(
            &train,
            &held,
            &gap::DiagnoseOptions::default(),
        )?;
        if let (Some(shard), Some(dir)) = (self.shard, &self.out) {
            // The folder is held before anything runs, as `hil umbmark --shard` holds it.
            let _shared = hil::output::share(dir)?;
            let partial = hil::runs::gap_bench::run_shard(
                &bench,
                &shortlist.shortlist,
                &train,
                &held,
                &self.select_options(),
                shard,
                &|line| eprintln!("{line}"),
            )?;
            let path = hil::runs::gap_bench::partial_path(dir, shard);
            super::write_output(&path, serde_json::to_string_pretty(&partial)?.as_bytes())?;
            eprintln!(
                "wrote {} ({} of {} candidates, {} bench runs)",
                path.display(),
                partial.candidates.len(),
                partial.plan.fit.candidates.len(),
                partial.nominal.bench_runs + partial.bench_runs
            );
            return Ok(());
        }
        let d = hil::runs::gap_bench::diagnose_bench(
            &bench,
            &shortlist,
            &train,
            &held,
            &self.select_options(),
            &|line| eprintln!("{line}"),
        )?;
        self.json.emit(&d, || d.render())
    }

    /// `--merge`: the partials' diagnosis. Partials that do not make one diagnosis are
    /// refused (exit 2) on one line naming the file or the shard.
    fn merge_shards(&self) -> Result<()> {
        let mut parts = Vec::new();
        for p in &self.merge {
            let text = input_file::read_text(p)
                .with_context(|| format!("reading {}", p.display()))
                .map_err(super::bad_input)?;
            let part: hil::runs::gap_bench::Partial = serde_json::from_str(&text)
                .with_context(|| {
                    format!(
                        "{} is not a partial result of `hil gap --bench --shard`",
                        p.display()
                    )
                })
                .map_err(super::bad_input)?;
            parts.push((p.display().to_string(), part));
        }
        let d = hil::runs::gap_bench::merge(parts).map_err(super::bad_input)?;
        self.json.emit(&d, || d.render())
    }

    fn bench_self_test(&self) -> Result<()> {
        let bench = self.bench_model(RobotConfig::default())?;
        // Each --hidden value is one case; effects joined by '+' are hidden together.
        let mut hidden: Vec<Vec<(String, f64)>> = Vec::new();
        for h in &self.hidden {
            let mut set = Vec::new();
            for one in h.split('+') {
                let parsed = one
                    .split_once('=')
                    .and_then(|(n, v)| Some((n.trim().to_owned(), v.trim().parse::<f64>().ok()?)));
                match parsed {
                    Some((n, v)) if v.is_finite() && !set.iter().any(|(m, _)| *m == n) => {
                        set.push((n, v))
                    }
                    _ => {
                        return Err(super::bad_input(anyhow::anyhow!(
                            "--hidden {h}: expected NAME=VALUE with a finite number, effects \
                             hidden together joined by '+' each once, e.g. battery_sag=0.5 or \
                             wheel_diameter_ratio=0.97+wheelbase_ratio=1.05"
                        )))
                    }
                }
            }
            hidden.push(set);
        }
        let real = match &self.real_robot {
            Some(path) => {
                let cfg = RobotConfig::load(path)
                    .with_context(|| format!("--real-robot {}", path.display()))
                    .map_err(super::bad_input)?;
                super::args::check_firmware_settings(path, &cfg)?;
                let (ours, theirs) = (
                    bench.reference(),
                    self.bench_model(cfg.clone())?.reference(),
                );
                if ours != theirs {
                    return Err(super::BadInput(format!(
                        "--real-robot {}: its geometry ({} mm wheelbase, {} mm per count) is \
                         not the nominal robot's ({} mm, {} mm per count): the self-test's \
                         data are recorded against the nominal robot",
                        path.display(),
                        theirs.wheelbase_mm,
                        theirs.mm_per_count,
                        ours.wheelbase_mm,
                        ours.mm_per_count
                    ))
                    .into());
                }
                Some(self.bench_model(cfg)?)
            }
            None => None,
        };
        let cases: Vec<Vec<(&str, f64)>> = if hidden.is_empty() && real.is_some() {
            vec![Vec::new()]
        } else if hidden.is_empty() {
            DEFAULT_CASES[..usize::from(self.cases)]
                .iter()
                .map(|&c| vec![c])
                .collect()
        } else {
            hidden
                .iter()
                .map(|set| set.iter().map(|(n, v)| (n.as_str(), *v)).collect())
                .collect()
        };
        let t = hil::runs::gap_bench::bench_self_test_on(
            &bench,
            real.as_ref().unwrap_or(&bench),
            &cases,
            SelfTestDesign {
                leg_mm: f64::from(self.leg_mm),
                shuttle: self.shuttle,
            },
            self.seed,
            &self.select_options(),
            &|line| eprintln!("{line}"),
        )?;
        self.json.emit(&t, || t.render())?;
        let failed: Vec<String> = t
            .cases
            .iter()
            .filter(|c| !c.passed())
            .map(|c| c.label())
            .collect();
        cases_failed(failed.iter().map(String::as_str), t.cases.len())
    }
}

/// A self-test whose cases did not all pass has not shown what it was asked to: after its
/// table, one line naming the failed cases, and exit 1 (as `hil faults` and `hil test`).
fn cases_failed<'a>(failed: impl Iterator<Item = &'a str>, total: usize) -> Result<()> {
    let failed: Vec<&str> = failed.collect();
    if failed.is_empty() {
        return Ok(());
    }
    anyhow::bail!(
        "self-test: {} of {total} cases failed: {}",
        failed.len(),
        failed.join(", ")
    )
}
