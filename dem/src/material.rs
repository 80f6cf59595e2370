//! Target material properties and the per-pair force parameters derived from them.
//!
//! Paper 000 (Pham-Ba & Molinari 2022) section 2.2 and appendix A.2:
//! - k_N = A_N E / (r_i + r_j)                          (eq 7)
//! - k_T = A_T E / (r_i + r_j)                          (eq 8)
//! - delta_e = (r_i + r_j) sigma_N / E                  (eq 9)
//! - delta_f = 4 gamma / sigma_N   if r_i + r_j <= d_c, else delta_e ((r_i + r_j) / d_c)^(-s)   (eq 10)
//! - F_mT = A_T sigma_T                                 (eq 11)
//! - c_N, c_T = 2 (1 - eta) / pi * sqrt(k m_eff)        (eqs 12-13)
//! - r_eff = min(r_i, r_j)                              (eq 14)
//! - A_N = sqrt(2) r_eff^2 / (1 - 2 nu),  A_T = sqrt(2) r_eff^2 (1 - 4 nu) / ((1 - 2 nu)(1 + nu))   (eqs 15-16)
//! - d_c = 4 gamma E / sigma_N^2 (eq 18), d_min = 4 gamma / sigma_N (eq 19)
//!
//! Paper 004 (normal-only variant): A_eff = 2 sqrt(2) r_eff^2 (eq 9), no tangential force, nu fixed at 1/4.
//!
//! Decision (eq 10 with s > 0): for r_i + r_j > d_c the rescaled delta_f is *smaller* than delta_e. Eq (3)
//! read literally would then keep the Hookean branch beyond delta_f; we instead end the interaction at
//! delta_f (the force drops to zero there), which is what eq (20) and Fig. A.2 describe: the matched
//! strength becomes k_N delta_f / A_N = sigma_N ((r_i + r_j)/d_c)^(-s) and, for s = 1/2, the fracture
//! energy 1/2 k_N delta_f^2 equals 2 gamma A_N.

use serde::{Deserialize, Serialize};
pub use wear::material::{SiMaterial, DEFAULT_SCALING};
use wear::scales::{self, LengthScales};

use crate::error::{not_positive, DemError, Result};
use crate::units::UnitSystem;

/// Target macroscopic properties of the material to model (paper 000 Table 3), in engine units.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Young's modulus E.
    pub young_modulus: f64,
    /// Poisson's ratio nu (at most 1/4 with tangential forces, exactly 1/4 for the normal-only law).
    pub poisson_ratio: f64,
    /// Tensile strength sigma_{m,N}.
    pub tensile_strength: f64,
    /// Shear strength sigma_{m,T}.
    pub shear_strength: f64,
    /// Surface energy gamma.
    pub surface_energy: f64,
    /// Restitution coefficient eta in (0, 1]: ratio of rebound to impact relative speed.
    pub restitution: f64,
    /// Mass density rho.
    pub density: f64,
    /// Scaling exponent s of eq (10) for pairs larger than d_c (0: constant strength, 1/2: constant gamma).
    #[serde(default)]
    pub scaling: f64,
}

impl Material {
    /// Paper 000 Table 4 (E = 1, sigma_N = 0.2, sigma_T = 0.1, gamma = 1.5, eta = 0.95, rho = 1) with the
    /// given Poisson's ratio and s = 0.
    pub fn table4(poisson_ratio: f64) -> Self {
        Material {
            young_modulus: 1.0,
            poisson_ratio,
            tensile_strength: 0.2,
            shear_strength: 0.1,
            surface_energy: 1.5,
            restitution: 0.95,
            density: 1.0,
            scaling: 0.0,
        }
    }

    /// The material `si` (SI units) in the engine's units `u`, with its exponent s of eq (10) (1/2
    /// where it names none): the one place SI numbers enter the engine.
    pub fn from_si(si: &SiMaterial, u: UnitSystem) -> Self {
        Material {
            young_modulus: u.stress_from_pa(si.young_modulus),
            poisson_ratio: si.poisson_ratio,
            tensile_strength: u.stress_from_pa(si.tensile_strength),
            shear_strength: u.stress_from_pa(si.shear_strength),
            surface_energy: u.surface_energy_from_si(si.surface_energy),
            restitution: si.restitution,
            density: u.density_from_si(si.density),
            scaling: si.scaling(),
        }
    }

    /// Critical diameter d_c = 4 gamma E / sigma_N^2 (eq 18).
    pub fn critical_diameter(&self) -> f64 {
        scales::critical_diameter(
            self.surface_energy,
            self.young_modulus,
            self.tensile_strength,
        )
    }

    /// Minimum sensible particle diameter d_min = 4 gamma / sigma_N (eq 19), the largest delta_f.
    pub fn min_diameter(&self) -> f64 {
        scales::min_diameter(self.surface_energy, self.tensile_strength)
    }

    /// d_min, d_c and d* (eqs 19, 18, 22) in the material's units.
    pub fn length_scales(&self) -> LengthScales {
        scales::length_scales(
            self.young_modulus,
            self.poisson_ratio,
            self.tensile_strength,
            self.shear_strength,
            self.surface_energy,
        )
    }

    /// Shear modulus G = E / (2 (1 + nu)).
    pub fn shear_modulus(&self) -> f64 {
        self.young_modulus / (2.0 * (1.0 + self.poisson_ratio))
    }

    /// Checks every property against what `law` can represent.
    pub fn validate(&self, law: ForceLaw) -> Result<()> {
        let bad = |m: String| Err(DemError::InvalidMaterial(m));
        let fields = [
            ("young_modulus", self.young_modulus),
            ("poisson_ratio", self.poisson_ratio),
            ("tensile_strength", self.tensile_strength),
            ("shear_strength", self.shear_strength),
            ("surface_energy", self.surface_energy),
            ("restitution", self.restitution),
            ("density", self.density),
            ("scaling", self.scaling),
        ];
        for (name, v) in fields {
            if !v.is_finite() {
                return bad(format!("{name} = {v} is not a finite number"));
            }
        }
        for (name, v) in [
            ("young_modulus", self.young_modulus),
            ("tensile_strength", self.tensile_strength),
            ("surface_energy", self.surface_energy),
            ("density", self.density),
        ] {
            if v <= 0.0 {
                return bad(format!("{name} = {v} must be positive"));
            }
        }
        if self.shear_strength < 0.0 {
            return bad(format!(
                "shear_strength = {} must not be negative",
                self.shear_strength
            ));
        }
        if !(self.restitution > 0.0 && self.restitution <= 1.0) {
            return bad(format!(
                "restitution = {} must lie in (0, 1]",
                self.restitution
            ));
        }
        if self.scaling < 0.0 {
            return bad(format!("scaling s = {} must be >= 0 (eq 10)", self.scaling));
        }
        // Each field may be finite while the derived lengths overflow (E = 1e308, say).
        let d_c = self.critical_diameter();
        if !(d_c.is_finite() && d_c > 0.0) {
            return bad(format!(
                "the critical diameter d_c = 4 gamma E / sigma_N^2 (eq 18) comes out as {d_c}: \
                 give the material in units where its values are of moderate size"
            ));
        }
        if self.poisson_ratio <= -1.0 {
            return bad(format!(
                "poisson_ratio = {} must be > -1",
                self.poisson_ratio
            ));
        }
        match law {
            ForceLaw::Cohesive if self.poisson_ratio > 0.25 => bad(format!(
                "poisson_ratio = {} cannot be modelled with tangential forces: A_T of eq (16) turns \
                 negative above 1/4 (paper 000 section 2.2)",
                self.poisson_ratio
            )),
            ForceLaw::NormalOnly if (self.poisson_ratio - 0.25).abs() > 1e-9 => bad(format!(
                "the normal-only force (paper 004) fixes poisson_ratio at 0.25, the material asks for {}",
                self.poisson_ratio
            )),
            _ => Ok(()),
        }
    }
}

/// Which pair-force formulation to use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ForceLaw {
    /// Paper 000: cohesive normal force with tangential force and history (A_N, A_T from nu).
    Cohesive,
    /// Paper 004: cohesive normal force only, A_eff = 2 sqrt(2) r_eff^2.
    NormalOnly,
}

/// How the pair damping coefficients follow from the restitution coefficient eta.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum DampingModel {
    /// Paper 000 eqs (12)-(13): c = 2 (1 - eta)/pi sqrt(k m_eff), a linearisation whose actual
    /// restitution is close to exp(-(1 - eta)).
    #[default]
    Linearised,
    /// The exact linear spring-dashpot value for restitution eta:
    /// c = 2 zeta sqrt(k m_eff), zeta = -ln(eta) / sqrt(pi^2 + ln(eta)^2).
    Exact,
}

/// Multipliers on the closed-form parameters (all 1 for the paper's first guess); the calibration's unknowns.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParamScale {
    /// Multiplier on k_N (eq 7).
    pub k_n: f64,
    /// Multiplier on k_T (eq 8).
    pub k_t: f64,
    /// Multiplier on delta_e (eq 9).
    pub delta_e: f64,
    /// Multiplier on delta_f (eq 10).
    pub delta_f: f64,
    /// Multiplier on F_mT (eq 11).
    pub f_mt: f64,
}

impl Default for ParamScale {
    fn default() -> Self {
        ParamScale {
            k_n: 1.0,
            k_t: 1.0,
            delta_e: 1.0,
            delta_f: 1.0,
            f_mt: 1.0,
        }
    }
}

impl ParamScale {
    fn validate(&self) -> Result<()> {
        match not_positive(&[
            ("k_n", self.k_n),
            ("k_t", self.k_t),
            ("delta_e", self.delta_e),
            ("delta_f", self.delta_f),
            ("f_mt", self.f_mt),
        ]) {
            Some(m) => Err(DemError::InvalidMaterial(format!(
                "parameter multiplier {m}"
            ))),
            None => Ok(()),
        }
    }
}

/// Which parts of the pair force are switched on (the relaxation of paper 000 section 3.2 switches them
/// on in stages).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Interactions {
    /// Cohesive range 0 < delta_N <= delta_f (off: purely repulsive Hookean contact).
    pub cohesion: bool,
    /// Tangential force and its history (only meaningful for [`ForceLaw::Cohesive`]).
    pub tangential: bool,
}

impl Interactions {
    /// Everything on.
    pub const FULL: Interactions = Interactions {
        cohesion: true,
        tangential: true,
    };
    /// Repulsive normal contact only (relaxation phase 1, restitution tests).
    pub const REPULSIVE: Interactions = Interactions {
        cohesion: false,
        tangential: false,
    };
    /// Cohesive normal force, no tangential force (relaxation phase 2).
    pub const NORMAL: Interactions = Interactions {
        cohesion: true,
        tangential: false,
    };
}

/// The complete pair model: material, formulation and switches. Per-pair parameters are derived on the
/// fly from the two radii and masses (cheaper than caching seven numbers per pair in memory).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PairModel {
    /// Target material.
    pub material: Material,
    /// Formulation.
    pub law: ForceLaw,
    /// Switches for the staged relaxation.
    pub interactions: Interactions,
    /// Damping from restitution.
    #[serde(default)]
    pub damping: DampingModel,
    /// Calibration multipliers.
    #[serde(default)]
    pub scale: ParamScale,
}

/// The seven parameters of one pair (paper 000 Table 2), already including multipliers and switches.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PairParams {
    pub k_n: f64,
    pub k_t: f64,
    /// Elastic limit, already min(delta_e, delta_f) (see the module docs on eq 10).
    pub delta_e: f64,
    /// End of the interaction range (0 when cohesion is off).
    pub delta_f: f64,
    pub f_mt: f64,
    pub c_n: f64,
    pub c_t: f64,
}

impl PairParams {
    /// Work needed to separate the pair quasi-statically from contact to beyond delta_f: the area under
    /// eq (3) for delta_N >= 0, 1/2 k_N delta_e delta_f (eqs A.31-A.32).
    pub fn bond_energy(&self) -> f64 {
        0.5 * self.k_n * self.delta_e * self.delta_f
    }
}

impl PairModel {
    /// The paper-000 model with everything switched on.
    pub fn cohesive(material: Material) -> Self {
        PairModel {
            material,
            law: ForceLaw::Cohesive,
            interactions: Interactions::FULL,
            damping: DampingModel::Linearised,
            scale: ParamScale::default(),
        }
    }

    /// The paper-004 normal-only model.
    pub fn normal_only(material: Material) -> Self {
        PairModel {
            material,
            law: ForceLaw::NormalOnly,
            interactions: Interactions::NORMAL,
            damping: DampingModel::Linearised,
            scale: ParamScale::default(),
        }
    }

    /// Checks the material against the formulation and the multipliers.
    pub fn validate(&self) -> Result<()> {
        self.material.validate(self.law)?;
        self.scale.validate()
    }

    /// Whether tangential forces are computed.
    pub fn has_tangential(&self) -> bool {
        self.law == ForceLaw::Cohesive && self.interactions.tangential
    }

    /// A_N / r_eff^2 and A_T / r_eff^2 (eqs 15-16, or 004 eq 9).
    fn area_coefficients(&self) -> (f64, f64) {
        let nu = self.material.poisson_ratio;
        match self.law {
            ForceLaw::Cohesive => {
                let an = std::f64::consts::SQRT_2 / (1.0 - 2.0 * nu);
                let at =
                    std::f64::consts::SQRT_2 * (1.0 - 4.0 * nu) / ((1.0 - 2.0 * nu) * (1.0 + nu));
                (an, at)
            }
            ForceLaw::NormalOnly => (2.0 * std::f64::consts::SQRT_2, 0.0),
        }
    }

    /// Damping coefficient per sqrt(k m_eff).
    pub fn damping_factor(&self) -> f64 {
        let eta = self.material.restitution;
        match self.damping {
            DampingModel::Linearised => 2.0 * (1.0 - eta) / std::f64::consts::PI,
            DampingModel::Exact => {
                let l = eta.ln();
                -2.0 * l / (std::f64::consts::PI.powi(2) + l * l).sqrt()
            }
        }
    }

    /// Parameters of the pair (r_i, m_i), (r_j, m_j).
    #[inline]
    pub fn params(&self, ri: f64, rj: f64, mi: f64, mj: f64) -> PairParams {
        let coefs = PairCoefficients::new(self);
        coefs.params(ri, rj, mi, mj)
    }

    /// Largest interaction distance between centres for radii ri, rj: r_i + r_j + delta_f.
    pub fn cutoff(&self, ri: f64, rj: f64) -> f64 {
        PairCoefficients::new(self).cutoff(ri, rj)
    }

    /// Critical time step of eq (6), dt_c = sqrt(2 m / k_N), for a particle paired with its twin.
    pub fn critical_time_step(&self, r: f64, m: f64) -> f64 {
        let p = self.params(r, r, m, m);
        (2.0 * m / p.k_n).sqrt()
    }

    /// Critical damping of eq (21), c_c = sqrt(2 k_N m), for a particle paired with its twin.
    pub fn critical_damping(&self, r: f64, m: f64) -> f64 {
        let p = self.params(r, r, m, m);
        (2.0 * p.k_n * m).sqrt()
    }
}

/// Material-level constants hoisted out of the pair loop: everything in [`PairParams`] that does not
/// depend on the two particles.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PairCoefficients {
    // The pair kernel derives k_N, k_T, delta_e, F_mT and c_T from a few stored per-pair values with
    // these (force::pair_consts::Shared), by the same expressions as `params_in_range`.
    pub(crate) kn_coef: f64,
    pub(crate) kt_coef: f64,
    pub(crate) fmt_coef: f64,
    pub(crate) strain_e: f64,
    delta_f_small: f64,
    d_c: f64,
    s: f64,
    pub(crate) scale_de: f64,
    scale_df: f64,
    damp: f64,
    pub(crate) ct_over_cn: f64,
    pub(crate) cohesion: bool,
    pub tangential: bool,
}

impl PairCoefficients {
    pub fn new(model: &PairModel) -> Self {
        let m = &model.material;
        let (an, at) = model.area_coefficients();
        let tangential = model.has_tangential();
        PairCoefficients {
            kn_coef: an * m.young_modulus * model.scale.k_n,
            kt_coef: if tangential {
                at * m.young_modulus * model.scale.k_t
            } else {
                0.0
            },
            fmt_coef: if tangential {
                at * m.shear_strength * model.scale.f_mt
            } else {
                0.0
            },
            strain_e: m.tensile_strength / m.young_modulus,
            delta_f_small: m.min_diameter(),
            d_c: m.critical_diameter(),
            s: m.scaling,
            scale_de: model.scale.delta_e,
            scale_df: model.scale.delta_f,
            damp: model.damping_factor(),
            ct_over_cn: if tangential && at > 0.0 {
                (at * model.scale.k_t / (an * model.scale.k_n)).sqrt()
            } else {
                0.0
            },
            cohesion: model.interactions.cohesion,
            tangential,
        }
    }

    /// delta_f before the cohesion switch (eq 10 with multiplier), for radii sum `d`.
    #[inline]
    fn raw_delta_f(&self, d: f64) -> f64 {
        let df = if d <= self.d_c {
            self.delta_f_small
        } else if self.s == 0.0 {
            // Avoid powf in the common s = 0 case: delta_f = delta_e.
            d * self.strain_e
        } else {
            d * self.strain_e * (d / self.d_c).powf(-self.s)
        };
        df * self.scale_df
    }

    #[inline]
    pub fn cutoff(&self, ri: f64, rj: f64) -> f64 {
        let (d, df) = self.range(ri, rj);
        d + df
    }

    /// Largest cutoff over all pairs with radii up to `r_max`: delta_f is constant up to d_c and
    /// monotone beyond, so its maximum is at d_c or at 2 r_max.
    pub fn max_cutoff(&self, r_max: f64) -> f64 {
        let d = 2.0 * r_max;
        if !self.cohesion {
            return d;
        }
        d + self.raw_delta_f(d).max(self.raw_delta_f(d.min(self.d_c)))
    }

    /// Sum of radii and delta_f of the pair (delta_f = 0 without cohesion): the reach is their sum.
    #[inline(always)]
    pub fn range(&self, ri: f64, rj: f64) -> (f64, f64) {
        let d = ri + rj;
        (
            d,
            if self.cohesion {
                self.raw_delta_f(d)
            } else {
                0.0
            },
        )
    }

    #[inline]
    pub fn params(&self, ri: f64, rj: f64, mi: f64, mj: f64) -> PairParams {
        let (d, df) = self.range(ri, rj);
        self.params_in_range(ri, rj, d, df, mi, mj)
    }

    /// [`PairCoefficients::params`] with the pair's [`PairCoefficients::range`] already computed.
    #[inline(always)]
    pub fn params_in_range(
        &self,
        ri: f64,
        rj: f64,
        d: f64,
        df: f64,
        mi: f64,
        mj: f64,
    ) -> PairParams {
        let reff = ri.min(rj);
        let r2 = reff * reff;
        let r2_over_d = r2 / d;
        let k_n = self.kn_coef * r2_over_d;
        let k_t = self.kt_coef * r2_over_d;
        // c_T / c_N = sqrt(k_T / k_N) is a material constant: one square root per pair, none undamped.
        let c_n = if self.damp == 0.0 {
            0.0
        } else {
            self.damp * (k_n * (mi * mj / (mi + mj))).sqrt()
        };
        let delta_e = if self.cohesion {
            (d * self.strain_e * self.scale_de).min(df)
        } else {
            0.0
        };
        PairParams {
            k_n,
            k_t,
            delta_e,
            delta_f: df,
            f_mt: self.fmt_coef * r2,
            c_n,
            c_t: c_n * self.ct_over_cn,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rel(a: f64, b: f64) -> f64 {
        ((a - b) / b).abs()
    }

    #[test]
    fn table4_derived_sizes_match_paper() {
        // Paper 000 section 3: d_min = 30, d_c = 150 for Table 4.
        let m = Material::table4(0.15);
        assert!(rel(m.min_diameter(), 30.0) < 1e-12);
        assert!(rel(m.critical_diameter(), 150.0) < 1e-12);
    }

    #[test]
    fn silica_table5_in_nano_units_keeps_the_papers_sizes() {
        // Paper 000 section 4: d_min = 0.37 nm, d_c = 1.7 nm, d* = 18.5 nm, whatever the units.
        let u = UnitSystem::NANO;
        let m = Material::from_si(&SiMaterial::table5(), u);
        assert_eq!(m.scaling, 0.5);
        assert!(rel(u.stress_to_pa(m.young_modulus), 73e9) < 1e-12);
        assert!(rel(u.surface_energy_to_si(m.surface_energy), 1.5) < 1e-12);
        let (l, si) = (m.length_scales(), SiMaterial::table5().length_scales());
        assert!(rel(u.length_to_m(l.d_min), si.d_min) < 1e-12, "{l:?}");
        assert!(rel(u.length_to_m(l.d_c), si.d_c) < 1e-12, "{l:?}");
        assert!(rel(u.length_to_m(l.d_star), si.d_star) < 1e-12, "{l:?}");
        assert!(
            (u.length_to_m(l.d_c) - 1.71e-9).abs() < 0.01e-9,
            "d_c = 1.7 nm"
        );
    }

    #[test]
    fn equal_spheres_reproduce_appendix_stiffnesses() {
        // A.62-A.63: k_N = sqrt2 E r / (2 (1-2nu)), k_T = sqrt2 E r (1-4nu) / (2 (1+nu)(1-2nu)).
        let nu = 0.15;
        let model = PairModel::cohesive(Material::table4(nu));
        let r = 45.0;
        let p = model.params(r, r, 1.0, 1.0);
        let s2 = std::f64::consts::SQRT_2;
        assert!(rel(p.k_n, s2 * r / (2.0 * (1.0 - 2.0 * nu))) < 1e-14);
        assert!(
            rel(
                p.k_t,
                s2 * r * (1.0 - 4.0 * nu) / (2.0 * (1.0 + nu) * (1.0 - 2.0 * nu))
            ) < 1e-14
        );
        // delta_f = 4 gamma / sigma = 30 below d_c; delta_e = 2r sigma/E = 18.
        assert!(rel(p.delta_f, 30.0) < 1e-14);
        assert!(rel(p.delta_e, 18.0) < 1e-14);
        // Bond energy 1/2 k delta_e delta_f = 2 gamma A_N (eqs A.31-A.34).
        let a_n = s2 * r * r / (1.0 - 2.0 * nu);
        assert!(rel(p.bond_energy(), 2.0 * 1.5 * a_n) < 1e-14);
    }

    #[test]
    fn scaling_above_d_c() {
        let mut mat = Material::table4(0.15);
        mat.scaling = 0.5;
        let model = PairModel::cohesive(mat.clone());
        let (ri, rj) = (150.0, 150.0); // r_i + r_j = 2 d_c
        let p = model.params(ri, rj, 1.0, 1.0);
        let de = 300.0 * 0.2;
        assert!(rel(p.delta_f, de * 2f64.powf(-0.5)) < 1e-14);
        assert_eq!(p.delta_e, p.delta_f, "elastic limit clipped at delta_f");
        // s = 1/2 keeps the surface energy: 1/2 k delta_f^2 = 2 gamma A_N.
        let a_n = std::f64::consts::SQRT_2 * 150.0 * 150.0 / (1.0 - 0.3);
        assert!(rel(0.5 * p.k_n * p.delta_f * p.delta_f, 2.0 * 1.5 * a_n) < 1e-12);
        // s = 0: delta_f = delta_e, constant strength.
        let p0 = PairModel::cohesive(Material::table4(0.15)).params(ri, rj, 1.0, 1.0);
        assert!(rel(p0.delta_f, de) < 1e-14);
    }

    #[test]
    fn r_eff_is_the_smaller_radius() {
        let model = PairModel::cohesive(Material::table4(0.0));
        let p = model.params(10.0, 20.0, 1.0, 8.0);
        assert!(rel(p.k_n, std::f64::consts::SQRT_2 * 100.0 / 30.0) < 1e-14);
        assert!(rel(p.f_mt, std::f64::consts::SQRT_2 * 100.0 * 0.1) < 1e-14);
    }

    #[test]
    fn normal_only_equals_cohesive_at_nu_quarter_without_tangential() {
        let mut mat = Material::table4(0.25);
        mat.scaling = 0.0;
        let a = PairModel::normal_only(mat.clone()).params(40.0, 50.0, 2.0, 3.0);
        let b = PairModel::cohesive(mat).params(40.0, 50.0, 2.0, 3.0);
        assert!(rel(a.k_n, b.k_n) < 1e-14);
        assert_eq!(a.k_t, 0.0);
        assert!(b.k_t.abs() < 1e-15);
    }

    #[test]
    fn invalid_materials_are_refused_with_reasons() {
        let mut m = Material::table4(0.3);
        let e = m.validate(ForceLaw::Cohesive).unwrap_err().to_string();
        assert!(e.contains("1/4"), "{e}");
        m.poisson_ratio = 0.15;
        assert!(m
            .validate(ForceLaw::NormalOnly)
            .unwrap_err()
            .to_string()
            .contains("0.25"));
        m.tensile_strength = -1.0;
        assert!(m
            .validate(ForceLaw::Cohesive)
            .unwrap_err()
            .to_string()
            .contains("tensile_strength"));
        m.tensile_strength = f64::NAN;
        assert!(m
            .validate(ForceLaw::Cohesive)
            .unwrap_err()
            .to_string()
            .contains("finite"));
        let mut m = Material::table4(-1.0);
        assert!(m.validate(ForceLaw::Cohesive).is_err());
        m.poisson_ratio = 0.1;
        m.shear_strength = -0.1;
        assert!(m.validate(ForceLaw::Cohesive).is_err());
        m.shear_strength = 0.1;
        m.restitution = 0.0;
        assert!(m.validate(ForceLaw::Cohesive).is_err());
        m.restitution = 0.5;
        assert!(m.validate(ForceLaw::Cohesive).is_ok());
    }

    #[test]
    fn damping_models() {
        let mut model = PairModel::cohesive(Material::table4(0.1));
        model.material.restitution = 0.5;
        assert!(rel(model.damping_factor(), 1.0 / std::f64::consts::PI) < 1e-14);
        model.damping = DampingModel::Exact;
        let zeta = model.damping_factor() / 2.0;
        // Exact restitution of a linear spring-dashpot: exp(-zeta pi / sqrt(1 - zeta^2)).
        let e = (-zeta * std::f64::consts::PI / (1.0 - zeta * zeta).sqrt()).exp();
        assert!(rel(e, 0.5) < 1e-12);
    }
}
