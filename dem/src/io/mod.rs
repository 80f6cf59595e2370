//! Output: LAMMPS-style dumps and checkpoints.
pub mod checkpoint;
pub mod dump;
pub mod progress;
pub mod sig;

pub use sig::Sig;
