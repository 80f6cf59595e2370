//! The calibration problem as the executor sees it: a vector of unknowns in, a vector of residuals out
//! (argmin-style: the problem knows nothing of the solver, the solver nothing of DEM).

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

/// A nonlinear least-squares problem: minimise 1/2 |r(x)|^2.
///
/// `residuals` must be deterministic (same x, same bits): the executor caches evaluations on disk and
/// a resumed run must retrace the uninterrupted one. It must be `Sync` because finite-difference
/// columns are evaluated in parallel.
pub trait Problem: Sync {
    /// Number of unknowns.
    fn dim(&self) -> usize;
    /// Names of the residuals (for the history), in order.
    fn residual_names(&self) -> Vec<String>;
    /// Residual vector at `x`.
    fn residuals(&self, x: &[f64]) -> Evaluation;
    /// Analytic Jacobian (row-major, one row per residual), when the problem has one; `None` lets the
    /// executor use finite differences.
    fn jacobian(&self, _x: &[f64]) -> Option<Vec<Vec<f64>>> {
        None
    }
}

/// Checks that an evaluation is usable: finite and of the announced length.
pub(crate) fn check(e: Evaluation, m: usize) -> Evaluation {
    let r = e?;
    if r.len() != m {
        return Err(EvalFailure(format!(
            "{} residuals where {m} were announced",
            r.len()
        )));
    }
    if let Some(i) = r.iter().position(|v| !v.is_finite()) {
        return Err(EvalFailure(format!("residual {i} is {}", r[i])));
    }
    Ok(r)
}
