//! The problem behind the on-disk evaluation cache (`DIR/evals/<hash>.json`, atomic writes), the
//! pool the evaluations run on, and the finite-difference Jacobian: a round's points evaluated side
//! by side and collected in order, so the same bits for any thread count.

use std::path::PathBuf;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::fingerprint;
use crate::error::{CalibrateError, Result};
use crate::problem::{check, EvalFailure, Measured, Problem};

pub(super) fn bits(x: &[f64]) -> Vec<u8> {
    x.iter().flat_map(|v| v.to_bits().to_le_bytes()).collect()
}

pub(super) type Outcome = std::result::Result<Measured, EvalFailure>;

#[derive(Serialize, Deserialize)]
struct CachedEval {
    x: Vec<f64>,
    outcome: Outcome,
}

/// The problem behind the on-disk evaluation cache, and the pool the evaluations run on.
pub(super) struct Evaluator<'a, P: Problem> {
    pub(super) problem: &'a P,
    pub(super) dir: Option<PathBuf>,
    pub(super) fingerprint: String,
    pub(super) pool: Option<rayon::ThreadPool>,
}

impl<P: Problem> Evaluator<'_, P> {
    /// Evaluates `xs` side by side on the pool, in order. An interrupt requested meanwhile ends the
    /// round with [`CalibrateError::Interrupted`] (the completed evaluations are cached).
    pub(super) fn batch(&self, xs: &[Vec<f64>]) -> Result<Vec<Outcome>> {
        let run = || -> Vec<Outcome> {
            xs.par_iter()
                .with_max_len(1)
                .map(|x| self.eval(x))
                .collect()
        };
        let out = match &self.pool {
            Some(pool) => pool.install(run),
            None => run(),
        };
        if dem::interrupt::requested() {
            return Err(CalibrateError::Interrupted);
        }
        Ok(out)
    }

    pub(super) fn one(&self, x: &[f64]) -> Result<Outcome> {
        let mut v = self.batch(&[x.to_vec()])?;
        Ok(v.remove(0))
    }

    fn eval(&self, x: &[f64]) -> Outcome {
        let m = self.problem.residual_names().len();
        let Some(dir) = &self.dir else {
            return check(self.problem.evaluate(x), m);
        };
        let key = fingerprint(&[self.fingerprint.as_bytes(), &bits(x)]);
        let path = dir.join("evals").join(format!("{key}.json"));
        if let Ok(text) = std::fs::read(&path) {
            if let Ok(c) = serde_json::from_slice::<CachedEval>(&text) {
                if bits(&c.x) == bits(x) {
                    return c.outcome;
                }
            }
        }
        let outcome = check(self.problem.evaluate(x), m);
        if outcome.is_err() && dem::interrupt::requested() {
            // Possibly a failure of the interrupt itself, not of the point: not cached.
            return outcome;
        }
        let c = CachedEval {
            x: x.to_vec(),
            outcome: outcome.clone(),
        };
        // A cache that cannot be written costs time on a resume, never correctness.
        if let Ok(bytes) = serde_json::to_vec(&c) {
            if let Err(e) = dem::io::checkpoint::write_atomic(&path, &bytes) {
                tracing::warn!(%e, "evaluation cache not written");
            }
        }
        outcome
    }

    /// Jacobian at (x, r): analytic when the problem has one, else finite differences (forward, or
    /// central when `central`) evaluated side by side; returns it with the number of evaluations
    /// requested.
    pub(super) fn jacobian(
        &self,
        x: &[f64],
        r: &[f64],
        h: f64,
        central: bool,
    ) -> Result<(Vec<Vec<f64>>, usize)> {
        if let Some(j) = self.problem.jacobian(x) {
            return Ok((j, 0));
        }
        let n = x.len();
        let shifted = |k: usize, sign: f64| {
            let mut xp = x.to_vec();
            xp[k] += sign * h;
            xp
        };
        let slope = |a: &[f64], b: &[f64], d: f64| -> Vec<f64> {
            a.iter().zip(b).map(|(p, q)| (p - q) / d).collect()
        };
        let ok = |k: usize, sign: f64, e: Outcome| match e {
            Ok(m) => Some(m.r),
            Err(e) => {
                tracing::warn!(unknown = k, sign, %e, "finite-difference point failed");
                None
            }
        };
        // All points of all columns in one parallel batch (collected in order).
        let points: Vec<(usize, f64)> = (0..n)
            .flat_map(|k| {
                if central {
                    vec![(k, 1.0), (k, -1.0)]
                } else {
                    vec![(k, 1.0)]
                }
            })
            .collect();
        let xs: Vec<Vec<f64>> = points.iter().map(|&(k, s)| shifted(k, s)).collect();
        let mut got: Vec<Option<Vec<f64>>> = self
            .batch(&xs)?
            .into_iter()
            .zip(&points)
            .map(|(e, &(k, s))| ok(k, s, e))
            .collect();
        let mut evaluations = points.len();
        let mut cols = Vec::with_capacity(n);
        for k in 0..n {
            let col = if central {
                match (got[2 * k].take(), got[2 * k + 1].take()) {
                    (Some(p), Some(m)) => slope(&p, &m, 2.0 * h),
                    (Some(p), None) => slope(&p, r, h),
                    (None, Some(m)) => slope(r, &m, h),
                    (None, None) => vec![0.0; r.len()],
                }
            } else if let Some(p) = got[k].take() {
                slope(&p, r, h)
            } else {
                // A failed forward point is retried backwards.
                evaluations += 1;
                ok(k, -1.0, self.one(&shifted(k, -1.0))?)
                    .map_or(vec![0.0; r.len()], |m| slope(r, &m, h))
            };
            cols.push(col);
        }
        let j = (0..r.len())
            .map(|i| (0..n).map(|k| cols[k][i]).collect())
            .collect();
        Ok((j, evaluations))
    }
}
