//! The fit's pieces on cases worked by hand.

use super::*;
use crate::data::{Dataset, ObservedRun, SplitRule};
use crate::kinematic::KinematicModel;
use crate::test_support::experiment;

/// Levenberg-Marquardt raises its damping on a step that raises the cost: from x = 700 the
/// Gauss-Newton step for atan x = 0 lands near −(1 + x²)·atan x, far past the root, and
/// only a damping raised by a factor per refusal finds a step down.
#[test]
fn marquardt_damps_the_steps_gauss_newton_overshoots() {
    let f = |x: &[f64]| -> Result<Vec<f64>, GapError> { Ok(vec![x[0].atan()]) };
    let out = levenberg_marquardt(&f, &[700.0], &[-1e4], &[1e4], 200).unwrap();
    assert!(
        out.x[0].abs() < 1e-6,
        "{:?} after {}",
        out.x,
        out.iterations
    );
    assert!(out.converged);
}

/// The centroid of each group is predicted from a seed of its own: distinct between groups
/// for one seed of the options (0 included), and distinct for each seed of the options.
#[test]
fn each_group_and_each_seed_its_own_centroid_stream() {
    let exp = experiment(TestKind::UmbmarkCw, 2000.0, 5);
    let seeds = |opts: &FitOptions, tags: &[&str]| -> Vec<u64> {
        let ev = Evaluator {
            model: &KinematicModel,
            specs: KinematicModel.parameters(),
            opts: opts.clone(),
            weights: Weights {
                pooled: vec![],
                floor_cm: opts.floor_cm,
            },
        };
        tags.iter()
            .map(|t| ev.centroid_experiment(&exp, t).seed)
            .collect()
    };
    let distinct = |mut v: Vec<u64>| {
        let n = v.len();
        v.sort_unstable();
        v.dedup();
        v.len() == n
    };
    let tags = [
        "a/umbmark_cw",
        "a/umbmark_ccw",
        "a/line",
        "b/umbmark_cw",
        "b/line",
    ];
    for seed in [0, FitOptions::default().seed] {
        let opts = FitOptions {
            seed,
            ..FitOptions::default()
        };
        assert!(distinct(seeds(&opts, &tags)), "seed {seed}");
    }
    let per_seed: Vec<u64> = (0..64)
        .map(|seed| {
            let opts = FitOptions {
                seed,
                ..FitOptions::default()
            };
            seeds(&opts, &tags[..1])[0]
        })
        .collect();
    assert!(distinct(per_seed));
}

/// The excess gaps of a group, as their docs define them, for a model without scatter (its
/// spread 0, from infinitely many runs): the centroid distance beyond s²/n per axis, the
/// spread beyond s²/(2(n − 1)) per axis.
#[test]
fn the_excess_gaps_are_beyond_the_sampling_errors() {
    let xs = [1.0, 2.0, 3.0, 4.0, 5.0];
    let ys = [0.0, 1.0, 0.0, -1.0, 0.0];
    let runs: Vec<ObservedRun> = xs
        .iter()
        .zip(ys)
        .map(|(&x, y)| ObservedRun {
            x_cm: x,
            y_cm: Some(y),
            theta_rad: None,
        })
        .collect();
    let mut d = Dataset::default();
    for name in ["a", "b"] {
        let g = Group::new(
            name,
            experiment(TestKind::UmbmarkCw, 2000.0, 5),
            runs.clone(),
        )
        .unwrap();
        d.push(g).unwrap();
    }
    let (train, _) = d.split(&SplitRule::LeaveOut(vec!["b".into()])).unwrap();
    let ev = Evaluator::new(&KinematicModel, &train, &FitOptions::default());
    let g = &ev.gap(&EffectParams::new(), train.groups()).unwrap().groups[0];
    let (vx, vy) = (2.5f64, 0.5f64);
    assert_eq!(g.observed.sd_x, vx.sqrt());
    assert_eq!(g.predicted.sd_x, 0.0);
    let scatter = (vx - vx / 8.0 + vy - vy / 8.0).sqrt();
    assert!((g.scatter_excess_cm - scatter).abs() < 1e-12, "{g:?}");
    let sys2 = g.residual_x_cm.powi(2) + g.residual_y_cm.unwrap().powi(2);
    assert!(sys2 > 1.0, "{g:?}");
    let sys = (sys2 - vx / 5.0 - vy / 5.0).max(0.0).sqrt();
    assert!((g.systematic_excess_cm - sys).abs() < 1e-12, "{g:?}");
}

/// A model whose runs alternate about x = 10 cm (11, 9, 11, ...) and y = 0: what no
/// parameter holds, as the bench's start phase.
struct Alternating;

impl Model for Alternating {
    fn name(&self) -> String {
        "alternating".to_owned()
    }
    fn parameters(&self) -> Vec<ParamSpec> {
        vec![]
    }
    fn predict(
        &self,
        _params: &EffectParams,
        exp: &crate::model::Experiment,
    ) -> Result<Vec<crate::model::RunEndpoint>, crate::ModelError> {
        Ok((0..exp.runs)
            .map(|i| crate::model::RunEndpoint {
                x_cm: if i % 2 == 0 { 11.0 } else { 9.0 },
                y_cm: 0.0,
                theta_rad: 0.0,
            })
            .collect())
    }
}

/// With several centroid runs the centroid is their mean and its standard error (their
/// spread over √k) adds to the real one's in the residual's weight and is subtracted, as
/// sampling error, from the excess gap; with one run the centroid is that run, with no
/// error of its own.
#[test]
fn a_centroid_of_several_runs_is_their_mean_and_weighs_its_own_error() {
    let runs: Vec<ObservedRun> = [12.0, 12.0, 12.0, 12.0]
        .iter()
        .map(|&x| ObservedRun {
            x_cm: x,
            y_cm: Some(0.0),
            theta_rad: None,
        })
        .collect();
    let mut d = Dataset::default();
    for name in ["a", "b"] {
        d.push(Group::new(name, experiment(TestKind::Line, 2000.0, 4), runs.clone()).unwrap())
            .unwrap();
    }
    let (train, _) = d.split(&SplitRule::LeaveOut(vec!["b".into()])).unwrap();
    let g = &train.groups()[0];
    let with = |k: usize| FitOptions {
        centroid_runs: k,
        ..FitOptions::default()
    };
    let one = Evaluator::new(&Alternating, &train, &with(1));
    let p = one.predict(&EffectParams::new(), g).unwrap();
    assert_eq!((p.mean_x, p.se_x, p.se_y), (11.0, 0.0, 0.0));
    let four = Evaluator::new(&Alternating, &train, &with(4));
    let p = four.predict(&EffectParams::new(), g).unwrap();
    let se = (4.0f64 / 3.0).sqrt() / 2.0;
    assert_eq!(p.mean_x, 10.0);
    assert!((p.se_x - se).abs() < 1e-12 && p.se_y == 0.0, "{p:?}");
    // The real runs agree exactly: the weight is the model's error and the floor.
    let floor2 = FitOptions::default().floor_cm.powi(2);
    let r = crate::Scorer::new(&Alternating, &train, &with(4))
        .centroid_residuals(&EffectParams::new(), g)
        .unwrap();
    assert!(
        (r[0] - 2.0 / (se * se + floor2).sqrt()).abs() < 1e-12,
        "{r:?}"
    );
    let gap = four.gap(&EffectParams::new(), train.groups()).unwrap();
    let excess = (4.0 - se * se).sqrt();
    assert!(
        (gap.groups[0].systematic_excess_cm - excess).abs() < 1e-12,
        "{gap:?}"
    );
}
