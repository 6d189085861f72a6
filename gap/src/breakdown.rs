//! Where the gap lies: the residual real − sim of each experiment's centroids decomposed into
//! the classical odometry error types, and the scatter.
//!
//! For the geometry of each test (leg length, corner angle, direction) the first-order
//! signatures of three systematic errors are computed numerically from an exact path:
//!
//! * **α** (type A, Borenstein): every corner turns α less than commanded (rad per corner;
//!   negative = over-rotation);
//! * **β** (type B): every leg's heading changes uniformly by β (rad per leg, left positive),
//!   a curved leg;
//! * **scale**: every leg is (1 + s) times as long as commanded.
//!
//! The centroid residuals of an experiment's groups (x and y where recorded) are then fitted
//! by weighted least squares (weights as in [`crate::fit`]); what the three cannot explain is
//! the *remainder*. For a UMBmark pair this is Borenstein's α and β from all four numbers at
//! once; a single direction cannot separate α from β, and a closed polygon has no scale
//! signature at all: components the data do not determine are reported as such, never as a
//! number.

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use crate::data::Group;
use crate::fit::{Gap, GroupGap, Weights};
use crate::model::TestKind;

/// One component of the decomposition.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Component {
    /// Value (`None` when the data do not determine it).
    pub value: Option<f64>,
    /// Standard error (covariance inflated by χ²/dof when above 1).
    pub std_err: Option<f64>,
}

/// The scatter of one group.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Scatter {
    /// The group.
    pub group: String,
    /// Runs.
    pub n: usize,
    /// Variance of x between runs, cm².
    pub var_x_cm2: f64,
    /// Variance of y, cm² (when recorded).
    pub var_y_cm2: Option<f64>,
    /// Covariance, cm².
    pub cov_xy_cm2: Option<f64>,
    /// Standard error of the centroid, cm (√(trace/n)).
    pub centroid_se_cm: f64,
}

/// The decomposition of one experiment's residual.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Decomposition {
    /// The experiment.
    pub experiment: String,
    /// Its groups.
    pub groups: Vec<String>,
    /// α, degrees per corner (under-rotation positive).
    pub alpha_deg: Component,
    /// β, degrees per leg (left positive).
    pub beta_deg: Component,
    /// Scale error of the legs, %.
    pub scale_pct: Component,
    /// RMS of the centroid residual the three leave unexplained, cm.
    pub remainder_cm: f64,
    /// RMS of the centroid residual before the decomposition, cm.
    pub residual_cm: f64,
    /// The scatter of each group.
    pub scatter: Vec<Scatter>,
    /// Remarks.
    pub notes: Vec<String>,
}

/// End error (x, y) in cm of an ideal path with corner error α, leg curvature β and scale s.
fn signature_path(
    test: TestKind,
    leg_mm: f64,
    turn_deg: f64,
    a: f64,
    b: f64,
    s: f64,
) -> (f64, f64) {
    let turn = turn_deg.to_radians();
    let sign = test.turn_sign();
    let (mut x, mut y, mut th) = (0.0f64, 0.0f64, 0.0f64);
    let (mut cx, mut cy) = (0.0f64, 0.0f64);
    for k in 0..test.legs() {
        let l = leg_mm * (1.0 + s);
        if b.abs() < 1e-15 {
            x += l * th.cos();
            y += l * th.sin();
        } else {
            let r = l / b;
            x += r * ((th + b).sin() - th.sin());
            y += r * (th.cos() - (th + b).cos());
        }
        th += b;
        let h = sign * turn * k as f64;
        cx += leg_mm * h.cos();
        cy += leg_mm * h.sin();
        if test != TestKind::Line {
            th += sign * (turn - a);
        }
    }
    ((x - cx) / 10.0, (y - cy) / 10.0)
}

/// d(x, y)/d(α, β, s) at zero, cm per unit.
fn signatures(test: TestKind, leg_mm: f64, turn_deg: f64) -> [[f64; 3]; 2] {
    let h = 1e-6;
    let mut out = [[0.0; 3]; 2];
    for i in 0..3 {
        let mut p = [0.0; 3];
        p[i] = h;
        let up = signature_path(test, leg_mm, turn_deg, p[0], p[1], p[2]);
        p[i] = -h;
        let dn = signature_path(test, leg_mm, turn_deg, p[0], p[1], p[2]);
        out[0][i] = (up.0 - dn.0) / (2.0 * h);
        out[1][i] = (up.1 - dn.1) / (2.0 * h);
    }
    out
}

/// Decomposes the residual (real − sim) of the groups of one experiment.
pub fn decompose(
    experiment: &str,
    groups: &[&Group],
    gaps: &[&GroupGap],
    floor_cm: f64,
) -> Decomposition {
    let owned: Vec<Group> = groups.iter().map(|g| (*g).clone()).collect();
    let w = Weights::from_groups(&owned, floor_cm);
    let mut rows: Vec<[f64; 3]> = Vec::new();
    let mut rhs = Vec::new();
    let mut wts = Vec::new();
    let mut scatter = Vec::new();
    for (g, gap) in groups.iter().zip(gaps) {
        let st = g.stats();
        let fw = &g.experiment.firmware;
        let sig = signatures(g.id.test, fw.leg_mm, g.id.test.turn_deg(fw));
        let (vx, vy) = w.var(g.id.test);
        let n = st.n as f64;
        rows.push(sig[0]);
        rhs.push(gap.residual_x_cm);
        wts.push(1.0 / (vx / n + floor_cm * floor_cm).sqrt());
        if let Some(ry) = gap.residual_y_cm {
            rows.push(sig[1]);
            rhs.push(ry);
            wts.push(1.0 / (vy / n + floor_cm * floor_cm).sqrt());
        }
        let var_x = st.sd_x.powi(2);
        let var_y = st.sd_y.map(|s| s * s);
        scatter.push(Scatter {
            group: g.id.to_string(),
            n: st.n,
            var_x_cm2: var_x,
            var_y_cm2: var_y,
            cov_xy_cm2: st.cov_xy,
            centroid_se_cm: ((var_x + var_y.unwrap_or(0.0)) / n).sqrt(),
        });
    }
    let m = rows.len();
    let a = DMatrix::from_fn(m, 3, |i, j| rows[i][j] * wts[i]);
    let b = DVector::from_fn(m, |i, _| rhs[i] * wts[i]);
    let residual_cm = (rhs.iter().map(|r| r * r).sum::<f64>() / m.max(1) as f64).sqrt();
    let svd = a.clone().svd(true, true);
    let smax = svd.singular_values.max();
    let tol = 1e-8 * smax.max(1e-300);
    let v_t = svd.v_t.clone().expect("requested");
    let u = svd.u.clone().expect("requested");
    // Pseudo-inverse solution and which components the null space touches.
    let mut theta = DVector::zeros(3);
    let mut cov = DMatrix::zeros(3, 3);
    let mut null: Vec<DVector<f64>> = Vec::new();
    for (k, &s) in svd.singular_values.iter().enumerate() {
        let vk = v_t.row(k).transpose();
        if s > tol {
            let coef = u.column(k).dot(&b) / s;
            theta += &vk * coef;
            cov += &vk * vk.transpose() / (s * s);
        } else {
            null.push(vk);
        }
    }
    // Directions not reached by the SVD (fewer rows than 3) are null too.
    if svd.singular_values.len() < 3 {
        let basis: Vec<DVector<f64>> = (0..v_t.nrows()).map(|k| v_t.row(k).transpose()).collect();
        for e in 0..3 {
            let mut ev = DVector::zeros(3);
            ev[e] = 1.0;
            let proj: DVector<f64> = basis
                .iter()
                .fold(DVector::zeros(3), |acc, vk| acc + vk * vk.dot(&ev));
            let rest = &ev - proj;
            if rest.norm() > 1e-9 {
                null.push(rest.normalize());
            }
        }
    }
    let determined = |i: usize| null.iter().all(|v| v[i].abs() < 1e-6);
    let fitted = &a * &theta;
    let chi2 = (&b - &fitted).norm_squared();
    let rank = svd.singular_values.iter().filter(|&&s| s > tol).count();
    let dof = m.saturating_sub(rank).max(1) as f64;
    let s2 = (chi2 / dof).max(1.0);
    let unexplained: Vec<f64> = (0..m)
        .map(|i| rhs[i] - (0..3).map(|j| rows[i][j] * theta[j]).sum::<f64>())
        .collect();
    let remainder_cm = (unexplained.iter().map(|r| r * r).sum::<f64>() / m.max(1) as f64).sqrt();
    let comp = |i: usize, k: f64| {
        if determined(i) {
            Component {
                value: Some(theta[i] * k),
                std_err: Some((cov[(i, i)] * s2).sqrt() * k),
            }
        } else {
            Component {
                value: None,
                std_err: None,
            }
        }
    };
    let mut notes = Vec::new();
    let names = ["α", "β", "scale"];
    let undetermined: Vec<&str> = (0..3)
        .filter(|&i| !determined(i))
        .map(|i| names[i])
        .collect();
    if !undetermined.is_empty() {
        notes.push(format!(
            "not determined by these tests: {} (a single direction mixes α and β; a closed \
             polygon has no scale signature; a line has no corners)",
            undetermined.join(", ")
        ));
    }
    Decomposition {
        experiment: experiment.to_owned(),
        groups: groups.iter().map(|g| g.id.to_string()).collect(),
        alpha_deg: comp(0, 180.0 / std::f64::consts::PI),
        beta_deg: comp(1, 180.0 / std::f64::consts::PI),
        scale_pct: comp(2, 100.0),
        remainder_cm,
        residual_cm,
        scatter,
        notes,
    }
}

/// Decompositions of every experiment in `groups`, against the residuals in `gap` (same
/// order as `groups`).
pub fn decompose_all(groups: &[Group], gap: &Gap, floor_cm: f64) -> Vec<Decomposition> {
    let mut names: Vec<&str> = Vec::new();
    for g in groups {
        if !names.contains(&g.id.experiment.as_str()) {
            names.push(&g.id.experiment);
        }
    }
    names
        .iter()
        .map(|name| {
            let idx: Vec<usize> = (0..groups.len())
                .filter(|&i| groups[i].id.experiment == *name)
                .collect();
            let gs: Vec<&Group> = idx.iter().map(|&i| &groups[i]).collect();
            let gg: Vec<&GroupGap> = idx.iter().map(|&i| &gap.groups[i]).collect();
            decompose(name, &gs, &gg, floor_cm)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::{ObservedRun, Stats};
    use crate::fit::Predicted;

    const LEG_MM: f64 = 2000.0;

    /// The end error (x, y) in cm of `test` driven with every corner turning `alpha` rad
    /// short and every leg bending by `beta` rad and stretched by `scale`, integrated in
    /// small straight steps: independent of the arcs of `signature_path`.
    fn driven(test: TestKind, alpha: f64, beta: f64, scale: f64) -> (f64, f64) {
        let steps = 2000;
        let turn = 90f64.to_radians() * test.turn_sign();
        let (mut x, mut y, mut th) = (0.0f64, 0.0f64, 0.0f64);
        let (mut ix, mut iy, mut ith) = (0.0f64, 0.0f64, 0.0f64);
        for _ in 0..test.legs() {
            let dl = LEG_MM * (1.0 + scale) / steps as f64;
            for _ in 0..steps {
                // The heading halfway through the step: second order in the step.
                let mid = th + 0.5 * beta / steps as f64;
                x += dl * mid.cos();
                y += dl * mid.sin();
                th += beta / steps as f64;
            }
            ix += LEG_MM * ith.cos();
            iy += LEG_MM * ith.sin();
            th += turn - test.turn_sign() * alpha;
            ith += turn;
        }
        ((x - ix) / 10.0, (y - iy) / 10.0)
    }

    fn group(test: TestKind, residual: (f64, f64)) -> (Group, GroupGap) {
        let experiment = crate::test_support::experiment(test, LEG_MM, 1);
        let run = ObservedRun {
            x_cm: 0.0,
            y_cm: Some(0.0),
            theta_rad: None,
        };
        let g = Group::new("e", experiment, vec![run]).unwrap();
        let zero = Predicted {
            mean_x: 0.0,
            mean_y: 0.0,
            sd_x: 0.0,
            sd_y: 0.0,
            mean_theta_deg: 0.0,
            se_x: 0.0,
            se_y: 0.0,
        };
        let gap = GroupGap {
            group: g.id.to_string(),
            observed: Stats::of(&[0.0], Some(&[0.0])),
            predicted: zero,
            residual_x_cm: residual.0,
            residual_y_cm: Some(residual.1),
            systematic_cm: 0.0,
            scatter_cm: 0.0,
            systematic_excess_cm: 0.0,
            scatter_excess_cm: 0.0,
        };
        (g, gap)
    }

    fn decomposed(tests: &[(TestKind, (f64, f64))]) -> Decomposition {
        let (groups, gaps): (Vec<Group>, Vec<GroupGap>) =
            tests.iter().map(|&(t, r)| group(t, r)).unzip();
        let gs: Vec<&Group> = groups.iter().collect();
        let gg: Vec<&GroupGap> = gaps.iter().collect();
        decompose("e", &gs, &gg, 0.5)
    }

    fn close(c: &Component, want: f64, rel: f64) {
        let v = c.value.expect("determined");
        assert!((v / want - 1.0).abs() < rel, "{v} against {want}");
    }

    /// A UMBmark pair determines α and β (to first order: 1 % at these sizes), never the
    /// scale of a closed square.
    #[test]
    fn a_umbmark_pair_gives_alpha_and_beta() {
        let (a, b) = (0.5f64.to_radians(), 0.2f64.to_radians());
        let d = decomposed(&[
            (TestKind::UmbmarkCw, driven(TestKind::UmbmarkCw, a, b, 0.0)),
            (
                TestKind::UmbmarkCcw,
                driven(TestKind::UmbmarkCcw, a, b, 0.0),
            ),
        ]);
        close(&d.alpha_deg, 0.5, 0.02);
        close(&d.beta_deg, 0.2, 0.02);
        assert_eq!(d.scale_pct.value, None);
        assert!(d.notes[0].contains("scale"), "{:?}", d.notes);
        assert!(d.remainder_cm < 0.05 * d.residual_cm, "{d:?}");
    }

    /// A line determines its curvature and its scale, and has no corners.
    #[test]
    fn a_line_gives_beta_and_scale() {
        let b = 0.3f64.to_radians();
        let d = decomposed(&[(TestKind::Line, driven(TestKind::Line, 0.0, b, 0.02))]);
        close(&d.beta_deg, 0.3, 0.02);
        close(&d.scale_pct, 2.0, 0.02);
        assert_eq!(d.alpha_deg.value, None);
    }

    /// The remainder is the rms, over the numbers fitted, of what the fitted components
    /// leave of the residual.
    #[test]
    fn the_remainder_is_what_the_components_leave() {
        let tests = [
            (TestKind::UmbmarkCw, (3.0, -1.0)),
            (TestKind::UmbmarkCcw, (2.0, 4.0)),
        ];
        let d = decomposed(&tests);
        let k = 180.0 / std::f64::consts::PI;
        let theta = [
            d.alpha_deg.value.unwrap() / k,
            d.beta_deg.value.unwrap() / k,
        ];
        let mut left = Vec::new();
        for (t, (x, y)) in tests {
            let sig = signatures(t, LEG_MM, 90.0);
            left.push(x - sig[0][0] * theta[0] - sig[0][1] * theta[1]);
            left.push(y - sig[1][0] * theta[0] - sig[1][1] * theta[1]);
        }
        let rms = (left.iter().map(|r| r * r).sum::<f64>() / 4.0).sqrt();
        assert!(
            rms > 0.3 * d.residual_cm,
            "a residual the two explain badly"
        );
        assert!(
            (d.remainder_cm - rms).abs() < 1e-9 * rms,
            "{d:?} against {rms}"
        );
        let all = (tests.iter().map(|(_, (x, y))| x * x + y * y).sum::<f64>() / 4.0).sqrt();
        assert!((d.residual_cm - all).abs() < 1e-12, "{d:?}");
        // The errors are those of a perfect fit inflated by √(χ²/dof), χ² weighted by
        // 1/floor (0.5 cm; one run, no scatter) and 4 numbers less 2 components.
        let exact = decomposed(&[
            (TestKind::UmbmarkCw, (0.0, 0.0)),
            (TestKind::UmbmarkCcw, (0.0, 0.0)),
        ]);
        let chi2 = left.iter().map(|r| (r / 0.5).powi(2)).sum::<f64>();
        let inflation = (chi2 / 2.0).sqrt();
        assert!(inflation > 2.0);
        for (c, e) in [
            (&d.alpha_deg, &exact.alpha_deg),
            (&d.beta_deg, &exact.beta_deg),
        ] {
            let ratio = c.std_err.unwrap() / e.std_err.unwrap();
            assert!(
                (ratio / inflation - 1.0).abs() < 1e-9,
                "{ratio} against {inflation}"
            );
        }
    }
}
