//! The least-squares machinery on problems whose answers are known: Cramer's rule on exact
//! systems, Levenberg-Marquardt where Gauss-Newton overshoots, the grid on a cost whose
//! least point is known.

use super::*;

#[test]
fn cramer_gives_the_exact_solution() {
    assert_eq!(solve([[4.0]], [2.0]), Some([0.5]));
    // 3x + y = 5, 5x + 3y = 7: x = 2, y = -1 (every step exact in f64).
    assert_eq!(
        solve([[3.0, 1.0], [5.0, 3.0]], [5.0, 7.0]),
        Some([2.0, -1.0])
    );
}

/// A zero pivot or determinant is singular; the smallest one the solver still divides by,
/// 1e-300, is solved (its quotient is finite).
#[test]
fn singular_systems_have_no_solution() {
    assert_eq!(solve([[0.0]], [1.0]), None);
    assert_eq!(solve([[1.0, 2.0], [2.0, 4.0]], [1.0, 1.0]), None);
    assert_eq!(solve([[1e-300]], [1e-300]), Some([1.0]));
    assert_eq!(
        solve([[1e-300, 0.0], [0.0, 1.0]], [1e-300, 2.0]),
        Some([1.0, 2.0])
    );
}

/// atan(x) = 0 from x = 700: the Gauss-Newton step (the slope there is 1/(1 + x²))
/// lands near −1.6·x², so only damping raised to about 0.8·x (over 500) finds a step that
/// lowers the cost, whether the undamped step lands inside the bounds (a worse cost) or
/// outside them (where it is cut to the bound, a worse cost too).
#[test]
fn marquardt_damps_the_steps_gauss_newton_overshoots() {
    let f = |[x]: [f64; 1]| [x.atan()];
    for bound in [1e30, 1400.0] {
        let [x] = marquardt([700.0], &f, [bound]).expect("a minimum");
        assert!(x.abs() < 1e-9, "bound {bound}: {x}");
    }
}

/// Rosenbrock's valley, residuals 10(y − x²) and 1 − x, from its classic start (−1.2, 1):
/// the minimum is (1, 1), where both residuals vanish.
#[test]
fn marquardt_follows_a_curved_valley_to_its_minimum() {
    let f = |[x, y]: [f64; 2]| [10.0 * (y - x * x), 1.0 - x];
    let [x, y] = marquardt([-1.2, 1.0], &f, [10.0, 10.0]).expect("a minimum");
    assert!((x - 1.0).abs() < 1e-9 && (y - 1.0).abs() < 1e-9, "{x} {y}");
}

/// The grid's least point of a bowl centred off the grid is the grid point next to the
/// centre; a bowl centred past the bounds gives the grid's edge, not a point beyond it.
#[test]
fn the_grid_keeps_its_least_point_within_the_bounds() {
    let bowl = |c: [f64; 2]| move |p: [f64; 2]| (p[0] - c[0]).powi(2) + (p[1] - c[1]).powi(2);
    let [x, y] = grid_minimum([0.6, 1.2], &bowl([0.211, -0.347]));
    assert!(
        (x - 0.22).abs() < 1e-12 && (y + 0.34).abs() < 1e-12,
        "{x} {y}"
    );
    let [x, y] = grid_minimum([0.6, 1.2], &bowl([0.9, -2.0]));
    assert!(
        (x - 0.6).abs() < 1e-12 && (y + 1.2).abs() < 1e-12,
        "{x} {y}"
    );
}

/// A bowl centred past one bound, residuals x − 2 and y − 0.3 in the box |x|, |y| ≤ 1:
/// the least point in the box is (1, 0.3), on the edge, and the solver reaches it from
/// inside (the first full step leaves the box and is cut to it) and from a start on the
/// edge (x is held at its bound while y moves).
#[test]
fn marquardt_finds_a_minimum_on_the_edge_of_the_box() {
    let f = |[x, y]: [f64; 2]| [x - 2.0, y - 0.3];
    for start in [[0.0, -0.5], [1.0, -1.0], [-1.0, 1.0]] {
        let [x, y] = marquardt(start, &f, [1.0, 1.0]).expect("a minimum");
        assert!(
            x == 1.0 && (y - 0.3).abs() < 1e-9,
            "from {start:?}: {x} {y}"
        );
    }
}
