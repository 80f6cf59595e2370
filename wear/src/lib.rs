//! # wear: where MD and DEM results meet
//!
//! The adhesive-wear physics that both sides of the workbench share, as plain Rust with no engine and
//! no Python in it, so that the DEM engine, the LAMMPS bridge and the validation report reach the same
//! code:
//! - [`material`]: the material in SI units, the one definition every card and config reads (Table 5
//!   typed once), converted to engine units at the engine's edge;
//! - [`scales`]: the length scales of paper 000, d_min (eq 19), d_c (eq 18) and the critical junction
//!   size d* (eq 22, after Aghababaei et al. 2016);
//! - [`outcome`]: the verdict on a sheared junction (plastic smoothing or a detached, rolling wear
//!   particle) from the junction members' frames, the same decision for MD atoms and DEM particles;
//! - [`detachment`]: the detachment probability P(wear | D), its D50 by a maximum-likelihood
//!   logistic fit in ln D, with a profile-likelihood interval;
//! - [`dstar`]: the bisection on the junction size D between a plastic and a debris outcome, with
//!   several seeds per D, that brackets d* from either side's runs;
//! - [`tbl`]: the measures of a third-body layer under sliding (paper 004): velocity and density
//!   profiles, the TBL's boundaries and thickness, rho_TBL from a Gaussian fit, the regime of a run.

pub mod detachment;
pub mod dstar;
pub mod error;
pub mod material;
pub mod outcome;
pub mod scales;
pub mod tbl;

pub use error::{Result, WearError};
pub use material::SiMaterial;
pub use outcome::{classify, ClassifyParams, Outcome, Verdict};
pub use scales::LengthScales;
