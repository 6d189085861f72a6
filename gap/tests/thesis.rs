//! The thesis data: the effects fitted on experiment 1 predict experiments 2 and 3, run
//! after the firmware corrections the thesis applied (the physical robot unchanged), and
//! the motor model fitted on three PWM levels predicts the other two. Numbers are printed
//! (`--nocapture`) and asserted against the measured values.

use std::path::PathBuf;

use gap::effects::{COAST, DISTANCE_SCALE, WHEELBASE_RATIO, WHEEL_DIAMETER_RATIO};
use gap::{
    diagnose_manifests, load_dir, render_markdown, render_text, DiagnoseOptions, Diagnosis,
    GroupGap, KinematicModel, LoadedManifest, SplitRule,
};

fn manifests(prefixes: &[&str]) -> Vec<LoadedManifest> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/real/thesis");
    load_dir(dir)
        .unwrap()
        .into_iter()
        .filter(|m| {
            prefixes
                .iter()
                .any(|p| m.manifest.experiment.starts_with(p))
        })
        .collect()
}

fn run(prefixes: &[&str], train: &[&str]) -> Diagnosis {
    diagnose_manifests(
        &KinematicModel,
        &manifests(prefixes),
        &SplitRule::TrainOnExperiments(train.iter().map(|s| (*s).to_owned()).collect()),
        &DiagnoseOptions::default(),
    )
    .unwrap()
}

fn group<'a>(g: &'a [GroupGap], name: &str) -> &'a GroupGap {
    g.iter().find(|x| x.group == name).unwrap()
}

/// Standard error of a measured centroid, cm (over the recorded axes).
fn se(g: &GroupGap) -> f64 {
    let o = &g.observed;
    ((o.sd_x.powi(2) + o.sd_y.map_or(0.0, |s| s * s)) / o.n as f64).sqrt()
}

/// Fitted on experiment 1 (UMBmark and Triangular Path), the model predicts experiments 2
/// and 3 from the corrections applied between them. The leg curvature the set-points would
/// cause (15/14.47) is the bulk of the gap: Ed comes out at the set-point ratio. Next comes
/// coast (a constant over-rotation per turn, which the 90° and 120° corners tell from a
/// wheelbase error). With that pair the CW squares and the line are predicted within the
/// measured scatter; the CCW squares and the triangle are not: a gap remains that no
/// kinematic effect closes, and the test pins it.
#[test]
fn experiment_1_predicts_2_and_3() {
    let d = run(&["umbmark", "triangle"], &["umbmark-1", "triangle-1"]);
    println!("{}", render_text(&d));
    assert_eq!(d.which.winner[..2], [WHEEL_DIAMETER_RATIO, COAST]);
    let w = d
        .which
        .pairs
        .iter()
        .find(|r| r.fit.effects == d.which.winner[..2])
        .unwrap();
    let ed = w.fit.estimate(WHEEL_DIAMETER_RATIO).unwrap();
    assert!((ed.value - 15.0 / 14.47).abs() < 1e-3, "{ed:?}");
    let coast = w.fit.estimate(COAST).unwrap();
    assert!((5.0..7.5).contains(&coast.value), "{coast:?}");
    assert!(coast.std_err.unwrap() < 1.0);
    // The winner carries bootstrap uncertainties over the runs: about a fifth of the
    // Jacobian's errors here (those carry the floor and the misfit too), never the rounding
    // noise of refitting the same runs.
    let winner = d.winner_fit().unwrap();
    for e in &winner.estimates {
        println!(
            "{}: {:.5} ± {:.5} (bootstrap sd {:.5})",
            e.name,
            e.value,
            e.std_err.unwrap(),
            e.bootstrap_sd.unwrap()
        );
        let (sd, se) = (e.bootstrap_sd.unwrap(), e.std_err.unwrap());
        assert!(
            sd > 0.05 * se && sd < 2.0 * se,
            "{}: {sd} against {se}",
            e.name
        );
    }

    let s = &d.shrink;
    println!(
        "held-out systematic gap: {:.2} cm before, {:.2} cm after ({:.1} % removed)",
        s.before.systematic_cm,
        s.after.systematic_cm,
        100.0 * s.reduction_systematic
    );
    assert!(s.before.systematic_cm > 200.0);
    assert!(
        (13.0..16.0).contains(&s.after.systematic_cm),
        "{}",
        s.after.systematic_cm
    );
    for p in &s.path {
        println!(
            "  {:?}: held-out systematic {:.2} cm",
            p.effects, p.systematic_cm
        );
    }
    // Group by group, with the winning pair.
    let pair = w.fit.heldout.as_ref().unwrap();
    for name in [
        "umbmark-2/umbmark_cw",
        "umbmark-3/umbmark_cw",
        "triangle-2/line",
    ] {
        let g = group(&pair.groups, name);
        println!(
            "{name}: measured ({:+.2}, {:+.2?}), predicted ({:+.2}, {:+.2}), off by {:.2} cm, \
             centroid se {:.2} cm",
            g.observed.mean_x,
            g.observed.mean_y,
            g.predicted.mean_x,
            g.predicted.mean_y,
            g.systematic_cm,
            se(g)
        );
        assert!(g.systematic_cm < 3.0 * se(g) + 2.0, "{name}: {g:?}");
    }
    for name in [
        "umbmark-2/umbmark_ccw",
        "umbmark-3/umbmark_ccw",
        "triangle-2/triangle_ccw",
    ] {
        let g = group(&pair.groups, name);
        println!(
            "{name}: measured ({:+.2}, {:+.2?}), predicted ({:+.2}, {:+.2}), off by {:.2} cm \
             (remaining gap), centroid se {:.2} cm",
            g.observed.mean_x,
            g.observed.mean_y,
            g.predicted.mean_x,
            g.predicted.mean_y,
            g.systematic_cm,
            se(g)
        );
        assert!(
            g.systematic_cm > 3.0 * se(g),
            "{name} is now explained: update the test"
        );
    }
    let md = render_markdown(&d, Some("gap.svg"));
    assert!(md.contains("## 3. How far it shrinks"));
}

/// From the UMBmark squares alone (90° corners only, no line) a wheelbase error, coast and a
/// scale error cannot be told apart next to Ed: the diagnosis says so and names the
/// measurements that separate them (turns of two angles, a measured line), which are the
/// Triangular Path's.
#[test]
fn umbmark_alone_cannot_separate_the_turn_effects() {
    let d = run(&["umbmark"], &["umbmark-1"]);
    println!("{}", render_text(&d));
    let pairs: Vec<&Vec<String>> = d
        .which
        .indistinguishable
        .iter()
        .map(|c| &c.effects)
        .collect();
    let has = |a: &str, b: &str| {
        pairs
            .iter()
            .any(|p| p.contains(&a.to_owned()) && p.contains(&b.to_owned()))
    };
    assert!(has(COAST, WHEELBASE_RATIO), "{pairs:?}");
    assert!(has(DISTANCE_SCALE, WHEELBASE_RATIO), "{pairs:?}");
    let c = d
        .which
        .indistinguishable
        .iter()
        .find(|c| c.effects.contains(&COAST.to_owned()))
        .unwrap();
    assert!(
        c.suggestion.contains("two different angles"),
        "{}",
        c.suggestion
    );
    assert_eq!(c.given, [WHEEL_DIAMETER_RATIO]);
    assert!(
        d.notes.iter().any(|n| n.contains("cannot be told apart")),
        "{:?}",
        d.notes
    );
}

/// The motor model fitted on PWM 170, 210 and 250 predicts 190 and 230: adding Coulomb
/// friction (a dead band) to a first-order model whose speed is proportional to the duty
/// cuts the held-out RMS error of both motors, and the fit is the one
/// `plant_model::identify` makes with the same levels.
#[test]
fn motor_friction_on_held_out_pwm_levels() {
    let d = run(&["umbmark-1", "umbmark-2", "motor"], &["umbmark-1"]);
    assert_eq!(d.motor.len(), 2);
    let report = plant_model::identify::holdout_report();
    for m in &d.motor {
        println!(
            "{} motor: train {:?}, held out {:?}: RMS {:.2} -> {:.2} thesis RPM ({:.0} % removed), \
             dead band PWM {:.1}",
            m.side,
            m.train,
            m.held_out,
            m.heldout_rms_before,
            m.heldout_rms_after,
            100.0 * m.reduction,
            m.after_dead_band_pwm
        );
        assert_eq!(m.held_out, [190, 230]);
        // The model without friction is the least-squares gain through zero of the
        // training levels' steady speeds against their duties.
        let (sxy, sxx) = m
            .levels
            .iter()
            .filter(|l| !l.held_out)
            .fold((0.0, 0.0), |(a, b), l| {
                let d = f64::from(l.pwm) / 255.0;
                (a + d * l.measured_steady_rpm, b + d * d)
            });
        let g = m.before_gain_rpm_per_duty;
        assert!(
            (g / (sxy / sxx) - 1.0).abs() < 1e-9,
            "{g} against {}",
            sxy / sxx
        );
        assert!(m.reduction > 0.35, "{m:?}");
        assert!(m.heldout_rms_after < 3.0, "{m:?}");
        let theirs = report
            .sides
            .iter()
            .find(|s| s.side == m.side)
            .unwrap()
            .splits
            .iter()
            .find(|s| s.train == m.train)
            .unwrap();
        for l in m.levels.iter().filter(|l| l.held_out) {
            let t = theirs.fit.levels.iter().find(|x| x.pwm == l.pwm).unwrap();
            assert!(
                (t.rms_error_rpm - l.after_rms_rpm).abs() < 1e-9,
                "{l:?} vs {t:?}"
            );
        }
    }
}
