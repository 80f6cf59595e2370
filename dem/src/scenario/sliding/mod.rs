//! Sliding with a third-body layer (paper 004 sections 2-3, Figs. 2-6): a quasi-2D box of two halves
//! between rigid bodies, the top one pressed with p_N and dragged at v; the layer that forms between
//! the halves is measured by its velocity and density profiles (see [`wear::tbl`]).
//!
//! Set-up (defaults: the paper's, in its units E = rho = L = 1):
//! - a relaxed amorphous box L x L x B (x sliding, y normal, z width), B = 3 d0, d0 = 0.01 L, sizes of
//!   the paper-004 log-normal (mode d0, std 0.1 d0, truncated to [0.75, 1.25] d0), relaxed as in
//!   paper 000 section 3.2;
//! - two halves with a non-matching interface (see `geometry`); rigid bodies of the particles within
//!   1.5 d0 of the top and bottom faces; the bottom one fixed, the top one under the normal pressure
//!   p_N (0.01 E) and dragged along x at v = 0.1 sqrt(E / rho); periodic along x and z;
//! - the normal-only law (paper 004 eqs 2-10: A_eff = 2 sqrt(2) r_eff^2, nu = 1/4, eta = 0.95), the
//!   material given by its strength sigma_m and either its surface energy gamma or its critical size
//!   d* = 32 gamma E / sigma_m^2 (eq 13, [`wear::scales::surface_energy_for_paper004`]);
//! - dt = 0.1 dt_c, for a sliding distance of 50 L.
//!
//! Decision (eq 11, r_i + r_j <= d_m = 4 gamma E / sigma_m^2 = d* / 8): at d0 = 0.01 L the paper's
//! d* = 0.05 L gives d_m = 0.625 d0, so every pair breaks the condition; the paper runs it anyway
//! ("the actual values of sigma_m and gamma may deviate"). The engine then ends such a pair at
//! delta_e (eq 10 with s = 0, see `dem::material`): the strength is kept, gamma is not. Accepted and
//! stated in the summary as `d_m_over_d0`.
//!
//! Measures (each a [`wear::tbl`] function): profiles on `bins` bins over the current height H,
//! averaged over windows of `samples_per_window` samples; per window h_TBL / H and rho_TBL / rho_0;
//! over the steady part (the windows after `steady_from` of the run) the averaged profiles, rho_TBL
//! from the Gaussian fit, the mean h_TBL / H, p_T from the bodies' horizontal forces, and the regime.
//!
//! Decision (the start): paper 004 drags the top body "at a fixed velocity" and reports that "at the
//! very beginning of sliding, before any amount of damage, the shear deformation is uniform" (Fig. 5).
//! A velocity step of v0 = 0.1 sqrt(E / rho) sends a shear wave of stress rho c_s v0 = 0.063 E
//! (c_s = sqrt(0.4 E / rho) at nu = 1/4) into the sample, 2.4 times tau_m = 0.027 E of the sigma_m =
//! 0.1 E material: measured, the quick runs then shear at the top body's face from the first window
//! on, the case the paper drops as unphysical, and never have the uniform start the paper saw. So the
//! body is ramped to v0 at the acceleration a = f tau_m / (rho L) with f = 0.5 by default
//! (`start_ramp_over_tau_m`; 0 restores the step): carrying the sample along then takes a shear
//! stress of half its strength. The ramp lasts v0 / a (0.37 L of slide at sigma_m = 0.1 E, less for
//! the stronger materials), inside the start-up that the measures leave out, and the run is longer
//! by the ramp's lag v0 / (2 a) so that the body still slides the whole distance
//! ([`SlidingConfig::steps`]). docs/sliding.md, "Where the TBL sits", has the runs behind it.
//!
//! Decision (the interior phase): paper 004 measures "the first stationary phase" and drops the
//! parts after the TBL "reaches the system's boundary" (section 3, Fig. 5). The steady part above is
//! kept as the run's headline measure, and beside it the run measures its interior phase: the
//! windows after the `startup` fraction of the run whose TBL lies inside the material
//! ([`wear::tbl::touches_body`] false), with their mean p_T (force samples inside those windows),
//! mean rho_TBL (each window's fit) and mean h_TBL. A TBL that wanders back off a body adds its
//! windows again: what counts is where the sheared band is, not when.
//!
//! The material's shear strength tau_m, which p_T is compared with (paper 004 section 3), is measured
//! on the run's own relaxed box with the patch-test rig ([`measure_strength`], module `strength`).

mod geometry;
mod run;
mod strength;
mod wear_probe;

use serde::{Deserialize, Serialize};
use wear::tbl::{LayerParams, RegimeParams};

use crate::error::{DemError, Result};
use crate::material::{ForceLaw, Material, PairModel};
use crate::sample::{RelaxConfig, SampleSpec};

pub use geometry::{build, Geometry, BODY_BOTTOM_HALF, BODY_TOP_HALF};
pub use run::{
    interior_phase, run, run_resumable, slide, time_to_slide, InteriorPhase, SlidingResult,
    WindowRecord, HEIGHT_BANDS,
};
pub use strength::{
    flow_stress, measure_strength, FlowStress, MaterialStrength, MeasuredPeak, StrengthTests,
    MIN_FLOW_WINDOW,
};
pub use wear_probe::{WearRecord, WearSummary};

/// The material of paper 004: its strength and one of its surface energy or critical size.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SlidingMaterial {
    /// Strength sigma_m (units of E); default 0.1 (paper, Fig. 6a).
    #[serde(default = "d_strength")]
    pub strength: f64,
    /// Surface energy gamma (units of E L); give this or `d_star`.
    #[serde(default)]
    pub surface_energy: Option<f64>,
    /// Critical size d* (units of L), turned into gamma by eq (13); give this or `surface_energy`.
    #[serde(default)]
    pub d_star: Option<f64>,
}

fn d_strength() -> f64 {
    0.1
}

impl Default for SlidingMaterial {
    fn default() -> Self {
        SlidingMaterial {
            strength: 0.1,
            surface_energy: None,
            d_star: Some(0.1),
        }
    }
}

/// A sliding run, in the units E = rho = L = 1 of paper 004 unless `young_modulus`, `density` or
/// `length` say otherwise.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SlidingConfig {
    /// Young's modulus E; default 1 (paper: the unit of stress).
    pub young_modulus: f64,
    /// Mass density rho; default 1 (paper: the unit of density).
    pub density: f64,
    /// Restitution eta; default 0.95 (paper).
    pub restitution: f64,
    /// sigma_m and gamma or d*; default sigma_m = 0.1 E, d* = 0.1 L (the centre of the paper's grid).
    pub material: SlidingMaterial,
    /// Box side L; default 1 (paper: the unit of length).
    pub length: f64,
    /// d0 / L; default 0.01 (paper; quick runs use 0.05).
    pub d0_over_l: f64,
    /// Width B / d0; default 3 (paper).
    pub width_over_d0: f64,
    /// Seed of the random insertion; default 1.
    pub seed: u64,
    /// Volume fraction of the random insertion; default 0.75 (paper 000 section 3.2).
    pub insert_fraction: f64,
    /// Relaxation; default paper 000's.
    pub relax: RelaxConfig,
    /// Rigid body thickness / d0; default 1.5 (paper).
    pub body_thickness_over_d0: f64,
    /// Normal pressure p_N on the top body (units of E); default 0.01 (paper's lowest).
    pub pressure: f64,
    /// Sliding velocity over sqrt(E / rho); default 0.1 (paper).
    pub velocity_over_wave_speed: f64,
    /// Sliding distance over L; default 50 (paper).
    pub distance_over_l: f64,
    /// Time step over dt_c (paper 000 eq 6); default 0.1 (paper 000).
    pub time_step_fraction: f64,
    /// Neighbour skin of the sliding run over the median diameter; default 0.3, not the engine's 0.05:
    /// the layer moves at up to v0 = 0.1 sqrt(E / rho), so a thin skin rebuilds the list every few
    /// steps (`configs/sliding-quick.toml`, 1 627 particles, 2 threads: 14.4-15.2 s of run at 0.05,
    /// 5.2-5.7 at 0.2, 4.8-4.9 at 0.3, 4.6 at 0.5, 5.8 at 0.8; docs/performance.md). The skin changes
    /// only which zero-force pairs the list holds: results agree to round-off (dem/tests/sliding.rs).
    pub skin_fraction: f64,
    /// Rebuild only the neighbour rows of the particles that moved (`dem::neighbor`'s local
    /// rebuilds); default true: once the band lies against a body, a few per cent of the particles
    /// move (L = 100 d0, p_N = 0.01 E, from 4 L on, 2 threads, the same checkpoint: 10 300 steps in
    /// 90 s against 8 825 with full builds); where the band is wide, most rebuilds stay full and the
    /// cost is unchanged (L = 50 d0 over 6 L: 57.6 s against 57.9 s; the quick box: no local rebuild).
    pub local_rebuilds: bool,
    /// Profile bins over the height; default 400 (paper, Fig. 4).
    pub bins: usize,
    /// Measurement windows over the run (one h_TBL and rho_TBL each, Fig. 5); default 100 (one per
    /// half L of sliding at the paper's distance).
    pub windows: u64,
    /// Profile samples averaged in a window; default 10 (each sample already averages B / d0 x L / d0
    /// particles per bin row).
    pub samples_per_window: u64,
    /// Force samples on the bodies over the run; default 1000.
    pub force_samples: u64,
    /// Dump frames over the run (0: none); default 50 (a film in OVITO).
    pub dump_frames: u64,
    /// Fraction of the run after which it is taken as steady; default 0.5 (Fig. 5: the start-up peak
    /// lasts a few L of the 50 L; later windows are safely past it).
    pub steady_from: f64,
    /// Fraction of the run taken as start-up, left out of the interior phase and of where the TBL
    /// first reached a body; default 0.1 (Fig. 5's start-up peak of uniform shear spans the whole
    /// height, both bodies included: the first window or two of a quick run).
    pub startup: f64,
    /// The top body's start: 0 puts it at v0 on the first step (the paper's words, "dragged ... at a
    /// fixed velocity"); f > 0 ramps it up at the acceleration a = f tau_m / (rho L), which needs a
    /// shear stress rho L a = f tau_m to carry the sample along. Default 0.5 (the decision above:
    /// half the strength, reached in 0.37 L of slide at sigma_m = 0.1 E).
    /// The run is lengthened by the ramp's lag v0 / (2 a), so that the body still slides
    /// `distance_over_l` L; the windows' `slide` is the body's own.
    pub start_ramp_over_tau_m: f64,
    /// Shear strength tau_m / sigma_m of the material, when given; default none: tau_m is measured on
    /// the run's own relaxed box with the patch-test rig ([`measure_strength`]; paper 004 gives
    /// 0.22 without its method).
    pub shear_strength_over_strength: Option<f64>,
    /// The patch tests that measure tau_m and sigma_t; default [`StrengthTests::default`].
    pub strength_tests: StrengthTests,
    /// Velocity thresholds and filter of the profiles; default the paper's (the fit's smallest width
    /// is set to d0 / H by the run).
    pub layer: LayerParams,
    /// Regime thresholds; default [`RegimeParams::default`].
    pub regime: RegimeParams,
    /// Particles a loose cluster needs to count as a wear particle (`wear::tbl::wear_particles`);
    /// default 10: about 2 d0 across in the 3 d0 thick box, twice the largest particle, where the
    /// crumbs of a flowing band are single particles and pairs.
    pub wear_particle_members: usize,
}

impl Default for SlidingConfig {
    fn default() -> Self {
        SlidingConfig {
            young_modulus: 1.0,
            density: 1.0,
            restitution: 0.95,
            material: SlidingMaterial::default(),
            length: 1.0,
            d0_over_l: 0.01,
            width_over_d0: 3.0,
            seed: 1,
            insert_fraction: 0.75,
            relax: RelaxConfig::default(),
            body_thickness_over_d0: 1.5,
            pressure: 0.01,
            velocity_over_wave_speed: 0.1,
            distance_over_l: 50.0,
            time_step_fraction: 0.1,
            skin_fraction: 0.3,
            local_rebuilds: true,
            bins: 400,
            windows: 100,
            samples_per_window: 10,
            force_samples: 1000,
            dump_frames: 50,
            steady_from: 0.5,
            startup: 0.1,
            start_ramp_over_tau_m: 0.5,
            shear_strength_over_strength: None,
            strength_tests: StrengthTests::default(),
            layer: LayerParams::default(),
            regime: RegimeParams::default(),
            wear_particle_members: 10,
        }
    }
}

impl SlidingConfig {
    /// Nominal diameter d0.
    pub fn d0(&self) -> f64 {
        self.d0_over_l * self.length
    }

    /// Sliding velocity v.
    pub fn velocity(&self) -> f64 {
        self.velocity_over_wave_speed * (self.young_modulus / self.density).sqrt()
    }

    /// Surface energy gamma (given, or from d* by eq 13).
    pub fn surface_energy(&self) -> Result<f64> {
        let m = &self.material;
        match (m.surface_energy, m.d_star) {
            (Some(g), None) => Ok(g),
            (None, Some(d)) => Ok(wear::scales::surface_energy_for_paper004(
                d,
                self.young_modulus,
                m.strength,
            )),
            _ => Err(DemError::InvalidConfig(
                "sliding: give the material's surface_energy or its d_star (eq 13), exactly one"
                    .into(),
            )),
        }
    }

    /// d* of eq (13).
    pub fn d_star(&self) -> Result<f64> {
        Ok(wear::scales::critical_size_paper004(
            self.surface_energy()?,
            self.young_modulus,
            self.material.strength,
        ))
    }

    /// The paper-004 material (nu = 1/4, no tangential strength: the normal-only law has none).
    pub fn material(&self) -> Result<Material> {
        Ok(Material {
            young_modulus: self.young_modulus,
            poisson_ratio: 0.25,
            tensile_strength: self.material.strength,
            shear_strength: 0.0,
            surface_energy: self.surface_energy()?,
            restitution: self.restitution,
            density: self.density,
            scaling: 0.0,
        })
    }

    /// The normal-only pair model of this material.
    pub fn model(&self) -> Result<PairModel> {
        let m = PairModel::normal_only(self.material()?);
        m.validate()?;
        Ok(m)
    }

    /// The recipe of the relaxed box (d0 in units of the material's d_c, eq 18).
    pub fn recipe(&self) -> Result<SampleSpec> {
        let d_c = self.material()?.critical_diameter();
        Ok(SampleSpec::Amorphous {
            d0_over_dc: self.d0() / d_c,
            l_over_d0: 1.0 / self.d0_over_l,
            w_over_d0: self.width_over_d0,
            h_over_d0: None,
            ds_over_d0: 0.75,
            dl_over_d0: 1.25,
            dl_over_l: None,
            seed: self.seed,
            insert_fraction: self.insert_fraction,
        })
    }

    /// Checks everything that does not need the sample.
    pub fn validate(&self) -> Result<()> {
        let bad = |m: String| Err(DemError::InvalidConfig(format!("sliding: {m}")));
        let positive = [
            ("young_modulus", self.young_modulus),
            ("density", self.density),
            ("restitution", self.restitution),
            ("material.strength", self.material.strength),
            ("length", self.length),
            ("d0_over_l", self.d0_over_l),
            ("width_over_d0", self.width_over_d0),
            ("insert_fraction", self.insert_fraction),
            ("body_thickness_over_d0", self.body_thickness_over_d0),
            ("velocity_over_wave_speed", self.velocity_over_wave_speed),
            ("time_step_fraction", self.time_step_fraction),
            ("skin_fraction", self.skin_fraction),
            (
                "shear_strength_over_strength",
                self.shear_strength_over_strength.unwrap_or(1.0),
            ),
        ];
        if let Some(m) = crate::error::not_positive(&positive) {
            return bad(m);
        }
        if !(self.pressure.is_finite() && self.pressure > 0.0) {
            return bad(format!(
                "pressure p_N = {} must be positive (the top body is pressed on the layer)",
                self.pressure
            ));
        }
        if self.pressure >= self.young_modulus {
            return bad(format!(
                "pressure p_N = {:.4e} is not below E = {:.4e}: a strain of order one, far outside \
                 the elastic pair law (paper 004: p_N of 0.01-0.04 E)",
                self.pressure, self.young_modulus
            ));
        }
        if !(self.distance_over_l.is_finite() && self.distance_over_l > 0.0) {
            return bad(format!(
                "the sliding distance distance_over_l = {} must be positive",
                self.distance_over_l
            ));
        }
        let gamma = self.surface_energy()?;
        if !(gamma.is_finite() && gamma > 0.0) {
            return bad(format!("surface energy {gamma} must be positive"));
        }
        let d_star = self.d_star()?;
        let d0 = self.d0();
        if d_star <= d0 {
            return bad(format!(
                "d* = {d_star:.4e} is not above d0 = {d0:.4e}: the model needs particles smaller than \
                 the smallest wear particle (paper 004 section 2; a smaller d0_over_l)"
            ));
        }
        if d_star >= 0.5 * self.length {
            return bad(format!(
                "d* = {d_star:.4e} does not fit the box: a wear particle of that size must fit in one \
                 half of L = {} (paper's largest: 0.2 L)",
                self.length
            ));
        }
        // Two bodies, a free part of at least two particles each side of the interface.
        let l_over_d0 = 1.0 / self.d0_over_l;
        if l_over_d0 < 2.0 * self.body_thickness_over_d0 + 4.0 {
            return bad(format!(
                "d0 = {d0:.4e} does not fit the box: L / d0 = {l_over_d0:.3} leaves no room between two \
                 bodies of {} d0 for two halves of at least two particles",
                self.body_thickness_over_d0
            ));
        }
        if self.width_over_d0 < 2.0 {
            return bad(format!(
                "width_over_d0 = {} is below 2: the periodic width must hold a pair's range",
                self.width_over_d0
            ));
        }
        if self.bins < self.layer.sg_window || self.windows < 1 || self.samples_per_window < 1 {
            return bad(format!(
                "bins ({}) must be at least the filter window ({}), windows and samples_per_window at \
                 least 1",
                self.bins, self.layer.sg_window
            ));
        }
        if self.wear_particle_members < 1 {
            return bad("wear_particle_members must be at least 1".to_string());
        }
        if !(self.steady_from >= 0.0 && self.steady_from < 1.0) {
            return bad(format!(
                "steady_from = {} must lie in [0, 1)",
                self.steady_from
            ));
        }
        if !(self.start_ramp_over_tau_m >= 0.0 && self.start_ramp_over_tau_m.is_finite()) {
            return bad(format!(
                "start_ramp_over_tau_m = {} must be 0 (a velocity step) or positive",
                self.start_ramp_over_tau_m
            ));
        }
        if !(self.startup >= 0.0 && self.startup < 1.0) {
            return bad(format!(
                "startup = {} (a fraction of the run) must lie in [0, 1)",
                self.startup
            ));
        }
        if self.force_samples < 1 {
            return bad("force_samples must be at least 1".into());
        }
        let model = self.model()?;
        // The slide's length in steps, bounded from below before any sample exists: the time step is
        // a fraction of eq 6's step of the smallest particle, and a particle of 2 d0 (larger than any
        // of the size distribution) has a longer one. A distance in the wrong units is so refused
        // before the relaxation and the strength tests rather than after them.
        let r = self.d0();
        let mass = crate::state::sphere_mass(self.density, r);
        self.steps(
            self.time_step_fraction * model.critical_time_step(r, mass),
            None,
        )
        .map(|_| ())
    }

    /// Checks that `model` is the law this scenario is defined for (paper 004: normal-only, nu = 1/4).
    pub fn check_model(model: &PairModel) -> Result<()> {
        if model.law != ForceLaw::NormalOnly || model.has_tangential() {
            return Err(DemError::InvalidConfig(
                "sliding: paper 004 uses the normal-only force; this model has the tangential law \
                 (use PairModel::normal_only)"
                    .into(),
            ));
        }
        if (model.material.poisson_ratio - 0.25).abs() > 1e-12 {
            return Err(DemError::InvalidConfig(format!(
                "sliding: the normal-only force fixes nu = 1/4, the model has {}",
                model.material.poisson_ratio
            )));
        }
        model.validate()
    }

    /// tau_m when the config gives it (`shear_strength_over_strength` sigma_m), else none: measure it.
    pub fn given_shear_strength(&self) -> Option<f64> {
        self.shear_strength_over_strength
            .map(|r| r * self.material.strength)
    }

    /// The part of this config that the material's strength tests depend on (the relaxed box: material,
    /// sizes, seed, relaxation; and the tests), the rest at its defaults: runs that differ only in
    /// p_N, distance or measures share one strength measurement (one job key).
    pub fn material_test(&self) -> SlidingConfig {
        SlidingConfig {
            young_modulus: self.young_modulus,
            density: self.density,
            restitution: self.restitution,
            material: self.material.clone(),
            length: self.length,
            d0_over_l: self.d0_over_l,
            width_over_d0: self.width_over_d0,
            seed: self.seed,
            insert_fraction: self.insert_fraction,
            relax: self.relax,
            strength_tests: self.strength_tests,
            ..SlidingConfig::default()
        }
    }

    /// The top body's acceleration a = f tau_m / (rho L) from rest to v0, for the material's shear
    /// strength `tau_m`; `None` when the body starts at v0 (f = 0).
    pub fn ramp_acceleration(&self, tau_m: f64) -> Option<f64> {
        (self.start_ramp_over_tau_m > 0.0)
            .then(|| self.start_ramp_over_tau_m * tau_m / (self.density * self.length))
    }

    /// Steps for the sliding distance at time step `dt`, with the body ramped at `ramp` (or started
    /// at v0 with `None`): the time the body takes to slide it ([`time_to_slide`]: distance /
    /// v0 plus the ramp's lag v0 / (2 a)), so that every run slides its full distance.
    pub fn steps(&self, dt: f64, ramp: Option<f64>) -> Result<u64> {
        let distance = self.distance_over_l * self.length;
        crate::scenario::step_budget(
            "the slide (distance_over_l L at the sliding speed)",
            (time_to_slide(self.velocity(), ramp, distance) / dt).ceil(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eq_13_sets_gamma_and_bad_settings_are_named() {
        let c = SlidingConfig::default();
        // d* = 0.1 L at sigma_m = 0.1 E: gamma = d* sigma_m^2 / (32 E).
        assert!((c.surface_energy().unwrap() - 0.1 * 0.01 / 32.0).abs() < 1e-18);
        assert!((c.d_star().unwrap() - 0.1).abs() < 1e-15);
        c.validate().unwrap();
        let m = c.model().unwrap();
        SlidingConfig::check_model(&m).unwrap();
        let with = |f: &dyn Fn(&mut SlidingConfig)| {
            let mut c = SlidingConfig::default();
            f(&mut c);
            c.validate().unwrap_err().to_string()
        };
        assert!(with(&|c| c.pressure = 0.0).contains("p_N"));
        assert!(with(&|c| c.pressure = -0.01).contains("p_N"));
        assert!(with(&|c| c.distance_over_l = 0.0).contains("distance"));
        assert!(with(&|c| c.pressure = 1.0).contains("not below E"));
        assert!(with(&|c| c.distance_over_l = 1e300).contains("steps, more than"));
        assert!(with(&|c| c.material.d_star = Some(0.6)).contains("does not fit the box"));
        assert!(with(&|c| c.material.d_star = Some(0.005)).contains("not above d0"));
        assert!(with(&|c| {
            c.d0_over_l = 0.15;
            c.material.d_star = Some(0.3);
        })
        .contains("L / d0"));
        assert!(with(&|c| c.material.surface_energy = Some(1e-4)).contains("exactly one"));
        assert!(with(&|c| c.startup = 1.0).contains("startup"));
        assert!(with(&|c| c.start_ramp_over_tau_m = -0.5).contains("start_ramp_over_tau_m"));
        assert!(with(&|c| c.start_ramp_over_tau_m = f64::NAN).contains("start_ramp_over_tau_m"));
        let mut both_none = SlidingConfig::default();
        both_none.material.d_star = None;
        assert!(both_none.validate().is_err());
        // Runs that differ in p_N or distance share their strength test; another seed does not.
        let other = SlidingConfig {
            pressure: 0.04,
            distance_over_l: 3.0,
            ..c.clone()
        };
        assert_eq!(other.material_test(), c.material_test());
        let seeded = SlidingConfig {
            seed: 2,
            ..c.clone()
        };
        assert_ne!(seeded.material_test(), c.material_test());
        assert_eq!(c.given_shear_strength(), None);
        let given = SlidingConfig {
            shear_strength_over_strength: Some(0.22),
            ..c.clone()
        };
        assert!((given.given_shear_strength().unwrap() - 0.022).abs() < 1e-15);
        assert!(with(&|c| c.shear_strength_over_strength = Some(-0.2)).contains("shear_strength"));
        let mut by_gamma = both_none.clone();
        by_gamma.material.surface_energy = Some(0.1 * 0.01 / 32.0);
        assert!((by_gamma.d_star().unwrap() - 0.1).abs() < 1e-12);
        // A tangential law, or nu != 1/4, is refused.
        let mut mat = c.material().unwrap();
        assert!(SlidingConfig::check_model(&PairModel::cohesive(mat.clone())).is_err());
        mat.poisson_ratio = 0.2;
        let e = SlidingConfig::check_model(&PairModel::normal_only(mat)).unwrap_err();
        assert!(
            e.to_string().contains("0.25") || e.to_string().contains("1/4"),
            "{e}"
        );
    }
}
