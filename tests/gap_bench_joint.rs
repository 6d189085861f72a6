//! The bench's joint fit of Borenstein's two errors (Ed, the wheels' diameter ratio, and
//! Eb, the wheelbase) on self-test data hiding both at once, both directions: no single
//! effect fits such a robot, and the joint fit must find both values within 10 % of their
//! deviations from nominal and cut the held-out gap beyond noise by 80 % or more. The fit
//! starts from the nominal robot (as the forward selection does when neither effect was
//! fitted alone) so that it is the fit, not its start, that finds them. One test per
//! direction, so that the two run side by side.
//!
//! With coasting as a third hidden effect a wider wheelbase and a longer coast trade off in
//! UMBmark's end points, and the bench's answer is rough along that ridge: the triple's fit
//! ends with regression steps, which follow the trend, and its data hold a shuttle, whose
//! turns of 180° tell the two apart (docs/guide/diagnose.md#joint-fits).

#[path = "support/mod.rs"]
mod support;

use gap::{EffectParams, Scorer};
use hil::runs::gap_bench::{
    fit_effects_jointly, self_test_split, third_starts, BenchModel, SelectOptions, SelfTestDesign,
    HELDOUT_CUT_PCT, RUNS_PER_GROUP, SHUTTLE_CORNER_DEG, SHUTTLE_GROUP, THREE_EFFECT_CASE,
    TWO_EFFECT_CASES, VALUE_WITHIN_PCT,
};
use plant_model::RobotConfig;

/// Leg of every test, mm: UMBmark's turn effects outweigh the wheel ratio's curvature on
/// short legs, so the legs are longer than the single-effect self-test's.
const LEG_MM: f64 = 1000.0;

fn joint_case(k: usize) {
    let design = SelfTestDesign::legs(LEG_MM);
    let cut = hidden_case(&TWO_EFFECT_CASES[k], design, 46 + k as u64);
    assert!(cut >= HELDOUT_CUT_PCT, "cut {cut:.0} %");
}

/// Fits the effects of `case` jointly on self-test data of `design` hiding them (seed `seed`); checks
/// each value within [`VALUE_WITHIN_PCT`] of its deviation and every value determined;
/// returns the held-out gap beyond noise's cut, %.
fn hidden_case(case: &[(&str, f64)], design: SelfTestDesign, seed: u64) -> f64 {
    let bench = BenchModel::new(support::firmware("robust"), RobotConfig::default(), 2);
    let specs = hil::runs::gap_bench::bench_parameters();
    let mut hidden = EffectParams::new();
    for (e, v) in case {
        hidden.set(e, *v);
    }
    let (train, held) = self_test_split(&bench, &hidden, design, seed).unwrap();
    // The shuttle, when asked: trained on, its corners and runs as the design says.
    let shuttles: Vec<_> = train
        .groups()
        .iter()
        .filter(|g| g.id.experiment == SHUTTLE_GROUP)
        .map(|g| (g.experiment.firmware.turn_umbmark_deg, g.runs.len()))
        .collect();
    let want = if design.shuttle {
        vec![(SHUTTLE_CORNER_DEG, 2 * RUNS_PER_GROUP)]
    } else {
        Vec::new()
    };
    assert_eq!(shuttles, want);
    let opts = SelectOptions::default();
    let effects: Vec<&str> = case.iter().map(|c| c.0).collect();
    let nominal: Vec<f64> = effects
        .iter()
        .map(|e| specs.iter().find(|s| s.name == *e).unwrap().neutral)
        .collect();
    // A third effect starts as the forward selection starts it (see `third_starts`), the
    // pair at nominal; not fitted alone, its single value is its neutral one.
    let starts = match case {
        [_, _, (third, _)] => third_starts(&nominal[..2], third, nominal[2], &opts),
        _ => vec![nominal.clone()],
    };
    let f = fit_effects_jointly(&bench, &train, &held, &opts, &effects, &starts).unwrap();
    let before = Scorer::new(&bench, &train, &opts.fit)
        .gap(&EffectParams::new(), held.groups())
        .unwrap();
    let cut = 100.0 * (1.0 - f.heldout.systematic_excess_cm / before.systematic_excess_cm);
    let report = format!(
        "hidden {case:?}: fitted {:?} ± {:?}, training score {:.1}, held-out gap beyond noise {:.2} -> {:.2} cm \
         (cut {cut:.0} %), {} bench runs",
        f.values,
        f.std_err,
        f.train_score(),
        before.systematic_excess_cm,
        f.heldout.systematic_excess_cm,
        f.bench_runs
    );
    eprintln!("{report}");
    for (((effect, injected), got), neutral) in case.iter().zip(&f.values).zip(&nominal) {
        let (want, found) = (injected - neutral, got - neutral);
        assert!(
            100.0 * (found - want).abs() <= VALUE_WITHIN_PCT * want.abs(),
            "{effect}: {report}"
        );
    }
    assert!(f.determined, "{report}");
    cut
}

#[test]
fn a_small_right_wheel_and_a_wide_wheelbase_are_both_found() {
    joint_case(0);
}

#[test]
fn a_large_right_wheel_and_a_narrow_wheelbase_are_both_found() {
    joint_case(1);
}

/// Ed, Eb and coasting hidden together, the shuttle in the training data: each within 10 %
/// of its deviation, the held-out gap beyond noise cut by 80 % or more. UMBmark and the
/// line alone do not determine a wheelbase beside a coast (both change the 90° turns; the
/// guide's joint fits): at this seed the wheelbase ended 15.7 % off without the shuttle and
/// 10.1 % off with a shuttle of 5 runs. Measured with its 10: Ed 0.9693, Eb 1.0522, coast
/// 0.130 s (2.4, 4.5 and 8.3 % off), cut 100 %, 1575 bench runs. Over seeds 46 to 51 all
/// three within 10 % in 6 of 6, the wheelbase within 5 %; the cut 80 % or more in 5 of 6
/// (seed 47: 78 %, which the hidden values themselves cut).
#[test]
fn a_coasting_robot_with_both_errors_is_found_with_all_three() {
    let design = SelfTestDesign::legs(LEG_MM).with_shuttle();
    let cut = hidden_case(&THREE_EFFECT_CASE, design, 51);
    assert!(cut >= HELDOUT_CUT_PCT, "cut {cut:.0} %");
}
