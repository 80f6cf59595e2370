//! The material in SI units: the one definition of what a material card's `[material]` table holds,
//! whoever fills it (Table 5 of paper 000, an MD measurement of `cgdem md silica`, a user's TOML).
//!
//! The engine works in its own coherent units: `dem::Material::from_si` converts this struct at
//! the input edge, and nothing else carries SI numbers into a simulation. Paper 000 Table 5 is typed
//! here and nowhere else ([`SiMaterial::table5`]); the length scales of eqs 18, 19 and 22 come from
//! [`crate::scales`].

use serde::{Deserialize, Serialize};

use crate::scales::{length_scales, LengthScales};

/// Exponent s of eq (10) where a material names none: 1/2, the constant-surface-energy scaling paper
/// 000 section 4 uses for silica.
pub const DEFAULT_SCALING: f64 = 0.5;

/// The properties the coarse-grained model is matched to, in SI units.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SiMaterial {
    /// Free-text name (e.g. "silica"); default none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Young's modulus E, Pa.
    pub young_modulus: f64,
    /// Poisson's ratio nu.
    pub poisson_ratio: f64,
    /// Ideal (defect-free) tensile strength sigma_N, Pa.
    pub tensile_strength: f64,
    /// Peak shear strength sigma_T, Pa.
    pub shear_strength: f64,
    /// Surface energy gamma, J/m^2.
    pub surface_energy: f64,
    /// Coefficient of restitution eta (a modelling input, never an MD measurement).
    pub restitution: f64,
    /// Mass density rho, kg/m^3.
    pub density: f64,
    /// Exponent s of eq (10): a choice of the discretisation, not a property MD can measure, so a
    /// measured card has none; default [`DEFAULT_SCALING`] (read with [`SiMaterial::scaling`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scaling: Option<f64>,
}

impl SiMaterial {
    /// Paper 000 Table 5: amorphous silica (E 73 GPa, nu 0.17, sigma_N 16 GPa, sigma_T 9 GPa,
    /// gamma 1.5 J/m^2, eta 0.9, rho 2200 kg/m^3) with s = 1/2 (section 4).
    pub fn table5() -> Self {
        SiMaterial {
            name: Some("silica (paper 000 Table 5)".into()),
            young_modulus: 73e9,
            poisson_ratio: 0.17,
            tensile_strength: 16e9,
            shear_strength: 9e9,
            surface_energy: 1.5,
            restitution: 0.9,
            density: 2200.0,
            scaling: Some(DEFAULT_SCALING),
        }
    }

    /// The exponent s of eq (10): the material's own, or [`DEFAULT_SCALING`].
    pub fn scaling(&self) -> f64 {
        self.scaling.unwrap_or(DEFAULT_SCALING)
    }

    /// d_min, d_c and d* (eqs 19, 18, 22) in metres.
    pub fn length_scales(&self) -> LengthScales {
        length_scales(
            self.young_modulus,
            self.poisson_ratio,
            self.tensile_strength,
            self.shear_strength,
            self.surface_energy,
        )
    }

    /// The name, or `fallback` where the material has none.
    pub fn name_or<'a>(&'a self, fallback: &'a str) -> &'a str {
        self.name.as_deref().unwrap_or(fallback)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table5_gives_the_papers_lengths() {
        // Paper 000 section 4: d_min = 0.37 nm, d_c = 1.7 nm, d* ~ 18 nm.
        let l = SiMaterial::table5().length_scales();
        assert!((l.d_min * 1e9 - 0.375).abs() < 1e-9, "{l:?}");
        assert!((l.d_c * 1e9 - 1.7109375).abs() < 1e-9, "{l:?}");
        assert!((l.d_star * 1e9 - 18.48).abs() < 0.01, "{l:?}");
    }

    #[test]
    fn a_measured_card_without_name_or_scaling_reads_and_writes_back_the_same() {
        let mut m = SiMaterial::table5();
        m.name = None;
        m.scaling = None;
        let text = serde_json::to_string(&m).unwrap();
        assert!(
            !text.contains("scaling") && !text.contains("name"),
            "{text}"
        );
        let back: SiMaterial = serde_json::from_str(&text).unwrap();
        assert_eq!(back, m);
        assert_eq!(back.scaling(), DEFAULT_SCALING);
        assert_eq!(back.name_or("SI material"), "SI material");
    }

    #[test]
    fn a_given_scaling_is_kept_and_an_unknown_field_is_refused() {
        let mut m = SiMaterial::table5();
        m.scaling = Some(0.0);
        let back: SiMaterial = serde_json::from_str(&serde_json::to_string(&m).unwrap()).unwrap();
        assert_eq!(back.scaling(), 0.0);
        let typo = r#"{"young_modulus":1,"poisson_ratio":0.2,"tensile_strength":1,
            "shear_strength":1,"surface_energy":1,"restitution":0.9,"density":1,"scalling":0.5}"#;
        let err = serde_json::from_str::<SiMaterial>(typo)
            .unwrap_err()
            .to_string();
        assert!(err.contains("scalling"), "{err}");
    }
}
