//! The search's steps: where a pair's and an extension's fits start, the path of forward
//! selection and the note on a step that raised the held-out gap.

use crate::fit::CandidateFit;

/// The probe experiments: variations of a template experiment.
/// The starts of a pair's joint fit, from its two singles' fitted `values` and the effects'
/// `neutrals`: both singles' values; and when neither effect is `stochastic` (a
/// deterministic fit is cheap), each single's value with the other effect neutral too.
pub(super) fn pair_starts(
    values: [f64; 2],
    neutrals: [f64; 2],
    stochastic: [bool; 2],
) -> Vec<Vec<f64>> {
    let [vi, vj] = values;
    let [ni, nj] = neutrals;
    if stochastic[0] || stochastic[1] {
        vec![vec![vi, vj]]
    } else {
        vec![vec![vi, vj], vec![vi, nj], vec![ni, vj]]
    }
}

/// Where the fit of `winner` with effect `n` more starts: the winner's values, then n's
/// value fitted alone (one of `singles`).
pub(super) fn extension_start(
    winner: &CandidateFit,
    singles: &[CandidateFit],
    n: &str,
) -> Vec<f64> {
    let single = singles
        .iter()
        .find(|s| s.effects == [n])
        .expect("every candidate is fitted alone");
    let mut start: Vec<f64> = winner.estimates.iter().map(|e| e.value).collect();
    start.push(single.estimates[0].value);
    start
}

/// A note for each step of forward selection (`steps`, from [`path_pairs`]) whose added
/// effect raised the held-out gap (total, cm).
pub(super) fn heldout_worse_notes(steps: &[(&CandidateFit, &CandidateFit)]) -> Vec<String> {
    let total = |f: &CandidateFit| f.heldout.as_ref().expect("computed").total_cm;
    steps
        .iter()
        .filter(|(a, b)| total(b) > total(a))
        .map(|(a, b)| {
            format!(
                "adding {} lowered the training BIC but not the held-out gap ({:.2} → {:.2} cm): \
                 it fits something of the training data that does not carry over",
                b.effects.last().expect("non-empty"),
                total(a),
                total(b)
            )
        })
        .collect()
}

/// Consecutive steps of forward selection: (pair, first extension), (first, second), ...
pub(super) fn path_pairs<'a>(
    extended: &'a [CandidateFit],
    pairs: &'a [CandidateFit],
    winner: &CandidateFit,
) -> Vec<(&'a CandidateFit, &'a CandidateFit)> {
    let Some(first) = extended.first() else {
        return vec![];
    };
    let Some(pair) = pairs.iter().find(|p| p.effects[..] == first.effects[..2]) else {
        return vec![];
    };
    let _ = winner;
    let mut out = vec![(pair, first)];
    for w in extended.windows(2) {
        out.push((&w[0], &w[1]));
    }
    out
}
