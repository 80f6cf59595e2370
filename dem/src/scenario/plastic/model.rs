//! The inputs every plastic-wear run shares (SI, as users write them) and their engine-unit form.

use serde::{Deserialize, Serialize};

use super::flow::LateralOffset;
use super::surface::SurfaceSpec;
use crate::error::{not_positive, DemError, Result};
use crate::force::hertz::{
    contact_modulus_rigid, contact_shear_modulus_rigid, effective_radius, mindlin_stiffness,
    HertzLaw,
};
use crate::units::UnitSystem;

/// Which contact modulus E* the Hertz law uses (see `force::hertz`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ContactModulus {
    /// E / (2 (1 - nu^2)): LAMMPS's `hertz/material` for two particles given the same E and nu, what
    /// the paper's simulations ran.
    #[default]
    Lammps,
    /// E / (1 - nu^2): an elastic sphere against a rigid one, as the paper's text describes.
    Rigid,
}

impl ContactModulus {
    /// E* of surface spheres of modulus `young` and ratio `poisson`.
    pub fn of(self, young: f64, poisson: f64) -> f64 {
        match self {
            ContactModulus::Lammps => 0.5 * contact_modulus_rigid(young, poisson),
            ContactModulus::Rigid => contact_modulus_rigid(young, poisson),
        }
    }
}

/// The surface and its contact with the projectile (paper 001 section 3), in SI.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PlasticModel {
    /// Young's modulus of the surface spheres (Pa); default 200 GPa (paper 001 section 3).
    pub young_modulus: f64,
    /// Poisson's ratio of the surface spheres; default 0.3 (paper).
    pub poisson_ratio: f64,
    /// The Hertz contact modulus; default lammps, E / (2 (1 - nu^2)) (see `force::hertz`).
    pub contact_modulus: ContactModulus,
    /// Coulomb friction coefficient mu of the contacts; default 0.5 (paper).
    pub friction: f64,
    /// Hardness H (Pa); default 1.7 GPa (paper, "unless otherwise specified").
    pub hardness: f64,
    /// mu_a = H_l / H, the shear hardness over the hardness; default 0.25 (paper's standard value).
    pub mu_a: f64,
    /// Tangential stiffness k_t (N/m); default (absent): Mindlin's 8 G* a at the overlap where a
    /// sphere of the flat surface starts to flow (see `force::hertz`).
    pub tangential_stiffness: Option<f64>,
    /// Offset eq (5) uses; default paper, eq 5 as printed (see `flow`).
    pub lateral_offset: LateralOffset,
    /// The strip of spheres; default the paper's.
    pub surface: SurfaceSpec,
}

impl Default for PlasticModel {
    fn default() -> Self {
        PlasticModel {
            young_modulus: 200e9,
            poisson_ratio: 0.3,
            contact_modulus: ContactModulus::Lammps,
            friction: 0.5,
            hardness: 1.7e9,
            mu_a: 0.25,
            tangential_stiffness: None,
            lateral_offset: LateralOffset::Paper,
            surface: SurfaceSpec::default(),
        }
    }
}

impl PlasticModel {
    /// Rejects what the model cannot represent: H <= 0, mu_a outside (0, mu) (section 3.1: scratching
    /// without indentation needs mu_a < mu), a non-positive modulus or friction, nu outside (-1, 0.5).
    pub fn validate(&self) -> Result<()> {
        if let Some(m) = not_positive(&[
            ("hardness", self.hardness),
            ("young_modulus", self.young_modulus),
            ("friction", self.friction),
        ]) {
            return Err(DemError::InvalidConfig(format!(
                "{m} (paper 001: H > 0, E > 0, mu > 0)"
            )));
        }
        if !(self.poisson_ratio > -1.0 && self.poisson_ratio < 0.5) {
            return Err(DemError::InvalidConfig(format!(
                "poisson_ratio = {} must lie in (-1, 0.5)",
                self.poisson_ratio
            )));
        }
        if !(self.mu_a > 0.0 && self.mu_a < self.friction) {
            return Err(DemError::InvalidConfig(format!(
                "mu_a = {} must lie in (0, mu) = (0, {}): paper 001 section 3.1, the shear hardness \
                 H_l = mu_a H can only be reached by friction when mu_a < mu",
                self.mu_a, self.friction
            )));
        }
        if let Some(k) = self.tangential_stiffness {
            if let Some(m) = not_positive(&[("tangential_stiffness", k)]) {
                return Err(DemError::InvalidConfig(m));
            }
        }
        self.surface.validate()
    }
}

/// A rigid sphere: the projectile of an impact or the indenter of a scratch (SI).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Projectile {
    /// Radius R_p (m).
    pub radius: f64,
    /// Density (kg/m^3).
    pub density: f64,
}

impl Projectile {
    /// Mass (kg) of the solid sphere.
    pub fn mass(&self) -> f64 {
        crate::state::sphere_mass(self.density, self.radius)
    }

    /// Rejects a non-positive radius or density.
    pub fn validate(&self, what: &str) -> Result<()> {
        match not_positive(&[
            (&format!("{what}.radius"), self.radius),
            (&format!("{what}.density"), self.density),
        ]) {
            Some(m) => Err(DemError::InvalidConfig(m)),
            None => Ok(()),
        }
    }
}

/// The time step: a fraction of the stable step of the Hertzian contacts, or seconds.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PlasticTimeStep {
    /// A fraction of `Params::stable_step`'s estimate.
    FractionOfStable(f64),
    /// Seconds; refused above the stable step.
    Seconds(f64),
}

/// The model in engine units ([`UnitSystem::MILLI`]: mm, g, ms; force N, stress MPa, energy mJ).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Params {
    pub units: UnitSystem,
    /// Projectile radius R_p, mass, moment of inertia (solid sphere).
    pub radius: f64,
    pub mass: f64,
    pub inertia: f64,
    /// r = R_p + r_s, the effective radius of App. A and B.
    pub reach: f64,
    pub hertz: HertzLaw,
    pub k_t: f64,
    pub friction: f64,
    pub hardness: f64,
    pub shear_hardness: f64,
    pub lateral: LateralOffset,
    /// a_s, filled from the surface.
    pub cell_area: f64,
}

impl Params {
    /// Engine-unit parameters of `model` with projectile `p` on a surface of area per sphere
    /// `cell_area` (engine units).
    pub fn new(model: &PlasticModel, p: &Projectile, cell_area: f64) -> Params {
        let u = UnitSystem::MILLI;
        let radius = u.length_from_m(p.radius);
        let r_s = u.length_from_m(model.surface.sphere_radius);
        let mass = u.mass_from_kg(p.mass());
        let e_star = u.stress_from_pa(
            model
                .contact_modulus
                .of(model.young_modulus, model.poisson_ratio),
        );
        let r_star = effective_radius(radius, r_s);
        let hertz = HertzLaw::new(e_star, r_star);
        let hardness = u.stress_from_pa(model.hardness);
        let k_t = match model.tangential_stiffness {
            Some(k) => u.force_from_n(k) / u.length_from_m(1.0),
            None => {
                // The shear modulus takes the same factor as E*.
                let rigid = contact_modulus_rigid(model.young_modulus, model.poisson_ratio);
                let share = model
                    .contact_modulus
                    .of(model.young_modulus, model.poisson_ratio)
                    / rigid;
                let g_star = u.stress_from_pa(
                    share * contact_shear_modulus_rigid(model.young_modulus, model.poisson_ratio),
                );
                mindlin_stiffness(g_star, r_star, hertz.overlap_at(cell_area * hardness))
            }
        };
        Params {
            units: u,
            radius,
            mass,
            inertia: 0.4 * mass * radius * radius,
            reach: radius + r_s,
            hertz,
            k_t,
            friction: model.friction,
            hardness,
            shear_hardness: model.mu_a * hardness,
            lateral: model.lateral_offset,
            cell_area,
        }
    }

    /// Force at which a sphere of the flat surface starts to flow, a_s H.
    pub fn flow_force(&self) -> f64 {
        self.cell_area * self.hardness
    }

    /// Overlap at which a sphere of the flat surface starts to flow.
    pub fn flow_overlap(&self) -> f64 {
        self.hertz.overlap_at(self.flow_force())
    }

    /// The overlap a contact of the run can reach: the flow overlap, unless `cap` (what the run's
    /// energy or load allows one contact) is smaller.
    pub fn contact_overlap(&self, cap: f64) -> f64 {
        self.flow_overlap().min(cap)
    }

    /// Stable step of symplectic Euler for a projectile on `contacts` contacts at `overlap`: 2 / omega,
    /// omega^2 = K / m with K the larger of the normal stiffnesses and the tangential ones seen through
    /// the rolling mass (2/7 m with spin).
    pub fn stable_step(&self, contacts: f64, spin: bool, overlap: f64) -> f64 {
        let n = contacts.max(1.0);
        let k =
            (n * self.hertz.stiffness(overlap)).max(n * self.k_t * if spin { 3.5 } else { 1.0 });
        2.0 * (self.mass / k).sqrt()
    }

    /// The largest number of contacts a flat-surface indentation of depth `depth` (plus a contact's
    /// `overlap`) can hold: the spherical cap's area 2 pi r h over a_s, plus a ring.
    pub fn contacts_at_depth(&self, depth: f64, overlap: f64) -> f64 {
        let h = depth.max(0.0) + overlap;
        let area = 2.0 * std::f64::consts::PI * self.reach * h;
        area / self.cell_area
            + 2.0 * std::f64::consts::PI * (2.0 * self.reach * h).sqrt() / self.cell_area.sqrt()
    }

    /// The time step of `spec` with the stable step `stable` (engine units), refusing one above it.
    /// A fraction of the stable step is also kept below `max_advance` contact overlaps (`overlap`)
    /// per step at the projectile's fastest `speed` (see [`RunSettings`](super::RunSettings)).
    pub fn time_step(
        &self,
        spec: PlasticTimeStep,
        stable: f64,
        (max_advance, overlap, speed): (f64, f64, f64),
    ) -> Result<f64> {
        if max_advance.is_nan() || max_advance <= 0.0 {
            return Err(DemError::InvalidConfig(format!(
                "run.max_advance = {max_advance} must be positive"
            )));
        }
        let dt = match spec {
            PlasticTimeStep::FractionOfStable(f) => {
                if !(f > 0.0 && f <= 1.0) {
                    return Err(DemError::InvalidConfig(format!(
                        "time_step.fraction_of_stable = {f} must lie in (0, 1]"
                    )));
                }
                (f * stable).min(max_advance * overlap / speed)
            }
            PlasticTimeStep::Seconds(s) => {
                if let Some(m) = not_positive(&[("time_step.seconds", s)]) {
                    return Err(DemError::InvalidConfig(m));
                }
                self.units.time_from_s(s)
            }
        };
        if dt > stable {
            return Err(DemError::InvalidConfig(format!(
                "time step {:.4e} s exceeds the stable step {:.4e} s of the Hertzian contacts \
                 (2 sqrt(m / K), K the stiffness of the contacts the run will meet); lower it",
                self.units.time_to_s(dt),
                self.units.time_to_s(stable)
            )));
        }
        Ok(dt)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_parameters_in_engine_units() {
        let model = PlasticModel::default();
        model.validate().unwrap();
        let p = Projectile {
            radius: 0.01,
            density: 8000.0,
        };
        let a_s = 93.5 * 16.8 / 5012.0;
        let q = Params::new(&model, &p, a_s);
        // Mass 33.5 g; H a_s = 1700 MPa * 0.313 mm^2 = 533 N.
        assert!((q.mass - 33.51).abs() < 0.01);
        assert!((q.flow_force() - 1700.0 * a_s).abs() < 1e-9);
        // E* = 200 GPa / (2 * 0.91) (LAMMPS's mixing), R* = 10 * 0.25 / 10.25 mm:
        // k_h = 4/3 E* sqrt(R*) in N/mm^1.5.
        let k_h = 4.0 / 3.0 * 100e3 / 0.91 * (2.5f64 / 10.25).sqrt();
        assert!((q.hertz.k_h - k_h).abs() / k_h < 1e-12);
        // The overlap at the flow force is ~ 38 um, small against the 0.8 mm crater of Fig. 4.
        let d = q.flow_overlap();
        assert!(d > 0.035 && d < 0.040, "{d}");
        assert!(q.k_t > 0.0 && q.reach == 10.25);
        // The rigid-projectile modulus is twice as stiff: the overlap shrinks by 2^(2/3).
        let mut rigid = model;
        rigid.contact_modulus = ContactModulus::Rigid;
        let r = Params::new(&rigid, &p, a_s);
        assert!((r.hertz.k_h / q.hertz.k_h - 2.0).abs() < 1e-12);
        assert!((d / r.flow_overlap() - 2f64.powf(2.0 / 3.0)).abs() < 1e-9);
    }

    #[test]
    fn bad_models_are_errors() {
        let bad = |f: fn(&mut PlasticModel)| {
            let mut m = PlasticModel::default();
            f(&mut m);
            m.validate().unwrap_err().to_string()
        };
        assert!(bad(|m| m.hardness = 0.0).contains("hardness"));
        assert!(bad(|m| m.hardness = -1e9).contains("hardness"));
        assert!(bad(|m| m.mu_a = 0.5).contains("mu_a"));
        assert!(bad(|m| m.mu_a = 0.0).contains("mu_a"));
        assert!(bad(|m| m.mu_a = f64::NAN).contains("mu_a"));
        assert!(bad(|m| m.poisson_ratio = 0.5).contains("poisson"));
        assert!(bad(|m| m.tangential_stiffness = Some(-1.0)).contains("tangential"));
    }

    #[test]
    fn time_steps_above_the_stable_one_are_refused() {
        let q = Params::new(
            &PlasticModel::default(),
            &Projectile {
                radius: 0.01,
                density: 8000.0,
            },
            0.3134,
        );
        let d = q.flow_overlap();
        let stable = q.stable_step(100.0, true, d);
        let s = q.units.time_to_s(stable);
        let slow = 1e-3;
        let step = |spec| q.time_step(spec, stable, (0.01, d, slow));
        assert!(step(PlasticTimeStep::Seconds(0.5 * s)).is_ok());
        let e = step(PlasticTimeStep::Seconds(2.0 * s)).unwrap_err();
        assert!(e.to_string().contains("stable step"), "{e}");
        assert!(step(PlasticTimeStep::FractionOfStable(1.5)).is_err());
        let dt = step(PlasticTimeStep::FractionOfStable(0.1)).unwrap();
        assert!((dt - 0.1 * stable).abs() < 1e-18);
        // A fast projectile: at most 1 % of the flow overlap per step.
        let fast = 45.0;
        let dt = q
            .time_step(
                PlasticTimeStep::FractionOfStable(0.1),
                stable,
                (0.01, d, fast),
            )
            .unwrap();
        assert!((dt * fast - 0.01 * d).abs() < 1e-15);
        assert!(q
            .time_step(
                PlasticTimeStep::FractionOfStable(0.1),
                stable,
                (0.0, d, fast)
            )
            .is_err());
    }
}
