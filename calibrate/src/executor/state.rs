//! What the executor is configured with and what it writes: the solver choice and stopping rules
//! ([`Settings`]), the loop's state and history ([`State`], [`Record`]) and the checkpoint on disk.

use serde::{Deserialize, Serialize};

use crate::error::{CalibrateError, Result};
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
    /// Wall time spent on the calibration up to this checkpoint, s, summed over the processes that
    /// ran it (a kill loses the part of the iteration it interrupts; its cached evaluations are
    /// then reused for free).
    #[serde(default)]
    pub wall_seconds: f64,
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
    /// Wall time of the calibration up to this record, s, over all the processes that ran it (not
    /// compared on resume: see [`Checkpoint::without_times`]).
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

impl Checkpoint {
    /// The checkpoint with its wall times set to zero: what a resumed run must reproduce bit for bit
    /// (everything else is a function of the inputs).
    pub fn without_times(mut self) -> Checkpoint {
        self.state.wall_seconds = 0.0;
        self.history.iter_mut().for_each(|r| r.seconds = 0.0);
        self
    }
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
