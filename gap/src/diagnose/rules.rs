//! The diagnosis's rules of evidence, each a number or a yes/no from fits already made: when
//! every parameter of a fit is determined, when a joint fit is degenerate, when a candidate
//! improves markedly on what a stage left, what an added effect gains, and how a probe
//! separates two fits. The module docs of [`crate::diagnose`] state them in words.

use crate::fit::{CandidateFit, Evaluator};

/// BIC difference that counts as strong evidence for the lower (Kass & Raftery's "strong").
pub(super) const STRONG_BIC: f64 = 6.0;
/// BIC difference below which neither of two candidates is preferred.
pub(super) const TIE_BIC: f64 = 2.0;

/// Whether every parameter of a fit is determined: a finite condition number below 10⁶ and
/// every value more than two standard errors from neutral.
pub(super) fn separable(ev: &Evaluator, f: &CandidateFit) -> bool {
    f.condition_number.is_finite()
        && f.condition_number < 1e6
        && f.estimates.iter().all(|e| {
            let neutral = ev.spec(&e.name).map_or(0.0, |s| s.neutral);
            e.std_err
                .is_some_and(|se| (e.value - neutral).abs() > 2.0 * se)
        })
}

/// Whether a joint fit is degenerate: singular, or a condition number above 10⁸.
pub(super) fn degenerate(f: &CandidateFit) -> bool {
    !f.condition_number.is_finite() || f.condition_number > 1e8 || f.correlation.is_none()
}

/// Whether `f` improves markedly on a stage that left `chi_s` of χ²: it removes at least 6
/// and at least a quarter of it. Only such candidates are compared for being alike.
pub(super) fn improves(chi_s: f64, f: &CandidateFit) -> bool {
    let gain = chi_s - f.chi2;
    gain >= 6.0 && gain >= 0.25 * chi_s
}

/// What `larger` (`smaller` with one effect more) gains over `smaller` in BIC, with its χ²
/// gain divided by `larger`'s χ²/dof when that exceeds 1 (quasi-likelihood: the weights
/// then understate what the model misses, and a χ² gain is worth that much less).
pub(super) fn extension_gain(smaller: &CandidateFit, larger: &CandidateFit) -> f64 {
    let dof = larger.n_residuals.saturating_sub(larger.k).max(1) as f64;
    let c_hat = (larger.chi2 / dof).max(1.0);
    let penalty = (larger.bic - larger.chi2) - (smaller.bic - smaller.chi2);
    (smaller.chi2 - larger.chi2) / c_hat - penalty
}

/// Whether an effect earns its place in `f`: every parameter stays determined and it gains
/// more than [`STRONG_BIC`].
pub(super) fn worth_adding(ev: &Evaluator, f: &CandidateFit, gain: f64) -> bool {
    separable(ev, f) && gain > STRONG_BIC
}

/// How well a probe separates two fits whose predictions for it differ by `d_cm` in the
/// end point and `dth_deg` in the end heading: the larger, a degree of end heading counting
/// as 2 cm of end point.
pub(super) fn separation_score(d_cm: f64, dth_deg: f64) -> f64 {
    d_cm.max(dth_deg * 2.0)
}

#[cfg(test)]
mod tests;
