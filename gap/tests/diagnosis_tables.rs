//! The diagnosis's tables agree with the fits they list: ranks, reductions, the winner's
//! fit and the shrink path are what their docs say they are.

use gap::effects::{COAST, FLOOR_NOISE, TOE, WHEELBASE_RATIO, WHEEL_DIAMETER_RATIO};
use gap::{
    diagnose, Dataset, DiagnoseOptions, Diagnosis, EffectParams, Experiment, Firmware, FitOptions,
    Gap, Group, KinematicModel, Model, ObservedRun, RankedFit, Reference, SplitRule, TestKind,
};

/// Five runs of each test of `hidden` with two leg lengths; the 1.5 m legs held out.
fn diagnosis(hidden: &EffectParams, candidates: &[&str]) -> Diagnosis {
    diagnosis_with(hidden, candidates, FitOptions::default().max_effects)
}

/// As [`diagnosis`], with at most `max_effects` effects in the winner.
fn diagnosis_with(hidden: &EffectParams, candidates: &[&str], max_effects: usize) -> Diagnosis {
    try_diagnosis(hidden, candidates, max_effects).unwrap()
}

/// As [`diagnosis_with`], its error if it fails.
fn try_diagnosis(
    hidden: &EffectParams,
    candidates: &[&str],
    max_effects: usize,
) -> Result<Diagnosis, gap::GapError> {
    let reference = Reference {
        wheelbase_mm: 150.0,
        mm_per_count: 0.2,
    };
    let mut d = Dataset::default();
    for (name, leg) in [("a", 2000.0), ("b", 1500.0)] {
        for test in [TestKind::UmbmarkCw, TestKind::UmbmarkCcw, TestKind::Line] {
            let exp = Experiment {
                test,
                firmware: Firmware::nominal(&reference, leg),
                reference,
                runs: 5,
                seed: 1,
            };
            let runs = KinematicModel
                .predict(hidden, &exp)
                .unwrap()
                .into_iter()
                .map(|r| ObservedRun {
                    x_cm: r.x_cm,
                    y_cm: Some(r.y_cm),
                    theta_rad: None,
                })
                .collect();
            d.push(Group::new(name, exp, runs).unwrap()).unwrap();
        }
    }
    let (t, h) = d.split(&SplitRule::LeaveOut(vec!["b".into()])).unwrap();
    let opts = DiagnoseOptions {
        fit: FitOptions {
            bootstrap: 4,
            max_effects,
            ..FitOptions::default()
        },
        candidates: Some(candidates.iter().map(|c| (*c).to_owned()).collect()),
    };
    diagnose(&KinematicModel, &t, &h, &opts)
}

/// A candidate the model does not have is refused before anything is fitted, with the
/// names it has.
#[test]
fn an_unknown_candidate_is_refused_with_the_known_ones() {
    let hidden = EffectParams::new().with(WHEEL_DIAMETER_RATIO, 1.008);
    let err = try_diagnosis(&hidden, &[WHEEL_DIAMETER_RATIO, "wheel_size"], 2)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("has no parameter `wheel_size` (it implements: ")
            && err.contains(WHEEL_DIAMETER_RATIO)
            && err.contains(FLOOR_NOISE),
        "{err}"
    );
}

fn heldout(r: &RankedFit) -> &Gap {
    r.fit
        .heldout
        .as_ref()
        .expect("every candidate has its held-out gap")
}

/// Each list is in BIC order (χ² + k ln N; the AIC χ² + 2k) with ranks 1, 2, ...; the held-out ranks order the same fits by
/// their held-out total gap, 1 the smallest; the reductions are 1 − gap / the model's gap.
fn check_ranks(list: &[RankedFit], before: &Gap) {
    for (i, r) in list.iter().enumerate() {
        assert_eq!(r.rank_bic, i + 1, "{:?}", r.fit.effects);
        let (f, k) = (&r.fit, r.fit.k as f64);
        assert_eq!(k as usize, f.effects.len());
        assert!(
            (f.bic - f.chi2 - k * (f.n_residuals as f64).ln()).abs() < 1e-9,
            "{f:?}"
        );
        assert!((f.aic - f.chi2 - 2.0 * k).abs() < 1e-9, "{f:?}");
        if i > 0 {
            assert!(list[i - 1].fit.bic <= r.fit.bic);
        }
        let g = heldout(r);
        let expect = 1.0 - g.total_cm / before.total_cm;
        assert!((r.heldout_reduction - expect).abs() < 1e-12, "{r:?}");
        let expect = 1.0 - g.systematic_cm / before.systematic_cm;
        assert!(
            (r.heldout_systematic_reduction - expect).abs() < 1e-12,
            "{r:?}"
        );
    }
    let mut by_heldout: Vec<&RankedFit> = list.iter().collect();
    by_heldout.sort_by(|a, b| heldout(a).total_cm.total_cmp(&heldout(b).total_cm));
    for (i, r) in by_heldout.iter().enumerate() {
        assert_eq!(r.rank_heldout, i + 1, "{:?}", r.fit.effects);
    }
}

#[test]
fn ranks_and_reductions_follow_the_fits() {
    let d = diagnosis(
        &EffectParams::new().with(WHEEL_DIAMETER_RATIO, 1.008),
        &[WHEEL_DIAMETER_RATIO, COAST, TOE, WHEELBASE_RATIO],
    );
    let before = &d.shrink.before;
    assert_eq!(before, &d.where_.heldout);
    assert_eq!(d.which.singles.len(), 4);
    assert_eq!(d.which.pairs.len(), 6);
    check_ranks(&d.which.singles, before);
    check_ranks(&d.which.pairs, before);
}

/// A scatter between runs the centroids cannot show is added after the systematic effects,
/// on its own BIC: the pair Ed and coast from the centroids, then the floor noise from the
/// spread.
#[test]
fn the_spread_is_added_after_the_centroids_effects() {
    let d = diagnosis(
        &EffectParams::new()
            .with(WHEEL_DIAMETER_RATIO, 1.008)
            .with(COAST, 5.0)
            .with(FLOOR_NOISE, 1.0),
        &[WHEEL_DIAMETER_RATIO, COAST, TOE, FLOOR_NOISE],
    );
    assert_eq!(d.which.winner, [WHEEL_DIAMETER_RATIO, COAST, FLOOR_NOISE]);
    assert!(
        d.which
            .winner_reason
            .contains("; the spread between runs adds floor_noise"),
        "{}",
        d.which.winner_reason
    );
    let w = d.winner_fit().unwrap();
    let noise = w.estimate(FLOOR_NOISE).unwrap().value;
    assert!((noise / 1.0 - 1.0).abs() < 0.5, "{noise}");
    // The notes say which candidate is fitted to the spread, and only that one.
    let stochastic: Vec<&String> = d
        .notes
        .iter()
        .filter(|n| n.contains(" is stochastic"))
        .collect();
    assert_eq!(stochastic.len(), 1, "{stochastic:?}");
    assert!(
        stochastic[0].starts_with("floor_noise is stochastic"),
        "{stochastic:?}"
    );
}

/// Forward selection extends the best pair by the effect that lowers the BIC most (by more
/// than its threshold), and stops at `max_effects`: Ed, Eb and toe hidden, the winner is the
/// three, the third named in the reason; with at most two effects, a pair; and the spread
/// step adds nothing past the limit either.
#[test]
fn forward_selection_adds_the_third_effect_up_to_the_limit() {
    let hidden = EffectParams::new()
        .with(WHEEL_DIAMETER_RATIO, 1.008)
        .with(WHEELBASE_RATIO, 1.03)
        .with(TOE, 1.5);
    let candidates = [WHEEL_DIAMETER_RATIO, WHEELBASE_RATIO, TOE, FLOOR_NOISE];
    let d = diagnosis(&hidden, &candidates);
    let mut winner = d.which.winner.clone();
    winner.sort();
    assert_eq!(
        winner,
        [TOE, WHEEL_DIAMETER_RATIO, WHEELBASE_RATIO],
        "{}",
        d.which.winner_reason
    );
    let third = d.which.winner.last().unwrap();
    assert!(
        d.which
            .winner_reason
            .contains(&format!("; adding {third} lowers the BIC further")),
        "{}",
        d.which.winner_reason
    );
    assert_eq!(d.which.extended.len(), 1);
    let toe = d.winner_fit().unwrap().estimate(TOE).unwrap().value;
    assert!((toe / 1.5 - 1.0).abs() < 0.1, "{toe}");

    let two = diagnosis_with(&hidden, &candidates, 2);
    assert_eq!(two.which.winner.len(), 2, "{}", two.which.winner_reason);
    assert!(two.which.extended.is_empty());
    let noisy = hidden.clone().with(FLOOR_NOISE, 1.0);
    let two = diagnosis_with(&noisy, &candidates, 2);
    assert_eq!(two.which.winner.len(), 2, "{}", two.which.winner_reason);
}

/// A pair wins over the best single effect when its BIC is lower by more than the threshold
/// (6), and only then: a toe of 0.1° next to Ed is taken (BIC about 5 against 16), one of
/// 0.07° is not (BIC about 5 against 9: lower by 4, though the pair is separable, toe
/// 0.070 ± 0.027).
#[test]
fn a_pair_wins_by_the_bic_margin_only() {
    let candidates = [WHEEL_DIAMETER_RATIO, TOE, COAST];
    let ed = EffectParams::new().with(WHEEL_DIAMETER_RATIO, 1.008);
    let d = diagnosis(&ed.clone().with(TOE, 0.1), &candidates);
    assert_eq!(
        d.which.winner,
        [WHEEL_DIAMETER_RATIO, TOE],
        "{}",
        d.which.winner_reason
    );
    let d = diagnosis(&ed.with(TOE, 0.07), &candidates);
    let pair = d
        .which
        .pairs
        .iter()
        .find(|r| r.fit.effects == [WHEEL_DIAMETER_RATIO, TOE])
        .expect("the pair is fitted");
    let toe = &pair.fit.estimates[1];
    assert!(toe.value > 2.0 * toe.std_err.unwrap(), "separable: {toe:?}");
    assert_eq!(
        d.which.winner,
        [WHEEL_DIAMETER_RATIO],
        "{}",
        d.which.winner_reason
    );
    assert!(d
        .which
        .winner_reason
        .contains("no separable pair beats it by more than 6"));
}

/// Of several effects worth adding, forward selection adds the one that lowers the BIC
/// most, whatever their order: Ed, Eb, toe 1.5° and coast 3° hidden, at most three effects;
/// from the pair Ed + toe both Eb (BIC 23.9) and coast (20.1) are worth adding, and coast is
/// added though Eb comes first.
#[test]
fn forward_selection_adds_the_best_of_the_effects_worth_adding() {
    let hidden = EffectParams::new()
        .with(WHEEL_DIAMETER_RATIO, 1.008)
        .with(WHEELBASE_RATIO, 1.03)
        .with(TOE, 1.5)
        .with(COAST, 3.0);
    let candidates = [WHEEL_DIAMETER_RATIO, WHEELBASE_RATIO, COAST, TOE];
    let d = diagnosis_with(&hidden, &candidates, 3);
    assert_eq!(
        d.which.winner,
        [WHEEL_DIAMETER_RATIO, TOE, COAST],
        "{}",
        d.which.winner_reason
    );
    assert!(
        d.which
            .winner_reason
            .contains("; adding coast lowers the BIC further to 20.1"),
        "{}",
        d.which.winner_reason
    );
}

/// The spread's effect is added on a BIC lower by more than the threshold (6), as the
/// centroids' effects are: next to Ed and coast, a floor noise of 0.05 lowers the BIC from
/// 17.8 to 9.4 and is added; one of 0.03, from 10.8 to 8.3 only, is not.
#[test]
fn the_spread_is_added_by_the_bic_margin_only() {
    let with_noise = |noise: f64| {
        diagnosis(
            &EffectParams::new()
                .with(WHEEL_DIAMETER_RATIO, 1.008)
                .with(COAST, 5.0)
                .with(FLOOR_NOISE, noise),
            &[WHEEL_DIAMETER_RATIO, COAST, TOE, FLOOR_NOISE],
        )
    };
    let d = with_noise(0.05);
    assert_eq!(
        d.which.winner,
        [WHEEL_DIAMETER_RATIO, COAST, FLOOR_NOISE],
        "{}",
        d.which.winner_reason
    );
    assert!(
        d.which
            .winner_reason
            .contains("has BIC 17.8, below the best single")
            && d.which
                .winner_reason
                .ends_with("; the spread between runs adds floor_noise (BIC 9.4)"),
        "{}",
        d.which.winner_reason
    );
    let d = with_noise(0.03);
    assert_eq!(
        d.which.winner,
        [WHEEL_DIAMETER_RATIO, COAST],
        "{}",
        d.which.winner_reason
    );
}

/// On data the model as it is explains (nothing hidden) no effect lowers the BIC, and the
/// notes say so; on data with an effect hidden (Ed) the winner does, and they do not.
#[test]
fn the_notes_say_when_no_effect_improves_the_model() {
    let says = |d: &Diagnosis| {
        d.notes
            .iter()
            .any(|n| n.starts_with("no effect improves the BIC of the model as it is"))
    };
    let candidates = [WHEEL_DIAMETER_RATIO, TOE, COAST];
    let nothing = diagnosis(&EffectParams::new(), &candidates);
    assert!(says(&nothing), "{:?}", nothing.notes);
    let ed = diagnosis(
        &EffectParams::new().with(WHEEL_DIAMETER_RATIO, 1.008),
        &candidates,
    );
    assert!(!says(&ed), "{:?}", ed.notes);
}
