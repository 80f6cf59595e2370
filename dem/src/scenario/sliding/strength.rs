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
//!
//! After its peak the sheared box flows in stick-slip (docs/sliding.md, measured at sigma_m = 0.1 E:
//! sigma_xy saw-tooths between 0.5 and 0.9 of the peak). The steady sliding layer is such sheared,
//! re-bonded material, so beside the peak the shear test gives the **flow stress** tau_flow: the mean
//! sigma_xy over the strains from `flow_start` past the peak to the end of the test ([`flow_stress`]).
//! Decision: the default shear test runs 0.6 strain past the peak and the window starts 0.15 past it
//! (the post-peak drop is over by 0.1 past the peak in the measured curves; 0.45 strain of flow holds
//! several stick-slip cycles, whose means over three sub-windows agreed within 3 %).

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
    /// Simple shear; default the paper-000 test taken on to 0.6 strain past the peak (at most 0.8
    /// strain in all) so that the flow stress after the peak is measured (module docs).
    pub shear: StrengthConfig,
    /// Tension; default the paper-000 test stopped 0.05 strain past the peak (no fracture energy).
    pub tensile: StrengthConfig,
    /// Strain past the shear peak where the flow-stress window starts; default 0.15 (the post-peak
    /// drop is over by 0.1 past the peak, see the module docs).
    pub flow_start: f64,
}

impl Default for StrengthTests {
    fn default() -> Self {
        StrengthTests {
            shear: StrengthConfig {
                post_peak_strain: 0.6,
                max_strain: 0.8,
                ..StrengthConfig::paper(StrengthMode::Shear)
            },
            tensile: StrengthConfig {
                post_peak_strain: 0.05,
                ..StrengthConfig::paper(StrengthMode::Tensile)
            },
            flow_start: 0.15,
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
    /// Flow stress after the shear peak (engine units; module docs) and its strain window; none when
    /// the test stopped before `flow_start` + [`MIN_FLOW_WINDOW`] past the peak.
    #[serde(default)]
    pub tau_flow: Option<FlowStress>,
    /// How it was measured, in one line (written in summaries).
    pub how: String,
}

impl MaterialStrength {
    /// tau_m / sigma_m (paper 004: about 0.22).
    pub fn tau_over_sigma_m(&self) -> f64 {
        self.tau_m / self.sigma_m
    }
}

/// The mean stress of a flowing box over a strain window.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FlowStress {
    pub mean: f64,
    /// Lowest and highest stress in the window (the stick-slip amplitude).
    pub min: f64,
    pub max: f64,
    /// The strain window [from, to] and the records in it.
    pub from: f64,
    pub to: f64,
    pub records: usize,
}

/// Shortest strain window a flow stress is averaged over: shorter holds one or two stick-slip
/// cycles (measured period about 0.05-0.1 strain), whose phase then biases the mean.
pub const MIN_FLOW_WINDOW: f64 = 0.2;

/// Mean stress of `curve` ((strain, stress, ..) records) over the strains from `strain_at_peak +
/// start` to the last record, or none if that window is shorter than [`MIN_FLOW_WINDOW`] or empty.
pub fn flow_stress(
    curve: &[(f64, f64, f64)],
    strain_at_peak: f64,
    start: f64,
) -> Option<FlowStress> {
    let from = strain_at_peak + start;
    let to = curve.last()?.0;
    let span = to - from;
    if span.is_nan() || span < MIN_FLOW_WINDOW {
        return None;
    }
    // Not empty: the last record is at `to`, past `from`.
    let window: Vec<f64> = curve.iter().filter(|p| p.0 >= from).map(|p| p.1).collect();
    Some(FlowStress {
        mean: window.iter().sum::<f64>() / window.len() as f64,
        min: window.iter().copied().fold(f64::INFINITY, f64::min),
        max: window.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        from,
        to,
        records: window.len(),
    })
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
    if !(tests.flow_start >= 0.0 && tests.flow_start.is_finite()) {
        return Err(DemError::InvalidConfig(format!(
            "sliding strength tests: flow_start = {} must be a strain >= 0",
            tests.flow_start
        )));
    }
    let s = &tests.shear;
    let shear_peak = peak_of(StrengthMode::Shear, &shear);
    let tau_flow = flow_stress(
        &shear_peak.curve,
        shear_peak.strain_at_peak,
        tests.flow_start,
    );
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
        shear: shear_peak,
        tensile: peak_of(StrengthMode::Tensile, &tensile),
        tau_flow,
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
        assert_eq!(t.shear.post_peak_strain, 0.6);
        assert!(t.shear.max_strain >= t.shear.post_peak_strain + 0.15);
    }

    /// A synthetic curve: a linear rise to the peak at 0.15, then a saw-tooth of period 0.05 between
    /// 0.5 and 0.9 of the peak (mean 0.7).
    fn sawtooth(end: f64) -> Vec<(f64, f64, f64)> {
        (0..=(end / 1e-3).round() as usize)
            .map(|k| {
                let e = k as f64 * 1e-3;
                let s = if e <= 0.15 {
                    e / 0.15
                } else {
                    let phase = ((e - 0.15) / 0.05).fract();
                    0.9 - 0.4 * phase
                };
                (e, s, 0.0)
            })
            .collect()
    }

    #[test]
    fn the_flow_stress_is_the_mean_of_the_window_past_the_peak() {
        let f = flow_stress(&sawtooth(0.8), 0.15, 0.15).expect("a 0.5 strain window");
        assert!((f.mean - 0.7).abs() < 0.01, "{f:?}");
        assert!(
            (f.min - 0.5).abs() < 0.01 && (f.max - 0.9).abs() < 1e-12,
            "{f:?}"
        );
        assert_eq!((f.from, f.to), (0.3, 0.8));
        assert_eq!(f.records, 501);
        // The rise and the peak are outside the window: a window from the start would be lower.
        let all = flow_stress(&sawtooth(0.8), 0.0, 0.0).unwrap();
        assert!(all.mean < f.mean);
    }

    #[test]
    fn a_test_stopped_soon_after_the_peak_has_no_flow_stress() {
        // 0.05 past the peak (the old default): no window at all.
        assert_eq!(flow_stress(&sawtooth(0.2), 0.15, 0.15), None);
        // A window of 0.19 < MIN_FLOW_WINDOW: too few cycles.
        assert_eq!(flow_stress(&sawtooth(0.49), 0.15, 0.15), None);
        assert!(flow_stress(&sawtooth(0.5), 0.15, 0.15).is_some());
        assert_eq!(flow_stress(&[], 0.0, 0.0), None);
    }
}
