//! Units: the engine computes in one coherent unit system; conversions happen only at input and output.
//!
//! A [`UnitSystem`] names the SI value of the engine's length, mass and time units; every derived unit
//! (force, stress, energy, density, velocity) follows from those three, so the engine's equations never
//! carry conversion factors. Two systems are provided:
//! - [`UnitSystem::REDUCED`]: all scales 1, for dimensionless studies such as paper 000 Table 4;
//! - [`UnitSystem::NANO`]: nm, ns and attograms (1e-21 kg), for silica-like materials. Then force is pN,
//!   stress MPa, energy zJ (1e-21 J), surface energy mJ/m^2 and density 1e6 kg/m^3... all of order one to
//!   1e5 for the paper 000 Table 5 material, far from f64 trouble;
//! - [`UnitSystem::MILLI`]: mm, ms and grams, for the millimetre spheres of the plastic-wear model
//!   (paper 001). Then force is N, stress MPa, energy mJ, velocity m/s and density 1e6 kg/m^3.

use serde::{Deserialize, Serialize};

/// SI value of the engine's base units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct UnitSystem {
    /// Metres per engine length unit.
    pub length_m: f64,
    /// Kilograms per engine mass unit.
    pub mass_kg: f64,
    /// Seconds per engine time unit.
    pub time_s: f64,
}

impl UnitSystem {
    /// Dimensionless: every scale is one.
    pub const REDUCED: UnitSystem = UnitSystem {
        length_m: 1.0,
        mass_kg: 1.0,
        time_s: 1.0,
    };
    /// nm, attogram, ns.
    pub const NANO: UnitSystem = UnitSystem {
        length_m: 1e-9,
        mass_kg: 1e-21,
        time_s: 1e-9,
    };

    /// mm, gram, ms.
    pub const MILLI: UnitSystem = UnitSystem {
        length_m: 1e-3,
        mass_kg: 1e-3,
        time_s: 1e-3,
    };

    /// SI value of one engine force unit (N).
    pub fn force_n(&self) -> f64 {
        self.mass_kg * self.length_m / (self.time_s * self.time_s)
    }
    /// SI value of one engine stress unit (Pa).
    pub fn stress_pa(&self) -> f64 {
        self.force_n() / (self.length_m * self.length_m)
    }
    /// SI value of one engine energy unit (J).
    pub fn energy_j(&self) -> f64 {
        self.force_n() * self.length_m
    }
    /// SI value of one engine surface-energy unit (J/m^2 = N/m).
    pub fn surface_energy_j_m2(&self) -> f64 {
        self.energy_j() / (self.length_m * self.length_m)
    }
    /// SI value of one engine density unit (kg/m^3).
    pub fn density_kg_m3(&self) -> f64 {
        self.mass_kg / self.length_m.powi(3)
    }
    /// SI value of one engine velocity unit (m/s).
    pub fn velocity_m_s(&self) -> f64 {
        self.length_m / self.time_s
    }

    /// Pascal to engine stress.
    pub fn stress_from_pa(&self, pa: f64) -> f64 {
        pa / self.stress_pa()
    }
    /// Engine stress to pascal.
    pub fn stress_to_pa(&self, s: f64) -> f64 {
        s * self.stress_pa()
    }
    /// J/m^2 to engine surface energy.
    pub fn surface_energy_from_si(&self, j_m2: f64) -> f64 {
        j_m2 / self.surface_energy_j_m2()
    }
    /// Engine surface energy to J/m^2.
    pub fn surface_energy_to_si(&self, g: f64) -> f64 {
        g * self.surface_energy_j_m2()
    }
    /// kg/m^3 to engine density.
    pub fn density_from_si(&self, kg_m3: f64) -> f64 {
        kg_m3 / self.density_kg_m3()
    }
    /// Engine density to kg/m^3.
    pub fn density_to_si(&self, rho: f64) -> f64 {
        rho * self.density_kg_m3()
    }
    /// Metres to engine length.
    pub fn length_from_m(&self, m: f64) -> f64 {
        m / self.length_m
    }
    /// Engine length to metres.
    pub fn length_to_m(&self, l: f64) -> f64 {
        l * self.length_m
    }
    /// Seconds to engine time.
    pub fn time_from_s(&self, s: f64) -> f64 {
        s / self.time_s
    }
    /// Engine time to seconds.
    pub fn time_to_s(&self, t: f64) -> f64 {
        t * self.time_s
    }
    /// m/s to engine velocity.
    pub fn velocity_from_m_s(&self, v: f64) -> f64 {
        v / self.velocity_m_s()
    }
    /// Engine velocity to m/s.
    pub fn velocity_to_m_s(&self, v: f64) -> f64 {
        v * self.velocity_m_s()
    }
    /// Kilograms to engine mass.
    pub fn mass_from_kg(&self, kg: f64) -> f64 {
        kg / self.mass_kg
    }
    /// Engine mass to kilograms.
    pub fn mass_to_kg(&self, m: f64) -> f64 {
        m * self.mass_kg
    }
    /// Newtons to engine force.
    pub fn force_from_n(&self, n: f64) -> f64 {
        n / self.force_n()
    }
    /// Engine force to newtons.
    pub fn force_to_n(&self, f: f64) -> f64 {
        f * self.force_n()
    }
    /// Joules to engine energy.
    pub fn energy_from_j(&self, j: f64) -> f64 {
        j / self.energy_j()
    }
    /// Engine energy to joules.
    pub fn energy_to_j(&self, e: f64) -> f64 {
        e * self.energy_j()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        ((a - b) / b).abs() < 1e-12
    }

    #[test]
    fn nano_derived_units_are_the_named_si_values() {
        let u = UnitSystem::NANO;
        assert!(close(u.force_n(), 1e-12), "pN");
        assert!(close(u.stress_pa(), 1e6), "MPa");
        assert!(close(u.energy_j(), 1e-21), "zJ");
        assert!(close(u.surface_energy_j_m2(), 1e-3), "mJ/m^2");
        assert!(close(u.density_kg_m3(), 1e6));
        assert!(close(u.velocity_m_s(), 1.0), "nm/ns = m/s");
    }

    #[test]
    fn milli_derived_units_are_the_named_si_values() {
        let u = UnitSystem::MILLI;
        assert!(close(u.force_n(), 1.0), "N");
        assert!(close(u.stress_pa(), 1e6), "MPa");
        assert!(close(u.energy_j(), 1e-3), "mJ");
        assert!(close(u.density_kg_m3(), 1e6));
        assert!(close(u.velocity_m_s(), 1.0), "mm/ms = m/s");
        // Paper 001: H = 1.7 GPa is 1700 MPa, rho = 8 g/cm^3 is 8e-3 g/mm^3, 34 J is 34000 mJ.
        assert!(close(u.stress_from_pa(1.7e9), 1700.0));
        assert!(close(u.density_from_si(8000.0), 8e-3));
        assert!(close(u.energy_from_j(34.0), 34e3));
        assert!(close(u.mass_to_kg(u.mass_from_kg(0.0335)), 0.0335));
        assert!(close(u.force_to_n(u.force_from_n(527.0)), 527.0));
        assert!(close(u.energy_to_j(1.0), 1e-3));
    }

    #[test]
    fn silica_table5_round_trips() {
        let u = UnitSystem::NANO;
        let e = u.stress_from_pa(73e9);
        assert!(close(e, 73e3));
        assert!(close(u.stress_to_pa(e), 73e9));
        let g = u.surface_energy_from_si(1.5);
        assert!(close(g, 1500.0));
        assert!(close(u.surface_energy_to_si(g), 1.5));
        assert!(close(u.density_from_si(2200.0), 2.2e-3));
        assert!(close(u.length_to_m(u.length_from_m(3e-9)), 3e-9));
        assert!(close(u.time_to_s(u.time_from_s(2e-14)), 2e-14));
        assert!(close(u.velocity_from_m_s(10.0), 10.0));
    }

    #[test]
    fn d_c_is_unit_independent() {
        // d_c = 4 gamma E / sigma^2 (paper 000 eq 18) must give 1.7 nm for silica in any unit system.
        let dc_si = 4.0 * 1.5 * 73e9 / (16e9f64 * 16e9);
        let u = UnitSystem::NANO;
        let dc_nano = 4.0 * u.surface_energy_from_si(1.5) * u.stress_from_pa(73e9)
            / u.stress_from_pa(16e9).powi(2);
        assert!(close(u.length_to_m(dc_nano), dc_si));
        assert!((dc_si - 1.71e-9).abs() < 0.01e-9);
    }
}
