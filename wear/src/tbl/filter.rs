//! Smoothing of profiles and time series (paper 004 Figs. 4-5):
//! - [`moving_average`]: the centred moving average of the TBL thickness over time (Fig. 5's solid
//!   lines), shrinking symmetrically at the ends so that the smoothed series has no phase lag;
//! - [`savitzky_golay`]: the Savitzky-Golay filter of the density profile (order 3 on 7 samples in the
//!   paper): at every sample, the value at that sample of the least-squares polynomial of the given
//!   order through the window of samples around it. Near the ends the window stops at the end and the
//!   polynomial of the first (or last) full window is evaluated at the sample (scipy's `interp` mode),
//!   so a polynomial of the filter's order passes through unchanged everywhere.

use crate::error::{Result, WearError};

/// Centred moving average over `window` samples: sample i averages i - h ..= i + h with
/// h = (window - 1) / 2, shrunk to the largest symmetric window that fits near the ends.
pub fn moving_average(x: &[f64], window: usize) -> Vec<f64> {
    let h = window.saturating_sub(1) / 2;
    let n = x.len();
    (0..n)
        .map(|i| {
            let k = h.min(i).min(n - 1 - i);
            x[i - k..=i + k].iter().sum::<f64>() / (2 * k + 1) as f64
        })
        .collect()
}

/// Weights w_j (j = 0..window) giving the value at offset `at` (0..window) of the least-squares
/// polynomial of degree `order` through samples at offsets 0..window: w = e_at^T V (V^T V)^-1 V^T.
fn sg_weights(window: usize, order: usize, at: usize) -> Result<Vec<f64>> {
    let m = order + 1;
    // Offsets centred on the window keep V^T V well scaled.
    let c = (window as f64 - 1.0) / 2.0;
    let t: Vec<f64> = (0..window).map(|j| j as f64 - c).collect();
    let mut ata = vec![vec![0.0; m]; m];
    for a in 0..m {
        for b in 0..m {
            ata[a][b] = t.iter().map(|x| x.powi((a + b) as i32)).sum();
        }
    }
    // Solve (V^T V) z = v(at), then w_j = v(t_j) . z.
    let x0 = at as f64 - c;
    let mut rhs: Vec<f64> = (0..m).map(|a| x0.powi(a as i32)).collect();
    gauss_solve(&mut ata, &mut rhs)?;
    Ok(t.iter()
        .map(|x| (0..m).map(|a| x.powi(a as i32) * rhs[a]).sum())
        .collect())
}

/// Solves a small dense system in place (partial pivoting); the solution replaces `b`.
fn gauss_solve(a: &mut [Vec<f64>], b: &mut [f64]) -> Result<()> {
    let n = b.len();
    for col in 0..n {
        let p = (col..n)
            .max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))
            .unwrap_or(col);
        if a[p][col].abs() < 1e-300 {
            return Err(WearError::Setting("singular least-squares system".into()));
        }
        a.swap(col, p);
        b.swap(col, p);
        for r in col + 1..n {
            let f = a[r][col] / a[col][col];
            for k in col..n {
                a[r][k] -= f * a[col][k];
            }
            b[r] -= f * b[col];
        }
    }
    for col in (0..n).rev() {
        let s: f64 = (col + 1..n).map(|k| a[col][k] * b[k]).sum();
        b[col] = (b[col] - s) / a[col][col];
    }
    Ok(())
}

/// Savitzky-Golay filter of `y` with an odd `window` and a polynomial `order` below it (see the
/// module docs for the ends). Refuses a series shorter than the window.
pub fn savitzky_golay(y: &[f64], window: usize, order: usize) -> Result<Vec<f64>> {
    if window.is_multiple_of(2) || order >= window {
        return Err(WearError::Setting(format!(
            "Savitzky-Golay needs an odd window above the order (window {window}, order {order})"
        )));
    }
    if y.len() < window {
        return Err(WearError::Setting(format!(
            "Savitzky-Golay over {window} samples needs at least that many ({} given)",
            y.len()
        )));
    }
    let h = window / 2;
    let n = y.len();
    let centre = sg_weights(window, order, h)?;
    let edge: Vec<Vec<f64>> = (0..window)
        .map(|at| sg_weights(window, order, at))
        .collect::<Result<_>>()?;
    let dot =
        |w: &[f64], start: usize| -> f64 { w.iter().zip(&y[start..]).map(|(a, b)| a * b).sum() };
    Ok((0..n)
        .map(|i| {
            if i < h {
                dot(&edge[i], 0)
            } else if i + h >= n {
                dot(&edge[window - (n - i)], n - window)
            } else {
                dot(&centre, i - h)
            }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moving_average_is_centred_and_shrinks_at_the_ends() {
        let x = [0.0, 1.0, 2.0, 3.0, 10.0];
        let m = moving_average(&x, 3);
        assert_eq!(m, vec![0.0, 1.0, 2.0, 5.0, 10.0]);
        // A linear trend passes through unchanged (no lag).
        let lin: Vec<f64> = (0..20).map(|i| 0.5 * i as f64).collect();
        for (a, b) in moving_average(&lin, 7).iter().zip(&lin) {
            assert!((a - b).abs() < 1e-12);
        }
        assert_eq!(moving_average(&[], 5), Vec::<f64>::new());
        assert_eq!(moving_average(&[2.0], 5), vec![2.0]);
    }

    #[test]
    fn order_3_on_7_has_the_classic_weights() {
        // Savitzky & Golay (1964): (-2, 3, 6, 7, 6, 3, -2) / 21 for the smoothed centre.
        let w = sg_weights(7, 3, 3).unwrap();
        let expect = [-2.0, 3.0, 6.0, 7.0, 6.0, 3.0, -2.0];
        for (a, b) in w.iter().zip(expect) {
            assert!((a - b / 21.0).abs() < 1e-14, "{w:?}");
        }
    }

    #[test]
    fn cubics_pass_through_everywhere_and_noise_is_reduced() {
        let cubic: Vec<f64> = (0..30)
            .map(|i| {
                let x = i as f64 * 0.1;
                1.0 - 2.0 * x + 0.5 * x * x - 0.3 * x * x * x
            })
            .collect();
        let f = savitzky_golay(&cubic, 7, 3).unwrap();
        for (a, b) in f.iter().zip(&cubic) {
            assert!((a - b).abs() < 1e-10, "{a} {b}");
        }
        // Alternating noise of amplitude 1 (the shortest wave a profile can hold) comes out at
        // (2 + 3 - 6 + 7 - 6 + 3 + 2) / 21 = 5/21 of its amplitude.
        let noisy: Vec<f64> = (0..40)
            .map(|i| if i % 2 == 0 { 1.0 } else { -1.0 })
            .collect();
        let f = savitzky_golay(&noisy, 7, 3).unwrap();
        for v in &f[3..37] {
            assert!((v.abs() - 5.0 / 21.0).abs() < 1e-12, "{v}");
        }
        assert!(savitzky_golay(&noisy[..5], 7, 3).is_err());
        assert!(savitzky_golay(&noisy, 6, 3).is_err());
        assert!(savitzky_golay(&noisy, 7, 7).is_err());
    }
}
