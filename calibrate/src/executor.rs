//! The executor: owns the Levenberg-Marquardt loop, the stopping rules, observers, the on-disk
//! evaluation cache and the per-iteration checkpoint. The solver maths lives in [`crate::lm`].
//!
//! - **Iteration** = one trial step (accepted or rejected). The Jacobian is recomputed only after an
//!   accepted step, so a rejection costs one evaluation; with `broyden` it is updated by the secant of
//!   every trial step instead and recomputed only after `refresh_after` rejections in a row.
//! - **Finite differences** (when the problem has no analytic Jacobian): forward differences in the
//!   unknowns (log multipliers), the n perturbed points evaluated in parallel with rayon and collected
//!   in order. The step `fd_step` trades truncation error (the patch-test outputs are close to power
//!   laws in the multipliers, so nearly linear in log space) against the noise of the discrete
//!   dynamics (relative ~1e-4 from the elastic convergence test, ~1e-3 from sampling the peak stress):
//!   the classic optimum sqrt(noise) gives 0.01-0.03; default 0.03 (a 3 % change of one multiplier).
//!   A failed forward point is retried backwards; if both fail the column is zero (the damping then
//!   keeps that unknown still).
//! - **Failures**: a failed trial (NaN, divergence, collapsed sample) is recorded, rejected, and the
//!   damping grows (a trust region shrinking); only a failed first guess is fatal.
//! - **Resumability**: every evaluation is cached in `DIR/evals/<hash>.json` and the state plus the
//!   history go to `DIR/checkpoint.json` after every iteration, both by atomic rename. A rerun with the
//!   same fingerprint (problem description, settings, start) resumes; since evaluations are
//!   deterministic, it retraces the uninterrupted run bit for bit. A kill loses at most the
//!   evaluations in flight.

use std::path::{Path, PathBuf};
use std::time::Instant;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::error::{CalibrateError, Result};
use crate::lm;
use crate::problem::{check, EvalFailure, Evaluation, Problem};

/// Stopping rules and step control.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Settings {
    /// Converged when every |r_i| <= tolerance; default 2e-3: a fifth of the 1 % acceptance band and
    /// above the ~1e-3 noise of the patch tests.
    pub tolerance: f64,
    /// Budget of trial steps; default 15 (the patch-test problems converge in 3-8).
    pub max_iterations: usize,
    /// Forward-difference step in the unknowns; default 0.03 (see the module docs).
    pub fd_step: f64,
    /// Initial damping relative to max diag(J^T J); default 1e-2 (a first guess 10 % off is trusted
    /// nearly as a Gauss-Newton step).
    pub tau: f64,
    /// Largest change of one unknown in one step; default 0.4 (a factor 1.5 on a multiplier): keeps
    /// the first steps inside the range where the patch tests stay well-posed.
    pub max_step: f64,
    /// Stop when the step is shorter than this (infinity norm); default 1e-5.
    pub min_step: f64,
    /// Central differences (2n evaluations per Jacobian instead of n); default false. They remove the
    /// truncation error of forward differences, not the noise: worth it only when the step has to be
    /// large (noisy responses) and the response is curved over it.
    pub central: bool,
    /// Broyden (secant) updates: after every trial step, accepted or rejected, the Jacobian takes the
    /// rank-1 correction J += (dr - J h) h^T / |h|^2 that makes it reproduce the measured change (only
    /// for steps of at least fd_step / 2: shorter ones are inside the noise scale), and
    /// is recomputed by finite differences only after `refresh_after` rejections in a row, if an
    /// accepted step has moved the point since the last finite differences (Madsen,
    /// Nielsen & Tingleff 2004, section 3.4); default false (fresh finite differences after every
    /// accepted step). One evaluation per iteration instead of n + 1, and every trial, even a rejected
    /// one, teaches the model something: on noisy responses the secant over a real step is a better
    /// slope than a finite difference over a small one.
    pub broyden: bool,
    /// Rejections in a row that trigger a finite-difference refresh of a Broyden Jacobian (the damping
    /// restarts from tau); default 2.
    pub refresh_after: usize,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            tolerance: 2e-3,
            max_iterations: 15,
            fd_step: 0.03,
            tau: 1e-2,
            max_step: 0.4,
            min_step: 1e-5,
            central: false,
            broyden: false,
            refresh_after: 2,
        }
    }
}

impl Settings {
    /// Checks every setting (also done by [`crate::CalibrationConfig::prepare`], before any simulation).
    pub fn validate(&self) -> Result<()> {
        if let Some(m) = dem::error::not_positive(&[
            ("tolerance", self.tolerance),
            ("fd_step", self.fd_step),
            ("tau", self.tau),
            ("max_step", self.max_step),
            ("min_step", self.min_step),
        ]) {
            return Err(CalibrateError::InvalidConfig(format!("solver {m}")));
        }
        if self.refresh_after == 0 {
            return Err(CalibrateError::InvalidConfig(
                "solver refresh_after must be at least 1".into(),
            ));
        }
        Ok(())
    }
}

/// Where the loop stands.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    Running,
    /// Every residual within the tolerance.
    Converged,
    /// Budget spent.
    MaxIterations,
    /// No further progress possible (reason).
    Stalled(String),
}

/// The loop state, everything a resumed run needs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct State {
    pub x: Vec<f64>,
    pub r: Vec<f64>,
    /// Jacobian at x (rows = residuals), `None` until computed.
    pub jacobian: Option<Vec<Vec<f64>>>,
    /// Damping (set from the first Jacobian) and its growth factor.
    pub lambda: Option<f64>,
    pub nu: f64,
    pub iteration: usize,
    /// Trial steps rejected since the last accepted one (Broyden refresh rule).
    #[serde(default)]
    pub rejections: usize,
    /// An accepted step since the Jacobian was last computed (a refresh at the same point would
    /// only repeat it).
    #[serde(default)]
    pub moved: bool,
    /// Evaluations requested (cache hits included, so the count is the same after a resume).
    pub evaluations: usize,
    pub status: Status,
}

/// One line of the iteration history.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Record {
    pub iteration: usize,
    /// Trial point and its residuals (None when the evaluation failed, with the reason).
    pub x_trial: Vec<f64>,
    pub r_trial: Option<Vec<f64>>,
    pub failure: Option<String>,
    /// 1/2 |r|^2 before the step, at the trial point, and the linear model's prediction.
    pub cost: f64,
    pub cost_trial: Option<f64>,
    pub predicted: f64,
    pub accepted: bool,
    /// Damping after the update.
    pub lambda: f64,
    /// Residuals at the current point after this iteration.
    pub r: Vec<f64>,
    pub evaluations: usize,
    /// Wall time since the start of this process (not compared on resume).
    pub seconds: f64,
}

/// What is on disk.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Checkpoint {
    pub fingerprint: String,
    pub residual_names: Vec<String>,
    /// Residuals at the start (the uncalibrated measurement).
    pub r0: Vec<f64>,
    pub state: State,
    pub history: Vec<Record>,
}

/// FNV-1a 64 of the parts: a hash that is stable across Rust versions and platforms.
pub fn fingerprint(parts: &[&[u8]]) -> String {
    let mut h: u64 = 0xcbf29ce484222325;
    for p in parts {
        for b in p.iter().chain(&[0xff]) {
            h ^= u64::from(*b);
            h = h.wrapping_mul(0x100000001b3);
        }
    }
    format!("{h:016x}")
}

fn bits(x: &[f64]) -> Vec<u8> {
    x.iter().flat_map(|v| v.to_bits().to_le_bytes()).collect()
}

#[derive(Serialize, Deserialize)]
struct CachedEval {
    x: Vec<f64>,
    outcome: Evaluation,
}

type Observer<'a> = Box<dyn FnMut(&Record, &State) + 'a>;

/// The problem behind the on-disk evaluation cache (shared by the parallel finite-difference points).
struct Evaluator<'a, P: Problem> {
    problem: &'a P,
    dir: Option<PathBuf>,
    fingerprint: String,
}

/// The loop around a [`Problem`].
pub struct Executor<'a, P: Problem> {
    ev: Evaluator<'a, P>,
    settings: Settings,
    x0: Vec<f64>,
    observers: Vec<Observer<'a>>,
    stop_after: Option<usize>,
    t0: Instant,
}

impl<P: Problem> std::fmt::Debug for Executor<'_, P> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Executor")
            .field("settings", &self.settings)
            .field("x0", &self.x0)
            .field("dir", &self.ev.dir)
            .field("fingerprint", &self.ev.fingerprint)
            .finish_non_exhaustive()
    }
}

impl<'a, P: Problem> Executor<'a, P> {
    /// An executor starting at `x0`; `description` identifies the problem for checkpoints (e.g. its
    /// serialised configuration).
    pub fn new(problem: &'a P, x0: Vec<f64>, settings: Settings, description: &str) -> Self {
        // The stopping rules (budget, tolerance) do not change the trajectory, only where it ends:
        // left out of the fingerprint so that a finished run can be resumed with a larger budget.
        let path = Settings {
            max_iterations: 0,
            tolerance: 0.0,
            ..settings
        };
        let set = serde_json::to_vec(&path).unwrap_or_default();
        let fingerprint = fingerprint(&[description.as_bytes(), &set, &bits(&x0)]);
        Executor {
            ev: Evaluator {
                problem,
                dir: None,
                fingerprint,
            },
            settings,
            x0,
            observers: Vec::new(),
            stop_after: None,
            t0: Instant::now(),
        }
    }

    /// Checkpoint and cache evaluations in `dir` (resuming from it when it holds a checkpoint).
    pub fn checkpoint_dir(mut self, dir: &Path) -> Self {
        self.ev.dir = Some(dir.to_path_buf());
        self
    }

    /// Called after every iteration.
    pub fn observe(mut self, f: impl FnMut(&Record, &State) + 'a) -> Self {
        self.observers.push(Box::new(f));
        self
    }

    /// Return (status still `Running`) once the state reaches this iteration: what a kill right after a
    /// checkpoint leaves behind; used by the resume tests.
    pub fn stop_after(mut self, iteration: usize) -> Self {
        self.stop_after = Some(iteration);
        self
    }

    pub fn fingerprint(&self) -> &str {
        &self.ev.fingerprint
    }
}

impl<P: Problem> Evaluator<'_, P> {
    fn eval(&self, x: &[f64]) -> Evaluation {
        let m = self.problem.residual_names().len();
        let Some(dir) = &self.dir else {
            return check(self.problem.residuals(x), m);
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
        let outcome = check(self.problem.residuals(x), m);
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

    /// Jacobian at (x, r): analytic when the problem has one, else parallel finite differences
    /// (forward, or central when `central`); returns it with the number of evaluations requested.
    fn jacobian(&self, x: &[f64], r: &[f64], h: f64, central: bool) -> (Vec<Vec<f64>>, usize) {
        if let Some(j) = self.problem.jacobian(x) {
            return (j, 0);
        }
        let n = x.len();
        let shifted = |k: usize, sign: f64| {
            let mut xp = x.to_vec();
            xp[k] += sign * h;
            let e = self.eval(&xp);
            if let Err(e) = &e {
                tracing::warn!(unknown = k, sign, %e, "finite-difference point failed");
            }
            e.ok()
        };
        let slope = |a: &[f64], b: &[f64], d: f64| -> Vec<f64> {
            a.iter().zip(b).map(|(p, q)| (p - q) / d).collect()
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
        let mut got: Vec<Option<Vec<f64>>> = points
            .par_iter()
            .map(|&(k, sign)| shifted(k, sign))
            .collect();
        let mut evaluations = points.len();
        let cols: Vec<Vec<f64>> = (0..n)
            .map(|k| {
                if central {
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
                    shifted(k, -1.0).map_or(vec![0.0; r.len()], |m| slope(r, &m, h))
                }
            })
            .collect();
        let j = (0..r.len())
            .map(|i| (0..n).map(|k| cols[k][i]).collect())
            .collect();
        (j, evaluations)
    }
}

impl<'a, P: Problem> Executor<'a, P> {
    fn save(&self, cp: &Checkpoint) -> Result<()> {
        if let Some(dir) = &self.ev.dir {
            let path = dir.join("checkpoint.json");
            let bytes =
                serde_json::to_vec_pretty(cp).map_err(|e| CalibrateError::format(&path, e))?;
            dem::io::checkpoint::write_atomic(&path, &bytes)?;
        }
        Ok(())
    }

    fn load_or_start(&self) -> Result<Checkpoint> {
        if let Some(dir) = &self.ev.dir {
            let path = dir.join("checkpoint.json");
            if path.exists() {
                let text = std::fs::read(&path).map_err(|e| CalibrateError::io(&path, e))?;
                let cp: Checkpoint =
                    serde_json::from_slice(&text).map_err(|e| CalibrateError::format(&path, e))?;
                if cp.fingerprint != self.ev.fingerprint {
                    return Err(CalibrateError::ForeignCheckpoint {
                        path: path.display().to_string(),
                        found: cp.fingerprint,
                        expected: self.ev.fingerprint.clone(),
                    });
                }
                tracing::info!(iteration = cp.state.iteration, "resuming from checkpoint");
                let mut cp = cp;
                if matches!(cp.state.status, Status::Converged | Status::MaxIterations) {
                    // Re-judged with the current stopping rules (a larger budget continues).
                    cp.state.status = Status::Running;
                }
                return Ok(cp);
            }
        }
        let r = self
            .ev
            .eval(&self.x0)
            .map_err(|EvalFailure(e)| CalibrateError::StartFailed(e))?;
        let cp = Checkpoint {
            fingerprint: self.ev.fingerprint.clone(),
            residual_names: self.ev.problem.residual_names(),
            r0: r.clone(),
            state: State {
                x: self.x0.clone(),
                r,
                jacobian: None,
                lambda: None,
                nu: 2.0,
                iteration: 0,
                rejections: 0,
                moved: false,
                evaluations: 1,
                status: Status::Running,
            },
            history: Vec::new(),
        };
        self.save(&cp)?;
        Ok(cp)
    }

    /// Runs (or resumes) the loop to a stopping rule; returns the final checkpoint.
    pub fn run(mut self) -> Result<Checkpoint> {
        self.settings.validate()?;
        if self.x0.len() != self.ev.problem.dim() {
            return Err(CalibrateError::InvalidConfig(format!(
                "start has {} unknowns, the problem {}",
                self.x0.len(),
                self.ev.problem.dim()
            )));
        }
        let mut cp = self.load_or_start()?;
        let s = self.settings;
        while cp.state.status == Status::Running {
            let st = &mut cp.state;
            if st.r.iter().all(|v| v.abs() <= s.tolerance) {
                st.status = Status::Converged;
            } else if st.iteration >= s.max_iterations {
                st.status = Status::MaxIterations;
            } else if self.stop_after.is_some_and(|k| st.iteration >= k) {
                return Ok(cp);
            }
            if st.status != Status::Running {
                self.save(&cp)?;
                break;
            }
            if st.jacobian.is_none() {
                let (j, evaluations) = self.ev.jacobian(&st.x, &st.r, s.fd_step, s.central);
                st.evaluations += evaluations;
                st.lambda
                    .get_or_insert_with(|| lm::initial_lambda(&j, s.tau));
                st.jacobian = Some(j);
                st.moved = false;
                // Keep the finite-difference work even if the process dies in the trial evaluation.
                self.save(&cp)?;
            }
            self.iterate(&mut cp)?;
            self.save(&cp)?;
        }
        Ok(cp)
    }

    fn iterate(&mut self, cp: &mut Checkpoint) -> Result<()> {
        let s = self.settings;
        let st = &mut cp.state;
        let (Some(j), Some(lambda)) = (st.jacobian.clone(), st.lambda) else {
            return Ok(());
        };
        let n = st.x.len();
        let Some(mut h) = lm::damped_step(&j, &st.r, lambda, &vec![1.0; n]) else {
            st.status = Status::Stalled("the damped step is not finite".into());
            return Ok(());
        };
        let hmax = h.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if hmax > s.max_step {
            h.iter_mut().for_each(|v| *v *= s.max_step / hmax);
        }
        if hmax < s.min_step {
            st.status = Status::Stalled(format!("step {hmax:.2e} below min_step"));
            return Ok(());
        }
        let predicted = lm::predicted_reduction(&j, &st.r, &h);
        let xt: Vec<f64> = st.x.iter().zip(&h).map(|(a, b)| a + b).collect();
        let cost = 0.5 * lm::norm2(&st.r);
        let trial = self.ev.eval(&xt);
        st.evaluations += 1;
        let (rt, failure) = match trial {
            Ok(r) => (Some(r), None),
            Err(EvalFailure(e)) => (None, Some(e)),
        };
        let cost_trial = rt.as_ref().map(|r| 0.5 * lm::norm2(r));
        let rho = cost_trial
            .filter(|_| predicted > 0.0)
            .map(|ct| (cost - ct) / predicted);
        let accepted = rho.is_some_and(|r| r > 1e-3);
        let (lambda, nu) = lm::update_damping(lambda, st.nu, rho.filter(|_| accepted));
        st.lambda = Some(lambda);
        st.nu = nu;
        if s.broyden {
            // A step shorter than half the finite-difference step is inside the noise scale the
            // user declared with `fd_step`: its secant would be noise over a small denominator.
            let hmax = h.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            if let (Some(rt), Some(j)) = (&rt, st.jacobian.as_mut()) {
                if hmax >= 0.5 * s.fd_step {
                    lm::broyden_update(j, &h, &st.r, rt);
                }
            }
            st.rejections = if accepted { 0 } else { st.rejections + 1 };
            st.moved |= accepted;
            if st.rejections >= s.refresh_after && st.moved {
                // The secant model has misled twice in a row: fresh finite differences here, and
                // the damping restarts from them.
                st.jacobian = None;
                st.lambda = None;
                st.nu = 2.0;
                st.rejections = 0;
            }
        }
        if accepted {
            st.x = xt.clone();
            st.r = rt.clone().unwrap_or_default();
            if !s.broyden {
                st.jacobian = None;
            }
        }
        st.iteration += 1;
        if lambda > 1e12 {
            st.status = Status::Stalled("damping above 1e12: no descent direction left".into());
        }
        let rec = Record {
            iteration: st.iteration,
            x_trial: xt,
            r_trial: rt,
            failure,
            cost,
            cost_trial,
            predicted,
            accepted,
            lambda,
            r: st.r.clone(),
            evaluations: st.evaluations,
            seconds: self.t0.elapsed().as_secs_f64(),
        };
        tracing::info!(
            iteration = rec.iteration,
            accepted,
            cost = %dem::io::Sig(cost, 4),
            cost_trial = %cost_trial.map_or("-".to_string(), |c| dem::io::Sig(c, 4).to_string()),
            lambda = %dem::io::Sig(lambda, 3),
            "calibration step"
        );
        for o in &mut self.observers {
            o(&rec, st);
        }
        cp.history.push(rec);
        Ok(())
    }
}
