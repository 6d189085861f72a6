//! The bench-backed diagnosis' self-test, small enough for CI: "real" data made by the bench
//! with one hidden effect (a left dead band the kinematic model cannot represent, coasting
//! it can), 5 runs per group, floor noise 1°/√m, UMBmark both ways and a
//! line for training, the triangle held out. The hidden effect must be named first, fitted
//! within 10 %, and the held-out gap must shrink by three quarters at least.

#[path = "support/mod.rs"]
mod support;

use hil::gap_bench::{bench_self_test, BenchModel, SelectOptions, DEFAULT_CASES};
use plant_model::RobotConfig;

#[test]
fn the_hidden_effect_is_found_by_the_bench() {
    let bench = BenchModel::new(support::firmware("robust"), RobotConfig::default(), 2);
    let t = bench_self_test(
        &bench,
        &DEFAULT_CASES[..2],
        300.0,
        0,
        &SelectOptions::default(),
        &|line| eprintln!("{line}"),
    )
    .unwrap();
    eprint!("{}", t.render());
    for c in &t.cases {
        assert!(c.named_first(), "{}: {}", c.effect, t.render());
        assert!(c.value_close(), "{}: {}", c.effect, t.render());
        assert!(
            c.heldout_cut_pct() >= 75.0,
            "{}: held-out gap {:.2} -> {:.2} cm",
            c.effect,
            c.heldout_before_cm,
            c.heldout_after_cm
        );
        assert!(!c.grew_unreported(), "{}", t.render());
    }
}
