//! The bench's joint fit of Borenstein's two errors (Ed, the wheels' diameter ratio, and
//! Eb, the wheelbase) on self-test data hiding both at once, both directions: no single
//! effect fits such a robot, and the joint fit must find both values within 10 % of their
//! deviations from nominal and cut the held-out gap beyond noise by 80 % or more. The fit
//! starts from the nominal robot (as the forward selection does when neither effect was
//! fitted alone) so that it is the fit, not its start, that finds them. One test per
//! direction, so that the two run side by side.

#[path = "support/mod.rs"]
mod support;

use gap::{EffectParams, Scorer};
use hil::runs::gap_bench::{
    fit_effects_jointly, self_test_split, BenchModel, SelectOptions, HELDOUT_CUT_PCT,
    TWO_EFFECT_CASES, VALUE_WITHIN_PCT,
};
use plant_model::RobotConfig;

/// Leg of every test, mm: UMBmark's turn effects outweigh the wheel ratio's curvature on
/// short legs, so the legs are longer than the single-effect self-test's.
const LEG_MM: f64 = 1000.0;

fn joint_case(k: usize) {
    let bench = BenchModel::new(support::firmware("robust"), RobotConfig::default(), 2);
    let case = TWO_EFFECT_CASES[k];
    let mut hidden = EffectParams::new();
    for (e, v) in case {
        hidden.set(e, v);
    }
    let (train, held) = self_test_split(&bench, &hidden, LEG_MM, 46 + k as u64).unwrap();
    let opts = SelectOptions::default();
    let effects: Vec<&str> = case.iter().map(|c| c.0).collect();
    let f = fit_effects_jointly(&bench, &train, &held, &opts, &effects, &[vec![1.0, 1.0]]).unwrap();
    let before = Scorer::new(&bench, &train, &opts.fit)
        .gap(&EffectParams::new(), held.groups())
        .unwrap();
    let cut = 100.0 * (1.0 - f.heldout.systematic_excess_cm / before.systematic_excess_cm);
    let report = format!(
        "hidden {case:?}: fitted {:?} ± {:?}, held-out gap beyond noise {:.2} -> {:.2} cm \
         (cut {cut:.0} %), {} bench runs",
        f.values,
        f.std_err,
        before.systematic_excess_cm,
        f.heldout.systematic_excess_cm,
        f.bench_runs
    );
    eprintln!("{report}");
    for ((_, injected), got) in case.iter().zip(&f.values) {
        assert!(
            100.0 * (got - injected).abs() <= VALUE_WITHIN_PCT * (injected - 1.0).abs(),
            "{report}"
        );
    }
    assert!(f.determined, "{report}");
    assert!(cut >= HELDOUT_CUT_PCT, "{report}");
}

#[test]
fn a_small_right_wheel_and_a_wide_wheelbase_are_both_found() {
    joint_case(0);
}

#[test]
fn a_large_right_wheel_and_a_narrow_wheelbase_are_both_found() {
    joint_case(1);
}
