//! # calibrate: least-squares calibration of the CG-DEM pair parameters against patch tests
//!
//! Paper 000 gives the pair parameters in closed form (eqs 7-13, with the s-scaling of eq 10 and the
//! strengths of eq 20); measured on real samples they miss the targets (HCP: E and nu by up to 12 %;
//! amorphous: nu 0.20 for 0.15, strengths at about half), and section 3.4 leaves the correction to
//! manual iteration. This crate automates it:
//!
//! - [`problem`]: the problem trait (residuals, optional Jacobian), argmin-style;
//! - [`lm`]: the Levenberg-Marquardt step, solved as the augmented least-squares system
//!   [J; sqrt(lambda) D] h = [-r; 0] with faer's QR (never the normal equations);
//! - [`trust_region`]: a derivative-free trust region on a regression model of the residuals, for
//!   responses that are smooth in trend and noisy in detail (relaxed amorphous samples);
//! - [`executor`]: the loop, stopping rules, observers, parallel finite differences or geometry
//!   points on an explicit thread pool, evaluation cache and atomic per-iteration checkpoints
//!   (resumable, failed evaluations recorded and rejected, the noise of sampled responses honoured);
//! - [`recipe`]: the samples of the discretisation recipe every evaluation relaxes, cached by inputs;
//! - [`patch_problem`]: unknowns ln(multiplier) on k_N, k_T, delta_e, delta_f, F_mT; residuals the
//!   relative errors of the mean E, nu, sigma_N, sigma_T (and gamma) over the recipe's samples;
//! - [`verification`]: the card measured on fresh samples (mean, spread, d* of eq 22);
//! - [`config`]: the TOML input (engine or SI units), with unreachable targets refused up front;
//! - [`card`]: the calibrated parameter card; [`run`]: the whole calibration with its output files;
//! - [`source`]: where a scenario's material comes from (a preset, SI, engine units, an MD card, a card).

pub mod card;
pub mod config;
pub mod error;
pub mod executor;
pub mod lm;
pub mod patch_problem;
pub mod problem;
pub mod recipe;
pub mod run;
pub mod source;
pub mod trust_region;
pub mod verification;

pub use card::CalibratedCard;
pub use config::{card_material, CalibrationConfig, CardRef, SI_SEEDS, SI_THICKNESS};
pub use error::{CalibrateError, Result};
pub use executor::{Checkpoint, Executor, Method, Record, Settings, State, Status};
pub use patch_problem::{PatchProblem, Properties, Target, TestSettings, Unknown};
pub use problem::{EvalFailure, Evaluation, Measured, Problem};
pub use recipe::{RecipeSettings, SampleCache, Variant, VerifySettings};
pub use run::{calibrate, remeasure, verify_card, Outcome};
pub use source::{MaterialSource, ResolvedMaterial, Units};
pub use verification::{Check, Verification};
