//! The diagnosis's pieces on cases built by hand.

use super::*;
use crate::effects::*;
use crate::test_support::{candidate_fit as fit, estimate};

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

/// The probes change one thing each from the training experiment, and their names say
/// what: every test as trained, the CCW square with 45° and 180° corners, lines of half and
/// twice the leg, and the CCW square with the firmware's wheelbase 10 % short.
#[test]
fn each_probe_changes_one_thing_and_says_which() {
    use crate::model::TestKind;
    use crate::test_support::experiment;
    let template = experiment(TestKind::UmbmarkCw, 2000.0, 5);
    let probes = probes(&template);
    let n = TestKind::ALL.len();
    assert_eq!(probes.len(), n + 5);
    for ((name, e), kind) in probes.iter().zip(TestKind::ALL) {
        assert_eq!(*name, format!("{kind} as in the training data"));
        assert_eq!(e.test, kind);
        assert_eq!(e.firmware, template.firmware);
    }
    let changed = |i: usize| {
        let (name, e) = &probes[n + i];
        (name.as_str(), e.test, e.firmware.clone())
    };
    let with = |f: &dyn Fn(&mut crate::model::Firmware)| {
        let mut fw = template.firmware.clone();
        f(&mut fw);
        fw
    };
    assert_eq!(
        changed(0),
        (
            "umbmark_ccw with 45° corners",
            TestKind::UmbmarkCcw,
            with(&|fw| fw.turn_umbmark_deg = 45.0)
        )
    );
    assert_eq!(
        changed(1),
        (
            "umbmark_ccw with 180° corners",
            TestKind::UmbmarkCcw,
            with(&|fw| fw.turn_umbmark_deg = 180.0)
        )
    );
    assert_eq!(
        changed(2),
        (
            "line of 1000 mm",
            TestKind::Line,
            with(&|fw| fw.leg_mm = 1000.0)
        )
    );
    assert_eq!(
        changed(3),
        (
            "line of 4000 mm",
            TestKind::Line,
            with(&|fw| fw.leg_mm = 4000.0)
        )
    );
    assert_eq!(
        changed(4),
        (
            "umbmark_ccw with the firmware wheelbase at 135.0 mm",
            TestKind::UmbmarkCcw,
            with(&|fw| fw.wheelbase_mm = 135.0)
        )
    );
}

/// A deterministic pair starts from both singles' values and from each alone with the
/// other neutral; a pair with a stochastic effect (either one) from both values only.
#[test]
fn a_pair_starts_from_its_singles() {
    let starts = |stochastic| pair_starts([1.02, 3.0], [1.0, 0.0], stochastic);
    assert_eq!(
        starts([false, false]),
        [vec![1.02, 3.0], vec![1.02, 0.0], vec![1.0, 3.0]]
    );
    for stochastic in [[true, false], [false, true], [true, true]] {
        assert_eq!(starts(stochastic), [vec![1.02, 3.0]], "{stochastic:?}");
    }
}

/// A step of forward selection that raised the held-out gap gets a note naming its effect
/// and both gaps; a step that lowered it or left it as it was gets none.
#[test]
fn a_step_that_raises_the_held_out_gap_is_noted() {
    let with_gap = |effects: &[&str], total_cm: f64| {
        let mut f = fit(effects);
        let mut gap = f.train.clone();
        gap.total_cm = total_cm;
        f.heldout = Some(gap);
        f
    };
    let pair = with_gap(&[TOE, COAST], 1.0);
    let third = with_gap(&[TOE, COAST, TURN_SLIP], 1.5);
    let fourth = with_gap(&[TOE, COAST, TURN_SLIP, DEAD_BAND], 1.2);
    let fifth = with_gap(&[TOE, COAST, TURN_SLIP, DEAD_BAND, BACKLASH], 1.2);
    let notes = heldout_worse_notes(&[(&pair, &third), (&third, &fourth), (&fourth, &fifth)]);
    assert_eq!(notes.len(), 1, "{notes:?}");
    assert!(
        notes[0].starts_with(&format!(
            "adding {TURN_SLIP} lowered the training BIC but not the held-out gap (1.00 → 1.50 cm)"
        )),
        "{notes:?}"
    );
}

/// An extension starts from the winner's values and the added effect's own single fit.
#[test]
fn an_extension_starts_from_the_winner_and_the_effects_single_fit() {
    let with_values = |effects: &[&str], values: &[f64]| {
        let mut f = fit(effects);
        f.estimates = effects
            .iter()
            .zip(values)
            .map(|(e, &value)| estimate(e, value, None))
            .collect();
        f
    };
    let winner = with_values(&[TOE, COAST], &[1.5, 3.0]);
    let singles = [
        with_values(&[TOE], &[1.4]),
        with_values(&[COAST], &[2.5]),
        with_values(&[TURN_SLIP], &[0.02]),
        with_values(&[DEAD_BAND], &[0.1]),
    ];
    assert_eq!(
        extension_start(&winner, &singles, TURN_SLIP),
        [1.5, 3.0, 0.02]
    );
    assert_eq!(
        extension_start(&winner, &singles, DEAD_BAND),
        [1.5, 3.0, 0.1]
    );
}
