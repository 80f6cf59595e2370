//! The material card: the target properties that `cgdem calibrate` consumes, in SI units, with the
//! provenance of the MD run that measured them. Also the length scales of paper 000 that decide
//! which particle sizes and junction sizes make sense (eqs 18, 19 and 22).

use crate::error::{MdError, Result};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The `[material]` table: exactly the properties the coarse-grained model needs (SI units).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    pub name: String,
    /// Pa.
    pub young_modulus: f64,
    pub poisson_ratio: f64,
    /// Ideal (defect-free) tensile strength sigma_N, Pa.
    pub tensile_strength: f64,
    /// Peak shear strength sigma_T, Pa.
    pub shear_strength: f64,
    /// J/m^2.
    pub surface_energy: f64,
    /// Coefficient of restitution eta (not an MD measurement).
    pub restitution: f64,
    /// kg/m^3.
    pub density: f64,
}

/// Where the numbers come from, enough to reproduce them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Provenance {
    pub source: String,
    pub lammps_version: String,
    pub potential: String,
    pub potential_sha256: String,
    pub input_hash: String,
    pub seed: u64,
    pub mpi_ranks: u32,
    pub cgdem_version: String,
    /// Free-text notes (e.g. that restitution is taken from Table 5, not measured).
    pub notes: Vec<String>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MaterialCard {
    pub material: Material,
    pub provenance: Provenance,
}

impl MaterialCard {
    pub fn to_toml(&self) -> Result<String> {
        toml::to_string_pretty(self).map_err(|e| MdError::config("material card", e))
    }
    pub fn from_toml(s: &str) -> Result<Self> {
        toml::from_str(s).map_err(|e| MdError::config("material card", e))
    }
    pub fn write(&self, path: &Path) -> Result<()> {
        std::fs::write(path, self.to_toml()?).map_err(|e| MdError::io(path, e))
    }
}

/// Length scales of paper 000 (eqs 18, 19, 22), metres for a card in SI.
pub use wear::scales::{length_scales, LengthScales};

impl Material {
    /// Paper 000 Table 5 (amorphous silica targets).
    pub fn table5() -> Self {
        Material {
            name: "silica (paper 000 Table 5)".into(),
            young_modulus: 73e9,
            poisson_ratio: 0.17,
            tensile_strength: 16e9,
            shear_strength: 9e9,
            surface_energy: 1.5,
            restitution: 0.9,
            density: 2200.0,
        }
    }

    pub fn length_scales(&self) -> LengthScales {
        length_scales(
            self.young_modulus,
            self.poisson_ratio,
            self.tensile_strength,
            self.shear_strength,
            self.surface_energy,
        )
    }
}

/// Side-by-side text table of a measured card and Table 5, with the derived lengths.
pub fn compare_with_table5(m: &Material) -> String {
    let t = Material::table5();
    let (lm, lt) = (m.length_scales(), t.length_scales());
    let rows: [(&str, f64, f64); 10] = [
        ("E (GPa)", m.young_modulus / 1e9, t.young_modulus / 1e9),
        ("nu", m.poisson_ratio, t.poisson_ratio),
        (
            "sigma_N (GPa)",
            m.tensile_strength / 1e9,
            t.tensile_strength / 1e9,
        ),
        (
            "sigma_T (GPa)",
            m.shear_strength / 1e9,
            t.shear_strength / 1e9,
        ),
        ("gamma (J/m2)", m.surface_energy, t.surface_energy),
        ("eta (not measured)", m.restitution, t.restitution),
        ("rho (kg/m3)", m.density, t.density),
        ("d_min (nm, eq 19)", lm.d_min * 1e9, lt.d_min * 1e9),
        ("d_c (nm, eq 18)", lm.d_c * 1e9, lt.d_c * 1e9),
        ("d* (nm, eq 22)", lm.d_star * 1e9, lt.d_star * 1e9),
    ];
    let mut s = format!("{:<20} {:>12} {:>12}\n", "property", "MD", "Table 5");
    for (name, a, b) in rows {
        s.push_str(&format!("{name:<20} {a:>12.4} {b:>12.4}\n"));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table5_lengths_match_paper() {
        let l = Material::table5().length_scales();
        assert!((l.d_min * 1e9 - 0.37).abs() < 0.01, "d_min {}", l.d_min);
        assert!((l.d_c * 1e9 - 1.7).abs() < 0.05, "d_c {}", l.d_c);
        assert!((l.d_star * 1e9 - 18.0).abs() < 1.0, "d* {}", l.d_star);
    }
}
