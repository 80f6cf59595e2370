//! Plastic wear by impact and scratching: the surface model of Capozza & Hanley (paper 001, Powder
//! Technology 410, 2022, sections 2-4 and appendices A-B).
//!
//! A flat surface of non-interacting spheres on a hexagonal grid ([`surface`]) meets a rigid sphere
//! through Hertzian contacts with Coulomb friction ([`crate::force::hertz`]). A surface sphere flows
//! when the force on it exceeds its area times the hardness, vertically (F_z,i > a_i H, eq 7) or
//! along the motion (F_x,i > a_i mu_a H, eq 8), and is then moved down, with the projectile (eqs 3-4)
//! or by eq (5) ([`flow`]); the worn volume is eq (6) and the energy spent, eqs (21)-(22) ([`ledger`]).
//!
//! The model runs its own small contact loop (`rig`), not the cohesive force phase: one body meets
//! at most a few hundred spheres, found through the grid (DESIGN.md section 7). It shares the
//! engine's units ([`crate::units::UnitSystem::MILLI`] inside, SI at the edges), its integrator
//! (symplectic Euler, paper 000 eq 1), its ledger conventions, progress files and jobs.
//!
//! - [`impact`]: normal and oblique impacts (Figs. 4-7, 12), with COR and deviation angle;
//! - [`scratch`]: indentation at constant speed to a set of loads, then sliding at constant speed
//!   under each load (Figs. 3, 8-10, 13);
//! - [`sweep`]: lists of impacts or scratches (angles, speeds, hardness, mu_a, loads) as jobs of
//!   [`crate::jobs`], cached by their inputs;
//! - [`lammps`]: LAMMPS decks of the same contact loop without wear (cross-check and cost).

pub mod flow;
pub mod impact;
pub mod lammps;
pub mod ledger;
pub mod model;
mod rig;
pub mod scratch;
pub mod surface;
pub mod sweep;

use serde::{Deserialize, Serialize};

pub use flow::LateralOffset;
pub use impact::{run_impact, ImpactConfig, ImpactResult, RunSettings, Shot};
pub use ledger::{EnergyReport, EnergySeries, PlasticLedger};
pub use model::{ContactModulus, PlasticModel, PlasticTimeStep, Projectile};
pub use scratch::{
    run_scratch_load, ArchardFit, Indent, IndentCurve, ScratchConfig, ScratchResult, ScratchRun,
    ShearHardness, Slide, SlideSeries,
};
pub use surface::{Surface, SurfaceSpec};
pub use sweep::{
    aim_in_cell, run_impacts, run_scratches, scratch_jobs, ImpactFile, ImpactPoint, ImpactSweep,
    ScratchFile, ScratchSweep,
};

use crate::units::UnitSystem;

/// The surface a run used (SI): the grid actually built from the [`SurfaceSpec`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SurfaceInfo {
    pub spheres: usize,
    /// a_s (m^2).
    pub cell_area: f64,
    pub length: f64,
    pub width: f64,
    pub sphere_radius: f64,
}

impl SurfaceInfo {
    pub(crate) fn of(s: &Surface, u: UnitSystem) -> Self {
        SurfaceInfo {
            spheres: s.len(),
            cell_area: u.length_to_m(u.length_to_m(s.cell_area)),
            length: u.length_to_m(s.length()),
            width: u.length_to_m(s.width()),
            sphere_radius: u.length_to_m(s.radius),
        }
    }
}
