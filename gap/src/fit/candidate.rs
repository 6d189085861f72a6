//! A candidate's fit: its estimates and criteria, fitted from several starts, its grid
//! start, and its bootstrap.

use nalgebra::DMatrix;
use serde::Serialize;

use super::lm::{covariance, levenberg_marquardt, sq, Covariance, LmOut};
use super::{hash, Evaluator, FitOptions, Gap};
use crate::data::{Group, TrainSet};
use crate::effects::{EffectParams, ParamSpec};
use crate::rng::Rng;
use crate::GapError;

/// One fitted parameter.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Estimate {
    /// Effect name.
    pub name: String,
    /// Symbol.
    pub symbol: String,
    /// Unit.
    pub unit: String,
    /// Fitted value.
    pub value: f64,
    /// Standard error from the Jacobian (covariance inflated by χ²/dof when above 1);
    /// `None` when the fit's Jacobian is singular.
    pub std_err: Option<f64>,
    /// Standard deviation over bootstrap refits (runs resampled within each group), when
    /// computed.
    pub bootstrap_sd: Option<f64>,
    /// Whether the value ended at a bound.
    pub at_bound: bool,
}

/// A fitted set of effects.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CandidateFit {
    /// The effects fitted (empty: the model as it is).
    pub effects: Vec<String>,
    /// Their values.
    pub estimates: Vec<Estimate>,
    /// Number of parameters.
    pub k: usize,
    /// Number of residuals.
    pub n_residuals: usize,
    /// Σ r² on the training data.
    pub chi2: f64,
    /// χ² + 2k.
    pub aic: f64,
    /// χ² + k ln N.
    pub bic: f64,
    /// Share of the training χ² of the model as it is that this fit removes.
    pub share_explained: f64,
    /// Training gap.
    pub train: Gap,
    /// Held-out gap (filled by the diagnosis).
    pub heldout: Option<Gap>,
    /// Parameter correlation matrix (k × k), when the Jacobian is not singular.
    pub correlation: Option<Vec<Vec<f64>>>,
    /// Condition number of the scaled Jacobian (∞ when singular).
    pub condition_number: f64,
    /// Iterations of Levenberg-Marquardt.
    pub iterations: usize,
    /// Whether it converged.
    pub converged: bool,
    /// The fitted values as parameters.
    #[serde(skip)]
    pub params: EffectParams,
}

impl CandidateFit {
    /// Display label: effect names joined by `+`, or `(model as is)`.
    pub fn label(&self) -> String {
        if self.effects.is_empty() {
            "(model as is)".to_owned()
        } else {
            self.effects.join(" + ")
        }
    }

    /// The estimate of `name`.
    pub fn estimate(&self, name: &str) -> Option<&Estimate> {
        self.estimates.iter().find(|e| e.name == name)
    }

    /// Largest |correlation| between two parameters (0 for one parameter).
    pub fn max_correlation(&self) -> Option<f64> {
        let c = self.correlation.as_ref()?;
        let mut m: f64 = 0.0;
        for (i, row) in c.iter().enumerate() {
            for (j, v) in row.iter().enumerate() {
                if i != j {
                    m = m.max(v.abs());
                }
            }
        }
        Some(m)
    }
}

/// Fits `effects` to the training groups from each of `starts` (values in parameter units)
/// and keeps the best.
pub(crate) fn fit_candidate(
    ev: &Evaluator,
    train: &[Group],
    effects: &[String],
    starts: &[Vec<f64>],
    baseline_chi2: f64,
) -> Result<CandidateFit, GapError> {
    let specs: Vec<&ParamSpec> = effects
        .iter()
        .map(|e| ev.known_spec(e))
        .collect::<Result<_, _>>()?;
    let to_params = |u: &[f64]| {
        let mut p = EffectParams::new();
        for (s, v) in specs.iter().zip(u) {
            p.set(&s.name, (s.neutral + v * s.scale).clamp(s.lower, s.upper));
        }
        p
    };
    let lo: Vec<f64> = specs
        .iter()
        .map(|s| (s.lower - s.neutral) / s.scale)
        .collect();
    let hi: Vec<f64> = specs
        .iter()
        .map(|s| (s.upper - s.neutral) / s.scale)
        .collect();
    let f = |u: &[f64]| ev.residuals(&to_params(u), train);
    let mut best: Option<LmOut> = None;
    if effects.is_empty() {
        let r = f(&[])?;
        best = Some(LmOut {
            x: vec![],
            chi2: sq(&r),
            jac: DMatrix::zeros(r.len(), 0),
            iterations: 0,
            converged: true,
        });
    }
    for start in starts {
        let u0: Vec<f64> = specs
            .iter()
            .zip(start)
            .map(|(s, v)| (v - s.neutral) / s.scale)
            .collect();
        let out = levenberg_marquardt(&f, &u0, &lo, &hi, ev.opts.max_iterations)?;
        if best.as_ref().is_none_or(|b| out.chi2 < b.chi2) {
            best = Some(out);
        }
    }
    let best = best.ok_or_else(|| GapError::Fit("no start values".into()))?;
    let n = best.jac.nrows();
    let k = effects.len();
    let Covariance {
        std_err: se,
        correlation: corr,
        condition: cond,
    } = if k == 0 {
        Covariance {
            std_err: Some(vec![]),
            correlation: Some(vec![]),
            condition: 1.0,
        }
    } else {
        covariance(&best.jac, best.chi2)
    };
    let params = to_params(&best.x);
    let estimates = specs
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let v = params.get_or(&s.name, s.neutral);
            Estimate {
                name: s.name.clone(),
                symbol: s.symbol.clone(),
                unit: s.unit.clone(),
                value: v,
                std_err: se.as_ref().map(|se| se[i] * s.scale),
                bootstrap_sd: None,
                at_bound: (v - s.lower).abs() < 1e-9 * s.scale.max(1e-12)
                    || (v - s.upper).abs() < 1e-9 * s.scale.max(1e-12),
            }
        })
        .collect();
    let train_gap = ev.gap(&params, train)?;
    Ok(CandidateFit {
        effects: effects.to_vec(),
        estimates,
        k,
        n_residuals: n,
        chi2: best.chi2,
        aic: best.chi2 + 2.0 * k as f64,
        bic: best.chi2 + k as f64 * (n.max(1) as f64).ln(),
        share_explained: if baseline_chi2 > 0.0 {
            1.0 - best.chi2 / baseline_chi2
        } else {
            0.0
        },
        train: train_gap,
        heldout: None,
        correlation: corr,
        condition_number: cond,
        iterations: best.iterations,
        converged: best.converged,
        params,
    })
}

/// Start values of a single-effect fit: the best point of a bounded grid (and the neutral
/// value) on the training χ².
pub(crate) fn grid_start(
    ev: &Evaluator,
    train: &[Group],
    spec: &ParamSpec,
) -> Result<Vec<Vec<f64>>, GapError> {
    // The grid only finds a start: a stochastic parameter's spread is estimated from an
    // eighth of the runs there.
    let coarse = Evaluator {
        model: ev.model,
        specs: ev.specs.clone(),
        opts: FitOptions {
            prediction_runs: (ev.opts.prediction_runs / 8).max(32),
            ..ev.opts.clone()
        },
        weights: ev.weights.clone(),
    };
    let ev = &coarse;
    let n = ev.opts.grid_points.max(3);
    let mut best = (f64::INFINITY, spec.neutral);
    for i in 0..n {
        let v = spec.lower + (spec.upper - spec.lower) * i as f64 / (n - 1) as f64;
        let p = EffectParams::new().with(&spec.name, v);
        let c = sq(&ev.residuals(&p, train)?);
        if c < best.0 {
            best = (c, v);
        }
    }
    let mut starts = vec![vec![best.1]];
    // A stochastic parameter at its neutral value has no derivative; start inside.
    let inside = if spec.stochastic() || !spec.two_sided() {
        (spec.neutral + 0.5 * spec.scale).clamp(spec.lower, spec.upper)
    } else {
        spec.neutral
    };
    starts.push(vec![inside]);
    Ok(starts)
}

/// Standard deviations of the estimates of `fit` over `b` bootstrap resamples of the runs.
pub(crate) fn bootstrap(
    ev: &Evaluator,
    train: &TrainSet,
    fit: &CandidateFit,
    b: usize,
    seed: u64,
) -> Result<Vec<Option<f64>>, GapError> {
    let k = fit.effects.len();
    if k == 0 || b < 2 {
        return Ok(vec![None; k]);
    }
    let mut rng = Rng::new(seed ^ hash(&fit.label()));
    let start: Vec<f64> = fit.estimates.iter().map(|e| e.value).collect();
    let mut samples: Vec<Vec<f64>> = vec![Vec::with_capacity(b); k];
    for _ in 0..b {
        let resampled = train.resampled(&mut rng);
        let sub = fit_candidate(
            ev,
            resampled.groups(),
            &fit.effects,
            std::slice::from_ref(&start),
            0.0,
        )?;
        for (i, e) in sub.estimates.iter().enumerate() {
            samples[i].push(e.value);
        }
    }
    Ok(samples
        .into_iter()
        .map(|s| {
            let m = s.iter().sum::<f64>() / s.len() as f64;
            Some((s.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (s.len() - 1) as f64).sqrt())
        })
        .collect())
}
