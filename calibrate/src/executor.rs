//! The executor: owns the loop, the stopping rules, observers, the on-disk evaluation cache and the
//! per-iteration checkpoint; the solvers' maths lives in [`crate::lm`] (Levenberg-Marquardt) and
//! [`crate::trust_region`] (the response-surface trust region).
//!
//! - **Iteration** = one trial step (accepted or rejected).
//! - **Levenberg-Marquardt** (`method = "levenberg_marquardt"`, the default): the Jacobian is
//!   recomputed only after an accepted step, so a rejection costs one evaluation; with `broyden` it is
//!   updated by the secant of every trial step instead and recomputed only after `refresh_after`
//!   rejections in a row. Finite differences (when the problem has no analytic Jacobian) are forward
//!   differences in the unknowns (log multipliers), the n perturbed points evaluated side by side and
//!   collected in order. The step `fd_step` trades truncation error (the patch-test outputs are close
//!   to power laws in the multipliers, so nearly linear in log space) against the noise of the discrete
//!   dynamics (relative ~1e-4 from the elastic convergence test, ~1e-3 from sampling the peak stress):
//!   the classic optimum sqrt(noise) gives 0.01-0.03; default 0.03 (a 3 % change of one multiplier).
//!   A failed forward point is retried backwards; if both fail the column is zero (the damping then
//!   keeps that unknown still).
//! - **Trust region** (`method = "trust_region"`): see [`crate::trust_region`]; one evaluation per
//!   iteration once the model has its points, plus geometry points when the region leaves them behind.
//! - **Noise**: a problem that averages samples reports the standard error of its residuals with
//!   every evaluation ([`Measured`]). Neither solver differences over less than `noise_factor` times
//!   the current point's noise (the finite-difference step of LM, the smallest trust radius), so
//!   that a slope is a trend and not the difference of two noise draws.
//! - **Failures**: a failed trial (NaN, divergence, collapsed sample) is recorded, rejected, and the
//!   damping grows / the radius shrinks; only a failed first guess is fatal.
//! - **Parallelism** is explicit: the points of a round and the samples and tests inside each point
//!   run on a rayon pool of the size given to [`Executor::parallelism`] (one thread by default),
//!   collected in order, so results are the same bits for any thread count.
//! - **Resumability**: every evaluation is cached in `DIR/evals/<hash>.json` and the state plus the
//!   history go to `DIR/checkpoint.json` after every iteration, both by atomic rename. A rerun with the
//!   same fingerprint (problem description, settings, start) resumes; since evaluations are
//!   deterministic, it retraces the uninterrupted run bit for bit. A kill loses at most the
//!   evaluations in flight; an interrupt (Ctrl-C) returns [`CalibrateError::Interrupted`] after the
//!   round in flight, whose completed evaluations are kept (a failure caused by the interrupt is not).

use std::path::{Path, PathBuf};
use std::time::Instant;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::error::{CalibrateError, Result};
use crate::lm;
use crate::problem::{check, EvalFailure, Measured, Problem};
use crate::trust_region as tr;

/// Which solver steps.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// Levenberg-Marquardt on a finite-difference (optionally Broyden-updated) Jacobian.
    #[default]
    LevenbergMarquardt,
    /// Derivative-free trust region on a regression model of the residuals.
    TrustRegion,
}

/// Stopping rules and step control.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Settings {
    /// Solver; default Levenberg-Marquardt (deterministic responses: lattices, analytic problems).
    pub method: Method,
    /// Converged when every |r_i| <= tolerance; default 2e-3: a fifth of the 1 % acceptance band and
    /// above the ~1e-3 noise of the patch tests.
    pub tolerance: f64,
    /// Budget of trial steps; default 15 (the patch-test problems converge in 3-8).
    pub max_iterations: usize,
    /// Forward-difference step in the unknowns (LM); default 0.03 (see the module docs).
    pub fd_step: f64,
    /// Initial damping relative to max diag(J^T J) (LM); default 1e-2 (a first guess 10 % off is
    /// trusted nearly as a Gauss-Newton step).
    pub tau: f64,
    /// Largest change of one unknown in one step (LM), and the largest trust radius; default 0.4 (a
    /// factor 1.5 on a multiplier): keeps the first steps inside the range where the patch tests stay
    /// well-posed.
    pub max_step: f64,
    /// Stop when the step is shorter than this (infinity norm); default 1e-5.
    pub min_step: f64,
    /// Central differences (LM: 2n evaluations per Jacobian instead of n); default false. They remove
    /// the truncation error of forward differences, not the noise: worth it only when the step has to
    /// be large (noisy responses) and the response is curved over it.
    pub central: bool,
    /// Broyden (secant) updates (LM): after every trial step, accepted or rejected, the Jacobian takes
    /// the rank-1 correction J += (dr - J h) h^T / |h|^2 that makes it reproduce the measured change
    /// (only for steps of at least fd_step / 2: shorter ones are inside the noise scale), and
    /// is recomputed by finite differences only after `refresh_after` rejections in a row, if an
    /// accepted step has moved the point since the last finite differences (Madsen,
    /// Nielsen & Tingleff 2004, section 3.4); default false (fresh finite differences after every
    /// accepted step). One evaluation per iteration instead of n + 1, and every trial, even a rejected
    /// one, teaches the model something: on noisy responses the secant over a real step is a better
    /// slope than a finite difference over a small one.
    pub broyden: bool,
    /// Rejections in a row that trigger a finite-difference refresh of a Broyden Jacobian (the damping
    /// restarts from tau), or (trust region) that end the run once the radius is within the noise
    /// floor; default 2.
    pub refresh_after: usize,
    /// Initial trust radius (Euclidean, in the unknowns); default 0.1: a 10 % change of a multiplier,
    /// above the scale of the jumps of relaxed packings (docs/calibration.md).
    pub radius: f64,
    /// Smallest trust radius; default 0.02 (the step radius after failed trials; the model's
    /// radius never goes below the noise floor, see `noise_factor`).
    pub min_radius: f64,
    /// Differences are taken over at least this many times the current point's noise (its largest
    /// standard error): the floor of the finite-difference step and of the trust radius; default 3.
    pub noise_factor: f64,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            method: Method::LevenbergMarquardt,
            tolerance: 2e-3,
            max_iterations: 15,
            fd_step: 0.03,
            tau: 1e-2,
            max_step: 0.4,
            min_step: 1e-5,
            central: false,
            broyden: false,
            refresh_after: 2,
            radius: 0.1,
            min_radius: 0.02,
            noise_factor: 3.0,
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
            ("radius", self.radius),
            ("min_radius", self.min_radius),
        ]) {
            return Err(CalibrateError::InvalidConfig(format!("solver {m}")));
        }
        if self.refresh_after == 0 {
            return Err(CalibrateError::InvalidConfig(
                "solver refresh_after must be at least 1".into(),
            ));
        }
        if !(self.noise_factor.is_finite() && self.noise_factor >= 0.0) {
            return Err(CalibrateError::InvalidConfig(
                "solver noise_factor must be a number >= 0".into(),
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
    /// Standard error of each residual at x (empty when the problem reports none).
    #[serde(default)]
    pub noise: Vec<f64>,
    /// Jacobian at x (rows = residuals), `None` until computed (LM).
    pub jacobian: Option<Vec<Vec<f64>>>,
    /// Damping (set from the first Jacobian) and its growth factor (LM).
    pub lambda: Option<f64>,
    pub nu: f64,
    /// Trust radius (trust region).
    #[serde(default)]
    pub radius: Option<f64>,
    /// Every successfully evaluated point, in order (trust region: the model is fitted on them).
    #[serde(default)]
    pub points: Vec<tr::Sample>,
    pub iteration: usize,
    /// Trial steps rejected since the last accepted one (Broyden refresh rule, trust-region stall).
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
    /// Standard error of the trial's residuals (the spread across its samples over sqrt(k)).
    #[serde(default)]
    pub noise_trial: Vec<f64>,
    pub failure: Option<String>,
    /// 1/2 |r|^2 before the step, at the trial point, and the model's prediction.
    pub cost: f64,
    pub cost_trial: Option<f64>,
    pub predicted: f64,
    pub accepted: bool,
    /// Damping (LM) or trust radius (trust region) after the update.
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
    /// Residuals at the start (the uncalibrated measurement) and their noise.
    pub r0: Vec<f64>,
    #[serde(default)]
    pub noise0: Vec<f64>,
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

type Outcome = std::result::Result<Measured, EvalFailure>;

#[derive(Serialize, Deserialize)]
struct CachedEval {
    x: Vec<f64>,
    outcome: Outcome,
}

type Observer<'a> = Box<dyn FnMut(&Record, &State) + 'a>;

/// The problem behind the on-disk evaluation cache, and the pool the evaluations run on.
struct Evaluator<'a, P: Problem> {
    problem: &'a P,
    dir: Option<PathBuf>,
    fingerprint: String,
    pool: Option<rayon::ThreadPool>,
}

/// The loop around a [`Problem`].
pub struct Executor<'a, P: Problem> {
    ev: Evaluator<'a, P>,
    settings: Settings,
    x0: Vec<f64>,
    observers: Vec<Observer<'a>>,
    stop_after: Option<usize>,
    threads: usize,
    t0: Instant,
}

impl<P: Problem> std::fmt::Debug for Executor<'_, P> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Executor")
            .field("settings", &self.settings)
            .field("x0", &self.x0)
            .field("dir", &self.ev.dir)
            .field("fingerprint", &self.ev.fingerprint)
            .field("threads", &self.threads)
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
                pool: None,
            },
            settings,
            x0,
            observers: Vec::new(),
            stop_after: None,
            threads: 1,
            t0: Instant::now(),
        }
    }

    /// Checkpoint and cache evaluations in `dir` (resuming from it when it holds a checkpoint).
    pub fn checkpoint_dir(mut self, dir: &Path) -> Self {
        self.ev.dir = Some(dir.to_path_buf());
        self
    }

    /// Evaluations (and the work inside each) run on `par`'s threads; default one thread. The
    /// results do not depend on it.
    pub fn parallelism(mut self, par: dem::Parallelism) -> Self {
        self.threads = match par {
            dem::Parallelism::Sequential => 1,
            dem::Parallelism::Threads(n) => n.max(1),
        };
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
    /// Evaluates `xs` side by side on the pool, in order. An interrupt requested meanwhile ends the
    /// round with [`CalibrateError::Interrupted`] (the completed evaluations are cached).
    fn batch(&self, xs: &[Vec<f64>]) -> Result<Vec<Outcome>> {
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

    fn one(&self, x: &[f64]) -> Result<Outcome> {
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
    fn jacobian(
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
        let m = self
            .ev
            .one(&self.x0)?
            .map_err(|EvalFailure(e)| CalibrateError::StartFailed(e))?;
        let cp = Checkpoint {
            fingerprint: self.ev.fingerprint.clone(),
            residual_names: self.ev.problem.residual_names(),
            r0: m.r.clone(),
            noise0: m.noise.clone(),
            state: State {
                x: self.x0.clone(),
                r: m.r.clone(),
                noise: m.noise,
                jacobian: None,
                lambda: None,
                nu: 2.0,
                radius: None,
                points: vec![tr::Sample {
                    x: self.x0.clone(),
                    r: m.r,
                }],
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
        if self.threads > 1 {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(self.threads)
                .build()
                .map_err(|e| {
                    CalibrateError::InvalidConfig(format!(
                        "cannot start {} threads: {e}",
                        self.threads
                    ))
                })?;
            self.ev.pool = Some(pool);
        } else {
            // One thread: the work of a point runs in order on a pool of one, not on the caller's.
            self.ev.pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().ok();
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
            match s.method {
                Method::LevenbergMarquardt => {
                    if st.jacobian.is_none() {
                        let h = self.difference_step(&st.noise);
                        let (j, evaluations) = self.ev.jacobian(&st.x, &st.r, h, s.central)?;
                        st.evaluations += evaluations;
                        st.lambda
                            .get_or_insert_with(|| lm::initial_lambda(&j, s.tau));
                        st.jacobian = Some(j);
                        st.moved = false;
                        // Keep the finite-difference work even if the process dies in the trial.
                        self.save(&cp)?;
                    }
                    self.iterate_lm(&mut cp)?;
                }
                Method::TrustRegion => self.iterate_tr(&mut cp)?,
            }
            self.save(&cp)?;
        }
        Ok(cp)
    }

    /// The finite-difference step: `fd_step`, or more when the point is noisier.
    fn difference_step(&self, noise: &[f64]) -> f64 {
        let n = noise.iter().fold(0.0f64, |a, v| a.max(*v));
        self.settings.fd_step.max(self.settings.noise_factor * n)
    }

    /// Evaluates the trial point `xt`: its measurement (or failure), bookkeeping of the count.
    fn trial(&self, st: &mut State, xt: &[f64]) -> Result<(Option<Measured>, Option<String>)> {
        let trial = self.ev.one(xt)?;
        st.evaluations += 1;
        Ok(match trial {
            Ok(m) => {
                st.points.push(tr::Sample {
                    x: xt.to_vec(),
                    r: m.r.clone(),
                });
                (Some(m), None)
            }
            Err(EvalFailure(e)) => (None, Some(e)),
        })
    }

    #[allow(clippy::too_many_arguments)]
    fn record(
        &mut self,
        cp: &mut Checkpoint,
        xt: Vec<f64>,
        mt: Option<Measured>,
        failure: Option<String>,
        cost: f64,
        predicted: f64,
        accepted: bool,
        lambda: f64,
    ) {
        let st = &mut cp.state;
        let rec = Record {
            iteration: st.iteration,
            x_trial: xt,
            cost_trial: mt.as_ref().map(|m| 0.5 * lm::norm2(&m.r)),
            noise_trial: mt.as_ref().map(|m| m.noise.clone()).unwrap_or_default(),
            r_trial: mt.map(|m| m.r),
            failure,
            cost,
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
            cost_trial = %rec.cost_trial.map_or("-".to_string(), |c| dem::io::Sig(c, 4).to_string()),
            lambda = %dem::io::Sig(lambda, 3),
            failure = ?rec.failure,
            "calibration step"
        );
        for o in &mut self.observers {
            o(&rec, st);
        }
        cp.history.push(rec);
    }

    fn iterate_lm(&mut self, cp: &mut Checkpoint) -> Result<()> {
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
        let fd = self.difference_step(&st.noise);
        let (mt, failure) = self.trial(st, &xt)?;
        let cost_trial = mt.as_ref().map(|m| 0.5 * lm::norm2(&m.r));
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
            if let (Some(m), Some(j)) = (&mt, st.jacobian.as_mut()) {
                if hmax >= 0.5 * fd {
                    lm::broyden_update(j, &h, &st.r, &m.r);
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
            if let Some(m) = &mt {
                st.x.clone_from(&xt);
                st.r.clone_from(&m.r);
                st.noise.clone_from(&m.noise);
            }
            if !s.broyden {
                st.jacobian = None;
            }
        }
        st.iteration += 1;
        if lambda > 1e12 {
            st.status = Status::Stalled("damping above 1e12: no descent direction left".into());
        }
        self.record(cp, xt, mt, failure, cost, predicted, accepted, lambda);
        Ok(())
    }

    /// One trust-region iteration: geometry points where the model lacks them, the model, the step,
    /// the trial and the radius update.
    ///
    /// Two radii: the model is fitted over, and its geometry points placed at, no less than the
    /// noise floor (differences over less are noise); the step may be shorter after failed trials (a
    /// collapsed relaxation says the boundary of the well-posed region is nearer, not that the slopes
    /// are wrong), so a failed trial halves the step radius down to `min_radius`.
    fn iterate_tr(&mut self, cp: &mut Checkpoint) -> Result<()> {
        let s = self.settings;
        let st = &mut cp.state;
        let floor = s
            .min_radius
            .max(s.noise_factor * st.noise.iter().fold(0.0f64, |a, v| a.max(*v)))
            .min(s.max_step);
        let radius = st
            .radius
            .unwrap_or(s.radius)
            .clamp(s.min_radius, s.max_step);
        st.radius = Some(radius);
        let model_radius = radius.max(floor);
        // Geometry: every direction must be covered by a point at a fair fraction of the radius.
        let reach = 2.0 * model_radius;
        let missing = {
            let near = tr::near(&st.points, &st.x, reach);
            tr::missing_directions(&near, &st.x, model_radius, THETA)
        };
        if !missing.is_empty() {
            let xc = st.x.clone();
            let along = |q: &Vec<f64>, sign: f64| -> Vec<f64> {
                xc.iter()
                    .zip(q)
                    .map(|(a, b)| a + sign * model_radius * b)
                    .collect()
            };
            let xs: Vec<Vec<f64>> = missing.iter().map(|q| along(q, 1.0)).collect();
            let got = self.ev.batch(&xs)?;
            st.evaluations += xs.len();
            let mut retry = Vec::new();
            for ((x, q), g) in xs.into_iter().zip(&missing).zip(got) {
                match g {
                    Ok(m) => st.points.push(tr::Sample { x, r: m.r }),
                    Err(e) => {
                        tracing::warn!(%e, "geometry point failed; trying the opposite side");
                        retry.push(along(q, -1.0));
                    }
                }
            }
            if !retry.is_empty() {
                let got = self.ev.batch(&retry)?;
                st.evaluations += retry.len();
                for (x, g) in retry.into_iter().zip(got) {
                    match g {
                        Ok(m) => st.points.push(tr::Sample { x, r: m.r }),
                        Err(e) => tracing::warn!(%e, "geometry point failed on both sides"),
                    }
                }
            }
            // Keep the geometry work even if the process dies in the trial.
            self.save(cp)?;
        }
        let st = &mut cp.state;
        let near = tr::near(&st.points, &st.x, reach);
        let model = tr::fit(&near, &st.x);
        let cost = 0.5 * lm::norm2(&st.r);
        let Some(h) = tr::step(&model, radius) else {
            st.status = Status::Stalled("the trust-region step is not finite".into());
            return Ok(());
        };
        let hlen = lm::norm2(&h).sqrt();
        if hlen < s.min_step {
            st.status = Status::Stalled(format!("step {hlen:.2e} below min_step"));
            return Ok(());
        }
        let predicted = tr::predicted(&model, &h);
        let xt: Vec<f64> = st.x.iter().zip(&h).map(|(a, b)| a + b).collect();
        let (mt, failure) = self.trial(st, &xt)?;
        let cost_trial = mt.as_ref().map(|m| 0.5 * lm::norm2(&m.r));
        // Accept any measured decrease (the centre is the best point seen); grow the radius when the
        // model predicted the decrease well and the step used the region, shrink it otherwise (to
        // the noise floor after a measured increase, below it after a failure).
        let accepted = cost_trial.is_some_and(|ct| ct < cost);
        let rho = cost_trial
            .filter(|_| predicted > 0.0)
            .map(|ct| (cost - ct) / predicted);
        let grown = if rho.is_some_and(|r| r >= 0.7) && hlen >= 0.9 * radius {
            (2.0 * radius).min(s.max_step)
        } else if rho.is_some_and(|r| r >= 0.1) {
            // A good step well inside the region: the region follows the step down (never below
            // the noise floor), so that the points the model is fitted over come closer as the
            // minimum nears and the fit's curvature bias goes with them.
            if hlen < 0.5 * radius {
                (2.0 * hlen).max(floor).min(radius)
            } else {
                radius
            }
        } else if mt.is_none() {
            (0.5 * radius).max(s.min_radius)
        } else {
            (0.5 * radius).max(floor.min(radius))
        };
        let at_floor = !accepted && radius <= floor * (1.0 + 1e-12);
        st.radius = Some(grown);
        st.rejections = if at_floor { st.rejections + 1 } else { 0 };
        if accepted {
            if let Some(m) = &mt {
                st.x.clone_from(&xt);
                st.r.clone_from(&m.r);
                st.noise.clone_from(&m.noise);
            }
        }
        st.iteration += 1;
        if st.rejections >= s.refresh_after {
            st.status = Status::Stalled(format!(
                "{} trial steps in a row rejected within the noise floor {floor:.3} of the \
                 trust radius: no descent left that the samples can resolve",
                st.rejections
            ));
        }
        self.record(cp, xt, mt, failure, cost, predicted, accepted, grown);
        Ok(())
    }
}

/// A direction is covered by a point whose displacement, orthogonal to the directions already
/// covered, is at least this fraction of the radius.
const THETA: f64 = 0.3;
