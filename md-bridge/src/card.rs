//! The material card: the target properties that `cgdem calibrate` consumes, in SI units, with the
//! provenance of the MD run that measured them. Also the length scales of paper 000 that decide
//! which particle sizes and junction sizes make sense (eqs 18, 19 and 22).

use crate::error::{MdError, Result};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The `[material]` table: the shared SI material of `wear` (one definition for MD cards,
/// calibration configs and Table 5); a measured card names the material and leaves the scaling
/// exponent of eq (10) out, since MD cannot measure it.
pub use wear::material::SiMaterial;

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
    pub material: SiMaterial,
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

/// Side-by-side text table of a measured card and Table 5, with the derived lengths.
pub fn compare_with_table5(m: &SiMaterial) -> String {
    let t = SiMaterial::table5();
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
