//! The UMBmark and Triangular Path models solved exactly instead of to first order.
//!
//! Both methods model a run as straight-ish legs of length L, each bending the heading
//! uniformly by β (a circular arc: its chord is L·sin(β/2)/(β/2) long and points at the
//! leg's start heading + β/2), joined by spin turns that each miss the nominal exterior
//! angle (90° or 120°) by the same turn error (α, δ: under-rotation positive). The
//! published formulas ([`crate::umbmark`], [`crate::triangle`]) are this model's
//! linearisation; they are exact only for vanishing errors. A robot whose turns overshoot by
//! a few degrees (a motor coasting after cut-off does that) is already far enough out for
//! the first-order α to be off by 10-15 % (a 6.6° overshoot reads as 7.6° from a
//! triangle's x), which then shows up as a wrong wheelbase in every calibration round.
//!
//! Here the same model is run forward ([`polygon_end`]) and inverted by Newton's method,
//! started from the first-order solution. The inversion reproduces the published formulas
//! in the small-error limit (tested) and recovers the model's parameters exactly from its own
//! end points (tested for errors up to 7°; far beyond, the x components alone admit other
//! solutions, and Newton's method returns the one it reaches from the first-order start).

use crate::types::{Direction, Endpoint};

/// Which solution of the error model feeds α (δ), β and everything derived from them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Solution {
    /// The published first-order formulas (Borenstein & Feng; Ruan, Li & Zhu).
    #[default]
    FirstOrder,
    /// The same model solved exactly (Newton's method from the first-order solution).
    Exact,
}

impl Solution {
    pub fn as_str(self) -> &'static str {
        match self {
            Solution::FirstOrder => "first-order",
            Solution::Exact => "exact",
        }
    }
}

/// End point (cm) of a closed polygon path driven from the origin along +x: `legs` legs of
/// length `l` (cm), each bending the heading by `beta` (rad, positive left), joined by turns
/// of `exterior - turn_error` (rad) to the left (CCW) or the right (CW). The turn after the
/// last leg does not move the end point and is left out.
pub fn polygon_end(
    turn_error: f64,
    beta: f64,
    l: f64,
    exterior: f64,
    direction: Direction,
    legs: usize,
) -> Endpoint {
    let chord = l * sinc(beta / 2.0);
    let turn = match direction {
        Direction::Ccw => exterior - turn_error,
        Direction::Cw => -(exterior - turn_error),
    };
    let (mut x, mut y, mut heading) = (0.0, 0.0, 0.0f64);
    for k in 0..legs {
        let mid = heading + beta / 2.0;
        x += chord * mid.cos();
        y += chord * mid.sin();
        heading += beta;
        if k + 1 < legs {
            heading += turn;
        }
    }
    Endpoint::new(x, y)
}

/// sin(x)/x, 1 at 0.
fn sinc(x: f64) -> f64 {
    if x.abs() < 1e-8 {
        1.0 - x * x / 6.0
    } else {
        x.sin() / x
    }
}

/// Largest error the solvers accept (rad): beyond it the model's legs and turns no longer
/// make a square or a triangle.
const MAX_ERROR_RAD: f64 = 0.6;
/// Convergence on the end point, cm.
const TOL_CM: f64 = 1e-9;
const MAX_ITER: usize = 60;

/// Newton's method on `f(p) = 0` for `N` unknowns with a central-difference Jacobian.
fn newton<const N: usize>(start: [f64; N], f: impl Fn([f64; N]) -> [f64; N]) -> Option<[f64; N]> {
    let mut p = start;
    for _ in 0..MAX_ITER {
        let r = f(p);
        if r.iter().all(|v| v.abs() < TOL_CM) {
            return Some(p);
        }
        let h = 1e-7;
        let mut jac = [[0.0; N]; N];
        for j in 0..N {
            let (mut hi, mut lo) = (p, p);
            hi[j] += h;
            lo[j] -= h;
            let (fh, fl) = (f(hi), f(lo));
            for i in 0..N {
                jac[i][j] = (fh[i] - fl[i]) / (2.0 * h);
            }
        }
        let step = solve(jac, r)?;
        for j in 0..N {
            p[j] -= step[j];
        }
        if p.iter().any(|v| !v.is_finite() || v.abs() > MAX_ERROR_RAD) {
            return None;
        }
    }
    let r = f(p);
    r.iter().all(|v| v.abs() < 1e3 * TOL_CM).then_some(p)
}

/// `a · x = b` for N = 1 or 2 (Cramer's rule); `None` when singular.
fn solve<const N: usize>(a: [[f64; N]; N], b: [f64; N]) -> Option<[f64; N]> {
    let mut x = [0.0; N];
    match N {
        1 => {
            if a[0][0].abs() < 1e-12 {
                return None;
            }
            x[0] = b[0] / a[0][0];
        }
        2 => {
            let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
            if det.abs() < 1e-12 {
                return None;
            }
            x[0] = (b[0] * a[1][1] - a[0][1] * b[1]) / det;
            x[1] = (a[0][0] * b[1] - b[0] * a[1][0]) / det;
        }
        _ => unreachable!("only one- and two-parameter models are solved"),
    }
    Some(x)
}

/// The heading change β (rad) of a straight line of length `l` whose end is `y` (cm) to the
/// side: an arc's end is y = l·(1 − cos β)/β. First order: β = 2y/l.
pub fn line_beta(y: f64, l: f64) -> Option<f64> {
    newton([2.0 * y / l], |[b]| {
        let end = polygon_end(0.0, b, l, 0.0, Direction::Ccw, 1);
        [end.y_cm - y]
    })
    .map(|[b]| b)
}

/// UMBmark's α and β (rad) from the x components of the CW and CCW centroids (default
/// frame), side `l` (cm): the exact counterpart of Borenstein's eqs. 7 and 9.
pub fn umbmark_alpha_beta(cw: Endpoint, ccw: Endpoint, l: f64) -> Option<(f64, f64)> {
    let k = -4.0 * l;
    let start = [(cw.x_cm + ccw.x_cm) / k, (cw.x_cm - ccw.x_cm) / k];
    let quarter = std::f64::consts::FRAC_PI_2;
    newton(start, |[a, b]| {
        [
            polygon_end(a, b, l, quarter, Direction::Cw, 4).x_cm - cw.x_cm,
            polygon_end(a, b, l, quarter, Direction::Ccw, 4).x_cm - ccw.x_cm,
        ]
    })
    .map(|[a, b]| (a, b))
}

/// The Triangular Path's turn error δ (rad) from the x component of the triangle centroid
/// (default frame), side `l` (cm), with the legs bending by `beta_t` (rad) during the
/// triangle runs: the exact counterpart of [`crate::triangle`]'s δ_x.
pub fn triangle_delta(x: f64, l: f64, beta_t: f64, direction: Direction) -> Option<f64> {
    let s3 = 3f64.sqrt();
    let start = match direction {
        Direction::Ccw => beta_t - 2.0 * x / (s3 * l),
        Direction::Cw => -beta_t - 2.0 * x / (s3 * l),
    };
    let third = 2.0 * std::f64::consts::FRAC_PI_3;
    newton([start], |[d]| {
        [polygon_end(d, beta_t, l, third, direction, 3).x_cm - x]
    })
    .map(|[d]| d)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const L: f64 = 200.0;

    #[test]
    fn small_errors_give_the_published_formulas() {
        // Borenstein: CW x = y = -2L(a + b); CCW x = -2L(a - b), y = 2L(a - b).
        let (a, b) = (1e-5, 4e-6);
        let q = std::f64::consts::FRAC_PI_2;
        let cw = polygon_end(a, b, L, q, Direction::Cw, 4);
        let ccw = polygon_end(a, b, L, q, Direction::Ccw, 4);
        let tol = 1e-6;
        assert!((cw.x_cm + 2.0 * L * (a + b)).abs() < tol, "{cw:?}");
        assert!((cw.y_cm + 2.0 * L * (a + b)).abs() < tol, "{cw:?}");
        assert!((ccw.x_cm + 2.0 * L * (a - b)).abs() < tol, "{ccw:?}");
        assert!((ccw.y_cm - 2.0 * L * (a - b)).abs() < tol, "{ccw:?}");
        // The triangle (crate::triangle's derivation): CCW x = (√3/2)L(β − δ), y = −(3/2)L(β − δ).
        let t = 2.0 * std::f64::consts::FRAC_PI_3;
        let s3 = 3f64.sqrt();
        let ccw = polygon_end(a, b, L, t, Direction::Ccw, 3);
        assert!((ccw.x_cm - s3 / 2.0 * L * (b - a)).abs() < tol, "{ccw:?}");
        assert!((ccw.y_cm + 1.5 * L * (b - a)).abs() < tol, "{ccw:?}");
        let cw = polygon_end(a, b, L, t, Direction::Cw, 3);
        assert!((cw.x_cm + s3 / 2.0 * L * (b + a)).abs() < tol, "{cw:?}");
        assert!((cw.y_cm + 1.5 * L * (b + a)).abs() < tol, "{cw:?}");
    }

    #[test]
    fn first_order_is_off_by_percent_at_a_few_degrees() {
        // A 6.6 degree overshoot in a CCW triangle: first order reads 15 % more.
        let d = (-6.6f64).to_radians();
        let t = 2.0 * std::f64::consts::FRAC_PI_3;
        let end = polygon_end(d, 0.0, L, t, Direction::Ccw, 3);
        let first = -2.0 * end.x_cm / (3f64.sqrt() * L);
        assert!((first / d - 1.15).abs() < 0.01, "{}", first / d);
        let exact = triangle_delta(end.x_cm, L, 0.0, Direction::Ccw).unwrap();
        assert!((exact - d).abs() < 1e-9);
    }

    proptest! {
        #[test]
        fn umbmark_inverts_its_model(a in -0.12f64..0.12, b in -0.12f64..0.12, l in 50.0f64..500.0) {
            let q = std::f64::consts::FRAC_PI_2;
            let cw = polygon_end(a, b, l, q, Direction::Cw, 4);
            let ccw = polygon_end(a, b, l, q, Direction::Ccw, 4);
            let (ea, eb) = umbmark_alpha_beta(cw, ccw, l).expect("converges");
            prop_assert!((ea - a).abs() < 1e-9 && (eb - b).abs() < 1e-9, "{ea} {eb}");
        }

        #[test]
        fn triangle_inverts_its_model(d in -0.12f64..0.12, b in -0.12f64..0.12, ccw in any::<bool>()) {
            let dir = if ccw { Direction::Ccw } else { Direction::Cw };
            let t = 2.0 * std::f64::consts::FRAC_PI_3;
            let end = polygon_end(d, b, L, t, dir, 3);
            let ed = triangle_delta(end.x_cm, L, b, dir).expect("converges");
            prop_assert!((ed - d).abs() < 1e-9, "{ed} vs {d}");
        }

        #[test]
        fn line_inverts_its_arc(b in -0.5f64..0.5) {
            let end = polygon_end(0.0, b, L, 0.0, Direction::Ccw, 1);
            let eb = line_beta(end.y_cm, L).expect("converges");
            prop_assert!((eb - b).abs() < 1e-9);
        }
    }
}
