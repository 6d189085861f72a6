//! The diagnosis's pieces on cases built by hand.

use super::*;
use crate::effects::*;

fn fit(effects: &[&str]) -> CandidateFit {
    let nothing = Gap {
        systematic_cm: 0.0,
        scatter_cm: 0.0,
        total_cm: 0.0,
        systematic_excess_cm: 0.0,
        scatter_excess_cm: 0.0,
        groups: vec![],
    };
    CandidateFit {
        effects: effects.iter().map(|e| (*e).to_owned()).collect(),
        estimates: vec![],
        k: effects.len(),
        n_residuals: 0,
        chi2: 0.0,
        aic: 0.0,
        bic: 0.0,
        share_explained: 0.0,
        train: nothing,
        heldout: None,
        correlation: None,
        condition_number: 1.0,
        iterations: 0,
        converged: true,
        params: EffectParams::new(),
    }
}

fn labels(steps: &[(&CandidateFit, &CandidateFit)]) -> Vec<(String, String)> {
    steps.iter().map(|(a, b)| (a.label(), b.label())).collect()
}

/// The steps of forward selection start from the pair the first extension grew from,
/// not from the best pair.
#[test]
fn the_path_starts_at_the_pair_extended() {
    let pairs = [fit(&[TOE, COAST]), fit(&[TOE, TURN_SLIP])];
    let extended = [
        fit(&[TOE, TURN_SLIP, COAST]),
        fit(&[TOE, TURN_SLIP, COAST, DEAD_BAND]),
    ];
    let steps = path_pairs(&extended, &pairs, &extended[1]);
    assert_eq!(
        labels(&steps),
        [
            (pairs[1].label(), extended[0].label()),
            (extended[0].label(), extended[1].label())
        ]
    );
    assert!(path_pairs(&[], &pairs, &pairs[0]).is_empty());
    assert!(path_pairs(&extended, &pairs[..1], &pairs[0]).is_empty());
}

/// The advice for a pair is the same in either order, and the pairs with a known
/// physical difference get it.
#[test]
fn the_advice_for_a_pair_is_its_own_in_either_order() {
    for a in ALL_EFFECTS {
        for b in ALL_EFFECTS {
            assert_eq!(
                separating_measurement(a, b),
                separating_measurement(b, a),
                "{a}, {b}"
            );
        }
    }
    for (a, b, says) in [
        (WHEELBASE_RATIO, TURN_SLIP, "drive arcs"),
        (TURN_SLIP, COAST, "two different angles"),
        (TOE, WHEEL_DIAMETER_RATIO, "drive a square"),
        (TURN_SLIP, DISTANCE_SCALE, "length of a straight line"),
        (DEAD_BAND, FLOOR_NOISE, "more runs per test"),
        (
            DEAD_BAND,
            BACKLASH,
            "the two fitted models predict different end points",
        ),
    ] {
        let advice = separating_measurement(a, b);
        assert!(advice.contains(says), "{a}, {b}: {advice}");
    }
}
