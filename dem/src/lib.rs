//! # dem: the CG-DEM engine of cgdem
//!
//! A discrete element engine for coarse-grained solids whose particles carry the cohesive, reversible
//! pair force of Pham-Ba & Molinari (paper 000, CMAME 2022): Hookean repulsion, a cohesive range with
//! linear softening (eq 3), a capped tangential spring with history (eqs 4-5), damping from the
//! restitution coefficient (eqs 12-13), parameters from E, nu, strengths and surface energy (eqs 7-20),
//! integrated with symplectic Euler (eq 1) under the critical time step of eq (6).
//!
//! Layout follows the pipeline and the maths:
//! - [`material`]: target properties and per-pair parameters;
//! - [`force`]: pair-force kernels and the parallel, deterministic force phase;
//! - [`state`], [`domain`], [`neighbor`], [`walls`]: particles, box, neighbour list, rigid groups;
//! - [`integrate`], [`sim`]: the step pipeline; [`energy`] the ledger;
//! - [`observe`]: observers a scenario composes (frames, wall forces, dumps); [`jobs`]: runs as cached jobs;
//! - [`sample`]: sample generators; [`io`]: dumps and checkpoints; [`units`]: unit systems.

pub mod domain;
pub mod energy;
pub mod error;
pub mod force;
pub mod history;
pub mod integrate;
pub mod interrupt;
pub mod io;
pub mod jobs;
pub mod material;
pub mod neighbor;
pub mod observe;
pub mod sample;
pub mod scenario;
pub mod sim;
pub mod state;
pub mod units;
pub mod walls;

/// Three-vector of f64, the engine's vector type.
pub type Vec3 = nalgebra::Vector3<f64>;

pub use domain::{BoxControl, SimBox};
pub use energy::EnergyLedger;
pub use error::{DemError, Result};
pub use material::{
    DampingModel, ForceLaw, Interactions, Material, PairModel, PairParams, ParamScale, SiMaterial,
};
pub use sim::{Parallelism, RunConfig, Simulation, TimeStep};
pub use state::Particles;
pub use units::UnitSystem;
pub use walls::{AxisControl, Group, RigidMotion};
