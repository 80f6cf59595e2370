//! The energy ledger of a plastic-wear run (paper 001 section 4.4, eqs 21-23), in the conventions of
//! [`crate::energy::EnergyLedger`]: stored energies (kinetic, Hertzian strain, normal and tangential),
//! cumulative dissipation (friction, wear) and cumulative work supplied from outside (the drive and the
//! load of a scratch, eq 23). The balance stored + dissipated - supplied stays constant.
//!
//! - Wear (eqs 21-22): each step, every displaced sphere adds F_z,i times its downward displacement,
//!   the work the projectile does on it. It is the exact counterpart of the energy the projectile and
//!   the springs lose as the sphere gives way (the sphere is massless and moved kinematically).
//! - Friction: the spring energy given up when a tangential spring is cut back to the Coulomb cap
//!   (`force::hertz`), and the energy left in a spring when its contact opens.
//!
//! Decision (time level): symplectic Euler is leapfrog in disguise: the velocity v_n that moved the
//! positions from step n-1 to n is v_{n-1/2}, the one computed from the forces at x_n is v_{n+1/2}. The
//! kinetic energy paired with the potential at x_n is 1/2 m v_{n-1/2} . v_{n+1/2} (exactly conserved
//! with it for a harmonic contact), not 1/2 m v_n^2, whose oscillation is of order omega dt (5 % at
//! a tenth of the stable step). So the ledger of step n holds the strain energy at x_n, the friction of
//! the slip that reached x_n, the wear and external work of the displacements up to x_n, and that
//! kinetic energy. Its balance then drifts by O(dt) (from the switching of contacts and flow), tested
//! by halving dt.

use serde::{Deserialize, Serialize};

/// Energies of one step (engine units).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct PlasticLedger {
    /// Kinetic energy of the projectile, translation and rotation (time-centred, see the module).
    pub kinetic: f64,
    /// Hertzian normal strain energy of the contacts.
    pub strain_normal: f64,
    /// Tangential spring energy of the contacts.
    pub strain_tangential: f64,
    /// Cumulative friction dissipation.
    pub friction: f64,
    /// Cumulative wear dissipation (eq 22).
    pub wear: f64,
    /// Cumulative work done on the projectile from outside (drive and load, eq 23).
    pub external_work: f64,
}

impl PlasticLedger {
    /// Hertzian strain energy, normal and tangential.
    pub fn strain(&self) -> f64 {
        self.strain_normal + self.strain_tangential
    }
    /// Kinetic + strain + friction + wear - external work: constant.
    pub fn balance(&self) -> f64 {
        self.kinetic + self.strain() + self.friction + self.wear - self.external_work
    }
}

/// Sampled energies of a run, in joules and seconds (structure of arrays, for figures and CSV).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct EnergySeries {
    pub time: Vec<f64>,
    pub kinetic: Vec<f64>,
    pub strain: Vec<f64>,
    pub friction: Vec<f64>,
    pub wear: Vec<f64>,
    pub external_work: Vec<f64>,
}

impl EnergySeries {
    /// Appends one sample (SI).
    pub fn push(&mut self, t: f64, l: &PlasticLedger, to_j: impl Fn(f64) -> f64) {
        self.time.push(t);
        self.kinetic.push(to_j(l.kinetic));
        self.strain.push(to_j(l.strain()));
        self.friction.push(to_j(l.friction));
        self.wear.push(to_j(l.wear));
        self.external_work.push(to_j(l.external_work));
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.time.len()
    }

    /// Whether there is no sample.
    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }

    /// kinetic + strain + friction + wear - external work of sample k.
    pub fn balance(&self, k: usize) -> f64 {
        self.kinetic[k] + self.strain[k] + self.friction[k] + self.wear[k] - self.external_work[k]
    }
}

/// The energy account of a finished run (J).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct EnergyReport {
    /// Kinetic energy at the start.
    pub initial_kinetic: f64,
    /// Strain energy at the start (zero for an impact; the indentation's for a scratch).
    pub initial_strain: f64,
    /// At the end: kinetic, strain, cumulative friction and wear, external work.
    pub kinetic: f64,
    pub strain: f64,
    pub friction: f64,
    pub wear: f64,
    pub external_work: f64,
    /// Largest |balance_n - balance_0| over the run, over the scale of the run's energy (the initial
    /// kinetic energy of an impact; the external work of a scratch).
    pub max_balance_error: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn balance_counts_supplied_work_against_the_rest() {
        let l = PlasticLedger {
            kinetic: 1.0,
            strain_normal: 0.5,
            strain_tangential: 0.25,
            friction: 2.0,
            wear: 3.0,
            external_work: 4.0,
        };
        assert_eq!(l.strain(), 0.75);
        assert_eq!(l.balance(), 2.75);
        let mut s = EnergySeries::default();
        s.push(0.5, &l, |e| e * 1e-3);
        assert_eq!(s.len(), 1);
        assert!((s.balance(0) - 2.75e-3).abs() < 1e-15);
    }
}
