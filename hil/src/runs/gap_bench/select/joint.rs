//! Joint fits of several effects on the bench, by forward selection: a robot with two
//! errors at once (Borenstein's Ed and Eb) is fitted by no single effect, and a single fit
//! then compensates with a wrong value or a wrong effect.
//!
//! Pairs come from the kinematic surrogate's best pairs (with its fitted values as a
//! start), Borenstein's Ed + Eb, and the bench's best single effects taken two at a time;
//! each fit begins at the best of its starts (single fits' values, each with the other
//! effect at neutral; see `forward.rs`). Each is fitted jointly by Levenberg-Marquardt on the weighted centroid residuals:
//! the Jacobian by forward differences of [`STEP`] scales, and three damping factors tried
//! in one batch per iteration, so an iteration is k + 3 predictions of the training groups,
//! run in parallel. Values are kept inside their effects' ranges. A pair is taken when it
//! improves markedly on the model so far (the single winner, or the nominal robot), predicts
//! the left-out groups markedly better (each fold refitted from the joint value), and every
//! value is determined (more than two standard errors from neutral); then a third effect is
//! tried the same way on top of it. A triple's fit ends with regression steps
//! (`regression.rs`): two of its effects trade off in the end points, and along that ridge
//! the local differences follow the bench's roughness, not its trend.

use std::collections::HashMap;

use gap::data::{Group, HeldOutSet, TrainSet};
use gap::fit::Gap;
use gap::{EffectParams, GapError, Model, ParamSpec, Scorer};
use serde::{Deserialize, Serialize};

use super::choose::MARKED_CHI2;
use super::linalg::{inverse, normal_equations, solve};
use super::regression;
use super::{fold_of, Batched, FitPlan, SelectOptions};

/// Forward-difference step of the Jacobian, in scales of each effect
/// ([`ParamSpec::scale`]): wide enough that the mean of [`super::CENTROID_RUNS`] runs moves
/// by more than its start phases' jumps.
const STEP: f64 = 0.3;
/// Damping factors tried together in each iteration, times the last accepted one.
const DAMPING: [f64; 3] = [0.1, 1.0, 10.0];
/// An iteration that lowers the χ² by less than this ends the fit.
const CONVERGED_CHI2: f64 = 0.5;

/// One joint fit: its effects, values and what it achieved.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JointFit {
    /// The effects, and their fitted values.
    pub effects: Vec<String>,
    pub values: Vec<f64>,
    /// Standard error of each value from the Jacobian at the fit (covariance inflated by
    /// χ²/dof when above 1); None when singular.
    pub std_err: Vec<Option<f64>>,
    /// Largest |correlation| between two values (None: singular).
    pub max_correlation: Option<f64>,
    /// Where it started ("kinematic surrogate", "single fits").
    pub start: String,
    /// Training χ² of the centroids, and of the series when scored.
    pub train_chi2: f64,
    pub series_chi2: Option<f64>,
    /// Cross-validated score (None: one fold).
    pub cv_chi2: Option<f64>,
    /// Training and held-out gap at its values.
    pub train_gap: Gap,
    pub heldout: Gap,
    /// Bench runs its fit, folds and held-out prediction took.
    pub bench_runs: usize,
    /// Whether every value is determined (see the module docs).
    pub determined: bool,
}

impl JointFit {
    /// Its training score: centroids, plus the series when scored.
    pub fn train_score(&self) -> f64 {
        self.train_chi2 + self.series_chi2.unwrap_or(0.0)
    }

    /// What the choice compares: cross-validated, else training.
    pub fn score(&self) -> f64 {
        self.cv_chi2.unwrap_or(self.train_score())
    }

    /// `effect = value` joined, for a report line.
    pub fn label(&self) -> String {
        self.effects.join(" + ")
    }
}

/// The evaluations of one set of effects: each (point, group)'s weighted centroid
/// residuals, its series' residuals and deviance, kept so that folds reuse the whole fit's
/// runs.
struct Joint<'a> {
    batched: &'a Batched<'a>,
    train: &'a TrainSet,
    opts: &'a SelectOptions,
    specs: Vec<ParamSpec>,
    /// (point bits, group) -> its evaluation.
    seen: HashMap<(Vec<u64>, usize), Evaluated>,
}

/// One (point, group)'s centroid residuals then series residuals, how many of them are the
/// centroid's, and the series deviance.
type Evaluated = (Vec<f64>, usize, f64);

fn bits(u: &[f64]) -> Vec<u64> {
    u.iter().map(|v| v.to_bits()).collect()
}

impl<'a> Joint<'a> {
    fn params(&self, v: &[f64]) -> EffectParams {
        let mut p = EffectParams::new();
        for (s, &x) in self.specs.iter().zip(v) {
            p.set(&s.name, x);
        }
        p
    }

    fn clamp(&self, v: &[f64]) -> Vec<f64> {
        self.specs
            .iter()
            .zip(v)
            .map(|(s, &x)| x.clamp(s.lower, s.upper))
            .collect()
    }

    /// The groups `keep` selects, by index.
    fn groups(&self, keep: &dyn Fn(&Group) -> bool) -> Vec<usize> {
        (0..self.train.groups().len())
            .filter(|&i| keep(&self.train.groups()[i]))
            .collect()
    }

    /// Every (point, group) of `points` × `groups` not evaluated yet, in one batch.
    fn eval(&mut self, points: &[Vec<f64>], groups: &[usize]) -> Result<(), GapError> {
        let mut todo: Vec<(Vec<f64>, usize)> = Vec::new();
        for p in points {
            for &g in groups {
                let k = (bits(p), g);
                if !self.seen.contains_key(&k)
                    && !todo.iter().any(|(q, h)| bits(q) == k.0 && *h == g)
                {
                    todo.push((p.clone(), g));
                }
            }
        }
        if todo.is_empty() {
            return Ok(());
        }
        let all = self.train.groups();
        let got = self.batched.eval(|m| -> Result<Vec<Vec<f64>>, GapError> {
            let sc = Scorer::new(m, self.train, &self.opts.fit);
            todo.iter()
                .map(|(p, g)| sc.centroid_residuals(&self.params(p), &all[*g]))
                .collect()
        })?;
        for ((p, g), mut r) in todo.into_iter().zip(got) {
            let (series, z) = super::telemetry::group_series(
                self.batched,
                self.train,
                &self.opts.fit,
                &self.params(&p),
                &all[g],
            )?;
            let ends = r.len();
            r.extend(z);
            self.seen.insert((bits(&p), g), (r, ends, series));
        }
        Ok(())
    }

    /// The residuals of `groups` at `p` (evaluated before), one vector: each group's
    /// centroid residuals, then its series' (a segment kind's mean speed and duty over their
    /// errors), so that the fit follows the whole training score the single fits are ranked
    /// by. The end points alone leave effects that trade off in them (a wider wheelbase and
    /// coasting both change UMBmark's turns) to the fit's start; the series tells them apart
    /// (the encoders count a coast, never a wheelbase).
    fn residuals(&self, p: &[f64], groups: &[usize]) -> Vec<f64> {
        groups
            .iter()
            .flat_map(|&g| self.seen[&(bits(p), g)].0.clone())
            .collect()
    }

    /// Centroid χ² and series deviance of `groups` at `p` (evaluated before).
    fn parts(&self, p: &[f64], groups: &[usize]) -> (f64, f64) {
        groups.iter().fold((0.0, 0.0), |(c, s), &g| {
            let (r, ends, d) = &self.seen[&(bits(p), g)];
            (c + super::chi2(&r[..*ends]), s + d)
        })
    }

    /// The whole training score of `groups` at `p`: what the fit minimises.
    fn score(&self, p: &[f64], groups: &[usize]) -> f64 {
        let (c, s) = self.parts(p, groups);
        c + s
    }

    /// The Jacobian of the residuals of `groups` at `p`, per scale of each effect (columns),
    /// by forward differences: toward the inside of the range at a bound.
    fn jacobian(&mut self, p: &[f64], groups: &[usize]) -> Result<Vec<Vec<f64>>, GapError> {
        let steps: Vec<f64> = self
            .specs
            .iter()
            .zip(p)
            .map(|(s, &x)| {
                let h = STEP * s.scale;
                if x + h > s.upper {
                    -h
                } else {
                    h
                }
            })
            .collect();
        let points: Vec<Vec<f64>> = (0..p.len())
            .map(|i| {
                let mut q = p.to_vec();
                q[i] += steps[i];
                q
            })
            .collect();
        self.eval(&points, groups)?;
        let r0 = self.residuals(p, groups);
        Ok(points
            .iter()
            .enumerate()
            .map(|(i, q)| {
                let per_scale = steps[i] / self.specs[i].scale;
                self.residuals(q, groups)
                    .iter()
                    .zip(&r0)
                    .map(|(a, b)| (a - b) / per_scale)
                    .collect()
            })
            .collect())
    }

    /// Levenberg-Marquardt on the centroid residuals of the groups `keep` selects, from
    /// `start`, at most `iterations` Jacobians. Returns the best point found.
    fn fit(
        &mut self,
        start: &[f64],
        keep: &dyn Fn(&Group) -> bool,
        iterations: usize,
    ) -> Result<Vec<f64>, GapError> {
        let groups = self.groups(keep);
        let mut p = self.clamp(start);
        self.eval(std::slice::from_ref(&p), &groups)?;
        let mut chi = self.score(&p, &groups);
        let mut damping = 1.0;
        for _ in 0..iterations {
            let jac = self.jacobian(&p, &groups)?;
            let r = self.residuals(&p, &groups);
            let (a, g) = normal_equations(&jac, &r);
            let trials: Vec<(f64, Vec<f64>)> = DAMPING
                .iter()
                .filter_map(|&f| {
                    let lambda = damping * f;
                    let mut m = a.clone();
                    for (i, row) in m.iter_mut().enumerate() {
                        row[i] += lambda * a[i][i].max(1e-9);
                    }
                    let step = solve(&m, &g.iter().map(|x| -x).collect::<Vec<_>>())?;
                    Some((lambda, self.offset(&p, &step)))
                })
                .collect();
            let points: Vec<Vec<f64>> = trials.iter().map(|t| t.1.clone()).collect();
            self.eval(&points, &groups)?;
            let best = trials
                .iter()
                .map(|(l, q)| (*l, q, self.score(q, &groups)))
                .min_by(|a, b| a.2.total_cmp(&b.2));
            match best {
                Some((lambda, q, c)) if c < chi => {
                    let gain = chi - c;
                    (p, chi, damping) = (q.clone(), c, lambda);
                    if gain < CONVERGED_CHI2 {
                        break;
                    }
                }
                _ => {
                    damping *= 100.0;
                    if damping > 1e4 {
                        break;
                    }
                }
            }
        }
        Ok(p)
    }

    /// [`super::regression`]'s steps from `p`, `steps` of them: the mean of the points
    /// they reach, and what its uncertainty takes from them (`p` itself and None when the
    /// first is undetermined).
    fn regression_steps(
        &mut self,
        p: &[f64],
        groups: &[usize],
        steps: usize,
    ) -> Result<(Vec<f64>, Option<Smoothed>), GapError> {
        let offsets = regression::design(p.len());
        let mut at = p.to_vec();
        let mut reached: Vec<Vec<f64>> = Vec::new();
        let mut slopes: Vec<Vec<Vec<f64>>> = Vec::new();
        for _ in 0..steps {
            let design: Vec<Vec<f64>> = offsets.iter().map(|d| self.offset(&at, d)).collect();
            self.eval(&design, groups)?;
            // The clamped points' own offsets, so a design cut by a bound regresses on
            // where it was evaluated.
            let actual: Vec<Vec<f64>> = design
                .iter()
                .map(|q| {
                    q.iter()
                        .zip(&at)
                        .zip(&self.specs)
                        .map(|((a, b), s)| (a - b) / s.scale)
                        .collect()
                })
                .collect();
            let residuals: Vec<Vec<f64>> =
                design.iter().map(|q| self.residuals(q, groups)).collect();
            let Some(t) = regression::trend(&actual, &residuals) else {
                break;
            };
            at = self.offset(&at, &t.step);
            reached.push(at.clone());
            slopes.push(t.jacobian);
        }
        if reached.is_empty() {
            return Ok((p.to_vec(), None));
        }
        let n = reached.len() as f64;
        let mean: Vec<f64> = (0..p.len())
            .map(|i| reached.iter().map(|q| q[i]).sum::<f64>() / n)
            .collect();
        let mean = self.clamp(&mean);
        self.eval(std::slice::from_ref(&mean), groups)?;
        // The points' variance about their mean, in scales², not over n: each step starts
        // where the last ended, so they are not independent draws.
        let spread2 = (0..p.len())
            .map(|i| {
                reached
                    .iter()
                    .map(|q| ((q[i] - mean[i]) / self.specs[i].scale).powi(2))
                    .sum::<f64>()
                    / (n - 1.0).max(1.0)
            })
            .collect();
        let jacobian = (0..p.len())
            .map(|c| {
                (0..slopes[0][c].len())
                    .map(|i| slopes.iter().map(|j| j[c][i]).sum::<f64>() / n)
                    .collect()
            })
            .collect();
        Ok((mean, Some(Smoothed { jacobian, spread2 })))
    }

    /// `p` moved by `d` scales of each effect, kept inside the ranges.
    fn offset(&self, p: &[f64], d: &[f64]) -> Vec<f64> {
        let q: Vec<f64> = p
            .iter()
            .zip(d)
            .zip(&self.specs)
            .map(|((x, d), s)| x + d * s.scale)
            .collect();
        self.clamp(&q)
    }

    /// Standard errors (in each effect's unit) and the largest |correlation| at `p` over
    /// all training groups: (JᵀJ)⁻¹ inflated by χ²/dof when above 1. None where singular.
    /// J is the forward differences' at `p`, or, for a fit that ended with regression
    /// steps, their models' mean slopes, and the spread of the points they reached is
    /// added to each variance: the forward differences of a rough answer are steeper than
    /// its trend, and would claim a precision the steps do not have.
    fn uncertainty(
        &mut self,
        p: &[f64],
        smoothed: Option<&Smoothed>,
    ) -> Result<(Vec<Option<f64>>, Option<f64>), GapError> {
        let groups = self.groups(&|_| true);
        let jac = match smoothed {
            Some(s) => s.jacobian.clone(),
            None => self.jacobian(p, &groups)?,
        };
        let r = self.residuals(p, &groups);
        let (a, _) = normal_equations(&jac, &r);
        let k = p.len();
        let dof = r.len().saturating_sub(k).max(1) as f64;
        let inflate = (super::chi2(&r) / dof).max(1.0);
        let Some(inv) = inverse(&a) else {
            return Ok((vec![None; k], None));
        };
        let se = (0..k)
            .map(|i| {
                let v = inv[i][i] * inflate + smoothed.map_or(0.0, |s| s.spread2[i]);
                (v.is_finite() && v > 0.0).then(|| v.sqrt() * self.specs[i].scale)
            })
            .collect();
        let mut corr: f64 = 0.0;
        for i in 0..k {
            for j in 0..k {
                if i != j {
                    corr = corr.max((inv[i][j] / (inv[i][i] * inv[j][j]).sqrt()).abs());
                }
            }
        }
        Ok((se, corr.is_finite().then_some(corr)))
    }
}

/// What a fit's uncertainty takes from its regression steps (see [`Joint::uncertainty`]).
struct Smoothed {
    /// The mean of their models' slopes: a column per effect (per scale).
    jacobian: Vec<Vec<f64>>,
    /// The variance of the points they reached, per effect, in scales².
    spread2: Vec<f64>,
}

/// Fits `effects` jointly from the best of `starts` on the training data (see the module
/// docs; all of them evaluated in one batch): the whole fit, its folds, its uncertainty, and
/// its training and held-out gaps.
#[allow(clippy::too_many_arguments)]
pub(super) fn fit_joint(
    batched: &Batched,
    plan: &FitPlan,
    train: &TrainSet,
    held: &HeldOutSet,
    opts: &SelectOptions,
    effects: &[String],
    starts: &[Vec<f64>],
    from: &str,
) -> Result<JointFit, GapError> {
    let before = batched.runs();
    let all = batched.parameters();
    let specs: Vec<ParamSpec> = effects
        .iter()
        .map(|e| {
            all.iter()
                .find(|s| s.name == *e)
                .cloned()
                .ok_or_else(|| GapError::Fit(format!("the bench has no parameter `{e}`")))
        })
        .collect::<Result<_, _>>()?;
    let mut j = Joint {
        batched,
        train,
        opts,
        specs,
        seen: HashMap::new(),
    };
    let groups = j.groups(&|_| true);
    let starts: Vec<Vec<f64>> = starts.iter().map(|v| j.clamp(v)).collect();
    j.eval(&starts, &groups)?;
    let start = starts
        .iter()
        .min_by(|a, b| j.score(a, &groups).total_cmp(&j.score(b, &groups)))
        .ok_or_else(|| GapError::Fit(format!("no start for {}", effects.join(" + "))))?
        .clone();
    let mut p = j.fit(&start, &|_| true, opts.joint_iterations)?;
    let mut smoothed = None;
    if effects.len() >= 3 {
        (p, smoothed) = j.regression_steps(&p, &groups, opts.joint_regression_steps)?;
    }
    let (train_chi2, series) = j.parts(&p, &groups);
    let scored_series = super::telemetry::scores_series(train, opts);
    let cv_chi2 = if plan.cv() {
        let mut total = 0.0;
        for f in &plan.folds {
            let by = plan.by_experiment;
            let q = j.fit(&p, &|g| fold_of(g, by) != *f, opts.joint_fold_iterations)?;
            let out = j.groups(&|g| fold_of(g, by) == *f);
            j.eval(std::slice::from_ref(&q), &out)?;
            let (c, s) = j.parts(&q, &out);
            total += c + s;
        }
        Some(total)
    } else {
        None
    };
    let (std_err, max_correlation) = j.uncertainty(&p, smoothed.as_ref())?;
    let determined = j
        .specs
        .iter()
        .zip(&p)
        .zip(&std_err)
        .all(|((s, v), se)| se.is_some_and(|se| (v - s.neutral).abs() > 2.0 * se));
    let params = j.params(&p);
    let (heldout, train_gap) = batched.eval(|m| -> Result<(Gap, Gap), GapError> {
        let sc = Scorer::new(m, train, &opts.fit);
        Ok((
            sc.gap(&params, held.groups())?,
            sc.gap(&params, train.groups())?,
        ))
    })?;
    Ok(JointFit {
        effects: effects.to_vec(),
        values: p,
        std_err,
        max_correlation,
        start: from.to_owned(),
        train_chi2,
        series_chi2: scored_series.then_some(series),
        cv_chi2,
        train_gap,
        heldout,
        bench_runs: batched.runs() - before,
        determined,
    })
}

/// The standard error of one effect's fitted `value` (see [`Joint::uncertainty`]): one
/// prediction beside the value's own.
pub(super) fn std_err_of(
    batched: &Batched,
    train: &TrainSet,
    opts: &SelectOptions,
    effect: &str,
    value: f64,
) -> Result<Option<f64>, GapError> {
    let Some(spec) = batched.parameters().into_iter().find(|s| s.name == effect) else {
        return Ok(None);
    };
    let mut j = Joint {
        batched,
        train,
        opts,
        specs: vec![spec],
        seen: HashMap::new(),
    };
    j.eval(&[vec![value]], &j.groups(&|_| true))?;
    Ok(j.uncertainty(&[value], None)?.0[0])
}

/// Whether `larger` earns its place over a model of score `base_train` (training) and
/// `base_score` (cross-validated, or training with one fold): a marked improvement on the
/// training data, a marked one on the left-out data, every value determined.
pub(super) fn earns_place(larger: &JointFit, base_train: f64, base_score: f64) -> bool {
    larger.determined
        && super::choose::marked(base_train, larger.train_score())
        && base_score - larger.score() >= MARKED_CHI2
}
