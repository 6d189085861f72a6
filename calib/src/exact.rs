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
//! Here the same model is run forward ([`polygon_end`]) and fitted to both components of
//! the end points by least squares, from the best point of a grid over every error a robot
//! can have (turns within 34°, legs bending up to 69°) and from the first-order solution.
//! The fit reproduces the published formulas in the small-error limit (tested) and recovers
//! the model's parameters exactly from its own end points over that whole range (tested),
//! where the x components alone, as the published formulas use them, admit other
//! solutions past ~7°: a 3 % wheel-diameter difference bends a 2 m leg by 25°, and the
//! x-only solution then read a 1.7° turn overshoot as a 15° one. What the model leaves
//! unexplained is reported ([`Fit::rms_cm`]).

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

    /// Curvature (1/cm) of a leg of length `l` (cm) whose heading changed by `beta` (rad):
    /// Borenstein's, with `l` the chord (2 sin(β/2)/L), or the model's, with `l` the arc
    /// driven (β/L; the chord differs by 0.8 % at a 25° bend).
    pub fn curvature(self, beta: f64, l: f64) -> f64 {
        match self {
            Solution::FirstOrder => crate::borenstein::curvature(beta, l),
            Solution::Exact => beta / l,
        }
    }
}

/// What a fit may leave unexplained (cm rms over the centroids' components) before the
/// report says so: about the scatter of a centroid of five floor runs.
pub const RESIDUAL_WARNING_CM: f64 = 5.0;

/// The warning for a fit that leaves `rms_cm` unexplained, if that is more than
/// [`RESIDUAL_WARNING_CM`].
pub fn residual_warning(rms_cm: f64) -> Option<String> {
    (rms_cm > RESIDUAL_WARNING_CM).then(|| {
        format!(
            "the error model (turn error and leg bend) leaves {rms_cm:.1} cm rms of the centroids unexplained: \
             the robot has an error it does not describe, and the correction is only as good as the rest"
        )
    })
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

/// Largest turn error the solvers accept (rad, about 34°): beyond it the turns no longer make
/// a square or a triangle.
const MAX_TURN_ERROR_RAD: f64 = 0.6;
/// Largest heading change of one leg the solvers accept (rad, about 69°): a robot whose wheel
/// diameters differ by 5 % bends a 2 m leg on a 130 mm wheelbase by 44°.
const MAX_LEG_BEND_RAD: f64 = 1.2;
/// Grid step of the global start (rad): fine enough that the best grid point lies in the
/// basin of the least-squares minimum.
const GRID_STEP_RAD: f64 = 0.02;
/// Convergence on the parameters, rad.
const TOL_RAD: f64 = 1e-13;
const MAX_ITER: usize = 100;

/// A least-squares solution of the error model: its parameters and the root mean square of
/// what the model leaves of the end points (cm): near 0 when the end points are the
/// model's, large when the robot does something the model has no parameter for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fit<const N: usize> {
    pub params: [f64; N],
    pub rms_cm: f64,
}

/// Least squares `min |f(p)|²` over `N` unknowns (each within `bounds`) for `M ≥ N`
/// residuals: Levenberg-Marquardt with a central-difference Jacobian, started from the best
/// point of a grid over the bounds and from `first` (the first-order solution), keeping the
/// better end. The grid makes the answer the global minimum, not the one next to a start
/// that large errors put far off (x components alone admit several solutions past ~7°).
fn least_squares<const N: usize, const M: usize>(
    first: [f64; N],
    bounds: [f64; N],
    f: impl Fn([f64; N]) -> [f64; M],
) -> Option<Fit<N>> {
    let cost = |p: [f64; N]| f(p).iter().map(|r| r * r).sum::<f64>();
    let inside = |p: &[f64; N]| {
        p.iter()
            .zip(&bounds)
            .all(|(v, b)| v.is_finite() && v.abs() <= *b)
    };
    let mut starts = vec![grid_minimum(bounds, &cost)];
    if inside(&first) {
        starts.push(first);
    }
    starts
        .into_iter()
        .filter_map(|s| marquardt(s, &f, bounds))
        .map(|p| (cost(p), p))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(c, p)| Fit {
            params: p,
            rms_cm: (c / M as f64).sqrt(),
        })
}

/// The grid point (step [`GRID_STEP_RAD`], within `bounds`) of least `cost`.
fn grid_minimum<const N: usize>(bounds: [f64; N], cost: &impl Fn([f64; N]) -> f64) -> [f64; N] {
    let steps: Vec<i64> = bounds
        .iter()
        .map(|b| (b / GRID_STEP_RAD).floor() as i64)
        .collect();
    let mut index = [0i64; N];
    for (i, s) in index.iter_mut().zip(&steps) {
        *i = -s;
    }
    let mut best = (f64::INFINITY, [0.0; N]);
    loop {
        let mut p = [0.0; N];
        for (v, i) in p.iter_mut().zip(&index) {
            *v = *i as f64 * GRID_STEP_RAD;
        }
        let c = cost(p);
        if c < best.0 {
            best = (c, p);
        }
        // The next grid point, the first index fastest.
        let mut k = 0;
        loop {
            if k == N {
                return best.1;
            }
            if index[k] < steps[k] {
                index[k] += 1;
                break;
            }
            index[k] = -steps[k];
            k += 1;
        }
    }
}

/// Levenberg-Marquardt from `start` within `|p_j| ≤ bounds[j]`: a step that would leave
/// the box is cut to it (projected), and a parameter held at its bound by the descent is
/// fixed there while the others move, so a minimum on an edge of the range (a turn error
/// at its largest, with offsets the model cannot explain) is found along that edge instead
/// of stalling where the first step out was refused. `None` when the normal equations are
/// singular or the residuals stop being finite.
fn marquardt<const N: usize, const M: usize>(
    start: [f64; N],
    f: &impl Fn([f64; N]) -> [f64; M],
    bounds: [f64; N],
) -> Option<[f64; N]> {
    let cost = |r: &[f64; M]| r.iter().map(|v| v * v).sum::<f64>();
    let mut p = start;
    let mut r = f(p);
    let mut lambda = 1e-3;
    for _ in 0..MAX_ITER {
        let h = 1e-7;
        let mut jac = [[0.0; N]; M];
        for j in 0..N {
            let (mut hi, mut lo) = (p, p);
            hi[j] += h;
            lo[j] -= h;
            let (fh, fl) = (f(hi), f(lo));
            for i in 0..M {
                jac[i][j] = (fh[i] - fl[i]) / (2.0 * h);
            }
        }
        // Normal equations (JᵀJ + λ diag(JᵀJ)) δ = Jᵀr.
        let mut jtj = [[0.0; N]; N];
        let mut jtr = [0.0; N];
        for (row, ri) in jac.iter().zip(&r) {
            for a in 0..N {
                jtr[a] += row[a] * ri;
                for b in 0..N {
                    jtj[a][b] += row[a] * row[b];
                }
            }
        }
        // At its bound with the descent (−Jᵀr) pointing out: held there this iteration.
        let held: [bool; N] =
            std::array::from_fn(|j| p[j].abs() >= bounds[j] && jtr[j] * p[j].signum() < 0.0);
        let mut improved = false;
        for _ in 0..30 {
            let mut damped = jtj;
            let mut rhs = jtr;
            for a in 0..N {
                damped[a][a] += lambda * jtj[a][a].max(1e-12);
                if held[a] {
                    // δ_a = 0, and no other unknown couples to it.
                    damped[a] = [0.0; N];
                    for row in damped.iter_mut() {
                        row[a] = 0.0;
                    }
                    damped[a][a] = 1.0;
                    rhs[a] = 0.0;
                }
            }
            let step = solve(damped, rhs)?;
            let q: [f64; N] =
                std::array::from_fn(|j| (p[j] - step[j]).clamp(-bounds[j], bounds[j]));
            let rq = f(q);
            if !rq.iter().all(|v| v.is_finite()) {
                return None;
            }
            if cost(&rq) <= cost(&r) {
                let moved = (0..N).map(|j| (q[j] - p[j]).abs()).fold(0.0, f64::max);
                (p, r) = (q, rq);
                lambda = (lambda / 10.0).max(1e-12);
                improved = true;
                if moved < TOL_RAD {
                    return Some(p);
                }
                break;
            }
            lambda *= 10.0;
        }
        if !improved {
            // No step lowers the cost: a minimum, to the precision the Jacobian allows.
            return Some(p);
        }
    }
    Some(p)
}

/// `a · x = b` for N = 1 or 2 (Cramer's rule); `None` when singular.
fn solve<const N: usize>(a: [[f64; N]; N], b: [f64; N]) -> Option<[f64; N]> {
    let mut x = [0.0; N];
    match N {
        1 => {
            if a[0][0].abs() < 1e-300 {
                return None;
            }
            x[0] = b[0] / a[0][0];
        }
        2 => {
            let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
            if det.abs() < 1e-300 {
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
/// side: an arc's end is y = l·(1 − cos β)/β. First order: β = 2y/l. `None` when no bend
/// within the solver's range ends there.
pub fn line_beta(y: f64, l: f64) -> Option<f64> {
    least_squares([2.0 * y / l], [MAX_LEG_BEND_RAD], |[b]| {
        let end = polygon_end(0.0, b, l, 0.0, Direction::Ccw, 1);
        [end.y_cm - y]
    })
    .filter(|fit| fit.rms_cm < 1e-6)
    .map(|fit| fit.params[0])
}

/// UMBmark's α and β (rad) from the CW and CCW centroids (default frame), side `l` (cm):
/// the exact counterpart of Borenstein's eqs. 7-10. Both components of both centroids are
/// fitted (least squares): the x components alone, as the published formulas use them,
/// stop telling the parameters apart once the errors reach several degrees.
pub fn umbmark_alpha_beta(cw: Endpoint, ccw: Endpoint, l: f64) -> Option<Fit<2>> {
    let k = -4.0 * l;
    let first = [(cw.x_cm + ccw.x_cm) / k, (cw.x_cm - ccw.x_cm) / k];
    let quarter = std::f64::consts::FRAC_PI_2;
    least_squares(first, [MAX_TURN_ERROR_RAD, MAX_LEG_BEND_RAD], |[a, b]| {
        let (pcw, pccw) = (
            polygon_end(a, b, l, quarter, Direction::Cw, 4),
            polygon_end(a, b, l, quarter, Direction::Ccw, 4),
        );
        [
            pcw.x_cm - cw.x_cm,
            pcw.y_cm - cw.y_cm,
            pccw.x_cm - ccw.x_cm,
            pccw.y_cm - ccw.y_cm,
        ]
    })
}

/// The Triangular Path's turn error δ (rad) from the triangle centroid (default frame; y
/// when it was recorded), side `l` (cm), with the legs bending by `beta_t` (rad) during the
/// triangle runs: the exact counterpart of [`crate::triangle`]'s δ, every component there is
/// fitted.
pub fn triangle_delta(
    x: f64,
    y: Option<f64>,
    l: f64,
    beta_t: f64,
    direction: Direction,
) -> Option<Fit<1>> {
    let s3 = 3f64.sqrt();
    let first = match direction {
        Direction::Ccw => beta_t - 2.0 * x / (s3 * l),
        Direction::Cw => -beta_t - 2.0 * x / (s3 * l),
    };
    let third = 2.0 * std::f64::consts::FRAC_PI_3;
    let fit = least_squares([first], [MAX_TURN_ERROR_RAD], |[d]| {
        let p = polygon_end(d, beta_t, l, third, direction, 3);
        [p.x_cm - x, y.map_or(0.0, |y| p.y_cm - y)]
    })?;
    // The rms over the components there are.
    let present: f64 = if y.is_some() { 2.0 } else { 1.0 };
    Some(Fit {
        params: fit.params,
        rms_cm: fit.rms_cm * (2.0 / present).sqrt(),
    })
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
        let exact = triangle_delta(end.x_cm, Some(end.y_cm), L, 0.0, Direction::Ccw).unwrap();
        assert!((exact.params[0] - d).abs() < 1e-9);
    }

    #[test]
    fn large_bends_are_told_from_turn_errors_with_both_components() {
        // A 3 % wheel-diameter difference on a 130 mm wheelbase bends a 2 m leg by 26°; the
        // firmware's turns overshoot by 1.7° (what the bench's robust build does there). The
        // first-order formulas read a 15° overshoot and an 12° bend from the x components.
        let (a, b) = ((-1.7f64).to_radians(), 26.4f64.to_radians());
        let q = std::f64::consts::FRAC_PI_2;
        let cw = polygon_end(a, b, L, q, Direction::Cw, 4);
        let ccw = polygon_end(a, b, L, q, Direction::Ccw, 4);
        let first_alpha = (cw.x_cm + ccw.x_cm) / (-4.0 * L);
        assert!(
            (first_alpha.to_degrees() + 15.36).abs() < 0.01,
            "{first_alpha}"
        );
        let fit = umbmark_alpha_beta(cw, ccw, L).unwrap();
        assert!((fit.params[0] - a).abs() < 1e-9 && (fit.params[1] - b).abs() < 1e-9);
    }

    #[test]
    fn what_the_model_cannot_explain_is_its_residual() {
        // The model's own end points, then both centroids moved 3 cm to the left: no α, β
        // moves a CW and a CCW end the same way, so the fit leaves about that much.
        let q = std::f64::consts::FRAC_PI_2;
        let (a, b) = (0.02, 0.01);
        let mut cw = polygon_end(a, b, L, q, Direction::Cw, 4);
        let mut ccw = polygon_end(a, b, L, q, Direction::Ccw, 4);
        cw.y_cm += 3.0;
        ccw.y_cm += 3.0;
        let fit = umbmark_alpha_beta(cw, ccw, L).unwrap();
        assert!(fit.rms_cm > 1.0 && fit.rms_cm < 3.0, "{}", fit.rms_cm);
    }

    proptest! {
        #[test]
        fn umbmark_inverts_its_model(a in -0.35f64..0.35, b in -1.0f64..1.0, l in 50.0f64..500.0) {
            let q = std::f64::consts::FRAC_PI_2;
            let cw = polygon_end(a, b, l, q, Direction::Cw, 4);
            let ccw = polygon_end(a, b, l, q, Direction::Ccw, 4);
            let fit = umbmark_alpha_beta(cw, ccw, l).expect("converges");
            let [ea, eb] = fit.params;
            prop_assert!((ea - a).abs() < 1e-9 && (eb - b).abs() < 1e-9, "{ea} {eb}");
            prop_assert!(fit.rms_cm < 1e-9, "{}", fit.rms_cm);
        }

        #[test]
        fn triangle_inverts_its_model(d in -0.35f64..0.35, b in -1.0f64..1.0, ccw in any::<bool>()) {
            let dir = if ccw { Direction::Ccw } else { Direction::Cw };
            let t = 2.0 * std::f64::consts::FRAC_PI_3;
            let end = polygon_end(d, b, L, t, dir, 3);
            let ed = triangle_delta(end.x_cm, Some(end.y_cm), L, b, dir).expect("converges").params[0];
            prop_assert!((ed - d).abs() < 1e-9, "{ed} vs {d}");
        }

        #[test]
        fn line_inverts_its_arc(b in -1.0f64..1.0) {
            let end = polygon_end(0.0, b, L, 0.0, Direction::Ccw, 1);
            let eb = line_beta(end.y_cm, L).expect("converges");
            prop_assert!((eb - b).abs() < 1e-9);
        }
    }
}

#[cfg(test)]
mod solver_tests;
