//! Recipe-level samples (issue 16): a card is calibrated on the material's *discretisation recipe*
//! (sample kind, d0, size distribution, L, W, relaxation), not on one sample. Every evaluation relaxes
//! k samples of the recipe (one per seed) with the trial parameters, so the packing follows the
//! parameters as it will in any scenario that relaxes a new sample with the card; the tests' mean is the
//! response, the spread across the seeds its noise.
//!
//! Relaxed samples are cached by their inputs (recipe with its seed, the pair model as the relaxation
//! sees it, relaxation settings): a repeated point, a resumed run, and the trial points that differ
//! only in k_T or F_mT (the relaxation has no tangential force, `dem/tests/sample_amorphous.rs`
//! checks that those multipliers leave the sample bit-identical) reuse the sample. A relaxation that
//! fails under a trial model (the collapse `RelaxConfig::fail_stress` detects, no convergence within
//! the step budget, a box shrinking below one interaction range) is cached as a failure with its
//! reason, so the point is rejected again at no cost. An interrupt (Ctrl-C) is never cached.

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use dem::jobs::JobCache;
use dem::material::{Interactions, PairModel, ParamScale};
use dem::sample::{make_sample, relax as relax_sample, RelaxConfig, Sample, SampleSpec};
use dem::scenario::patch::CompactionConfig;
use dem::{DemError, Parallelism};
use serde::{Deserialize, Serialize};

use crate::problem::EvalFailure;

/// `[recipe]`: which samples of the recipe every evaluation relaxes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields, default)]
pub struct RecipeSettings {
    /// Seeds of the samples every evaluation relaxes with the trial parameters; default the recipe's
    /// seed and the next two (k = 3: the smallest k whose spread says something, at three times the
    /// cost of one sample). Ignored for an HCP lattice or a saved file (one sample).
    pub seeds: Option<Vec<u64>>,
}

/// One sample the card is verified on: a seed of the recipe, optionally larger.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Variant {
    pub seed: u64,
    /// Multiplier on the recipe's in-plane edge L; default 1.
    #[serde(default = "one")]
    pub length: f64,
    /// Multiplier on the recipe's thickness W; default 1.
    #[serde(default = "one")]
    pub width: f64,
}

fn one() -> f64 {
    1.0
}

/// `[verification]`: the fresh samples the calibrated card is measured on before it is written.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct VerifySettings {
    /// Default: seeds 101 and 102 at the recipe's size and seed 103 twice as wide (W x 2), three
    /// samples no evaluation of the calibration saw (issue 16's acceptance).
    pub samples: Vec<Variant>,
    /// Tensile test run this much strain past the peak, so that the sample separates and the surface
    /// energy (half the fracture energy) is measured; default 0.3 (the paper's tensile setting).
    pub post_peak_strain: f64,
    /// Skip the verification (the card then has no `[verification]` table); default false.
    pub skip: bool,
    /// The shear-under-load test every verification sample runs; default the test's defaults
    /// (0.01 E, shear strain 1, limit 5 %), whatever `[tests.compaction]` the calibration used. Not
    /// written when default, so that the calibrations' fingerprints (which serialise the default
    /// verification) stay those of the runs made before the test existed, and they resume.
    #[serde(skip_serializing_if = "is_default_compaction")]
    pub compaction: CompactionConfig,
}

fn is_default_compaction(c: &CompactionConfig) -> bool {
    *c == CompactionConfig::default()
}

impl Default for VerifySettings {
    fn default() -> Self {
        let v = |seed, width| Variant {
            seed,
            length: 1.0,
            width,
        };
        VerifySettings {
            samples: vec![v(101, 1.0), v(102, 1.0), v(103, 2.0)],
            post_peak_strain: 0.3,
            skip: false,
            compaction: CompactionConfig::default(),
        }
    }
}

/// The distinct samples of `recipe` for `seeds`: one per seed for an amorphous recipe, one in all for
/// an HCP lattice or a saved file (their seeds change nothing).
pub fn recipe_samples(recipe: &SampleSpec, seeds: &[u64]) -> Vec<SampleSpec> {
    let mut out: Vec<SampleSpec> = Vec::new();
    for &s in seeds {
        let spec = recipe.with_seed(s);
        if !out.contains(&spec) {
            out.push(spec);
        }
    }
    if out.is_empty() {
        out.push(recipe.clone());
    }
    out
}

/// Relaxed samples (and failed relaxations) by their inputs, in memory and under `dir`.
#[derive(Debug, Default)]
pub struct SampleCache {
    dir: Option<PathBuf>,
    memory: Mutex<HashMap<String, Result<Arc<Sample>, EvalFailure>>>,
}

#[derive(Serialize, Deserialize)]
struct Failed {
    failure: EvalFailure,
}

impl SampleCache {
    /// A cache kept in memory and, with `dir`, on disk (`<dir>/<key>.json`, or `<key>.failed.json`).
    pub fn new(dir: Option<PathBuf>) -> Self {
        SampleCache {
            dir,
            memory: Mutex::new(HashMap::new()),
        }
    }

    /// The key of a relaxation: the recipe, the model as the relaxation uses it (the tangential
    /// multipliers and sigma_T set to fixed values, since they cannot change the sample) and the
    /// relaxation settings, hashed like every job of `dem::jobs`.
    pub fn key(spec: &SampleSpec, model: &PairModel, relax: &RelaxConfig) -> String {
        let mut m = model.clone();
        m.scale.k_t = 1.0;
        m.scale.f_mt = 1.0;
        m.material.shear_strength = 0.0;
        m.interactions = Interactions::FULL;
        // Serialising plain data cannot fail; a key that could not be made would only cost a cache miss.
        JobCache::key(&(spec, &m, relax)).map_or_else(|e| format!("unkeyed {e}"), |k| k.0)
    }

    /// The sample of `spec` relaxed with `model`: from the cache, or made (sequentially: the
    /// samples of one evaluation are made side by side) and stored. `Err` is a failure of the
    /// relaxation under this model, with its reason; an interrupt is returned as a failure but not
    /// stored (the executor notices the interrupt and stops).
    pub fn get(
        &self,
        spec: &SampleSpec,
        model: &PairModel,
        relax: &RelaxConfig,
    ) -> Result<Arc<Sample>, EvalFailure> {
        // Relaxation by continuation (`[relax] continuation`) changes nothing for the closed-form
        // model itself: one key for both, so that its sample is made once and shared as every
        // trial's starting packing.
        let relax = &RelaxConfig {
            continuation: relax.continuation && model.scale != ParamScale::default(),
            ..*relax
        };
        let key = Self::key(spec, model, relax);
        if let Some(hit) = self.lock().get(&key) {
            return hit.clone();
        }
        if let Some(hit) = self.load(&key) {
            // A sample stored before `fail_coordination` existed may be a collapse it now refuses.
            let hit =
                match hit {
                    Ok(s) => match s.relaxation.as_ref().and_then(|r| {
                        relax.collapsed(r.coordination.interacting, r.volume_fraction)
                    }) {
                        Some(why) => Err(EvalFailure(format!("{}: {why}", describe(spec)))),
                        None => Ok(s),
                    },
                    failed => failed,
                };
            self.lock().insert(key, hit.clone());
            return hit;
        }
        let made = if relax.continuation {
            // `make_sample` would relax the closed-form sample again for every trial: take it from
            // the cache, then phase 2 with the trial model (the same bits, `dem`'s test).
            let mut base = model.clone();
            base.scale = ParamScale::default();
            let start = self.get(spec, &base, relax)?;
            relax_sample(&start, model, &relax.phase2_only(), Parallelism::Sequential)
        } else {
            make_sample(spec, model, relax, Parallelism::Sequential)
        };
        let outcome = match made {
            Err(DemError::Interrupted { step }) => {
                return Err(EvalFailure(format!("interrupted at step {step}")))
            }
            Err(e) => Err(EvalFailure(format!("{}: {e}", describe(spec)))),
            Ok(s) => match &s.relaxation {
                Some(r) if !r.converged => Err(EvalFailure(format!(
                    "{}: relaxation did not reach {:.0e} E in {} phase-2 steps (|sigma| {:.1e} E)",
                    describe(spec),
                    relax.stress_tolerance,
                    r.phase2_steps,
                    r.max_stress_over_e
                ))),
                _ => Ok(Arc::new(s)),
            },
        };
        self.store(&key, &outcome);
        self.lock().insert(key, outcome.clone());
        outcome
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, HashMap<String, Result<Arc<Sample>, EvalFailure>>> {
        // A poisoned lock only means another thread panicked while inserting; the map is still valid.
        self.memory.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn load(&self, key: &str) -> Option<Result<Arc<Sample>, EvalFailure>> {
        let dir = self.dir.as_ref()?;
        let ok = dir.join(format!("{key}.json"));
        if ok.exists() {
            return Sample::load(&ok).ok().map(|s| Ok(Arc::new(s)));
        }
        let bytes = std::fs::read(dir.join(format!("{key}.failed.json"))).ok()?;
        serde_json::from_slice::<Failed>(&bytes)
            .ok()
            .map(|f| Err(f.failure))
    }

    fn store(&self, key: &str, outcome: &Result<Arc<Sample>, EvalFailure>) {
        let Some(dir) = &self.dir else { return };
        // A cache that cannot be written costs time on a rerun, never correctness.
        let written = match outcome {
            Ok(s) => s.save(&dir.join(format!("{key}.json"))),
            Err(f) => serde_json::to_vec(&Failed { failure: f.clone() })
                .map_err(|e| DemError::InvalidConfig(e.to_string()))
                .and_then(|b| {
                    dem::io::checkpoint::write_atomic(&dir.join(format!("{key}.failed.json")), &b)
                }),
        };
        if let Err(e) = written {
            tracing::warn!(%e, "relaxed sample not cached");
        }
    }
}

/// "seed 3" / "HCP lattice" / "file s.json": which sample a failure concerns.
pub fn describe(spec: &SampleSpec) -> String {
    match spec {
        SampleSpec::Amorphous {
            seed,
            l_over_d0,
            w_over_d0,
            ..
        } => format!("sample seed {seed} ({l_over_d0} x {l_over_d0} x {w_over_d0} d0)"),
        SampleSpec::Hcp { .. } => "HCP lattice".into(),
        SampleSpec::HexMonolayer { seed, .. } => format!("hex monolayer seed {seed}"),
        SampleSpec::File { path } => format!("sample file {}", path.display()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use dem::material::Material;

    fn amorphous() -> SampleSpec {
        serde_json::from_str(
            r#"{"kind": "amorphous", "d0_over_dc": 0.6, "l_over_d0": 10.0, "w_over_d0": 3.0}"#,
        )
        .unwrap()
    }

    #[test]
    fn seeds_give_one_sample_each_and_lattices_one_in_all() {
        assert_eq!(recipe_samples(&amorphous(), &[1, 2, 2, 5]).len(), 3);
        let hcp = SampleSpec::Hcp {
            d0_over_dc: 0.6,
            l_over_d0: 8.0,
            w_over_d0: 3.0,
        };
        assert_eq!(recipe_samples(&hcp, &[1, 2, 3]), vec![hcp.clone()]);
        assert_eq!(recipe_samples(&hcp, &[]), vec![hcp]);
    }

    #[test]
    fn keys_ignore_what_the_relaxation_does_not_use() {
        let model = PairModel::cohesive(Material::table4(0.15));
        let relax = RelaxConfig::default();
        let k = SampleCache::key(&amorphous(), &model, &relax);
        let mut tangential = model.clone();
        tangential.scale.k_t = 2.0;
        tangential.scale.f_mt = 0.3;
        assert_eq!(k, SampleCache::key(&amorphous(), &tangential, &relax));
        let mut normal = model.clone();
        normal.scale.delta_e = 1.1;
        assert_ne!(k, SampleCache::key(&amorphous(), &normal, &relax));
        assert_ne!(
            k,
            SampleCache::key(&amorphous().with_seed(2), &model, &relax)
        );
    }
}
