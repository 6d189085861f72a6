//! Splits hand out disjoint sets, and the diagnosis says when a split leaves effects it
//! cannot separate.

use gap::effects::{FLOOR_NOISE, WHEELBASE_RATIO, WHEEL_DIAMETER_RATIO};
use gap::{
    diagnose, Dataset, DiagnoseOptions, EffectParams, Experiment, Firmware, FitOptions, Group,
    KinematicModel, Model, ObservedRun, Reference, SplitRule, TestKind,
};

/// Five runs per test of the hidden effects on a floor that scatters them by a few cm.
fn dataset(hidden: &EffectParams) -> Dataset {
    let hidden = &hidden.clone().with(FLOOR_NOISE, 0.5);
    let reference = Reference {
        wheelbase_mm: 150.0,
        mm_per_count: 0.2,
    };
    let mut d = Dataset::default();
    for (name, b) in [("e1", 150.0), ("e2", 146.0)] {
        for test in [TestKind::UmbmarkCw, TestKind::UmbmarkCcw] {
            let exp = Experiment {
                test,
                firmware: Firmware {
                    wheelbase_mm: b,
                    ..Firmware::nominal(&reference, 2000.0)
                },
                reference,
                runs: 5,
                seed: 3,
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
    d
}

fn fast() -> DiagnoseOptions {
    DiagnoseOptions {
        fit: FitOptions {
            bootstrap: 5,
            ..FitOptions::default()
        },
        candidates: Some(vec![
            WHEEL_DIAMETER_RATIO.to_owned(),
            WHEELBASE_RATIO.to_owned(),
        ]),
    }
}

/// Every split puts each group in exactly one of the two sets.
#[test]
fn splits_are_disjoint_and_complete() {
    let d = dataset(&EffectParams::new().with(WHEEL_DIAMETER_RATIO, 1.01));
    let all: Vec<String> = d.groups().iter().map(|g| g.id.to_string()).collect();
    for rule in [
        SplitRule::TrainOnExperiments(vec!["e1".into()]),
        SplitRule::LeaveOut(vec!["e1".into()]),
        SplitRule::TrainOnTests(vec![TestKind::UmbmarkCw]),
    ] {
        let (t, h) = d.clone().split(&rule).unwrap();
        let ti: Vec<String> = t.groups().iter().map(|g| g.id.to_string()).collect();
        let hi: Vec<String> = h.groups().iter().map(|g| g.id.to_string()).collect();
        assert!(ti.iter().all(|x| !hi.contains(x)), "{rule:?}");
        let mut both: Vec<String> = ti.into_iter().chain(hi).collect();
        both.sort();
        let mut a = all.clone();
        a.sort();
        assert_eq!(both, a, "{rule:?}");
    }
}

/// A split that leaves one side empty, or names an unknown experiment, is refused.
#[test]
fn bad_splits() {
    let d = dataset(&EffectParams::new());
    let e = d
        .clone()
        .split(&SplitRule::TrainOnExperiments(vec![
            "e1".into(),
            "e2".into(),
        ]))
        .unwrap_err();
    assert!(e.to_string().contains("nothing held out"), "{e}");
    let e = d
        .split(&SplitRule::LeaveOut(vec!["e9".into()]))
        .unwrap_err();
    assert!(e.to_string().contains("`e9` is not in the data"), "{e}");
}

/// Trained on the CW squares only, Ed and Eb both explain the scattered data (a single
/// direction mixes corner and leg errors to first order): the diagnosis reports them as
/// indistinguishable and finds a test that separates them, and the held-out CCW squares
/// then show which one was right.
#[test]
fn cw_only_cannot_separate_ed_and_eb() {
    let d = dataset(&EffectParams::new().with(WHEELBASE_RATIO, 1.03));
    let (t, h) = d
        .split(&SplitRule::TrainOnTests(vec![TestKind::UmbmarkCw]))
        .unwrap();
    let diag = diagnose(&KinematicModel, &t, &h, &fast()).unwrap();
    print!("{}", gap::render_text(&diag));
    let c = diag
        .which
        .indistinguishable
        .iter()
        .find(|c| c.effects.contains(&WHEELBASE_RATIO.to_owned()))
        .expect("reported");
    assert!(c.effects.contains(&WHEEL_DIAMETER_RATIO.to_owned()));
    // The evidence: alike on the training data, within 2 standard errors in total, and their
    // training centroids as far apart as the fits' predictions say.
    let single = |name: &str| {
        &diag
            .which
            .singles
            .iter()
            .find(|r| r.fit.effects == [name])
            .unwrap()
            .fit
    };
    let (fa, fb) = (single(WHEELBASE_RATIO), single(WHEEL_DIAMETER_RATIO));
    let max_cm = fa
        .train
        .groups
        .iter()
        .zip(&fb.train.groups)
        .map(|(a, b)| {
            (a.predicted.mean_x - b.predicted.mean_x).hypot(a.predicted.mean_y - b.predicted.mean_y)
        })
        .fold(0.0, f64::max);
    let alike = c
        .evidence
        .iter()
        .find(|e| e.contains("predict the training data alike"))
        .unwrap_or_else(|| panic!("{:?}", c.evidence));
    assert!(
        alike.contains(&format!("centroids by at most {max_cm:.2} cm")),
        "{alike}: {max_cm:.2}"
    );
    let d: f64 = alike
        .split("residuals differ by ")
        .nth(1)
        .and_then(|r| r.split(' ').next())
        .unwrap()
        .parse()
        .unwrap();
    assert!(d < 2.0, "{alike}");
    // And fitted together, their correlation and condition number as the joint fit has them.
    let joint = &diag
        .which
        .pairs
        .iter()
        .find(|r| {
            r.fit.effects.len() == 2
                && r.fit.effects.contains(&WHEELBASE_RATIO.to_owned())
                && r.fit.effects.contains(&WHEEL_DIAMETER_RATIO.to_owned())
        })
        .expect("the pair is fitted")
        .fit;
    let together = format!(
        "fitted together their parameters are correlated (|ρ| = {:.4}, condition number {:.3e})",
        joint.max_correlation().expect("a correlation"),
        joint.condition_number
    );
    assert!(
        c.evidence.contains(&together),
        "{together}: {:?}",
        c.evidence
    );
    // The separating probe is a CCW square with 45° corners (the turn error grows with the
    // angle, the leg error does not), and the difference it states is the one the two fits
    // predict there.
    let probe = c
        .separating_test
        .as_deref()
        .expect("a probe separates them");
    assert!(
        probe.starts_with("umbmark_ccw with 45° corners: "),
        "{probe}"
    );
    let mut exp = t.groups()[0].experiment.clone();
    exp.test = TestKind::UmbmarkCcw;
    exp.firmware.turn_umbmark_deg = 45.0;
    exp.runs = 1;
    let end = |name: &str| {
        let fit = &diag
            .which
            .singles
            .iter()
            .find(|r| r.fit.effects == [name])
            .unwrap()
            .fit;
        let run = KinematicModel.predict(&fit.params, &exp).unwrap()[0];
        (run.x_cm, run.y_cm)
    };
    let (a, b) = (end(WHEELBASE_RATIO), end(WHEEL_DIAMETER_RATIO));
    let d = (a.0 - b.0).hypot(a.1 - b.1);
    assert!(d > 10.0, "{d}");
    assert!(
        probe.contains(&format!("end points differ by {d:.2} cm")),
        "{probe}: {d:.2}"
    );
    // On the held-out CCW squares the right effect wins by far.
    let ho = |name: &str| {
        diag.which
            .singles
            .iter()
            .find(|r| r.fit.effects == [name])
            .unwrap()
            .fit
            .heldout
            .as_ref()
            .unwrap()
            .systematic_cm
    };
    assert!(ho(WHEELBASE_RATIO) < 0.1 * ho(WHEEL_DIAMETER_RATIO));
}

/// Trained on both directions the same effects separate, and the right one wins.
#[test]
fn both_directions_separate_them() {
    let d = dataset(&EffectParams::new().with(WHEELBASE_RATIO, 1.03));
    let (t, h) = d
        .split(&SplitRule::TrainOnExperiments(vec!["e1".into()]))
        .unwrap();
    let diag = diagnose(&KinematicModel, &t, &h, &fast()).unwrap();
    assert!(
        diag.which.indistinguishable.is_empty(),
        "{:?}",
        diag.which.indistinguishable
    );
    assert_eq!(diag.which.winner, [WHEELBASE_RATIO]);
    assert!(diag.shrink.reduction_systematic > 0.8, "{:?}", diag.shrink);
}
