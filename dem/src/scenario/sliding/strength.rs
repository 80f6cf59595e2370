//! The sliding material's own strengths, measured with the patch-test rig (paper 000 section 3,
//! Fig. 4b-c; [`crate::scenario::patch::strength`]) on the sliding run's relaxed box.
//!
//! Paper 004 section 3 compares p_T with the material's shear strength tau_m ("measured to be roughly
//! equal to tau_m = 0.22 sigma_m"), without saying how it was measured. Decision: the project's shear
//! patch test, unchanged: the relaxed L x L x B box of the run (the same recipe, law and seed, so the
//! same particles before the cut), rigid walls of the particles within 1.05 interaction ranges of the
//! faces normal to y, the top wall moved along x (the sliding direction) at constant wall separation
//! with a strain rate of 1e-5 per step, dt = 0.1 dt_c, global damping 0.01 c_c; tau_m is the peak of
//! the virial shear stress sigma_xy of the free particles. The tensile test (top wall pulled along y)
//! gives the tensile strength sigma_t of the same box, the counterpart of sigma_m at the scale of the
//! sample. Both stop a set strain past their peak: only the peaks are wanted, not the fracture energy.

use serde::{Deserialize, Serialize};

use super::SlidingConfig;
use crate::error::{DemError, Result};
use crate::sample::Sample;
use crate::scenario::patch::{
    strength_resumable, Curve, ProgressFile, StrengthConfig, StrengthMode,
};
use crate::sim::Parallelism;

/// The two patch tests of the sliding material.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct StrengthTests {
    /// Simple shear; default the paper-000 test stopped 0.05 strain past the peak (50 records past
    /// it; the box then flows in stick-slip at about 0.7 of the peak, docs/sliding.md: a larger
    /// `post_peak_strain` measures that flow stress).
    pub shear: StrengthConfig,
    /// Tension; default the paper-000 test stopped 0.05 strain past the peak (no fracture energy).
    pub tensile: StrengthConfig,
}

impl Default for StrengthTests {
    fn default() -> Self {
        let peak_only = |mode| StrengthConfig {
            post_peak_strain: 0.05,
            ..StrengthConfig::paper(mode)
        };
        StrengthTests {
            shear: peak_only(StrengthMode::Shear),
            tensile: peak_only(StrengthMode::Tensile),
        }
    }
}

/// One measured strength and its stress-strain curve.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MeasuredPeak {
    /// Peak virial stress (sigma_xy in shear, sigma_yy in tension), engine units.
    pub peak: f64,
    /// Strain at the peak (shear or normal, wall displacement over L0).
    pub strain_at_peak: f64,
    /// Steps run and wall-clock seconds.
    pub steps: u64,
    pub wall_seconds: f64,
    /// (strain, stress, sigma_yy) every `record_every` steps: the strain and stress of the test, and
    /// the normal stress (in shear, the walls' constant separation builds it up).
    pub curve: Vec<(f64, f64, f64)>,
}

/// The sliding material's strengths (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MaterialStrength {
    /// Shear strength tau_m and tensile strength sigma_t (engine units).
    pub tau_m: f64,
    pub sigma_t: f64,
    /// The material's sigma_m and E (engine units), for the ratios.
    pub sigma_m: f64,
    pub young_modulus: f64,
    /// Particles of the box (walls included).
    pub particles: usize,
    pub shear: MeasuredPeak,
    pub tensile: MeasuredPeak,
    /// How it was measured, in one line (written in summaries).
    pub how: String,
}

impl MaterialStrength {
    /// tau_m / sigma_m (paper 004: about 0.22).
    pub fn tau_over_sigma_m(&self) -> f64 {
        self.tau_m / self.sigma_m
    }
}

fn peak_of(mode: StrengthMode, r: &crate::scenario::patch::StrengthResult) -> MeasuredPeak {
    let curve: &Curve = &r.curve;
    let pts = curve
        .points
        .iter()
        .map(|p| match mode {
            StrengthMode::Shear => (p.strain_xy, p.stress[3], p.stress[1]),
            StrengthMode::Tensile => (p.strain_yy, p.stress[1], p.stress[1]),
        })
        .collect();
    MeasuredPeak {
        peak: r.strength,
        strain_at_peak: r.strain_at_peak,
        steps: r.steps,
        wall_seconds: r.wall_seconds,
        curve: pts,
    }
}

/// Measures tau_m and sigma_t of `cfg`'s material on `relaxed`, the run's relaxed box (made from
/// [`SlidingConfig::recipe`] with [`SlidingConfig::model`]). With `progress` (a folder), each test
/// keeps its progress there and a rerun continues it.
pub fn measure_strength(
    relaxed: &Sample,
    cfg: &SlidingConfig,
    tests: &StrengthTests,
    par: Parallelism,
    progress: Option<&std::path::Path>,
) -> Result<MaterialStrength> {
    cfg.validate()?;
    for (c, mode) in [
        (&tests.shear, StrengthMode::Shear),
        (&tests.tensile, StrengthMode::Tensile),
    ] {
        if c.mode != mode {
            return Err(DemError::InvalidConfig(format!(
                "sliding strength tests: the {mode:?} entry has mode {:?}",
                c.mode
            )));
        }
    }
    let model = cfg.model()?;
    let file = |name: &str| progress.map(|d| ProgressFile::new(d.join(name)));
    let (pf_s, pf_t) = (file("shear.progress.json"), file("tensile.progress.json"));
    let shear = strength_resumable(relaxed, &model, &tests.shear, par, pf_s.as_ref())?;
    let tensile = strength_resumable(relaxed, &model, &tests.tensile, par, pf_t.as_ref())?;
    for (r, what) in [(&shear, "shear"), (&tensile, "tensile")] {
        if !(r.strength.is_finite() && r.strength > 0.0) {
            return Err(DemError::InvalidConfig(format!(
                "sliding strength: the {what} test found no positive peak ({}); a longer max_strain?",
                r.strength
            )));
        }
    }
    for f in [pf_s, pf_t].iter().flatten() {
        crate::io::progress::remove(&f.path)?;
    }
    let s = &tests.shear;
    let how = format!(
        "peak sigma_xy of the patch-test shear (paper 000 Fig. 4c) on the run's relaxed box ({} \
         particles): walls of {} interaction ranges normal to y, top wall moved along x at constant \
         separation, strain rate {:e} per step, dt = {} dt_c, damping {} c_c; peak at shear strain {:.3}",
        shear.particles,
        s.walls.thickness,
        s.strain_rate,
        s.time_step_fraction,
        s.damping,
        shear.strain_at_peak
    );
    Ok(MaterialStrength {
        tau_m: shear.strength,
        sigma_t: tensile.strength,
        sigma_m: cfg.material.strength,
        young_modulus: cfg.young_modulus,
        particles: shear.particles,
        shear: peak_of(StrengthMode::Shear, &shear),
        tensile: peak_of(StrengthMode::Tensile, &tensile),
        how,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_tests_are_the_patch_tests_stopped_past_the_peak() {
        let t = StrengthTests::default();
        assert_eq!(t.shear.mode, StrengthMode::Shear);
        assert_eq!(t.tensile.mode, StrengthMode::Tensile);
        assert_eq!(t.shear.strain_rate, 1e-5);
        assert_eq!(t.tensile.post_peak_strain, 0.05);
    }
}
