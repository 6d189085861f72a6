//! The regression steps that end a joint fit of three effects (see `joint.rs`).
//!
//! The bench's answer is rough at the scale of a finite difference: a change of a coast
//! time constant by 0.2 % moves the tick on which one of the firmware's stops falls, and
//! with it one run's end point, so a centroid of [`super::CENTROID_RUNS`] runs jumps by
//! several standard errors where the robot's expected end point moves smoothly. Where two
//! effects trade off in the end points (a wider wheelbase and a longer coast both change
//! UMBmark's turns), Levenberg-Marquardt then stops in whichever dip of that roughness lies
//! nearest its start: on self-test robots hiding Ed, Eb and coasting it left the coast 5 to
//! 16 % short of the hidden value in 6 of 6 seeds, and the wheelbase up to 40 % off.
//!
//! A regression step looks at the trend instead of the dips. It evaluates a design around
//! the fit's point, the centre, ± [`RADIUS`] scales along each effect and each corner of
//! that cube (1 + 2k + 2^k points, 15 for three effects), regresses every residual on the
//! values over it (a linear model: intercept and slope per effect, least squares), and
//! moves to the Gauss-Newton minimum of that model, at most [`RADIUS`] scales along each
//! effect. Steps are repeated from each new point, and the fit's values are the mean of
//! the points they reach (the average that makes a stochastic approximation's estimate
//! settle; each step alone still carries the roughness left in its regression).

use super::linalg::{inverse, normal_equations, solve};

/// Half-width of the design, in scales of each effect ([`gap::ParamSpec::scale`]): wide
/// enough that the trend over it outweighs the jumps, narrow enough that the end points
/// are nearly linear in the values over it. Measured on the three-effect self-test robot
/// over 6 seeds with 3 steps: at 1 scale (the last step's point) the wheelbase was within
/// 10 % in 1 of 6, at 2 scales (the steps' mean) in 4 of 6.
pub(super) const RADIUS: f64 = 2.0;

/// The design's offsets from its centre, in scales: the centre, ± [`RADIUS`] along each
/// of `k` effects, and the 2^k corners.
pub(super) fn design(k: usize) -> Vec<Vec<f64>> {
    let mut out = vec![vec![0.0; k]];
    for i in 0..k {
        for sign in [-1.0, 1.0] {
            let mut d = vec![0.0; k];
            d[i] = sign * RADIUS;
            out.push(d);
        }
    }
    for corner in 0..(1usize << k) {
        out.push(
            (0..k)
                .map(|i| {
                    if corner >> i & 1 == 1 {
                        RADIUS
                    } else {
                        -RADIUS
                    }
                })
                .collect(),
        );
    }
    out
}

/// The linear model of the residuals over one design.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Trend {
    /// Its Gauss-Newton step from the design's centre, in scales, each component kept
    /// within ± [`RADIUS`].
    pub(super) step: Vec<f64>,
    /// Its slopes: one column per effect (per scale), one row per residual.
    pub(super) jacobian: Vec<Vec<f64>>,
}

/// The linear model of `residuals` (one vector per design point) regressed on `offsets`
/// (the points' offsets from the centre, in scales). None when the design or the model
/// leaves a direction undetermined.
pub(super) fn trend(offsets: &[Vec<f64>], residuals: &[Vec<f64>]) -> Option<Trend> {
    let k = offsets.first()?.len();
    let n = residuals.first()?.len();
    if offsets.len() != residuals.len() || residuals.iter().any(|r| r.len() != n) {
        return None;
    }
    // Regressors: 1 and each offset.
    let x: Vec<Vec<f64>> = offsets
        .iter()
        .map(|d| std::iter::once(1.0).chain(d.iter().copied()).collect())
        .collect();
    let xtx: Vec<Vec<f64>> = (0..=k)
        .map(|a| {
            (0..=k)
                .map(|b| x.iter().map(|row| row[a] * row[b]).sum())
                .collect()
        })
        .collect();
    let inv = inverse(&xtx)?;
    // coef[a][i]: regressor a's coefficient in residual i (a = 0 the intercept).
    let mut coef = vec![vec![0.0; n]; k + 1];
    for i in 0..n {
        let xty: Vec<f64> = (0..=k)
            .map(|a| x.iter().zip(residuals).map(|(row, r)| row[a] * r[i]).sum())
            .collect();
        for (a, c) in coef.iter_mut().enumerate() {
            c[i] = (0..=k).map(|b| inv[a][b] * xty[b]).sum();
        }
    }
    let (jtj, jtr) = normal_equations(&coef[1..], &coef[0]);
    let s = solve(&jtj, &jtr.iter().map(|g| -g).collect::<Vec<_>>())?;
    Some(Trend {
        step: s.iter().map(|d| d.clamp(-RADIUS, RADIUS)).collect(),
        jacobian: coef.split_off(1),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two effects on a ridge (the first residual moves with their sum, the second a fifth
    /// as much with their difference, as a wheelbase and a coast share UMBmark's turns),
    /// their trend's minimum at (0.7, −0.4) scales from the centre, and a roughness of the
    /// bench's kind: a deterministic jump at every point, uniform over ± 0.3. Over 20
    /// draws of that roughness the regression step lands on average within 0.5 scale of
    /// the trend's minimum, and less than half as far as the step of a forward difference
    /// of 0.3 scales (the Levenberg-Marquardt Jacobian's), which follows the roughness.
    #[test]
    fn a_regression_step_follows_the_trend_not_the_roughness() {
        let truth = [0.7, -0.4];
        let (mut regression_miss, mut local_miss) = (0.0, 0.0);
        let draws = 20;
        for draw in 0..draws {
            let jump = |a: f64, b: f64| {
                let h = ((a * 12.9898 + b * 78.233 + f64::from(draw) * 0.618).sin() * 43_758.545_3)
                    .fract();
                0.6 * (h.abs() - 0.5)
            };
            let rough = |d: &[f64]| -> Vec<f64> {
                let (u, v) = (d[0] - truth[0], d[1] - truth[1]);
                vec![
                    u + v + jump(d[0], d[1]),
                    0.2 * (u - v) + jump(d[1] + 0.37, d[0]),
                ]
            };
            let offsets = design(2);
            let residuals: Vec<Vec<f64>> = offsets.iter().map(|d| rough(d)).collect();
            let s = trend(&offsets, &residuals).unwrap().step;
            regression_miss += (s[0] - truth[0]).hypot(s[1] - truth[1]) / f64::from(draws);

            let h = 0.3;
            let r0 = rough(&[0.0, 0.0]);
            let jac: Vec<Vec<f64>> = (0..2)
                .map(|i| {
                    let mut d = vec![0.0, 0.0];
                    d[i] = h;
                    rough(&d)
                        .iter()
                        .zip(&r0)
                        .map(|(a, b)| (a - b) / h)
                        .collect()
                })
                .collect();
            let (a, g) = normal_equations(&jac, &r0);
            let local = solve(&a, &g.iter().map(|x| -x).collect::<Vec<_>>())
                .map_or(vec![0.0, 0.0], |l| {
                    l.iter().map(|d| d.clamp(-RADIUS, RADIUS)).collect()
                });
            local_miss += (local[0] - truth[0]).hypot(local[1] - truth[1]) / f64::from(draws);
        }
        assert!(
            regression_miss < 0.5 && regression_miss < 0.5 * local_miss,
            "mean miss of the regression step {regression_miss:.3} scales, of the local step {local_miss:.3}"
        );
    }

    /// A step is kept within the design; a design with no extent along an effect, or
    /// residuals of unequal lengths, give none.
    #[test]
    fn steps_stay_within_the_design_and_undetermined_ones_are_refused() {
        let offsets = design(1);
        let far: Vec<Vec<f64>> = offsets.iter().map(|d| vec![d[0] - 10.0]).collect();
        assert_eq!(trend(&offsets, &far).unwrap().step, vec![RADIUS]);
        let flat = vec![vec![0.0]; 3];
        assert_eq!(trend(&flat, &[vec![1.0], vec![2.0], vec![3.0]]), None);
        assert_eq!(trend(&offsets, &[vec![1.0], vec![2.0, 0.0]]), None);
    }
}
