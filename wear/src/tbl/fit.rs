//! The least-squares Gaussian of paper 004 Fig. 4b, whose minimum is the TBL density rho_TBL:
//!
//!   rho(y) = b - a exp(-(y - mu)^2 / (2 s^2))
//!
//! fitted to the unfiltered density profile. For fixed (mu, s) the model is linear in (b, a), which
//! is solved exactly (variable projection); (mu, s) come from a coarse grid over the profile followed
//! by a Nelder-Mead refinement of (mu, ln s). The width is held at or above `min_width` (a dip
//! narrower than a particle is a single noisy bin, not a layer), and mu inside the fitted range.
//!
//! rho_TBL is the minimum of the fitted curve over the fitted range: b - a for a dip (a > 0) centred
//! inside it; for a bump (a < 0) or a flat profile the curve's lowest end, close to b, the density of
//! a layer as dense as the bodies (paper: "it is possible to have a homogeneous density with
//! rho_TBL = rho_0").

use serde::{Deserialize, Serialize};

use crate::error::{Result, WearError};

/// A fitted Gaussian dip.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GaussFit {
    /// Baseline b.
    pub baseline: f64,
    /// Depth a (positive for a dip).
    pub depth: f64,
    /// Centre mu and width s (the x units).
    pub centre: f64,
    pub width: f64,
    /// Minimum of the fitted curve over the fitted range (rho_TBL).
    pub minimum: f64,
    /// Root-mean-square residual.
    pub rms: f64,
}

impl GaussFit {
    /// The fitted curve at `x`.
    pub fn at(&self, x: f64) -> f64 {
        let z = (x - self.centre) / self.width;
        self.baseline - self.depth * (-0.5 * z * z).exp()
    }
}

/// For fixed (mu, s): the least-squares (b, a) and the sum of squared residuals.
fn linear_part(x: &[f64], y: &[f64], mu: f64, s: f64) -> (f64, f64, f64) {
    let n = x.len() as f64;
    let g: Vec<f64> = x
        .iter()
        .map(|&xi| (-0.5 * ((xi - mu) / s).powi(2)).exp())
        .collect();
    let gm = g.iter().sum::<f64>() / n;
    let ym = y.iter().sum::<f64>() / n;
    let (mut sgg, mut sgy) = (0.0, 0.0);
    for (gi, yi) in g.iter().zip(y) {
        sgg += (gi - gm) * (gi - gm);
        sgy += (gi - gm) * (yi - ym);
    }
    // y ~ b - a g: a regression of y on g (a flat g leaves only the mean).
    let slope = if sgg > 1e-14 * n { sgy / sgg } else { 0.0 };
    let (a, b) = (-slope, ym - slope * gm);
    let ssr = g
        .iter()
        .zip(y)
        .map(|(gi, yi)| (yi - (b - a * gi)).powi(2))
        .sum();
    (b, a, ssr)
}

/// Fits the dip to the points (x, y) (at least 4, x increasing), width at least `min_width`.
pub fn fit_gaussian_dip(x: &[f64], y: &[f64], min_width: f64) -> Result<GaussFit> {
    if x.len() != y.len() || x.len() < 4 {
        return Err(WearError::Setting(format!(
            "a Gaussian fit needs at least 4 points and one y per x ({} x, {} y)",
            x.len(),
            y.len()
        )));
    }
    if !x.iter().chain(y).all(|v| v.is_finite()) || x.windows(2).any(|w| w[1] <= w[0]) {
        return Err(WearError::Setting(
            "a Gaussian fit needs finite values at increasing x".into(),
        ));
    }
    let (x0, x1) = (x[0], x[x.len() - 1]);
    let span = x1 - x0;
    if !(min_width.is_finite() && min_width > 0.0 && min_width < span) {
        return Err(WearError::Setting(format!(
            "the fit's smallest width {min_width} must be positive and below the range {span}"
        )));
    }
    let clamp = |mu: f64, ls: f64| (mu.clamp(x0, x1), ls.clamp(min_width.ln(), span.ln()));
    let cost = |mu: f64, ls: f64| {
        let (mu, ls) = clamp(mu, ls);
        linear_part(x, y, mu, ls.exp()).2
    };
    // Coarse grid: 64 centres by 16 widths (log-spaced from min_width to the range).
    let mut best = (f64::INFINITY, x0, min_width.ln());
    for i in 0..64 {
        let mu = x0 + span * (i as f64 + 0.5) / 64.0;
        for j in 0..16 {
            let ls = min_width.ln() + (span.ln() - min_width.ln()) * j as f64 / 15.0;
            let c = cost(mu, ls);
            if c < best.0 {
                best = (c, mu, ls);
            }
        }
    }
    // Nelder-Mead on (mu, ln s) from the grid's best.
    let step = (span / 64.0, (span.ln() - min_width.ln()) / 15.0);
    let mut simplex = [
        (best.1, best.2),
        (best.1 + step.0, best.2),
        (best.1, best.2 + step.1),
    ];
    let f = |p: (f64, f64)| cost(p.0, p.1);
    let mut vals = simplex.map(f);
    for _ in 0..400 {
        let mut order = [0, 1, 2];
        order.sort_by(|&a, &b| vals[a].total_cmp(&vals[b]));
        simplex = order.map(|k| simplex[k]);
        vals = order.map(|k| vals[k]);
        let size = (simplex[2].0 - simplex[0].0).abs() / span + (simplex[2].1 - simplex[0].1).abs();
        if size < 1e-10 {
            break;
        }
        let c = (
            0.5 * (simplex[0].0 + simplex[1].0),
            0.5 * (simplex[0].1 + simplex[1].1),
        );
        let along = |t: f64| {
            (
                c.0 + t * (simplex[2].0 - c.0),
                c.1 + t * (simplex[2].1 - c.1),
            )
        };
        let r = along(-1.0);
        let fr = f(r);
        if fr < vals[0] {
            let e = along(-2.0);
            let fe = f(e);
            (simplex[2], vals[2]) = if fe < fr { (e, fe) } else { (r, fr) };
        } else if fr < vals[1] {
            (simplex[2], vals[2]) = (r, fr);
        } else {
            let k = along(0.5);
            let fk = f(k);
            if fk < vals[2] {
                (simplex[2], vals[2]) = (k, fk);
            } else {
                for p in 1..3 {
                    simplex[p] = (
                        0.5 * (simplex[0].0 + simplex[p].0),
                        0.5 * (simplex[0].1 + simplex[p].1),
                    );
                    vals[p] = f(simplex[p]);
                }
            }
        }
    }
    let k = (0..3)
        .min_by(|&a, &b| vals[a].total_cmp(&vals[b]))
        .unwrap_or(0);
    let (mu, ls) = clamp(simplex[k].0, simplex[k].1);
    let s = ls.exp();
    let (b, a, ssr) = linear_part(x, y, mu, s);
    let mut fit = GaussFit {
        baseline: b,
        depth: a,
        centre: mu,
        width: s,
        minimum: 0.0,
        rms: (ssr / x.len() as f64).sqrt(),
    };
    // The curve is monotone on either side of mu: its minimum over [x0, x1] is at mu or an end.
    fit.minimum = [x0, x1, mu]
        .iter()
        .map(|&v| fit.at(v))
        .fold(f64::INFINITY, f64::min);
    Ok(fit)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    fn grid(n: usize) -> Vec<f64> {
        (0..n).map(|k| (k as f64 + 0.5) / n as f64).collect()
    }

    #[test]
    fn a_noisy_dip_is_recovered() {
        let x = grid(400);
        // Deterministic pseudo-noise of rms ~0.02 from incommensurate sines.
        let noise = |k: usize| 0.02 * ((k as f64 * 1.3).sin() + (k as f64 * TAU / 7.7).cos());
        let y: Vec<f64> = x
            .iter()
            .enumerate()
            .map(|(k, &v)| 1.02 - 0.35 * (-0.5 * ((v - 0.43) / 0.05f64).powi(2)).exp() + noise(k))
            .collect();
        let f = fit_gaussian_dip(&x, &y, 0.005).unwrap();
        assert!((f.centre - 0.43).abs() < 0.005, "{f:?}");
        assert!((f.width - 0.05).abs() < 0.005, "{f:?}");
        assert!((f.minimum - 0.67).abs() < 0.01, "{f:?}");
        assert!((f.baseline - 1.02).abs() < 0.005, "{f:?}");
        assert!(f.rms < 0.03);
    }

    #[test]
    fn a_flat_profile_reads_its_level_and_a_bump_its_baseline() {
        let x = grid(100);
        let flat = vec![0.98; 100];
        let f = fit_gaussian_dip(&x, &flat, 0.02).unwrap();
        assert!((f.minimum - 0.98).abs() < 1e-9, "{f:?}");
        let bump: Vec<f64> = x
            .iter()
            .map(|&v| 1.0 + 0.2 * (-0.5 * ((v - 0.5) / 0.1f64).powi(2)).exp())
            .collect();
        let f = fit_gaussian_dip(&x, &bump, 0.02).unwrap();
        assert!(f.depth < 0.0, "{f:?}");
        // The lowest end of the fitted bump: within a percent of the baseline.
        assert!((f.minimum - 1.0).abs() < 0.01, "{f:?}");
    }

    #[test]
    fn one_low_bin_is_not_a_layer() {
        // A single bin at half density: the width floor keeps the fit from diving into it.
        let x = grid(200);
        let mut y = vec![1.0; 200];
        y[100] = 0.5;
        let f = fit_gaussian_dip(&x, &y, 0.02).unwrap();
        assert!(f.width >= 0.02 - 1e-12);
        // At the width floor s the least-squares depth is the projection of the one-bin deficit on
        // the Gaussian: a = 0.5 / sum_k exp(-(k dx / s)^2) ~ 0.5 dx / (sqrt(pi) s) = 0.0705 here,
        // a dip of 7 % against the 50 % of the bin.
        let a = 0.5 * 0.005 / (std::f64::consts::PI.sqrt() * 0.02);
        assert!((f.depth - a).abs() < 0.03 * a, "{f:?} against {a}");
        assert!(f.minimum > 0.9, "{f:?}");
    }

    #[test]
    fn bad_inputs_are_refused() {
        let x = grid(10);
        assert!(fit_gaussian_dip(&x[..3], &x[..3], 0.1).is_err());
        assert!(fit_gaussian_dip(&x, &x[..9], 0.1).is_err());
        assert!(fit_gaussian_dip(&x, &x, 2.0).is_err());
        let mut y = x.clone();
        y[2] = f64::NAN;
        assert!(fit_gaussian_dip(&x, &y, 0.1).is_err());
    }
}
