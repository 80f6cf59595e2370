//! The length scales of paper 000 that decide which particle and junction sizes make sense, in
//! whatever coherent units the caller's properties are in:
//! - d_min = 4 gamma / sigma_N (eq 19): the largest cohesive range delta_f, the smallest sensible
//!   particle;
//! - d_c = 4 gamma E / sigma_N^2 (eq 18): above it a pair cannot match both strength and surface energy
//!   (eq 10's rescaling with s);
//! - d* = 32 gamma G / sigma_T^2 with G = E / (2 (1 + nu)) (eq 22, Aghababaei et al. 2016 for a junction
//!   sheared along its interface): junctions smaller than d* smooth plastically, larger ones detach as
//!   wear particles.

use serde::{Deserialize, Serialize};

/// d_min, d_c and d*, in the units of the properties they came from.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LengthScales {
    /// d_min = 4 gamma / sigma_N (eq 19).
    pub d_min: f64,
    /// d_c = 4 gamma E / sigma_N^2 (eq 18).
    pub d_c: f64,
    /// d* = 32 gamma G / sigma_T^2 (eq 22).
    pub d_star: f64,
}

/// Minimum particle diameter d_min = 4 gamma / sigma_N (eq 19).
pub fn min_diameter(surface_energy: f64, tensile_strength: f64) -> f64 {
    4.0 * surface_energy / tensile_strength
}

/// Critical particle diameter d_c = 4 gamma E / sigma_N^2 (eq 18).
pub fn critical_diameter(surface_energy: f64, young_modulus: f64, tensile_strength: f64) -> f64 {
    4.0 * surface_energy * young_modulus / (tensile_strength * tensile_strength)
}

/// Critical junction size d* = 32 gamma G / sigma_T^2, G = E / (2 (1 + nu)) (eq 22).
pub fn critical_junction_size(
    surface_energy: f64,
    young_modulus: f64,
    poisson_ratio: f64,
    shear_strength: f64,
) -> f64 {
    let g = young_modulus / (2.0 * (1.0 + poisson_ratio));
    32.0 * surface_energy * g / (shear_strength * shear_strength)
}

/// Critical size of paper 004 eq (13), d* = 32 gamma E / sigma_m^2: eq (22)'s scaling with the bulk
/// tensile strength sigma_m in place of the interface shear strength and E in place of G, as that paper
/// found numerically for its normal-only material (nu = 1/4).
pub fn critical_size_paper004(surface_energy: f64, young_modulus: f64, strength: f64) -> f64 {
    32.0 * surface_energy * young_modulus / (strength * strength)
}

/// The surface energy that gives the critical size `d_star` through paper 004 eq (13).
pub fn surface_energy_for_paper004(d_star: f64, young_modulus: f64, strength: f64) -> f64 {
    d_star * strength * strength / (32.0 * young_modulus)
}

/// The three scales of a material given by E, nu, sigma_N, sigma_T and gamma.
pub fn length_scales(e: f64, nu: f64, sigma_n: f64, sigma_t: f64, gamma: f64) -> LengthScales {
    LengthScales {
        d_min: min_diameter(gamma, sigma_n),
        d_c: critical_diameter(gamma, e, sigma_n),
        d_star: critical_junction_size(gamma, e, nu, sigma_t),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table5_silica_gives_the_papers_lengths() {
        // Paper 000 section 4: d_min = 0.37 nm, d_c = 1.7 nm, d* ~ 18 nm (SI in, metres out).
        let l = length_scales(73e9, 0.17, 16e9, 9e9, 1.5);
        assert!((l.d_min * 1e9 - 0.375).abs() < 1e-9, "{l:?}");
        assert!((l.d_c * 1e9 - 1.7109375).abs() < 1e-9, "{l:?}");
        assert!((l.d_star * 1e9 - 18.48).abs() < 0.01, "{l:?}");
    }

    #[test]
    fn paper004_eq13_inverts_to_the_surface_energy() {
        // Paper 004 Table 1: sigma_m = 0.1 E and d* = 0.1 L give gamma = d* sigma_m^2 / (32 E).
        let g = surface_energy_for_paper004(0.1, 1.0, 0.1);
        assert!((g - 3.125e-5).abs() < 1e-18);
        assert!((critical_size_paper004(g, 1.0, 0.1) - 0.1).abs() < 1e-15);
    }
}
