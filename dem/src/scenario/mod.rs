//! Scenarios: complete numerical experiments built on the engine. Each is a function with a typed serde
//! configuration (defaults are the papers' values) and a typed result, deterministic for a given sample
//! and model, returning errors rather than panicking.
//! - [`pair`]: two-particle experiments against paper 000's closed forms (period, stability limit,
//!   restitution, bond work), shared by the engine's tests and the validation report;
//! - [`rig`]: the shared ground: a sample between two rigid walls along a chosen axis;
//! - [`driven`]: the top wall dragged under pressure, and the resumable observed run the junction and
//!   the sliding layer share;
//! - [`patch`]: the patch tests of paper 000 section 3 (elastic constants, tensile and shear strength,
//!   fracture energy), the inner loop of the calibration;
//! - [`junction`]: junction shear of paper 000 section 4, plastic smoothing or a rolling wear particle;
//! - [`monolayer`]: the quasi-2D hex monolayer as a material (closed form to 2D properties, and their
//!   measurement), the DEM side of the comparison with the 2D MD model material;
//! - [`plastic`]: plastic wear by impact and scratching (paper 001), a rigid sphere against a surface
//!   of non-interacting spheres, with its own contact loop;
//! - [`sliding`]: sliding with a third-body layer (paper 004), its profiles, rho_TBL, p_T and regime.

pub mod driven;
pub mod junction;
pub mod monolayer;
pub mod pair;
pub mod patch;
pub mod plastic;
pub mod rig;
pub mod sliding;
