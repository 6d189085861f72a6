//! The rules on numbers worked by hand.

use super::*;
use crate::test_support::{candidate_fit, estimate};

/// A condition number past 10⁸ makes a joint fit degenerate even with its correlation
/// matrix at hand; so does a singular one; 10⁷ with a matrix does not.
#[test]
fn a_joint_fit_is_degenerate_past_a_condition_number_of_1e8() {
    let with = |condition_number: f64, correlation: bool| {
        let mut f = candidate_fit(&["a", "b"]);
        f.condition_number = condition_number;
        f.correlation = correlation.then(|| vec![vec![1.0, 0.9], vec![0.9, 1.0]]);
        degenerate(&f)
    };
    assert!(with(1e9, true));
    assert!(!with(1e8, true), "past, not at");
    assert!(!with(1e7, true));
    assert!(with(f64::INFINITY, true));
    assert!(with(10.0, false));
}

/// A stage left 100 of χ²: removing 25 is a quarter, 24 is not; of 20 left, removing 5 is a
/// quarter but under 6.
#[test]
fn a_candidate_improves_by_6_and_a_quarter_of_what_was_left() {
    let with = |chi2: f64| {
        let mut f = candidate_fit(&["a"]);
        f.chi2 = chi2;
        f
    };
    assert!(improves(100.0, &with(75.0)));
    assert!(!improves(100.0, &with(76.0)));
    assert!(!improves(20.0, &with(15.0)));
    assert!(improves(20.0, &with(14.0)));
}

/// From χ² 120 with 2 parameters to 60 with 3, on 22 residuals: χ²/dof 60/19 scales the
/// gain of 60 to 19, less the penalty ln 22 of the third parameter; at χ² 10 (χ²/dof under
/// 1) the gain is the plain 110 − ln 22.
#[test]
fn an_extension_gains_its_chi2_scaled_by_quasi_likelihood_less_its_penalty() {
    let fit = |k: usize, chi2: f64| {
        let mut f = candidate_fit(&["a", "b", "c"][..k]);
        f.n_residuals = 22;
        f.chi2 = chi2;
        f.bic = chi2 + k as f64 * 22f64.ln();
        f
    };
    let small = fit(2, 120.0);
    let gain = extension_gain(&small, &fit(3, 60.0));
    assert!((gain - (19.0 - 22f64.ln())).abs() < 1e-9, "{gain}");
    let gain = extension_gain(&small, &fit(3, 10.0));
    assert!((gain - (110.0 - 22f64.ln())).abs() < 1e-9, "{gain}");
}

/// A degree of end heading weighs as 2 cm of end point.
#[test]
fn a_probe_scores_the_larger_of_the_distance_and_twice_the_heading() {
    assert_eq!(separation_score(3.0, 1.0), 3.0);
    assert_eq!(separation_score(1.0, 3.0), 6.0);
}

/// An effect earns its place only when the fit that holds it stays determined and gains
/// more than the strong BIC margin: Ed 1.01 ± 0.001 with a gain of 7 does, with a gain of
/// 6 does not; Ed 1.01 ± 0.01 (within two errors of 1) does not, however large the gain,
/// nor does a determined value at a condition number of 10⁷ (or 10⁶: below it, not at it).
#[test]
fn an_effect_is_worth_adding_when_determined_and_strongly_better() {
    use crate::effects::WHEEL_DIAMETER_RATIO;
    use crate::fit::{FitOptions, Weights};
    use crate::kinematic::KinematicModel;
    use crate::model::Model;
    let ev = Evaluator {
        model: &KinematicModel,
        specs: KinematicModel.parameters(),
        opts: FitOptions::default(),
        weights: Weights::from_groups(&[], 1.0),
    };
    assert_eq!(ev.spec(WHEEL_DIAMETER_RATIO).unwrap().neutral, 1.0);
    let ed = |std_err: f64, condition_number: f64| {
        let mut f = candidate_fit(&[WHEEL_DIAMETER_RATIO]);
        f.condition_number = condition_number;
        f.estimates = vec![estimate(WHEEL_DIAMETER_RATIO, 1.01, Some(std_err))];
        f
    };
    assert!(worth_adding(&ev, &ed(0.001, 1.0), 7.0));
    assert!(!worth_adding(&ev, &ed(0.001, 1.0), STRONG_BIC));
    assert!(!worth_adding(&ev, &ed(0.01, 1.0), 100.0));
    assert!(!worth_adding(&ev, &ed(0.001, 1e7), 100.0));
    assert!(
        !worth_adding(&ev, &ed(0.001, 1e6), 100.0),
        "below 10⁶, not at"
    );
    assert!(worth_adding(&ev, &ed(0.001, 999_999.0), 100.0));
    // More than two errors from neutral, not two: 1.5 ± 0.25 is two exactly.
    let mut at_two = ed(0.25, 1.0);
    at_two.estimates[0].value = 1.5;
    assert!(!worth_adding(&ev, &at_two, 100.0));
    at_two.estimates[0].std_err = Some(0.2499);
    assert!(worth_adding(&ev, &at_two, 100.0));
}
