//! Levenberg-Marquardt within bounds on weighted residuals, with a forward-difference
//! Jacobian, and the covariance of the minimum it finds.

use nalgebra::{DMatrix, DVector};

use crate::GapError;

/// Residuals as a function of the scaled parameters.
pub(super) type Residuals<'a> = dyn Fn(&[f64]) -> Result<Vec<f64>, GapError> + 'a;

/// Standard errors, correlation matrix and condition number of a fit.
pub(super) struct Covariance {
    pub(super) std_err: Option<Vec<f64>>,
    pub(super) correlation: Option<Vec<Vec<f64>>>,
    pub(super) condition: f64,
}

pub(super) struct LmOut {
    pub(super) x: Vec<f64>,
    pub(super) chi2: f64,
    pub(super) jac: DMatrix<f64>,
    pub(super) iterations: usize,
    pub(super) converged: bool,
}

pub(super) fn jacobian(
    f: &Residuals,
    x: &[f64],
    r0: &[f64],
    lo: &[f64],
    hi: &[f64],
) -> Result<DMatrix<f64>, GapError> {
    let h = 1e-4;
    let mut j = DMatrix::zeros(r0.len(), x.len());
    for i in 0..x.len() {
        let up = (x[i] + h).min(hi[i]);
        let dn = (x[i] - h).max(lo[i]);
        let mut xu = x.to_vec();
        xu[i] = up;
        let mut xd = x.to_vec();
        xd[i] = dn;
        let ru = if up != x[i] { f(&xu)? } else { r0.to_vec() };
        let rd = if dn != x[i] { f(&xd)? } else { r0.to_vec() };
        let span = up - dn;
        if span <= 0.0 {
            continue;
        }
        for k in 0..r0.len() {
            j[(k, i)] = (ru[k] - rd[k]) / span;
        }
    }
    Ok(j)
}

pub(super) fn sq(r: &[f64]) -> f64 {
    r.iter().map(|v| v * v).sum()
}

/// Levenberg-Marquardt on `f` (residuals) from `x0` within [lo, hi] (projected steps).
pub(super) fn levenberg_marquardt(
    f: &Residuals,
    x0: &[f64],
    lo: &[f64],
    hi: &[f64],
    max_iter: usize,
) -> Result<LmOut, GapError> {
    let clamp = |x: &mut Vec<f64>| {
        for i in 0..x.len() {
            x[i] = x[i].clamp(lo[i], hi[i]);
        }
    };
    let mut x = x0.to_vec();
    clamp(&mut x);
    let mut r = f(&x)?;
    let mut chi = sq(&r);
    let mut lambda = 1e-3;
    let mut iterations = 0;
    let mut converged = false;
    while iterations < max_iter {
        iterations += 1;
        let j = jacobian(f, &x, &r, lo, hi)?;
        let rv = DVector::from_column_slice(&r);
        let g = j.transpose() * &rv;
        let a = j.transpose() * &j;
        let mut accepted = false;
        let mut last_step = 0.0;
        for _ in 0..12 {
            let mut m = a.clone();
            for i in 0..x.len() {
                m[(i, i)] += lambda * a[(i, i)].max(1e-9);
            }
            let Some(delta) = m.lu().solve(&(-&g)) else {
                lambda *= 10.0;
                continue;
            };
            let mut xn: Vec<f64> = x.iter().zip(delta.iter()).map(|(a, d)| a + d).collect();
            clamp(&mut xn);
            let rn = f(&xn)?;
            let chin = sq(&rn);
            if chin < chi {
                last_step = xn
                    .iter()
                    .zip(&x)
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max);
                let gain = chi - chin;
                x = xn;
                r = rn;
                chi = chin;
                lambda = (lambda / 10.0).max(1e-12);
                accepted = true;
                if gain <= 1e-10 * (1.0 + chi) {
                    converged = true;
                }
                break;
            }
            lambda *= 10.0;
        }
        if !accepted || converged || last_step < 1e-9 {
            converged = true;
            break;
        }
    }
    let jac = jacobian(f, &x, &r, lo, hi)?;
    Ok(LmOut {
        x,
        chi2: chi,
        jac,
        iterations,
        converged,
    })
}

/// Covariance-derived numbers of a fit in scaled units: (std errors, correlation, cond).
pub(super) fn covariance(jac: &DMatrix<f64>, chi2: f64) -> Covariance {
    let k = jac.ncols();
    let n = jac.nrows();
    // Condition number of the column-normalised Jacobian.
    let mut jn = jac.clone();
    for c in 0..k {
        let norm = jn.column(c).norm();
        if norm > 0.0 {
            jn.column_mut(c).scale_mut(1.0 / norm);
        }
    }
    let sv = jn.svd(false, false).singular_values;
    let (smax, smin) = sv
        .iter()
        .fold((0.0f64, f64::INFINITY), |(a, b), &s| (a.max(s), b.min(s)));
    let any_zero_col = (0..k).any(|c| jac.column(c).norm() == 0.0);
    let cond = if any_zero_col || smin <= 1e-12 * smax.max(1e-300) {
        f64::INFINITY
    } else {
        smax / smin
    };
    if !cond.is_finite() || cond > 1e10 {
        return Covariance {
            std_err: None,
            correlation: None,
            condition: cond,
        };
    }
    let jtj = jac.transpose() * jac;
    let Some(inv) = jtj.try_inverse() else {
        return Covariance {
            std_err: None,
            correlation: None,
            condition: f64::INFINITY,
        };
    };
    let dof = n.saturating_sub(k).max(1) as f64;
    let s2 = (chi2 / dof).max(1.0);
    let se: Vec<f64> = (0..k).map(|i| (inv[(i, i)] * s2).max(0.0).sqrt()).collect();
    let corr = (0..k)
        .map(|i| {
            (0..k)
                .map(|j| inv[(i, j)] / (inv[(i, i)] * inv[(j, j)]).sqrt())
                .collect()
        })
        .collect();
    Covariance {
        std_err: Some(se),
        correlation: Some(corr),
        condition: cond,
    }
}
