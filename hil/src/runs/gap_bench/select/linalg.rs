//! The small linear algebra of the joint fits (`joint.rs`, `regression.rs`): normal
//! equations, a solver and an inverse for systems of a few unknowns.

/// JᵀJ and Jᵀr of a Jacobian given by columns.
pub(super) fn normal_equations(jac: &[Vec<f64>], r: &[f64]) -> (Vec<Vec<f64>>, Vec<f64>) {
    let k = jac.len();
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let a = (0..k)
        .map(|i| (0..k).map(|j| dot(&jac[i], &jac[j])).collect())
        .collect();
    let g = (0..k).map(|i| dot(&jac[i], r)).collect();
    (a, g)
}

/// `m x = b` by Gaussian elimination with partial pivoting (None: singular).
pub(super) fn solve(m: &[Vec<f64>], b: &[f64]) -> Option<Vec<f64>> {
    let n = b.len();
    let mut a: Vec<Vec<f64>> = m
        .iter()
        .zip(b)
        .map(|(row, &y)| row.iter().copied().chain([y]).collect())
        .collect();
    let scale = m
        .iter()
        .flatten()
        .fold(0.0f64, |s, x| s.max(x.abs()))
        .max(f64::MIN_POSITIVE);
    for c in 0..n {
        let p = (c..n).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))?;
        if a[p][c].abs() <= 1e-12 * scale {
            return None;
        }
        a.swap(c, p);
        let pivot = a[c].clone();
        for (i, row) in a.iter_mut().enumerate() {
            if i != c {
                let f = row[c] / pivot[c];
                for (x, p) in row.iter_mut().zip(&pivot).skip(c) {
                    *x -= f * p;
                }
            }
        }
    }
    Some((0..n).map(|i| a[i][n] / a[i][i]).collect())
}

/// The inverse of `m` (None: singular).
pub(super) fn inverse(m: &[Vec<f64>]) -> Option<Vec<Vec<f64>>> {
    let n = m.len();
    let cols: Vec<Vec<f64>> = (0..n)
        .map(|j| {
            solve(
                m,
                &(0..n)
                    .map(|i| f64::from(u8::from(i == j)))
                    .collect::<Vec<_>>(),
            )
        })
        .collect::<Option<_>>()?;
    Some(
        (0..n)
            .map(|i| (0..n).map(|j| cols[j][i]).collect())
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The small linear algebra of the fit: a 2 × 2 and a 3 × 3 system solved, a singular
    /// one refused, an inverse times its matrix the identity.
    #[test]
    fn systems_are_solved_and_singular_ones_refused() {
        let m = vec![vec![4.0, 1.0], vec![1.0, 3.0]];
        let x = solve(&m, &[1.0, 2.0]).unwrap();
        assert!((4.0 * x[0] + x[1] - 1.0).abs() < 1e-12 && (x[0] + 3.0 * x[1] - 2.0).abs() < 1e-12);
        let m3 = vec![
            vec![0.0, 2.0, 1.0],
            vec![1.0, 0.0, 0.0],
            vec![3.0, 1.0, 5.0],
        ];
        let inv = inverse(&m3).unwrap();
        for (i, row) in m3.iter().enumerate() {
            for j in 0..3 {
                let v: f64 = row.iter().zip(&inv).map(|(a, r)| a * r[j]).sum();
                assert!(
                    (v - f64::from(u8::from(i == j))).abs() < 1e-12,
                    "{i} {j} {v}"
                );
            }
        }
        assert_eq!(solve(&[vec![1.0, 2.0], vec![2.0, 4.0]], &[1.0, 2.0]), None);
    }
}
