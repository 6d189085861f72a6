//! The bench-backed diagnosis' self-test, small enough for CI: "real" data made by the bench
//! with one hidden effect (a left dead band the kinematic model cannot represent, coasting
//! it can), 5 runs per group, floor noise 1°/√m, UMBmark both ways and a
//! line for training, the triangle held out. The hidden effect must be named first and the
//! held-out gap beyond noise cut by 80 % at least; the dead band fitted within 10 %. Gear
//! play, taken up in a spin and given back after it, leaves no trace in these tests: the
//! report must take no effect.

#[path = "support/mod.rs"]
mod support;

use hil::runs::gap_bench::{bench_self_test, BenchModel, SelectOptions, DEFAULT_CASES};
use plant_model::RobotConfig;

#[test]
fn the_hidden_effect_is_found_by_the_bench() {
    let bench = BenchModel::new(support::firmware("robust"), RobotConfig::default(), 2);
    let backlash = *DEFAULT_CASES
        .iter()
        .find(|c| c.0 == gap::effects::BACKLASH)
        .expect("a self-test case");
    let cases = [DEFAULT_CASES[0], DEFAULT_CASES[1], backlash];
    let t = bench_self_test(
        &bench,
        &cases,
        300.0,
        0,
        &SelectOptions::default(),
        &|line| eprintln!("{line}"),
    )
    .unwrap();
    eprint!("{}", t.render());
    let (found, none) = t.cases.split_at(2);
    for c in found {
        assert!(c.visible(), "{}: {}", c.effect, t.render());
        assert!(c.named_first(), "{}: {}", c.effect, t.render());
        assert!(
            c.heldout_cut_enough(),
            "{}: held-out gap beyond noise {:.2} -> {:.2} cm",
            c.effect,
            c.heldout_excess_before_cm,
            c.heldout_excess_after_cm
        );
        assert!(!c.grew_unreported(), "{}", t.render());
    }
    // The dead band within the 10 %; coasting, measured 11.5 % off on these data
    // (the stops it shows in scatter with the start phase), within 15 %.
    assert!(t.cases[0].passed(), "{}", t.render());
    assert!(
        t.cases[1].value_error_pct.is_some_and(|e| e < 15.0),
        "{}",
        t.render()
    );
    // The truth itself scores the training data about as the nominal robot does, and no
    // candidate fitted to their noise is named.
    let c = &none[0];
    assert!(!c.visible(), "{}", t.render());
    assert_eq!(c.winner, None, "{}", c.diagnosis.render());
    assert!(c.passed() && c.honest(), "{}", t.render());
}

/// Without telemetry scored the diagnosis is the end points' alone: the dead band case
/// gives, to the last bit, the numbers that diagnosis gave when it was measured (its
/// candidates the effects the kinematic model cannot represent), and no series field is
/// filled. (`series: false` takes the path of data without telemetry: no series
/// recorded, none scored.)
#[test]
fn without_series_the_diagnosis_is_the_end_points_alone() {
    let bench = BenchModel::new(support::firmware("robust"), RobotConfig::default(), 2);
    let opts = SelectOptions {
        series: false,
        shortlist: 0,
        ..SelectOptions::default()
    };
    let t = bench_self_test(&bench, &DEFAULT_CASES[..1], 300.0, 0, &opts, &|_| {}).unwrap();
    let c = &t.cases[0];
    assert_eq!(c.fitted, Some(0.176393202250021), "{}", t.render());
    assert_eq!(c.heldout_before_cm, 1.4474630489271887);
    assert_eq!(c.heldout_after_cm, 0.17472996679771946);
    let d = &c.diagnosis;
    assert_eq!(d.nominal_train_chi2.round(), 400.0);
    assert!(d.nominal_series_chi2.is_none() && d.series.is_empty());
    assert!(d
        .candidates
        .iter()
        .all(|c| c.series_chi2.is_none() && c.series_rms_rpm.is_none()));
    assert!(!d.render().contains("series"), "{}", d.render());
}

/// A motor gain asymmetry: the speed controller holds both wheels at the set-point, so the
/// end points barely say which motor is the stronger; the telemetry's duties do: with the
/// series scored it is ranked first with the right sign (its candidates the effects the
/// kinematic model cannot represent).
#[test]
fn the_series_gives_the_gain_asymmetry_its_sign() {
    let bench = BenchModel::new(support::firmware("robust"), RobotConfig::default(), 2);
    let case = *DEFAULT_CASES
        .iter()
        .find(|c| c.0 == gap::effects::MOTOR_GAIN_ASYMMETRY)
        .expect("a self-test case");
    assert!(case.1 > 0.0);
    let opts = SelectOptions {
        shortlist: 0,
        ..SelectOptions::default()
    };
    let t = bench_self_test(&bench, &[case], 300.0, 0, &opts, &|_| {}).unwrap();
    eprint!("{}", t.render());
    let c = &t.cases[0];
    assert_eq!(c.ranked_first, c.effect, "{}", c.diagnosis.render());
    let fitted = c.fitted.unwrap();
    assert!(
        fitted > 0.05 && c.value_error_pct.unwrap() < 50.0,
        "fitted {fitted:.4}: {}",
        c.diagnosis.render()
    );
}

/// A case the diagnosis does not pass fails the command: with only the effects the
/// kinematic model cannot represent as candidates (`--shortlist 0`), a hidden wheelbase
/// error has no candidate to be named by. The table prints, then one line names the failed
/// case, and the exit code is 1.
#[test]
fn a_failed_case_fails_the_command() {
    let out = support::hil(&[
        "gap",
        "--self-test",
        "--bench",
        "--hidden",
        "wheelbase_ratio=1.05",
        "--shortlist",
        "0",
        "--leg-mm",
        "100",
        "--jobs",
        "2",
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stdout}{stderr}");
    let row = stdout
        .lines()
        .find(|l| l.trim_start().starts_with("wheelbase_ratio"))
        .unwrap_or_else(|| panic!("{stdout}"));
    assert!(row.ends_with("FAIL"), "{row}");
    assert_eq!(
        stderr.lines().last(),
        Some("error: self-test: 1 of 1 cases failed: wheelbase_ratio"),
        "{stderr}"
    );
}
