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

mod evaluator;
mod state;

use std::path::Path;
use std::time::Instant;

use crate::error::{CalibrateError, Result};
use crate::lm;
use crate::problem::{EvalFailure, Measured, Problem};
use crate::trust_region as tr;
use evaluator::{bits, Evaluator};
pub use state::{fingerprint, Checkpoint, Method, Record, Settings, State, Status};

type Observer<'a> = Box<dyn FnMut(&Record, &State) + 'a>;

/// The loop around a [`Problem`].
pub struct Executor<'a, P: Problem> {
    ev: Evaluator<'a, P>,
    settings: Settings,
    x0: Vec<f64>,
    observers: Vec<Observer<'a>>,
    stop_after: Option<usize>,
    threads: usize,
    /// Start of this process's part and the wall time the checkpoint had already recorded.
    t0: Instant,
    seconds_before: f64,
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
            seconds_before: 0.0,
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
        self.threads = par.threads();
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

impl<'a, P: Problem> Executor<'a, P> {
    /// Wall time of the calibration so far: the earlier processes' (as checkpointed) and this one's.
    fn wall_seconds(&self) -> f64 {
        self.seconds_before + self.t0.elapsed().as_secs_f64()
    }

    fn save(&self, cp: &mut Checkpoint) -> Result<()> {
        cp.state.wall_seconds = self.wall_seconds();
        if let Some(dir) = &self.ev.dir {
            let path = dir.join("checkpoint.json");
            let bytes =
                serde_json::to_vec_pretty(cp).map_err(|e| CalibrateError::format(&path, e))?;
            dem::io::checkpoint::write_atomic(&path, &bytes)?;
        }
        Ok(())
    }

    fn load_or_start(&mut self) -> Result<Checkpoint> {
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
                tracing::info!(target: "stage", iteration = cp.state.iteration, "resuming from checkpoint");
                let mut cp = cp;
                self.seconds_before = cp.state.wall_seconds;
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
        let mut cp = Checkpoint {
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
                wall_seconds: 0.0,
            },
            history: Vec::new(),
        };
        self.save(&mut cp)?;
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
                self.save(&mut cp)?;
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
                        self.save(&mut cp)?;
                    }
                    self.iterate_lm(&mut cp)?;
                }
                Method::TrustRegion => self.iterate_tr(&mut cp)?,
            }
            self.save(&mut cp)?;
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
            seconds: self.wall_seconds(),
        };
        tracing::info!(
            target: "stage",
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
