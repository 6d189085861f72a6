//! The diagnosis: where the gap lies, which effect explains it, how far it shrinks on
//! held-out data.
//!
//! 1. **Where** ([`Where`]): the residual real − model (the model as it is) of every group,
//!    training and held out, with its scatter, and each experiment's residual decomposed
//!    into corner error α, leg curvature β, scale and an unexplained remainder
//!    ([`crate::breakdown`]).
//! 2. **Which** ([`Which`]): every effect the model implements is fitted alone to the
//!    training groups (a bounded grid, then Levenberg-Marquardt), and every pair (started from
//!    the singles' values). Candidates are ranked by BIC on the training data and, separately,
//!    by their held-out gap. The *winner* is chosen on the training data only (so the
//!    held-out gap that follows is an honest estimate): the best single effect by BIC, or the
//!    best pair when its BIC is lower by more than 6 ("strong" evidence) and both of its
//!    parameters are determined (condition number below 10⁶, each more than two standard
//!    errors from neutral); from a winning pair, forward selection adds further effects while
//!    each lowers the BIC by more than 6 (its χ² gain divided by the larger model's χ²/dof
//!    when that exceeds 1, as in quasi-likelihood criteria) and all stay determined; then a
//!    stochastic effect is added on the plain BIC when it earns its place (it only moves the
//!    scatter residuals). A step that lowers the training BIC but raises the held-out gap is
//!    noted. Uncertainties: the Jacobian's standard errors and a bootstrap
//!    over runs.
//!
//!    **Indistinguishable effects.** Given a set S of effects already in (none, or the best
//!    single), two further effects A and B are reported as indistinguishable when both
//!    improve the fit markedly (χ² falls by at least 6 and 25 %) and the fitted S + A and
//!    S + B predict the training data alike (their weighted residual vectors differ by less
//!    than 2 standard errors in total), or when the joint fit of A and B is degenerate
//!    (singular, or a condition number above 10⁸). A high correlation alone is not enough:
//!    two correlated parameters are still told apart when the data pin both down. A *tie*
//!    (both improve, their predictions differ, but their BICs are within 2) is reported too:
//!    the data then prefer neither, and both are absorbing something the model lacks. The diagnosis then looks for a test that
//!    separates them: it predicts a menu of variations of the training tests (other test
//!    kinds, corner angles, leg lengths, firmware wheelbase) with both fits and names the one
//!    where their end points (or end headings) differ most; and it adds what is known to
//!    separate the pair physically.
//! 3. **Shrink** ([`Shrink`]): the held-out gap of the model as it is and with the winner.

use serde::Serialize;

use crate::breakdown::{decompose_all, Decomposition};
use crate::data::{Group, HeldOutSet, TrainSet};
use crate::effects::{EffectParams, ParamSpec, Unsupported};
use crate::fit::{
    bootstrap, fit_candidate, grid_start, reduction, CandidateFit, Evaluator, FitOptions, Gap,
};
use crate::model::Model;
use crate::series::{MotorHoldout, SeriesGap};
use crate::GapError;
use rules::{degenerate, extension_gain, improves, separable, worth_adding, STRONG_BIC, TIE_BIC};

mod manifests;
mod probe;
mod rules;
mod steps;

pub use manifests::diagnose_manifests;
use probe::find_separating_test;
#[cfg(test)]
use probe::probes;
pub use probe::separating_measurement;
use steps::{extension_start, heldout_worse_notes, pair_starts, path_pairs};

/// Options of [`diagnose`].
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct DiagnoseOptions {
    /// Fit options.
    pub fit: FitOptions,
    /// The effects to try (`None`: every parameter of the model).
    pub candidates: Option<Vec<String>>,
}

/// A candidate with its ranks.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RankedFit {
    /// The fit.
    pub fit: CandidateFit,
    /// Rank by BIC among its kind (singles or pairs), 1 = best.
    pub rank_bic: usize,
    /// Rank by held-out total gap among its kind, 1 = best.
    pub rank_heldout: usize,
    /// 1 − held-out total gap / the model as it is.
    pub heldout_reduction: f64,
    /// 1 − held-out systematic gap / the model as it is.
    pub heldout_systematic_reduction: f64,
}

/// Effects the data cannot tell apart.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Confusion {
    /// The effects.
    pub effects: Vec<String>,
    /// Effects already in the model when they were compared.
    pub given: Vec<String>,
    /// Why they are reported.
    pub evidence: Vec<String>,
    /// The probe test where the two fits differ most, and by how much (`None`: no probe
    /// separates them by more than a centimetre or half a degree).
    pub separating_test: Option<String>,
    /// What measurement would separate them.
    pub suggestion: String,
}

/// Answer 1.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Where {
    /// Residual of the model as it is on the training groups.
    pub train: Gap,
    /// On the held-out groups.
    pub heldout: Gap,
    /// Per experiment, of the residual against the model as it is.
    pub decomposition: Vec<Decomposition>,
    /// Per experiment, of the residual left by the winner (what the fitted effects do not
    /// explain).
    pub decomposition_after_winner: Vec<Decomposition>,
}

/// Answer 2.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Which {
    /// The model as it is.
    pub baseline: CandidateFit,
    /// Single effects, best BIC first.
    pub singles: Vec<RankedFit>,
    /// Pairs, best BIC first.
    pub pairs: Vec<RankedFit>,
    /// Larger sets from forward selection after the best pair, in the order they were
    /// accepted (empty when no third effect earns its place).
    pub extended: Vec<CandidateFit>,
    /// The chosen effect(s).
    pub winner: Vec<String>,
    /// Why.
    pub winner_reason: String,
    /// Effects the data cannot tell apart.
    pub indistinguishable: Vec<Confusion>,
    /// Effects of the library the model cannot represent.
    pub unsupported: Vec<Unsupported>,
}

/// Answer 3.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Shrink {
    /// The winner.
    pub winner: Vec<String>,
    /// Held-out gap of the model as it is.
    pub before: Gap,
    /// Held-out gap with the winner's fitted values.
    pub after: Gap,
    /// 1 − after/before, total.
    pub reduction_total: f64,
    /// 1 − after/before, systematic.
    pub reduction_systematic: f64,
    /// 1 − after/before, scatter.
    pub reduction_scatter: f64,
    /// The held-out gap step by step: the model as it is, the best single effect, the
    /// winner.
    pub path: Vec<ShrinkStep>,
}

/// One step of [`Shrink::path`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ShrinkStep {
    /// Effects in the model.
    pub effects: Vec<String>,
    /// Held-out systematic gap, cm.
    pub systematic_cm: f64,
    /// Held-out scatter gap, cm.
    pub scatter_cm: f64,
    /// Held-out total gap, cm.
    pub total_cm: f64,
}

/// The whole diagnosis.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Diagnosis {
    /// The model diagnosed.
    pub model: String,
    /// The split rule.
    pub split: String,
    /// Training groups.
    pub train_groups: Vec<String>,
    /// Held-out groups.
    pub heldout_groups: Vec<String>,
    /// Where the gap lies.
    #[serde(rename = "where")]
    pub where_: Where,
    /// Which effect explains it.
    pub which: Which,
    /// How far it shrinks.
    pub shrink: Shrink,
    /// Time-series comparisons attached by the caller.
    pub series: Vec<SeriesGap>,
    /// Motor held-out checks attached by the caller.
    pub motor: Vec<MotorHoldout>,
    /// Remarks (data notes, fit warnings).
    pub notes: Vec<String>,
}

impl Diagnosis {
    /// The winner's fit (values, uncertainties, gaps).
    pub fn winner_fit(&self) -> Option<&CandidateFit> {
        self.which
            .singles
            .iter()
            .chain(&self.which.pairs)
            .map(|r| &r.fit)
            .chain(&self.which.extended)
            .find(|f| f.effects == self.which.winner)
    }
}

fn rank(fits: Vec<CandidateFit>, base_heldout: &Gap) -> Vec<RankedFit> {
    let mut by_bic: Vec<usize> = (0..fits.len()).collect();
    by_bic.sort_by(|&a, &b| fits[a].bic.total_cmp(&fits[b].bic));
    let mut by_ho: Vec<usize> = (0..fits.len()).collect();
    let ho = |f: &CandidateFit| f.heldout.as_ref().map_or(f64::INFINITY, |g| g.total_cm);
    by_ho.sort_by(|&a, &b| ho(&fits[a]).total_cmp(&ho(&fits[b])));
    let mut out: Vec<RankedFit> = by_bic
        .iter()
        .map(|&i| {
            let f = &fits[i];
            let h = f.heldout.as_ref().expect("held-out gap computed");
            RankedFit {
                fit: f.clone(),
                rank_bic: by_bic.iter().position(|&j| j == i).unwrap_or(0) + 1,
                rank_heldout: by_ho.iter().position(|&j| j == i).unwrap_or(0) + 1,
                heldout_reduction: reduction(base_heldout.total_cm, h.total_cm),
                heldout_systematic_reduction: reduction(
                    base_heldout.systematic_cm,
                    h.systematic_cm,
                ),
            }
        })
        .collect();
    out.sort_by_key(|r| r.rank_bic);
    out
}

/// Runs the diagnosis of `model` on the training groups, evaluated on the held-out groups.
pub fn diagnose(
    model: &dyn Model,
    train: &TrainSet,
    held: &HeldOutSet,
    opts: &DiagnoseOptions,
) -> Result<Diagnosis, GapError> {
    let ev = Evaluator::new(model, train, &opts.fit);
    let tg = train.groups();
    let hg = held.groups();
    let mut notes = Vec::new();

    let mut base = fit_candidate(&ev, tg, &[], &[], 0.0)?;
    base.share_explained = 0.0;
    let base_heldout = ev.gap(&EffectParams::new(), hg)?;
    base.heldout = Some(base_heldout.clone());
    let base_chi2 = base.chi2;

    let is_stochastic = |n: &String| ev.spec(n).is_some_and(ParamSpec::stochastic);
    let names: Vec<String> = match &opts.candidates {
        Some(c) => c.clone(),
        None => ev.specs.iter().map(|s| s.name.clone()).collect(),
    };
    for n in &names {
        ev.known_spec(n)?;
    }

    // Singles.
    let mut singles = Vec::new();
    for n in &names {
        let spec = ev.spec(n).expect("checked").clone();
        let starts = grid_start(&ev, tg, &spec)?;
        let mut f = fit_candidate(&ev, tg, std::slice::from_ref(n), &starts, base_chi2)?;
        f.heldout = Some(ev.gap(&f.params, hg)?);
        if !f.converged {
            notes.push(format!("fit of {} did not converge", f.label()));
        }
        singles.push(f);
    }

    // Pairs.
    let mut pairs = Vec::new();
    if opts.fit.pairs {
        for i in 0..names.len() {
            for j in i + 1..names.len() {
                let (si, sj) = (&singles[i], &singles[j]);
                let (ni, nj) = (
                    ev.spec(&names[i]).expect("checked").neutral,
                    ev.spec(&names[j]).expect("checked").neutral,
                );
                let starts = pair_starts(
                    [si.estimates[0].value, sj.estimates[0].value],
                    [ni, nj],
                    [is_stochastic(&names[i]), is_stochastic(&names[j])],
                );
                let effects = vec![names[i].clone(), names[j].clone()];
                let mut f = fit_candidate(&ev, tg, &effects, &starts, base_chi2)?;
                f.heldout = Some(ev.gap(&f.params, hg)?);
                pairs.push(f);
            }
        }
    }

    // Indistinguishable effects: given nothing, and given the best single.
    let mut confusions: Vec<Confusion> = Vec::new();
    let best_single_idx = (0..singles.len())
        .min_by(|&a, &b| singles[a].bic.total_cmp(&singles[b].bic))
        .ok_or_else(|| GapError::Fit("no candidate effects".into()))?;
    let mut stages: Vec<(Vec<String>, f64, Vec<&CandidateFit>)> =
        vec![(vec![], base_chi2, singles.iter().collect())];
    let best_single = singles[best_single_idx].clone();
    let best_single = &best_single;
    if !pairs.is_empty() {
        let with_best: Vec<&CandidateFit> = pairs
            .iter()
            .filter(|p| p.effects.contains(&best_single.effects[0]))
            .collect();
        stages.push((best_single.effects.clone(), best_single.chi2, with_best));
    }
    let template = &tg[0].experiment;
    for (given, chi_s, fits) in &stages {
        let improving: Vec<&CandidateFit> = fits
            .iter()
            .copied()
            .filter(|f| improves(*chi_s, f))
            .collect();
        for a in 0..improving.len() {
            for b in a + 1..improving.len() {
                let (fa, fb) = (improving[a], improving[b]);
                let extra = |f: &CandidateFit| -> String {
                    f.effects
                        .iter()
                        .find(|e| !given.contains(e))
                        .cloned()
                        .unwrap_or_default()
                };
                let (ea, eb) = (extra(fa), extra(fb));
                let ra = ev.residuals(&fa.params, tg)?;
                let rb = ev.residuals(&fb.params, tg)?;
                let d = ra
                    .iter()
                    .zip(&rb)
                    .map(|(x, y)| (x - y).powi(2))
                    .sum::<f64>()
                    .sqrt();
                let max_cm = fa
                    .train
                    .groups
                    .iter()
                    .zip(&fb.train.groups)
                    .map(|(x, y)| {
                        (x.predicted.mean_x - y.predicted.mean_x)
                            .hypot(x.predicted.mean_y - y.predicted.mean_y)
                    })
                    .fold(0.0, f64::max);
                let mut evidence = Vec::new();
                let alike = d < 2.0;
                if alike {
                    evidence.push(format!(
                        "fitted alone{} they predict the training data alike: residuals differ \
                         by {d:.2} standard errors in total, centroids by at most {max_cm:.2} cm \
                         (χ² {:.1} vs {:.1})",
                        if given.is_empty() {
                            String::new()
                        } else {
                            format!(" next to {}", given.join(" + "))
                        },
                        fa.chi2,
                        fb.chi2
                    ));
                }
                let joint = pairs.iter().find(|p| {
                    p.effects.len() == 2 && p.effects.contains(&ea) && p.effects.contains(&eb)
                });
                if !alike && (fa.bic - fb.bic).abs() < TIE_BIC {
                    evidence.push(format!(
                        "their predictions differ (by {d:.1} standard errors in total) but they fit the training data equally well (BIC {:.1} vs {:.1}): the data do not prefer either, and both absorb something the model lacks",
                        fa.bic, fb.bic
                    ));
                }
                if let Some(j) = joint {
                    if !evidence.is_empty() || degenerate(j) {
                        evidence.push(format!(
                            "fitted together their parameters are {}",
                            match j.max_correlation() {
                                Some(c) => format!(
                                    "correlated (|ρ| = {c:.4}, condition number {:.3e})",
                                    j.condition_number
                                ),
                                None => "not identifiable (singular Jacobian)".to_owned(),
                            }
                        ));
                    }
                }
                if evidence.is_empty() {
                    continue;
                }
                let mut pair = vec![ea.clone(), eb.clone()];
                pair.sort();
                if confusions.iter().any(|c| c.effects == pair) {
                    continue;
                }
                let separating_test = find_separating_test(&ev, template, &fa.params, &fb.params)?;
                confusions.push(Confusion {
                    suggestion: separating_measurement(&ea, &eb),
                    effects: pair,
                    given: given.clone(),
                    evidence,
                    separating_test,
                });
            }
        }
    }

    // Winner, on training data only.
    let best_pair = pairs
        .iter()
        .filter(|p| separable(&ev, p))
        .min_by(|a, b| a.bic.total_cmp(&b.bic));
    let (winner, winner_reason) = match best_pair {
        Some(p) if p.bic < best_single.bic - STRONG_BIC => (
            p.clone(),
            format!(
                "the pair {} has BIC {:.1}, below the best single effect's {:.1} by more than \
                 {STRONG_BIC}",
                p.label(),
                p.bic,
                best_single.bic
            ),
        ),
        _ => (
            best_single.clone(),
            format!(
                "lowest BIC of the single effects ({:.1}); no separable pair beats it by more \
                 than {STRONG_BIC}",
                best_single.bic
            ),
        ),
    };
    // Forward selection beyond the pair: add the effect that lowers the BIC most, while it
    // does so by more than STRONG_BIC and every parameter stays determined.
    let (mut winner, mut winner_reason) = (winner, winner_reason);
    // The lowest BIC of `winner` extended by each effect of `ns` that its `gain` over the
    // winner makes worth adding, if any.
    let best_extension = |winner: &CandidateFit,
                          ns: Vec<&String>,
                          gain: &dyn Fn(&CandidateFit, &CandidateFit) -> f64|
     -> Result<Option<CandidateFit>, GapError> {
        let mut best: Option<CandidateFit> = None;
        for n in ns {
            let mut effects = winner.effects.clone();
            effects.push(n.clone());
            let start = extension_start(winner, &singles, n);
            let f = fit_candidate(&ev, tg, &effects, &[start], base_chi2)?;
            if worth_adding(&ev, &f, gain(winner, &f))
                && best.as_ref().is_none_or(|b| f.bic < b.bic)
            {
                best = Some(f);
            }
        }
        Ok(best)
    };
    let mut extended = Vec::new();
    while winner.effects.len() >= 2 && winner.effects.len() < opts.fit.max_effects {
        let ns = names
            .iter()
            .filter(|n| !winner.effects.contains(n) && !is_stochastic(n));
        let Some(mut b) = best_extension(&winner, ns.collect(), &extension_gain)? else {
            break;
        };
        b.heldout = Some(ev.gap(&b.params, hg)?);
        winner_reason = format!(
            "{winner_reason}; adding {} lowers the BIC further to {:.1}",
            b.effects.last().expect("non-empty"),
            b.bic
        );
        extended.push(b.clone());
        winner = b;
    }
    // The spread: stochastic effects only move the scatter residuals (the centroids are
    // predicted with them off), so they are added on their own evidence, plain BIC.
    if winner.effects.len() < opts.fit.max_effects && !winner.effects.iter().any(&is_stochastic) {
        let ns = names.iter().filter(|n| is_stochastic(n)).collect();
        let plain_bic = |w: &CandidateFit, f: &CandidateFit| w.bic - f.bic;
        if let Some(mut b) = best_extension(&winner, ns, &plain_bic)? {
            b.heldout = Some(ev.gap(&b.params, hg)?);
            winner_reason = format!(
                "{winner_reason}; the spread between runs adds {} (BIC {:.1})",
                b.effects.last().expect("non-empty"),
                b.bic
            );
            extended.push(b.clone());
            winner = b;
        }
    }
    if winner.bic >= base.bic {
        notes.push(format!(
            "no effect improves the BIC of the model as it is ({:.1}); the winner is reported \
             for completeness",
            base.bic
        ));
    }
    notes.extend(heldout_worse_notes(&path_pairs(&extended, &pairs, &winner)));
    for c in &confusions {
        if let Some(w) = c.effects.iter().find(|e| winner.effects.contains(e)) {
            let others: Vec<&String> = c.effects.iter().filter(|e| *e != w).collect();
            notes.push(format!(
                "the winner's {w} cannot be told apart from {} by these data (see \
                 \"indistinguishable\"); the held-out numbers are {w}'s, the others' are in the \
                 tables",
                others
                    .iter()
                    .map(|s| s.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
    }
    let sds = bootstrap(&ev, train, &winner, opts.fit.bootstrap, opts.fit.seed)?;
    for (e, sd) in winner.estimates.iter_mut().zip(sds) {
        e.bootstrap_sd = sd;
    }
    // Carry the bootstrap into the ranked lists too.
    let patch = |f: &mut CandidateFit| {
        if f.effects == winner.effects {
            f.estimates = winner.estimates.clone();
        }
    };
    for f in singles
        .iter_mut()
        .chain(pairs.iter_mut())
        .chain(extended.iter_mut())
    {
        patch(f);
    }

    let after = winner.heldout.clone().expect("computed");
    let step = |effects: &[String], g: &Gap| ShrinkStep {
        effects: effects.to_vec(),
        systematic_cm: g.systematic_cm,
        scatter_cm: g.scatter_cm,
        total_cm: g.total_cm,
    };
    let mut path = vec![step(&[], &base_heldout)];
    path.push(step(
        &best_single.effects,
        best_single.heldout.as_ref().expect("computed"),
    ));
    for f in pairs
        .iter()
        .filter(|p| p.effects == winner.effects[..2.min(winner.effects.len())])
        .chain(extended.iter())
    {
        path.push(step(&f.effects, f.heldout.as_ref().expect("computed")));
    }
    let shrink = Shrink {
        path,
        winner: winner.effects.clone(),
        reduction_total: reduction(base_heldout.total_cm, after.total_cm),
        reduction_systematic: reduction(base_heldout.systematic_cm, after.systematic_cm),
        reduction_scatter: reduction(base_heldout.scatter_cm, after.scatter_cm),
        before: base_heldout.clone(),
        after,
    };

    // Where.
    let all: Vec<Group> = tg.iter().chain(hg).cloned().collect();
    let mut all_gap = base.train.clone();
    all_gap.groups.extend(base_heldout.groups.iter().cloned());
    let decomposition = decompose_all(&all, &all_gap, opts.fit.floor_cm);
    let mut winner_gap = winner.train.clone();
    winner_gap.groups.extend(
        winner
            .heldout
            .as_ref()
            .expect("computed")
            .groups
            .iter()
            .cloned(),
    );
    let decomposition_after_winner = decompose_all(&all, &winner_gap, opts.fit.floor_cm);
    for s in &ev.specs {
        if s.stochastic() && names.contains(&s.name) {
            notes.push(format!(
                "{} is stochastic: it is fitted to the spread between runs, predicted with {} runs \
                 per group",
                s.name, opts.fit.prediction_runs
            ));
        }
    }

    Ok(Diagnosis {
        model: model.name(),
        split: train.rule().to_owned(),
        train_groups: tg.iter().map(|g| g.id.to_string()).collect(),
        heldout_groups: hg.iter().map(|g| g.id.to_string()).collect(),
        where_: Where {
            train: base.train.clone(),
            heldout: base_heldout.clone(),
            decomposition,
            decomposition_after_winner,
        },
        which: Which {
            baseline: base,
            singles: rank(singles, &base_heldout),
            pairs: rank(pairs, &base_heldout),
            extended,
            winner: winner.effects.clone(),
            winner_reason,
            indistinguishable: confusions,
            unsupported: model.unsupported(),
        },
        shrink,
        series: vec![],
        motor: vec![],
        notes,
    })
}

#[cfg(test)]
mod tests;
