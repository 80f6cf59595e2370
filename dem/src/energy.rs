//! Energy ledger: where the energy of the system went.
//!
//! Stored: kinetic (translation + rotation), normal pair potential (zero for separated pairs, so bonds
//! hold negative energy), tangential spring energy. Spent: cumulative work done on the system by the
//! walls, cumulative dissipation by damping (pair dampers + global viscous damping) and by sliding.
//! Balance: stored + dissipated - wall work stays constant up to the O(dt) oscillation of the scheme.

use serde::{Deserialize, Serialize};

/// Snapshot of stored energies and cumulative transfers.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct EnergyLedger {
    /// Kinetic energy (at the time level of the last force evaluation).
    pub kinetic: f64,
    /// Normal pair potential energy.
    pub normal: f64,
    /// Tangential spring energy.
    pub tangential: f64,
    /// Cumulative work done on the system by the walls.
    pub wall_work: f64,
    /// Cumulative energy dissipated by pair and global damping.
    pub damping: f64,
    /// Cumulative energy dissipated by sliding (including cap reductions).
    pub sliding: f64,
}

impl EnergyLedger {
    /// Energy stored in the system.
    pub fn stored(&self) -> f64 {
        self.kinetic + self.normal + self.tangential
    }
    /// Stored + dissipated - supplied: constant for a correct integration.
    pub fn balance(&self) -> f64 {
        self.stored() + self.damping + self.sliding - self.wall_work
    }
}
