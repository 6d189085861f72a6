//! Fitting effect parameters to training groups: the residuals, Levenberg-Marquardt with
//! bounds, the gap measures, and information criteria.
//!
//! # Residuals
//!
//! For every training group and every recorded axis (x, y):
//!
//! * the centroid residual `(x̄_real − x̄_model) / se`, `se² = s²/n + se²_model + floor²`, and
//! * the scatter residual `(s_real − c4(n)·s_model) / se_s`, `se_s² = s²/(2(n − 1)) + floor²`
//!   (c4(n) = E\[s\]/σ for n Gaussian runs: 0.94 for five runs),
//!
//! where `s²` is the within-group variance pooled over the training groups of the same test
//! kind (five runs give a poor variance each), `n` the group's runs and `floor` a small
//! length (0.1 cm by default) so that noise-free data do not divide by zero. The model's
//! centroid comes from [`FitOptions::centroid_runs`] runs of [`crate::Model::predict`] (one
//! by default, `se_model` 0; with k of them their mean, and `se_model` their spread over
//! √k) with the stochastic effects off
//! (a stochastic effect is zero-mean by definition: its second-order pull on the centroid is
//! neglected, and Monte Carlo noise cannot tie it to the centroids); its spread from
//! [`FitOptions::prediction_runs`] runs with everything on (common random numbers: the same
//! seed for every evaluation). Every candidate is
//! scored on the same residuals, with the same weights, so their χ² compare.
//!
//! # Criteria
//!
//! With Gaussian errors of known spread, −2 ln L = χ² + const, so AIC = χ² + 2k and
//! BIC = χ² + k ln N (N residuals, k parameters). The weights come from the data, so both
//! are approximate; they rank candidates fitted to the same data.
//!
//! # Gap measures (cm, never weighted)
//!
//! Per group: the *systematic* gap `|c̄_real − c̄_model|` (centroid distance, over the
//! recorded axes) and the *scatter* gap `√((s_x,real − c4·s_x,model)² + (s_y,real − c4·s_y,model)²)`.
//! Over groups: the root mean square of each, and the *total* `√(systematic² + scatter²)`,
//! which is the 2-Wasserstein distance between per-axis Gaussian fits of the two clouds
//! of end points. Even a perfect model leaves some gap, because n runs only estimate a
//! centroid to `s/√n` and a spread to `s/√(2(n−1))`; the *excess* gaps subtract these
//! sampling variances (and the model's, for m predicted runs) before the root, and measure
//! what the model itself misses.

use serde::{Deserialize, Serialize};

use crate::data::{Group, Stats, TrainSet};
use crate::effects::{EffectParams, ParamSpec};
use crate::model::{Model, TestKind};
use crate::GapError;

mod candidate;
mod lm;

pub(crate) use candidate::{bootstrap, fit_candidate, grid_start};
pub use candidate::{CandidateFit, Estimate};
#[cfg(test)]
use lm::levenberg_marquardt;

/// Options of the fits.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FitOptions {
    /// Runs predicted per group when a stochastic parameter is fitted.
    pub prediction_runs: usize,
    /// Seed of the model's predictions and of the bootstrap.
    pub seed: u64,
    /// Levenberg-Marquardt iterations at most.
    pub max_iterations: usize,
    /// Smallest standard error of a centroid or spread, cm.
    pub floor_cm: f64,
    /// Points of the bounded 1-D grid that starts each single-effect fit.
    pub grid_points: usize,
    /// Bootstrap resamples over runs for the uncertainty of the leading candidates.
    pub bootstrap: usize,
    /// Fit pairs of effects too.
    pub pairs: bool,
    /// Largest number of effects the winner may grow to by forward selection beyond the
    /// best pair (each added effect must lower the BIC by more than 6 and stay determined).
    pub max_effects: usize,
    /// Runs a centroid is predicted from (see the module docs): 1 for a model whose run is
    /// a smooth function of its parameters; more for one whose runs differ by what no
    /// parameter holds (the bench's start phase), so that the centroid is their mean and
    /// its own standard error weighs the residuals.
    #[serde(default = "one")]
    pub centroid_runs: usize,
}

fn one() -> usize {
    1
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            prediction_runs: 512,
            seed: 0x6A70_2024,
            max_iterations: 100,
            floor_cm: 0.1,
            grid_points: 41,
            bootstrap: 40,
            pairs: true,
            max_effects: 4,
            centroid_runs: 1,
        }
    }
}

/// A model's centroid and spread for one group.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Predicted {
    /// Mean x, cm.
    pub mean_x: f64,
    /// Mean y, cm.
    pub mean_y: f64,
    /// Standard deviation of x between runs, cm.
    pub sd_x: f64,
    /// Standard deviation of y, cm.
    pub sd_y: f64,
    /// Mean heading error, degrees.
    pub mean_theta_deg: f64,
    /// Standard error of the predicted centroid's x and y, cm: 0 when it is one run
    /// ([`FitOptions::centroid_runs`]).
    #[serde(default)]
    pub se_x: f64,
    #[serde(default)]
    pub se_y: f64,
}

/// The gap of one group.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GroupGap {
    /// The group (`experiment/test`).
    pub group: String,
    /// What was measured.
    pub observed: Stats,
    /// What the model predicts.
    pub predicted: Predicted,
    /// Real − model centroid, x, cm.
    pub residual_x_cm: f64,
    /// Real − model centroid, y, cm (when y was recorded).
    pub residual_y_cm: Option<f64>,
    /// Centroid distance, cm.
    pub systematic_cm: f64,
    /// Spread mismatch, cm.
    pub scatter_cm: f64,
    /// Centroid distance beyond what the sampling error of the centroids explains,
    /// `√max(0, |Δ|² − Σ_axes (s²_real/n + s²_model/m))`, cm.
    pub systematic_excess_cm: f64,
    /// Spread mismatch beyond the sampling error of the spreads,
    /// `√max(0, Σ_axes ((s_real − s_model)² − s²_real/(2(n−1)) − s²_model/(2(m−1))))`, cm.
    pub scatter_excess_cm: f64,
}

/// The gap over a set of groups.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Gap {
    /// RMS over groups of the centroid distance, cm.
    pub systematic_cm: f64,
    /// RMS over groups of the spread mismatch, cm.
    pub scatter_cm: f64,
    /// √(systematic² + scatter²), cm.
    pub total_cm: f64,
    /// RMS over groups of the systematic gap beyond sampling error, cm.
    pub systematic_excess_cm: f64,
    /// RMS over groups of the scatter gap beyond sampling error, cm.
    pub scatter_excess_cm: f64,
    /// Per group.
    pub groups: Vec<GroupGap>,
}

impl Gap {
    /// The fraction of `before` this gap removed, on the total (1 − after/before).
    pub fn reduction_from(&self, before: &Gap) -> f64 {
        reduction(before.total_cm, self.total_cm)
    }
}

pub(crate) fn reduction(before: f64, after: f64) -> f64 {
    if before > 0.0 {
        1.0 - after / before
    } else {
        0.0
    }
}

/// Pooled within-group variances per test kind (x, y), cm².
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Weights {
    pooled: Vec<(TestKind, f64, Option<f64>)>,
    floor_cm: f64,
}

impl Weights {
    /// Pooled over `groups`.
    pub fn from_groups(groups: &[Group], floor_cm: f64) -> Weights {
        let mut pooled = Vec::new();
        for kind in TestKind::ALL {
            let (mut sx, mut sy, mut dof, mut dof_y) = (0.0, 0.0, 0.0, 0.0);
            for g in groups.iter().filter(|g| g.id.test == kind) {
                let st = g.stats();
                if st.n < 2 {
                    continue;
                }
                let d = (st.n - 1) as f64;
                sx += d * st.sd_x.powi(2);
                dof += d;
                if let Some(s) = st.sd_y {
                    sy += d * s.powi(2);
                    dof_y += d;
                }
            }
            if dof > 0.0 {
                pooled.push((kind, sx / dof, (dof_y > 0.0).then(|| sy / dof_y)));
            }
        }
        Weights { pooled, floor_cm }
    }

    pub(crate) fn var(&self, kind: TestKind) -> (f64, f64) {
        self.pooled
            .iter()
            .find(|p| p.0 == kind)
            .map(|p| (p.1, p.2.unwrap_or(p.1)))
            .unwrap_or((0.0, 0.0))
    }
}

/// Computes predictions, residuals and gaps of a model on groups.
pub(crate) struct Evaluator<'a> {
    pub model: &'a dyn Model,
    pub specs: Vec<ParamSpec>,
    pub opts: FitOptions,
    pub weights: Weights,
}

impl<'a> Evaluator<'a> {
    pub fn new(model: &'a dyn Model, train: &TrainSet, opts: &FitOptions) -> Self {
        Evaluator {
            model,
            specs: model.parameters(),
            opts: opts.clone(),
            weights: Weights::from_groups(train.groups(), opts.floor_cm),
        }
    }

    pub fn spec(&self, name: &str) -> Option<&ParamSpec> {
        self.specs.iter().find(|s| s.name == name)
    }

    /// The parameter `name` of the model, or the error that names the ones it has.
    pub fn known_spec(&self, name: &str) -> Result<&ParamSpec, GapError> {
        Ok(crate::model::known_spec(
            &self.model.name(),
            &self.specs,
            name,
        )?)
    }

    fn stochastic(&self, params: &EffectParams) -> bool {
        params.iter().any(|(n, v)| {
            self.spec(n)
                .is_some_and(|s| s.stochastic() && v != s.neutral)
        })
    }

    /// The model's centroid and spread for `group` under `params`.
    pub fn predict(&self, params: &EffectParams, group: &Group) -> Result<Predicted, GapError> {
        self.predict_experiment(params, &group.experiment, &group.id.to_string())
    }

    /// The runs the centroid of `experiment` is predicted from
    /// ([`FitOptions::centroid_runs`]): its seed from `tag`.
    pub fn centroid_experiment(
        &self,
        experiment: &crate::model::Experiment,
        tag: &str,
    ) -> crate::model::Experiment {
        let mut exp = experiment.clone();
        exp.seed = self.opts.seed ^ hash(tag);
        exp.runs = self.opts.centroid_runs.max(1);
        exp
    }

    /// The model's centroid and spread for `experiment`; `tag` seeds its randomness.
    pub fn predict_experiment(
        &self,
        params: &EffectParams,
        experiment: &crate::model::Experiment,
        tag: &str,
    ) -> Result<Predicted, GapError> {
        let mut exp = self.centroid_experiment(experiment, tag);
        // The centroid from one run with the stochastic effects off (they are zero-mean by
        // definition), so that the Monte Carlo noise of the spread's runs cannot leak into
        // the centroid and tie a stochastic parameter to it.
        let mut systematic = EffectParams::new();
        for (n, v) in params.iter() {
            if self.spec(n).is_none_or(|s| !s.stochastic()) {
                systematic.set(n, v);
            }
        }
        let centre = self.model.predict(&systematic, &exp)?;
        if centre.is_empty() {
            return Err(GapError::Model(crate::ModelError::InvalidExperiment(
                "the model returned no runs".into(),
            )));
        }
        let k = centre.len();
        let (cx, cy): (Vec<f64>, Vec<f64>) = centre.iter().map(|r| (r.x_cm, r.y_cm)).unzip();
        let middle = Stats::of(&cx, Some(&cy));
        // One run is its own centroid, bit for bit (no mean taken).
        let (mean_x, mean_y, mean_theta_deg) = if k == 1 {
            (cx[0], cy[0], centre[0].theta_rad.to_degrees())
        } else {
            let theta = centre.iter().map(|r| r.theta_rad).sum::<f64>() / k as f64;
            (
                middle.mean_x,
                middle.mean_y.unwrap_or(0.0),
                theta.to_degrees(),
            )
        };
        let se = |sd: f64| if k >= 2 { sd / (k as f64).sqrt() } else { 0.0 };
        let (mut sd_x, mut sd_y) = (0.0, 0.0);
        if self.stochastic(params) {
            exp.runs = self.opts.prediction_runs.max(2);
            let runs = self.model.predict(params, &exp)?;
            let xs: Vec<f64> = runs.iter().map(|r| r.x_cm).collect();
            let ys: Vec<f64> = runs.iter().map(|r| r.y_cm).collect();
            let st = Stats::of(&xs, Some(&ys));
            sd_x = st.sd_x;
            sd_y = st.sd_y.unwrap_or(0.0);
        }
        Ok(Predicted {
            mean_x,
            mean_y,
            sd_x,
            sd_y,
            mean_theta_deg,
            se_x: se(middle.sd_x),
            se_y: se(middle.sd_y.unwrap_or(0.0)),
        })
    }

    /// The weighted centroid residuals of a group of `test` with stats `st` against the
    /// prediction `p` (x, and y when recorded): real − model over the centroid's standard
    /// error, the real one's (pooled scatter over √n), the model's own (0 for a centroid of
    /// one run) and the floor.
    pub(crate) fn centroid_part(&self, p: &Predicted, st: &Stats, test: TestKind) -> Vec<f64> {
        let floor2 = self.opts.floor_cm.powi(2);
        let (vx, vy) = self.weights.var(test);
        let n = st.n as f64;
        let mut r = vec![(st.mean_x - p.mean_x) / (vx / n + p.se_x.powi(2) + floor2).sqrt()];
        if let Some(my) = st.mean_y {
            r.push((my - p.mean_y) / (vy / n + p.se_y.powi(2) + floor2).sqrt());
        }
        r
    }

    /// Weighted residuals (see the module docs).
    pub fn residuals(&self, params: &EffectParams, groups: &[Group]) -> Result<Vec<f64>, GapError> {
        let floor2 = self.opts.floor_cm.powi(2);
        let mut r = Vec::with_capacity(groups.len() * 4);
        for g in groups {
            let p = self.predict(params, g)?;
            let st = g.stats();
            let (vx, vy) = self.weights.var(g.id.test);
            let n = st.n as f64;
            r.extend(self.centroid_part(&p, &st, g.id.test));
            if st.n >= 2 {
                let d = 2.0 * (n - 1.0);
                let c4 = c4(st.n);
                r.push((st.sd_x - c4 * p.sd_x) / (vx / d + floor2).sqrt());
                if let Some(sy) = st.sd_y {
                    r.push((sy - c4 * p.sd_y) / (vy / d + floor2).sqrt());
                }
            }
        }
        Ok(r)
    }

    /// The gap in cm.
    pub fn gap(&self, params: &EffectParams, groups: &[Group]) -> Result<Gap, GapError> {
        let m = if self.stochastic(params) {
            self.opts.prediction_runs.max(2) as f64
        } else {
            f64::INFINITY
        };
        let mut out = Vec::with_capacity(groups.len());
        for g in groups {
            let p = self.predict(params, g)?;
            let st = g.stats();
            let n = st.n as f64;
            let rx = st.mean_x - p.mean_x;
            let ry = st.mean_y.map(|y| y - p.mean_y);
            let c4 = c4(st.n);
            let scatter = ((st.sd_x - c4 * p.sd_x).powi(2)
                + st.sd_y.map_or(0.0, |s| (s - c4 * p.sd_y).powi(2)))
            .sqrt();
            // Sampling variances of the centroids and of the spreads, per axis.
            let axes: Vec<(f64, f64)> = std::iter::once((st.sd_x, p.sd_x))
                .chain(st.sd_y.map(|s| (s, p.sd_y)))
                .collect();
            let se_mean: f64 = axes
                .iter()
                .map(|(so, sp)| so * so / n + sp * sp / m)
                .sum::<f64>()
                + p.se_x.powi(2)
                + st.sd_y.map_or(0.0, |_| p.se_y.powi(2));
            let se_sd: f64 = if st.n >= 2 {
                axes.iter()
                    .map(|(so, sp)| so * so / (2.0 * (n - 1.0)) + sp * sp / (2.0 * (m - 1.0)))
                    .sum()
            } else {
                0.0
            };
            let sys2 = rx * rx + ry.map_or(0.0, |y| y * y);
            out.push(GroupGap {
                systematic_excess_cm: (sys2 - se_mean).max(0.0).sqrt(),
                scatter_excess_cm: if st.n >= 2 {
                    (scatter * scatter - se_sd).max(0.0).sqrt()
                } else {
                    0.0
                },
                group: g.id.to_string(),
                observed: st,
                predicted: p,
                residual_x_cm: rx,
                residual_y_cm: ry,
                systematic_cm: rx.hypot(ry.unwrap_or(0.0)),
                scatter_cm: if st.n >= 2 { scatter } else { 0.0 },
            });
        }
        let rms = |f: &dyn Fn(&GroupGap) -> f64| {
            (out.iter().map(|g| f(g).powi(2)).sum::<f64>() / out.len().max(1) as f64).sqrt()
        };
        let systematic_cm = rms(&|g| g.systematic_cm);
        let scatter_cm = rms(&|g| g.scatter_cm);
        Ok(Gap {
            systematic_cm,
            scatter_cm,
            total_cm: systematic_cm.hypot(scatter_cm),
            systematic_excess_cm: rms(&|g| g.systematic_excess_cm),
            scatter_excess_cm: rms(&|g| g.scatter_excess_cm),
            groups: out,
        })
    }
}

/// E\[s\]/σ for the sample standard deviation of n Gaussian values (c4; 1 for n < 2).
pub fn c4(n: usize) -> f64 {
    if n < 2 {
        return 1.0;
    }
    let n = n as f64;
    (2.0 / (n - 1.0)).sqrt()
        * (crate::stats::ln_gamma(n / 2.0) - crate::stats::ln_gamma((n - 1.0) / 2.0)).exp()
}

/// FNV-1a, for seeds from names.
pub(crate) fn hash(s: &str) -> u64 {
    s.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

#[cfg(test)]
mod tests;
