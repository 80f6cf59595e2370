//! The card's `[verification]` table (issue 16): the calibrated model measured on fresh samples of its
//! recipe that no evaluation of the calibration saw (other seeds, a larger sample), with every test:
//! E and nu (elastic), sigma_N and the surface energy (tensile test run to separation; the surface
//! energy is half the fracture energy, `dem::scenario::patch::strength`), sigma_T (shear). For each
//! property: the target, the mean over the samples, the spread (the largest deviation of one sample
//! from the target, relative) and every sample's value; and d* of paper 000 eq (22) from the measured
//! means, d* = 32 gamma G / sigma_T^2 with G = E / (2 (1 + nu)), beside the same formula on the targets.
//!
//! Every sample is also sheared under normal load (`dem::scenario::patch::compaction`): a packing
//! that compacts when it flows is reported (`compaction`), and the scenarios refuse such a card.
//!
//! Each sample's result is a job of `dem::jobs` keyed by its inputs (recipe and seed, model,
//! relaxation and test settings) under `DIR/verify/`, so a rerun costs nothing. A sample whose
//! relaxation or test fails under the card is kept in the table with the reason: the card did not
//! hold on it.

use dem::jobs::JobCache;
use dem::material::{Material, PairModel};
use dem::sample::{RelaxConfig, SampleSpec};
use dem::scenario::patch::CompactionResult;
use serde::{Deserialize, Serialize};
use wear::scales::critical_junction_size;

use crate::error::{CalibrateError, Result};
use crate::patch_problem::{measure_on, target_value, Properties, Target, TestSettings};
use crate::problem::EvalFailure;
use crate::recipe::{describe, SampleCache, VerifySettings};

/// One property over the verification samples.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Check {
    /// Target (strengths from eq 20 at the recipe's d0; the surface energy's is gamma).
    pub target: f64,
    /// Mean over the samples that gave a value.
    pub mean: f64,
    /// Largest |value - target| / |target| over the samples.
    pub spread: f64,
    /// Each sample's value, in the order of `samples`.
    pub values: Vec<f64>,
}

impl Check {
    fn of(target: f64, values: Vec<f64>) -> Option<Self> {
        if values.is_empty() {
            return None;
        }
        let mean = values.iter().sum::<f64>() / values.len() as f64;
        let spread = values
            .iter()
            .map(|v| (v - target).abs() / target.abs())
            .fold(0.0, f64::max);
        Some(Check {
            target,
            mean,
            spread,
            values,
        })
    }

    /// (mean - target) / |target|.
    pub fn mean_error(&self) -> f64 {
        (self.mean - self.target) / self.target.abs()
    }
}

/// One verification sample.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct VerifiedSample {
    /// Its recipe (the calibration's recipe with this seed and size).
    pub spec: SampleSpec,
    /// Particles and relaxed volume fraction (0 when the relaxation failed).
    pub particles: usize,
    pub volume_fraction: f64,
    /// Pairs of the relaxed sample overlapping by more than half the smaller radius, per particle: an
    /// interpenetrated packing is metastable and can compact under shear (closed-form silica 0-0.025;
    /// the calibrated silica cards whose junctions collapsed, 0.06-0.35: dem::sample::stats). None
    /// where not recorded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub deep_overlaps: Option<f64>,
    /// Whether the tensile test separated the sample (the surface energy is then that of two clean
    /// surfaces; otherwise a lower bound).
    pub separated: bool,
    /// Why the sample gave no values (relaxation or test failure under the card); none when it did.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub failure: Option<String>,
    /// Largest compaction of the shear-under-load test (fraction of the sample height); none where
    /// not measured (a failed sample, a card verified before the test existed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub compaction: Option<f64>,
}

/// The shear-under-load test over the verification samples: does the card's packing hold its volume
/// when it flows (`dem::scenario::patch::compaction`)?
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CompactionCheck {
    /// Normal pressure as a fraction of E.
    pub pressure: f64,
    /// Shear strain the test runs to.
    pub strain: f64,
    /// Compaction (fraction of the sample height) above which a sample counts as collapsing.
    pub limit: f64,
    /// Each measured sample's largest compaction, in the order of `samples`.
    pub values: Vec<f64>,
    /// Samples past the limit.
    pub collapsed: usize,
}

impl CompactionCheck {
    /// Whether every measured sample held (none past the limit).
    pub fn holds(&self) -> bool {
        self.collapsed == 0
    }
    /// The largest compaction over the measured samples (NaN when none was measured).
    pub fn largest(&self) -> f64 {
        self.values.iter().cloned().fold(f64::NAN, f64::max)
    }
    /// One line for summaries and scenario logs.
    pub fn describe(&self) -> String {
        let largest = self.largest();
        format!(
            "shear under {} E to strain {}: largest compaction {:.1} % (limit {:.0} %), {} of {} samples \
             collapsing{}",
            self.pressure,
            self.strain,
            100.0 * largest,
            100.0 * self.limit,
            self.collapsed,
            self.values.len(),
            if self.holds() {
                ""
            } else {
                ": the packing is pulled into itself when it flows, a junction with this card collapses"
            }
        )
    }
}

/// The `[verification]` table of a card.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Verification {
    /// Seeds of the verification samples (none for a lattice or a file).
    pub seeds: Vec<u64>,
    /// d* of eq (22) from the measured means (E, nu, sigma_T, surface energy), in the card's
    /// length unit (nm for `units = "nano"`).
    pub dstar: f64,
    /// d* of eq (22) from the calibration's targets (gamma, E, nu and sigma_T of eq 20 at d0).
    pub dstar_target: f64,
    /// The calibration's recipe (its seed is the first calibration sample's).
    pub recipe: SampleSpec,
    pub samples: Vec<VerifiedSample>,
    pub young_modulus: Check,
    pub poisson_ratio: Check,
    pub tensile_strength: Check,
    pub shear_strength: Check,
    pub surface_energy: Check,
    /// The shear-under-load test; none for cards verified before it existed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub compaction: Option<CompactionCheck>,
}

impl Verification {
    /// The check of `t`.
    pub fn get(&self, t: Target) -> &Check {
        match t {
            Target::YoungModulus => &self.young_modulus,
            Target::PoissonRatio => &self.poisson_ratio,
            Target::TensileStrength => &self.tensile_strength,
            Target::ShearStrength => &self.shear_strength,
            Target::SurfaceEnergy => &self.surface_energy,
        }
    }

    /// The means, as properties.
    pub fn means(&self) -> Properties {
        Properties {
            young_modulus: Some(self.young_modulus.mean),
            poisson_ratio: Some(self.poisson_ratio.mean),
            tensile_strength: Some(self.tensile_strength.mean),
            shear_strength: Some(self.shear_strength.mean),
            surface_energy: Some(self.surface_energy.mean),
        }
    }

    /// The target of each check (strengths from eq 20 at the recipe's d0, gamma for the surface
    /// energy), whether or not the calibration fitted it.
    pub fn targets(&self) -> Properties {
        Properties {
            young_modulus: Some(self.young_modulus.target),
            poisson_ratio: Some(self.poisson_ratio.target),
            tensile_strength: Some(self.tensile_strength.target),
            shear_strength: Some(self.shear_strength.target),
            surface_energy: Some(self.surface_energy.target),
        }
    }

    /// Samples that failed under the card.
    pub fn failures(&self) -> usize {
        self.samples.iter().filter(|s| s.failure.is_some()).count()
    }
}

/// What one verification job stores.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct SampleResult {
    particles: usize,
    volume_fraction: f64,
    #[serde(default)]
    deep_overlaps: Option<f64>,
    separated: bool,
    outcome: std::result::Result<Properties, EvalFailure>,
    #[serde(default)]
    compaction: Option<CompactionResult>,
}

/// Everything a verification needs besides the model.
#[derive(Debug, Clone, Copy)]
pub struct VerifyInputs<'a> {
    pub recipe: &'a SampleSpec,
    pub relax: &'a RelaxConfig,
    pub tests: &'a TestSettings,
    pub target: &'a Material,
    pub d0: f64,
    pub settings: &'a VerifySettings,
}

/// Measures `model` on the verification samples of `inp` (side by side on the current rayon pool),
/// with results cached under `dir` when given.
pub fn verify(
    model: &PairModel,
    inp: VerifyInputs<'_>,
    cache: &SampleCache,
    dir: Option<&std::path::Path>,
) -> Result<Verification> {
    use rayon::prelude::*;
    let mut specs: Vec<SampleSpec> = Vec::new();
    for v in &inp.settings.samples {
        let s = inp.recipe.with_seed(v.seed).resized(v.length, v.width)?;
        if !specs.contains(&s) {
            specs.push(s);
        }
    }
    if specs.is_empty() {
        return Err(CalibrateError::InvalidConfig(
            "[verification] needs at least one sample (or skip = true)".into(),
        ));
    }
    let mut tests = *inp.tests;
    tests.tensile.post_peak_strain = inp.settings.post_peak_strain;
    // Always sheared under load: the check a scenario needs of a card.
    let compaction_cfg = inp.settings.compaction;
    tests.compaction = Some(compaction_cfg);
    let jobs = dir.map(JobCache::new);
    let one = |spec: &SampleSpec| -> Result<SampleResult> {
        let key = JobCache::key(&(spec, model, inp.relax, &tests))?;
        if let Some(jobs) = &jobs {
            if let Some(r) = jobs.get::<SampleResult>(&key)? {
                return Ok(r);
            }
        }
        let r = match cache.get(spec, model, inp.relax) {
            Err(f) => SampleResult {
                particles: 0,
                volume_fraction: 0.0,
                deep_overlaps: None,
                separated: false,
                outcome: Err(f),
                compaction: None,
            },
            Ok(sample) => {
                let m = measure_on(&sample, model, &Target::ALL, &tests);
                SampleResult {
                    particles: sample.particles.len(),
                    volume_fraction: sample.volume_fraction(),
                    deep_overlaps: sample
                        .relaxation
                        .as_ref()
                        .and_then(|r| r.coordination.deep_overlaps),
                    separated: m.as_ref().ok().and_then(|m| m.separated).unwrap_or(false),
                    compaction: m.as_ref().ok().and_then(|m| m.compaction.clone()),
                    outcome: m.map(|m| m.properties),
                }
            }
        };
        if dem::interrupt::requested() {
            return Err(CalibrateError::Interrupted);
        }
        if let Some(jobs) = &jobs {
            jobs.put(&key, &(spec, model, inp.relax, &tests), &r)?;
        }
        Ok(r)
    };
    let results: Vec<SampleResult> = specs
        .par_iter()
        .with_max_len(1)
        .map(one)
        .collect::<Vec<_>>()
        .into_iter()
        .collect::<Result<_>>()?;
    let samples: Vec<VerifiedSample> = specs
        .iter()
        .zip(&results)
        .map(|(spec, r)| VerifiedSample {
            spec: spec.clone(),
            particles: r.particles,
            volume_fraction: r.volume_fraction,
            deep_overlaps: r.deep_overlaps,
            separated: r.separated,
            failure: r
                .outcome
                .as_ref()
                .err()
                .map(|EvalFailure(e)| format!("{}: {e}", describe(spec))),
            compaction: r.compaction.as_ref().map(|c| c.largest_compaction),
        })
        .collect();
    let props: Vec<&Properties> = results
        .iter()
        .filter_map(|r| r.outcome.as_ref().ok())
        .collect();
    let check = |t: Target| -> Result<Check> {
        let values: Vec<f64> = props.iter().filter_map(|p| p.get(t)).collect();
        Check::of(target_value(inp.target, inp.d0, t), values).ok_or_else(|| {
            CalibrateError::StartFailed(format!(
                "verification: no sample gave {} ({})",
                t.name(),
                samples
                    .iter()
                    .filter_map(|s| s.failure.clone())
                    .collect::<Vec<_>>()
                    .join("; ")
            ))
        })
    };
    let (e, nu, sn, st, g) = (
        check(Target::YoungModulus)?,
        check(Target::PoissonRatio)?,
        check(Target::TensileStrength)?,
        check(Target::ShearStrength)?,
        check(Target::SurfaceEnergy)?,
    );
    let values: Vec<f64> = samples.iter().filter_map(|s| s.compaction).collect();
    let compaction = CompactionCheck {
        pressure: compaction_cfg.pressure,
        strain: compaction_cfg.strain,
        limit: compaction_cfg.max_compaction,
        collapsed: results
            .iter()
            .filter(|r| r.compaction.as_ref().is_some_and(|c| c.collapsed))
            .count(),
        values,
    };
    let dstar = critical_junction_size(g.mean, e.mean, nu.mean, st.mean);
    let dstar_target = critical_junction_size(g.target, e.target, nu.target, st.target);
    Ok(Verification {
        seeds: specs.iter().filter_map(SampleSpec::seed).collect(),
        dstar,
        dstar_target,
        recipe: inp.recipe.clone(),
        samples,
        young_modulus: e,
        poisson_ratio: nu,
        tensile_strength: sn,
        shear_strength: st,
        surface_energy: g,
        compaction: Some(compaction),
    })
}
