//! The calibration problem as the executor sees it: a vector of unknowns in, a vector of residuals out
//! (argmin-style: the problem knows nothing of the solver, the solver nothing of DEM).
//!
//! A problem whose residuals are means over several samples (the recipe-level patch problem: k
//! relaxed samples per evaluation) also reports each sample's residuals and the standard error of
//! the mean ([`Measured`]); the solvers take that as the noise level of the response.

use serde::{Deserialize, Serialize};

/// Why one evaluation produced no usable residuals (diverged run, NaN, collapsed sample ...). It is a
/// value, not an error: the executor records it and treats the point as infinitely bad.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct EvalFailure(pub String);

impl std::fmt::Display for EvalFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

/// Outcome of one evaluation.
pub type Evaluation = Result<Vec<f64>, EvalFailure>;

/// The residuals of one evaluation with what is known of their noise.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Measured {
    /// The residuals (of the mean over the samples, for a sampled problem).
    pub r: Vec<f64>,
    /// Standard error of each residual: the standard deviation across the samples over sqrt(k);
    /// empty for a problem without samples (deterministic, no noise estimate).
    #[serde(default)]
    pub noise: Vec<f64>,
    /// Each sample's residuals (one row per sample); empty for a problem without samples.
    #[serde(default)]
    pub samples: Vec<Vec<f64>>,
}

impl Measured {
    /// Residuals without noise information.
    pub fn exact(r: Vec<f64>) -> Self {
        Measured {
            r,
            noise: Vec::new(),
            samples: Vec::new(),
        }
    }

    /// The mean of per-sample residual rows, with the standard error of the mean as the noise (zero
    /// for a single sample: one sample says nothing about the spread).
    pub fn mean_of(samples: Vec<Vec<f64>>) -> Self {
        let k = samples.len();
        let m = samples.first().map_or(0, Vec::len);
        let mean: Vec<f64> = (0..m)
            .map(|i| samples.iter().map(|s| s[i]).sum::<f64>() / k as f64)
            .collect();
        let noise = (0..m)
            .map(|i| {
                if k < 2 {
                    return 0.0;
                }
                let var = samples
                    .iter()
                    .map(|s| (s[i] - mean[i]).powi(2))
                    .sum::<f64>()
                    / (k - 1) as f64;
                (var / k as f64).sqrt()
            })
            .collect();
        Measured {
            r: mean,
            noise,
            samples,
        }
    }

    /// The largest noise over the residuals (0 without noise information).
    pub fn max_noise(&self) -> f64 {
        self.noise.iter().fold(0.0f64, |a, v| a.max(*v))
    }
}

/// A nonlinear least-squares problem: minimise 1/2 |r(x)|^2.
///
/// `residuals` must be deterministic (same x, same bits): the executor caches evaluations on disk and
/// a resumed run must retrace the uninterrupted one. It must be `Sync` because evaluations (finite
/// difference columns, interpolation points) run in parallel.
pub trait Problem: Sync {
    /// Number of unknowns.
    fn dim(&self) -> usize;
    /// Names of the residuals (for the history), in order.
    fn residual_names(&self) -> Vec<String>;
    /// Residual vector at `x`.
    fn residuals(&self, x: &[f64]) -> Evaluation;
    /// Residuals at `x` with their noise; the default has none (a deterministic problem).
    fn evaluate(&self, x: &[f64]) -> Result<Measured, EvalFailure> {
        self.residuals(x).map(Measured::exact)
    }
    /// Analytic Jacobian (row-major, one row per residual), when the problem has one; `None` lets the
    /// executor use finite differences.
    fn jacobian(&self, _x: &[f64]) -> Option<Vec<Vec<f64>>> {
        None
    }
}

/// Checks that an evaluation is usable: finite and of the announced length.
pub(crate) fn check(e: Result<Measured, EvalFailure>, m: usize) -> Result<Measured, EvalFailure> {
    let e = e?;
    if e.r.len() != m {
        return Err(EvalFailure(format!(
            "{} residuals where {m} were announced",
            e.r.len()
        )));
    }
    if let Some(i) = e.r.iter().position(|v| !v.is_finite()) {
        return Err(EvalFailure(format!("residual {i} is {}", e.r[i])));
    }
    Ok(e)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_mean_of_samples_carries_its_standard_error() {
        let m = Measured::mean_of(vec![vec![1.0, 0.0], vec![3.0, 0.0]]);
        assert_eq!(m.r, vec![2.0, 0.0]);
        // Sample standard deviation sqrt(2), over sqrt(2): 1.
        assert!((m.noise[0] - 1.0).abs() < 1e-15 && m.noise[1] == 0.0);
        assert_eq!(Measured::mean_of(vec![vec![0.5]]).noise, vec![0.0]);
        assert_eq!(m.max_noise(), m.noise[0]);
    }
}
