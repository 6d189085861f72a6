//! The bench as the gap model (`hil::runs::gap_bench::BenchModel`): effects move its predictions
//! the way the physics says, the answer depends on the seed only (not on the job count), and
//! the nominal robot's own behaviour is in the model: a nominal bench dataset leaves it a
//! residual at noise level where the kinematic model shows a systematic gap.

#[path = "support/mod.rs"]
mod support;

use gap::data::{Dataset, Group, ObservedRun, SplitRule};
use gap::effects::{DEAD_BAND, FLOOR_NOISE};
use gap::model::{Experiment, Firmware, Model, TestKind};
use gap::{EffectParams, FitOptions, KinematicModel, Scorer};
use hil::runs::gap_bench::BenchModel;
use plant_model::RobotConfig;

const LEG_MM: f64 = 300.0;

fn bench(jobs: usize) -> BenchModel {
    BenchModel::new(support::firmware("robust"), RobotConfig::default(), jobs)
}

fn experiment(bench: &BenchModel, test: TestKind, runs: usize, seed: u64) -> Experiment {
    let reference = bench.reference();
    Experiment {
        test,
        firmware: Firmware::nominal(&reference, LEG_MM),
        reference,
        runs,
        seed,
    }
}

/// A left dead band kicks the heading towards the stiffer side (`plant_model::effects::
/// dead_band`'s signature: the controller winds up past it at the start, and the stiffer
/// wheel stops first when the motors are cut), so the line ends to the left of the nominal
/// robot's (y larger); a right one to the right.
#[test]
fn a_dead_band_curves_the_line_towards_its_side() {
    let b = bench(2);
    let line = experiment(&b, TestKind::Line, 1, 7);
    let y = |v: f64| {
        let p = EffectParams::new().with(DEAD_BAND, v);
        b.predict(&p, &line).unwrap()[0].y_cm
    };
    let (left, nominal, right) = (y(0.15), y(0.0), y(-0.15));
    assert!(
        left > nominal + 0.2 && right < nominal - 0.2,
        "left dead band {left:.2} cm, nominal {nominal:.2} cm, right {right:.2} cm"
    );
}

/// Run i's seed comes from the experiment's seed and i: the same seed gives the same runs,
/// on one thread or two; another seed other runs (floor noise on, so runs differ).
#[test]
fn same_seed_same_runs_for_any_job_count() {
    let noisy = EffectParams::new().with(FLOOR_NOISE, 2.0);
    let exp = experiment(&bench(1), TestKind::Line, 3, 11);
    let one = bench(1).predict(&noisy, &exp).unwrap();
    let two = bench(2).predict(&noisy, &exp).unwrap();
    assert_eq!(one, two);
    assert_eq!(one, bench(2).predict(&noisy, &exp).unwrap());
    assert_ne!(one[0], one[1], "runs of one experiment differ");
    let other = bench(2)
        .predict(&noisy, &Experiment { seed: 12, ..exp })
        .unwrap();
    assert_ne!(one, other);
}

/// Data from the nominal bench robot (5 runs per group, floor noise 1°/√m): the nominal
/// bench model predicts them to noise level, the kinematic model (which lacks the firmware's
/// overshoot and start-up) far from it.
#[test]
fn the_nominal_robot_is_in_the_model() {
    let b = bench(2);
    let tests = [
        TestKind::UmbmarkCw,
        TestKind::UmbmarkCcw,
        TestKind::Line,
        TestKind::TriangleCcw,
    ];
    let noisy = EffectParams::new().with(FLOOR_NOISE, 1.0);
    let requests: Vec<_> = tests
        .iter()
        .enumerate()
        .map(|(i, &t)| (noisy.clone(), experiment(&b, t, 5, 100 + i as u64)))
        .collect();
    let mut groups = Vec::new();
    for ((_, exp), runs) in requests.iter().zip(b.predict_many(&requests)) {
        let runs = runs
            .unwrap()
            .into_iter()
            .map(|r| ObservedRun {
                x_cm: r.x_cm,
                y_cm: Some(r.y_cm),
                theta_rad: Some(r.theta_rad),
            })
            .collect();
        groups.push(Group::new("nominal", exp.clone(), runs).unwrap());
    }
    let rule = SplitRule::TrainOnTests(vec![
        TestKind::UmbmarkCw,
        TestKind::UmbmarkCcw,
        TestKind::Line,
    ]);
    let (train, _held) = Dataset::new(groups).unwrap().split(&rule).unwrap();
    // Each model with its own options: the bench's centroids are means of runs from
    // several start phases.
    let chi2 = |m: &dyn Model, opts: &FitOptions| -> (f64, usize) {
        let sc = Scorer::new(m, &train, opts);
        let r: Vec<f64> = train
            .groups()
            .iter()
            .flat_map(|g| sc.centroid_residuals(&EffectParams::new(), g).unwrap())
            .collect();
        (r.iter().map(|x| x * x).sum(), r.len())
    };
    let (bench_chi2, n) = chi2(&b, &hil::runs::gap_bench::SelectOptions::default().fit);
    let (kin_chi2, _) = chi2(&KinematicModel, &FitOptions::default());
    let p = gap::stats::chi2_sf(bench_chi2, n);
    assert!(
        p > 0.01,
        "the nominal bench leaves χ² {bench_chi2:.1} over {n} residuals (p = {p:.2e})"
    );
    assert!(
        kin_chi2 > 100.0 * n as f64,
        "the kinematic model's χ² is only {kin_chi2:.1} over {n} residuals"
    );
}

/// A model's clones share their answers: a question asked again, of the model or of a clone,
/// runs nothing and is answered the same to the bit as by a model that runs it; a question
/// whose series are asked for after its end points alone runs again, once; a builder that
/// changes what a run depends on starts with no answers.
#[test]
fn a_question_asked_again_is_not_run_again() {
    let b = bench(2);
    let noisy = EffectParams::new().with(FLOOR_NOISE, 2.0);
    let exp = experiment(&b, TestKind::Line, 2, 21);
    let first = b.predict(&noisy, &exp).unwrap();
    assert_eq!(b.runs_made(), 2);
    let clone = b.clone();
    assert_eq!(clone.predict(&noisy, &exp).unwrap(), first);
    assert_eq!(b.runs_made(), 2, "the clone ran the question again");
    assert_eq!(bench(2).predict(&noisy, &exp).unwrap(), first);
    let ask = |m: &BenchModel| m.run_many(&[(noisy.clone(), exp.clone())], true);
    let with_series = ask(&b).remove(0).unwrap();
    assert_eq!((with_series.0, with_series.1.len()), (first.clone(), 2));
    assert_eq!(b.runs_made(), 4, "the series were run");
    assert_eq!(ask(&clone).remove(0).unwrap().1.len(), 2);
    assert_eq!(b.runs_made(), 4, "the series were run again");
    let other = b.clone().with_params(Vec::new());
    assert_eq!(other.runs_made(), 0);
    assert_eq!(other.predict(&noisy, &exp).unwrap(), first);
    assert_eq!(other.runs_made(), 2);
}
