//! The Levenberg-Marquardt step (Moré 1978; Madsen, Nielsen & Tingleff 2004, section 3.2).
//!
//! Given the Jacobian J (m x n) and residuals r at x, the damped Gauss-Newton step h minimises
//!   |J h + r|^2 + lambda |D h|^2,
//! which is the linear least-squares problem of the augmented system
//! ```text
//!   [ J              ]     [ -r ]
//!   [ sqrt(lambda) D ] h = [  0 ].
//! ```
//! It is solved with faer's Householder QR of the (m + n) x n matrix: never the normal equations
//! (J^T J + lambda D^T D) h = -J^T r, whose condition number is the square of J's. With lambda > 0 the
//! augmented matrix has full column rank even when J does not (here: 5 unknowns, 4 residuals), and
//! the step tends to the minimum-norm Gauss-Newton step as lambda -> 0.
//!
//! The damping update is Nielsen's: on a gain ratio rho = actual / predicted reduction > 0 the step is
//! accepted and lambda *= max(1/3, 1 - (2 rho - 1)^3), nu = 2; otherwise lambda *= nu, nu *= 2.

use faer::prelude::*;
use faer::Mat;

/// The damped step h for Jacobian `j` (rows = residuals), residuals `r`, damping `lambda` and scaling
/// `d` (diagonal of D). Returns `None` when the factorisation gives non-finite numbers.
pub fn damped_step(j: &[Vec<f64>], r: &[f64], lambda: f64, d: &[f64]) -> Option<Vec<f64>> {
    let m = r.len();
    let n = d.len();
    let sl = lambda.max(0.0).sqrt();
    let a = Mat::<f64>::from_fn(m + n, n, |i, k| {
        if i < m {
            j[i][k]
        } else if i - m == k {
            sl * d[k]
        } else {
            0.0
        }
    });
    let b = Mat::<f64>::from_fn(m + n, 1, |i, _| if i < m { -r[i] } else { 0.0 });
    let h = a.qr().solve_lstsq(&b);
    let h: Vec<f64> = (0..n).map(|k| h[(k, 0)]).collect();
    h.iter().all(|v| v.is_finite()).then_some(h)
}

/// Predicted reduction of 1/2 |r|^2 by the linear model: 1/2 (|r|^2 - |r + J h|^2).
pub fn predicted_reduction(j: &[Vec<f64>], r: &[f64], h: &[f64]) -> f64 {
    let lin: f64 = j
        .iter()
        .zip(r)
        .map(|(row, ri)| {
            let v = ri + row.iter().zip(h).map(|(a, b)| a * b).sum::<f64>();
            v * v
        })
        .sum();
    0.5 * (norm2(r) - lin)
}

/// |v|^2.
pub fn norm2(v: &[f64]) -> f64 {
    v.iter().map(|a| a * a).sum()
}

/// Nielsen's update of (lambda, nu) after a step with gain ratio `rho` (accepted when `rho > 0`).
pub fn update_damping(lambda: f64, nu: f64, rho: Option<f64>) -> (f64, f64) {
    match rho {
        Some(rho) if rho > 0.0 => {
            let f = (1.0 - (2.0 * rho - 1.0).powi(3)).max(1.0 / 3.0);
            (lambda * f, 2.0)
        }
        _ => (lambda * nu, nu * 2.0),
    }
}

/// Broyden's rank-1 update of `j` (rows = residuals) after the step `h` from residuals `r` to `rt`:
/// J += (rt - r - J h) h^T / |h|^2, the smallest change (Frobenius norm) that makes J h reproduce
/// the measured change (Madsen, Nielsen & Tingleff 2004, eq 3.19). A zero step leaves J as it is.
pub fn broyden_update(j: &mut [Vec<f64>], h: &[f64], r: &[f64], rt: &[f64]) {
    let hh = norm2(h);
    if hh == 0.0 || !hh.is_finite() {
        return;
    }
    for ((row, ri), ti) in j.iter_mut().zip(r).zip(rt) {
        let jh: f64 = row.iter().zip(h).map(|(a, b)| a * b).sum();
        let c = (ti - ri - jh) / hh;
        row.iter_mut().zip(h).for_each(|(a, b)| *a += c * b);
    }
}

/// The starting damping: tau times the largest diagonal entry of J^T J (Madsen et al. eq 3.14), with
/// a floor so that a zero Jacobian still gives a finite, positive lambda.
pub fn initial_lambda(j: &[Vec<f64>], tau: f64) -> f64 {
    let n = j.first().map_or(0, |r| r.len());
    let max = (0..n)
        .map(|k| j.iter().map(|row| row[k] * row[k]).sum::<f64>())
        .fold(0.0, f64::max);
    (tau * max).max(1e-12)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_damping_gives_the_least_squares_solution() {
        // Overdetermined linear system with known solution x = (1, -2): J x = -r.
        let j = vec![vec![1.0, 0.0], vec![0.0, 1.0], vec![1.0, 1.0]];
        let r = vec![-1.0, 2.0, 1.0];
        let h = damped_step(&j, &r, 0.0, &[1.0, 1.0]).unwrap();
        assert!(
            (h[0] - 1.0).abs() < 1e-12 && (h[1] + 2.0).abs() < 1e-12,
            "{h:?}"
        );
        assert!((predicted_reduction(&j, &r, &h) - 0.5 * norm2(&r)).abs() < 1e-12);
    }

    #[test]
    fn damping_matches_the_regularised_solution_and_handles_rank_deficiency() {
        // One residual, two unknowns: J = [1 1], r = -2. The damped step solves
        // (J^T J + lambda I) h = -J^T r, i.e. h = 2 / (2 + lambda) (1, 1).
        let j = vec![vec![1.0, 1.0]];
        let r = vec![-2.0];
        for lambda in [1e-6, 0.1, 1.0, 10.0] {
            let h = damped_step(&j, &r, lambda, &[1.0, 1.0]).unwrap();
            let want = 2.0 / (2.0 + lambda);
            assert!((h[0] - want).abs() < 1e-10 && (h[1] - want).abs() < 1e-10);
        }
    }

    #[test]
    fn broyden_update_satisfies_the_secant_equation_and_leaves_the_orthogonal_part() {
        let mut j = vec![vec![1.0, 2.0], vec![0.0, -1.0]];
        let (h, r, rt) = ([0.5, 0.0], [1.0, 1.0], [2.0, 0.0]);
        broyden_update(&mut j, &h, &r, &rt);
        // J h = rt - r now; the column along the unstepped unknown is unchanged.
        assert!((j[0][0] * 0.5 - 1.0).abs() < 1e-15 && (j[1][0] * 0.5 + 1.0).abs() < 1e-15);
        assert_eq!((j[0][1], j[1][1]), (2.0, -1.0));
        // A linear map is learnt exactly along the step.
        let before = j.clone();
        broyden_update(&mut j, &[0.0, 0.0], &r, &rt);
        assert_eq!(j, before);
    }

    #[test]
    fn damping_update_follows_nielsen() {
        assert_eq!(update_damping(1.0, 2.0, None), (2.0, 4.0));
        assert_eq!(update_damping(1.0, 8.0, Some(-1.0)), (8.0, 16.0));
        let (l, nu) = update_damping(1.0, 8.0, Some(1.0));
        assert!((l - 1.0 / 3.0).abs() < 1e-15 && nu == 2.0);
    }
}
