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
