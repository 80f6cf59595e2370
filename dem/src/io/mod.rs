//! Output: LAMMPS-style dumps and checkpoints.
pub mod checkpoint;
pub mod dump;
pub mod progress;
