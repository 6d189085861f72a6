//! The bench-backed diagnosis: the kinematic diagnosis ranks candidates as a fast
//! surrogate; the bench then fits its shortlist (by default every effect it has) and every
//! effect the kinematic model cannot represent, each alone by a bounded 1-D search (a grid
//! over the effect's range, then a golden-section refinement around the best point), ranks
//! them by the bench's training residual, and chooses by cross-validation inside the
//! training data: leave one experiment out when there are several, else one group
//! (experiment/test), each fold's fit refined from the best value the whole fit's search
//! has seen for the fold's groups. A candidate is taken only when it predicts the left-out
//! data markedly better than the nominal robot (by the kinematic diagnosis' "marked" χ²
//! margin: the cross-validation's own estimate scatters), is fitted away from its neutral
//! value, and the nominal robot does not already explain the training data at noise level:
//! an effect that leaves no trace in the data is not named from their noise. The held-out
//! gap before and after is the bench's.
//!
//! Only centroids are scored (the weighted χ² of the end points' means, as [`gap::Scorer`]
//! weighs them): every candidate here is systematic, and the bench's nominal robot has no
//! floor noise, so the spreads would add the same constant to every candidate. Each
//! centroid is the mean of [`CENTROID_RUNS`] runs, each started at its own phase of the
//! firmware's control period ([`super::start_phase_s`]), its spread weighing the residual
//! beside the real centroid's: one run's end jumps as the firmware's discrete decisions flip
//! with the smallest change of an effect, and a search over such a function finds jumps,
//! not the effect.
//!
//! When training groups carry telemetry (one run logged every control period) and
//! [`SelectOptions::series`] is on, every bench run of a group's centroid records its series
//! too (the same runs, no extra one), and each value's score is the centroid χ² plus the
//! series χ² of [`super::series_chi2`]: per group, four residuals per segment kind (both
//! wheels' mean real − bench speed and duty over the segment; the bench's speeds from its
//! encoder counts, as a robot's firmware logs them), each over its standard error
//! σ/√n, σ the real series' own noise ([`super::series_noise`]: the long-run deviation of
//! its steady legs, by batch means), plus the spread of the bench runs' own segment means
//! ([`super::series_chi2_of_runs`]), that spread's widening charged back as the Gaussian
//! deviance does ([`super::SeriesScore::deviance`]). The fits, the cross-validation (a left-out
//! group's series is predicted too), the ranking and the comparison with the nominal robot
//! all use that sum, so a candidate that fits the end points but not the speeds ranks below
//! one that fits both. The p-value stays the end points' alone. Without telemetry nothing
//! changes.

use std::collections::BTreeMap;

use super::series::SeriesScore;
use gap::data::{Group, HeldOutSet, TrainSet};
use gap::effects::ParamKind;
use gap::fit::Gap;
use gap::{EffectParams, GapError, Model, Scorer};
use serde::{Deserialize, Serialize};

use super::{Batched, BenchModel};

mod choose;
#[cfg(test)]
pub(super) use choose::heldout_worse_note;
pub(super) use choose::{HELDOUT_WORSE, MARKED_CHI2};
mod forward;
mod joint;
mod linalg;
mod options;
mod regression;
mod render;
mod search;
mod telemetry;
pub use choose::choose;
pub use forward::third_starts;
pub use joint::JointFit;
pub use options::{SelectOptions, CENTROID_RUNS, GRID_POINTS, REFINE_STEPS};
use search::{grid, Search};
use telemetry::{scores_series, series_total};

/// One candidate fitted by the bench.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BenchCandidate {
    /// The effect.
    pub effect: String,
    /// Its symbol and unit.
    pub symbol: String,
    pub unit: String,
    /// Why it is a candidate.
    pub source: String,
    /// Fitted on all training groups.
    pub value: f64,
    /// Training χ² of the centroids at that value.
    pub train_chi2: f64,
    /// Cross-validated χ²: each fold predicted by a fit on the others (None: one group).
    pub cv_chi2: Option<f64>,
    /// Held-out systematic gap with it, cm.
    pub heldout_systematic_cm: f64,
    /// Standard error of the value, from the training residuals' slope at it (None: the
    /// residuals do not move with it there).
    #[serde(default)]
    pub std_err: Option<f64>,
    /// Training series χ² at that value, and the RMS of real − bench speed over every
    /// telemetry sample, thesis RPM (None: no telemetry scored).
    pub series_chi2: Option<f64>,
    pub series_rms_rpm: Option<f64>,
}

/// The answer of [`diagnose_bench`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BenchDiagnosis {
    /// The model.
    pub model: String,
    /// The split.
    pub rule: String,
    /// Candidates, best training residual first.
    pub candidates: Vec<BenchCandidate>,
    /// The nominal bench robot: training χ², its cross-validated χ² (no fit, the same
    /// folds) and the number of centroid residuals.
    pub nominal_train_chi2: f64,
    pub nominal_cv_chi2: Option<f64>,
    pub residuals: usize,
    /// What one fold leaves out ("experiment" or "group"), and the folds.
    pub fold_by: &'static str,
    pub folds: Vec<String>,
    /// Groups never left out ([`FitPlan::kept_out`]).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub folds_kept_out: Vec<String>,
    /// The best single effect taken, and its value (None: none taken).
    pub winner: Option<(String, f64)>,
    /// The chosen model: the single winner, or a joint fit that earned its place over it
    /// (empty: the nominal robot).
    pub chosen: Vec<ChosenValue>,
    /// The joint fits tried (see `select/joint.rs`), and the bench runs they took.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub joint: Vec<JointFit>,
    #[serde(skip_serializing_if = "is_zero")]
    pub joint_runs: usize,
    /// The winner's other name in the plant's library, with its value, when the plant makes
    /// the same robot under both ([`super::params::equivalent`]): no data can prefer one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub winner_equivalent: Option<(String, f64)>,
    /// The candidates these data cannot tell from the winner (see [`alike`]), and the
    /// held-out systematic gap predicted with each of them and the winner: (least, most),
    /// cm (None: no such candidate).
    pub alike: Vec<String>,
    pub heldout_after_range_cm: Option<(f64, f64)>,
    /// Held-out gap of the nominal bench robot, and with the winner.
    pub heldout_before: Gap,
    pub heldout_after: Gap,
    /// Whether the training residual left by the chosen model is at noise level (χ²
    /// p-value above 1 %), its p-value, and where it sits when it is not.
    pub at_noise_level: bool,
    pub p_value: f64,
    pub notes: Vec<String>,
    /// Bench runs made.
    pub bench_runs: usize,
    /// With telemetry: the nominal robot's training series χ² and RMS (thesis RPM), the
    /// number of series residuals, and the chosen model's per-segment gap of each training
    /// group with telemetry.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub nominal_series_chi2: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub nominal_series_rms_rpm: Option<f64>,
    #[serde(skip_serializing_if = "is_zero")]
    pub series_residuals: usize,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub series: Vec<SeriesScore>,
}

/// One value of the chosen model.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChosenValue {
    pub effect: String,
    pub value: f64,
    /// Its standard error (None: not determined from the data).
    pub std_err: Option<f64>,
    pub unit: String,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

fn chi2(r: &[f64]) -> f64 {
    r.iter().map(|x| x * x).sum()
}

/// The fold a group belongs to.
fn fold_of(g: &Group, by_experiment: bool) -> String {
    if by_experiment {
        g.id.experiment.clone()
    } else {
        g.id.to_string()
    }
}

/// What the kinematic diagnosis, the fast surrogate, gives the bench: its ranking of
/// single effects, best first (the shortlist the bench fits), and its fitted sets of
/// several effects, best first, with their values (the starts of the joint fits).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Surrogate {
    pub shortlist: Vec<String>,
    pub fits: Vec<(Vec<String>, Vec<f64>)>,
}

/// The kinematic diagnosis of `train` as the bench's [`Surrogate`].
pub fn kinematic_shortlist(
    train: &TrainSet,
    held: &HeldOutSet,
    opts: &gap::DiagnoseOptions,
) -> Result<Surrogate, GapError> {
    let kin = gap::diagnose(&gap::KinematicModel, train, held, opts)?;
    let values = |f: &gap::CandidateFit| -> (Vec<String>, Vec<f64>) {
        (
            f.effects.clone(),
            f.estimates.iter().map(|e| e.value).collect(),
        )
    };
    let mut fits: Vec<(Vec<String>, Vec<f64>)> = Vec::new();
    for f in kin
        .winner_fit()
        .into_iter()
        .chain(kin.which.pairs.iter().map(|r| &r.fit))
    {
        // Two starts from the surrogate (its winner and best pair, or its two best pairs):
        // the bench's own best singles make the others.
        if f.effects.len() == 2 && fits.len() < 2 && !fits.iter().any(|(e, _)| *e == f.effects) {
            fits.push(values(f));
        }
    }
    Ok(Surrogate {
        shortlist: kin
            .which
            .singles
            .iter()
            .flat_map(|r| r.fit.effects.clone())
            .collect(),
        fits,
    })
}

/// What [`diagnose_bench`] fits and how it cross-validates: it follows from the data, the
/// shortlist and the options alone, so every machine of a sharded diagnosis makes the same.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FitPlan {
    /// The model.
    pub model: String,
    /// The split.
    pub rule: String,
    /// The candidates in the order they are fitted: (effect, why it is one).
    pub candidates: Vec<(String, String)>,
    /// Whether a fold leaves out an experiment (else a group), and the folds.
    pub by_experiment: bool,
    pub folds: Vec<String>,
    /// Groups never left out: leaving them out would leave a training set without a turn
    /// (a line alone), on which no effect of the turns is fitted.
    #[serde(default)]
    pub kept_out: Vec<String>,
}

/// Whether a group's test turns the robot (every test but the line).
fn turns(g: &Group) -> bool {
    g.id.test != gap::model::TestKind::Line
}

/// The cross-validation's folds of `groups`: leave one experiment out when there are
/// several and each such fold still trains on a turn, else leave one group out; a group
/// whose leaving out would leave no turn to train on is never left out (the folds that
/// remain each keep turns and straights: every turning test has straight legs). Returns
/// (by experiment, folds, the groups never left out).
pub(super) fn folds_of(groups: &[Group]) -> (bool, Vec<String>, Vec<String>) {
    let trains_on_a_turn =
        |f: &str, by: bool| groups.iter().any(|g| fold_of(g, by) != f && turns(g));
    let unique = |by: bool| {
        let mut v: Vec<String> = groups.iter().map(|g| fold_of(g, by)).collect();
        v.dedup();
        v
    };
    let experiments = unique(true);
    if experiments.len() >= 2 && experiments.iter().all(|f| trains_on_a_turn(f, true)) {
        return (true, experiments, Vec::new());
    }
    let (kept, out): (Vec<String>, Vec<String>) = unique(false)
        .into_iter()
        .partition(|f| trains_on_a_turn(f, false));
    (false, kept, out)
}

impl FitPlan {
    /// The plan of `bench` on `train` (see [`diagnose_bench`] for `shortlist`).
    pub fn new(
        bench: &BenchModel,
        shortlist: &[String],
        train: &TrainSet,
        opts: &SelectOptions,
    ) -> Self {
        let specs = bench.parameters();
        let mut names: Vec<(String, String)> = Vec::new();
        let systematic = |n: &str| {
            specs
                .iter()
                .any(|s| s.name == n && s.kind == ParamKind::Systematic)
        };
        for n in shortlist
            .iter()
            .filter(|n| systematic(n))
            .take(opts.shortlist)
        {
            names.push((n.clone(), "kinematic shortlist".to_owned()));
        }
        // The kinematic ranking lists the singles it fitted; the rest of its effects
        // follow in the library's order, up to the same number.
        let unsupported = gap::kinematic::kinematic_unsupported();
        for s in &specs {
            let kinematic = !unsupported.iter().any(|u| u.name == s.name);
            if names.len() < opts.shortlist
                && kinematic
                && systematic(&s.name)
                && !names.iter().any(|(n, _)| *n == s.name)
            {
                names.push((s.name.clone(), "kinematic model, unranked".to_owned()));
            }
        }
        for u in unsupported {
            if systematic(&u.name) && !names.iter().any(|(n, _)| *n == u.name) {
                names.push((
                    u.name,
                    "not representable by the kinematic model".to_owned(),
                ));
            }
        }
        let (by_experiment, folds, kept_out) = folds_of(train.groups());
        FitPlan {
            model: bench.name(),
            rule: train.rule().to_owned(),
            candidates: names,
            by_experiment,
            folds,
            kept_out,
        }
    }

    /// Whether there is more than one fold to cross-validate with.
    pub(super) fn cv(&self) -> bool {
        self.folds.len() >= 2
    }
}

/// The nominal bench robot's numbers: training χ² (its cross-validated χ² is the same, as
/// nothing is fitted), centroid residuals, the gap on training and held-out data.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NominalFit {
    pub train_chi2: f64,
    pub residuals: usize,
    pub train_gap: Gap,
    pub heldout: Gap,
    /// Bench runs these took.
    pub bench_runs: usize,
    /// With telemetry: the training series' χ² and RMS (thesis RPM), and the number of
    /// series residuals (see the module docs).
    #[serde(default)]
    pub series_chi2: Option<f64>,
    #[serde(default)]
    pub series_rms_rpm: Option<f64>,
    #[serde(default)]
    pub series_residuals: usize,
    /// The per-segment score of each group with telemetry. Not in a shard's partial: a
    /// merged report has the series' χ² but not this table.
    #[serde(skip)]
    pub series_gaps: Vec<SeriesScore>,
}

/// One candidate fitted completely: its search, folds and held-out gap.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FittedCandidate {
    /// Its place in [`FitPlan::candidates`].
    pub index: usize,
    pub candidate: BenchCandidate,
    /// The gap at its fitted value on the training data (where a residual beyond noise
    /// sits) and on the held-out data.
    pub train_gap: Gap,
    pub heldout: Gap,
    /// Its prediction of the training centroids at its value: the weighted residuals of
    /// [`Scorer::centroid_residuals`], group after group (what [`alike`] compares).
    pub train_residuals: Vec<f64>,
    /// As [`NominalFit::series_gaps`], at its fitted value.
    #[serde(skip)]
    pub series_gaps: Vec<SeriesScore>,
}

/// Runs the bench-backed diagnosis (see the module docs). `shortlist` is the kinematic
/// diagnosis' ranking of single effects, best first; `progress` gets a line per step.
pub fn diagnose_bench(
    bench: &BenchModel,
    surrogate: &Surrogate,
    train: &TrainSet,
    held: &HeldOutSet,
    opts: &SelectOptions,
    progress: &dyn Fn(&str),
) -> Result<BenchDiagnosis, GapError> {
    let batched = Batched::with_series(bench, scores_series(train, opts));
    let plan = FitPlan::new(bench, &surrogate.shortlist, train, opts);
    let nominal = fit_nominal(&batched, &plan, train, held, opts, progress)?;
    let all: Vec<usize> = (0..plan.candidates.len()).collect();
    let fitted = fit_candidates(&batched, &plan, &all, train, held, opts, progress)?;
    let mut d = choose(&plan, &nominal, fitted, batched.runs());
    forward::forward(
        &batched,
        &plan,
        train,
        held,
        opts,
        &surrogate.fits,
        &mut d,
        progress,
    )?;
    Ok(d)
}

/// One joint fit of `effects` on the bench, from the best of `starts` on the training data,
/// as the forward selection makes it (with the folds [`FitPlan::new`] gives `train`): the
/// joint fit alone, for data whose effects are known, without the whole diagnosis' single
/// fits around it.
pub fn fit_effects_jointly(
    bench: &BenchModel,
    train: &TrainSet,
    held: &HeldOutSet,
    opts: &SelectOptions,
    effects: &[&str],
    starts: &[Vec<f64>],
) -> Result<JointFit, GapError> {
    let batched = Batched::with_series(bench, scores_series(train, opts));
    let plan = FitPlan::new(bench, &[], train, opts);
    let effects: Vec<String> = effects.iter().map(|e| (*e).to_owned()).collect();
    joint::fit_joint(
        &batched, &plan, train, held, opts, &effects, starts, "given",
    )
}

/// The training score of the bench under `params` as the searches count it (every
/// training centroid's χ², plus the series' deviance when telemetry is scored), with no
/// fit: what the self-test measures the hidden truth itself by.
pub fn training_score(
    bench: &BenchModel,
    train: &TrainSet,
    params: &EffectParams,
    opts: &SelectOptions,
) -> Result<f64, GapError> {
    let batched = Batched::with_series(bench, scores_series(train, opts));
    let ends = batched.eval(|m| -> Result<f64, GapError> {
        let sc = Scorer::new(m, train, &opts.fit);
        train
            .groups()
            .iter()
            .map(|g| Ok(chi2(&sc.centroid_residuals(params, g)?)))
            .sum()
    })?;
    let series = series_total(&batched, train, &opts.fit, params)?;
    Ok(ends + series.map_or(0.0, |t| t.chi2))
}

/// The nominal bench robot on the training and the held-out data, in one batch (so that
/// no candidate's count of runs includes one of the nominal robot's).
pub fn fit_nominal(
    batched: &Batched,
    plan: &FitPlan,
    train: &TrainSet,
    held: &HeldOutSet,
    opts: &SelectOptions,
    progress: &dyn Fn(&str),
) -> Result<NominalFit, GapError> {
    let neutral = EffectParams::new();
    let before = batched.runs();
    let (nominal_groups, heldout) = batched.eval(|m| -> Result<(Vec<f64>, Gap), GapError> {
        let sc = Scorer::new(m, train, &opts.fit);
        let groups = train
            .groups()
            .iter()
            .map(|g| Ok(chi2(&sc.centroid_residuals(&neutral, g)?)))
            .collect::<Result<_, GapError>>()?;
        Ok((groups, sc.gap(&neutral, held.groups())?))
    })?;
    let nominal_train_chi2: f64 = nominal_groups.iter().sum();
    let nominal_series = series_total(batched, train, &opts.fit, &neutral)?;
    let residuals = batched.eval(|m| -> Result<usize, GapError> {
        let sc = Scorer::new(m, train, &opts.fit);
        let mut n = 0;
        for g in train.groups() {
            n += sc.centroid_residuals(&neutral, g)?.len();
        }
        Ok(n)
    })?;
    let train_gap =
        batched.eval(|m| Scorer::new(m, train, &opts.fit).gap(&neutral, train.groups()))?;
    progress(&format!(
        "bench: nominal robot, training χ² {nominal_train_chi2:.1} over {residuals} residuals; \
         fitting {} candidates",
        plan.candidates.len()
    ));
    Ok(NominalFit {
        train_chi2: nominal_train_chi2,
        residuals,
        train_gap,
        heldout,
        bench_runs: batched.runs() - before,
        series_chi2: nominal_series.as_ref().map(|t| t.chi2),
        series_rms_rpm: nominal_series.as_ref().map(|t| t.rms_rpm),
        series_residuals: nominal_series.as_ref().map_or(0, |t| t.residuals),
        series_gaps: nominal_series.map_or(Vec::new(), |t| t.gaps),
    })
}

/// Fits the candidates `which` (places in `plan.candidates`) completely: each one's search
/// and folds, then all their held-out gaps in one batch.
pub fn fit_candidates(
    batched: &Batched,
    plan: &FitPlan,
    which: &[usize],
    train: &TrainSet,
    held: &HeldOutSet,
    opts: &SelectOptions,
    progress: &dyn Fn(&str),
) -> Result<Vec<FittedCandidate>, GapError> {
    let specs = batched.parameters();
    let (by_experiment, folds, cv) = (plan.by_experiment, &plan.folds, plan.cv());
    let mut candidates = Vec::new();
    let mut series_gaps = Vec::new();
    for &i in which {
        let (name, source) = &plan.candidates[i];
        let spec = specs
            .iter()
            .find(|s| s.name == *name)
            .expect("a bench parameter")
            .clone();
        let mut search = Search {
            batched,
            train,
            fit: &opts.fit,
            spec,
            seen: BTreeMap::new(),
            series: BTreeMap::new(),
        };
        let grid = grid(&search.spec, opts.grid);
        search.eval(&grid)?;
        let (value, _) = search.fit(&grid, opts.refine, &|_| true)?;
        let (train_chi2, series_chi2) = search.parts(value);
        let cv_chi2 = if cv {
            let mut total = 0.0;
            for f in folds {
                // From the best value the search has seen for this fold's groups: the points
                // near the whole fit's value are dense there, a grid's are far apart.
                let seen = search.evaluated();
                let (v, _) = search.fit(&seen, opts.fold_refine, &|g| {
                    fold_of(g, by_experiment) != *f
                })?;
                total += search.at(v, &|g| fold_of(g, by_experiment) == *f);
            }
            Some(total)
        } else {
            None
        };
        progress(&format!(
            "bench: [{}/{}] {name} {value:.4}: training χ² {train_chi2:.1}{}{} ({} bench runs \
             so far)",
            i + 1,
            plan.candidates.len(),
            series_chi2.map_or(String::new(), |c| format!(" + series {c:.1}")),
            cv_chi2.map_or(String::new(), |c| format!(", cross-validated {c:.1}")),
            batched.runs()
        ));
        let series = series_total(batched, train, &opts.fit, &search.params(value))?;
        candidates.push(BenchCandidate {
            effect: name.clone(),
            symbol: search.spec.symbol.clone(),
            unit: search.spec.unit.clone(),
            source: source.clone(),
            value,
            train_chi2,
            cv_chi2,
            heldout_systematic_cm: f64::NAN,
            std_err: joint::std_err_of(batched, train, opts, name, value)?,
            series_chi2,
            series_rms_rpm: series.as_ref().map(|t| t.rms_rpm),
        });
        series_gaps.push(series.map_or(Vec::new(), |t| t.gaps));
    }

    // Held out, every candidate in one batch; the training gap at each fitted value comes
    // from the search's runs.
    let params_of = |c: &BenchCandidate| EffectParams::new().with(&c.effect, c.value);
    let gaps = batched.eval(|m| -> Result<Vec<(Gap, Gap, Vec<f64>)>, GapError> {
        let sc = Scorer::new(m, train, &opts.fit);
        candidates
            .iter()
            .map(|c| {
                let mut residuals = Vec::new();
                for g in train.groups() {
                    residuals.extend(sc.centroid_residuals(&params_of(c), g)?);
                }
                Ok((
                    sc.gap(&params_of(c), held.groups())?,
                    sc.gap(&params_of(c), train.groups())?,
                    residuals,
                ))
            })
            .collect()
    })?;
    Ok(which
        .iter()
        .zip(candidates)
        .zip(gaps)
        .zip(series_gaps)
        .map(
            |(((&index, mut candidate), (heldout, train_gap, train_residuals)), series_gaps)| {
                candidate.heldout_systematic_cm = heldout.systematic_cm;
                FittedCandidate {
                    index,
                    candidate,
                    train_gap,
                    heldout,
                    train_residuals,
                    series_gaps,
                }
            },
        )
        .collect())
}

impl BenchCandidate {
    /// The training score the candidates are ranked by: the end points' χ², plus the
    /// series' when scored.
    pub fn train_score(&self) -> f64 {
        self.series_chi2
            .map_or(self.train_chi2, |s| self.train_chi2 + s)
    }
}

#[cfg(test)]
mod tests;
