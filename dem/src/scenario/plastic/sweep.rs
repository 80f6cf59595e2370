//! Config files of impacts and scratches, with optional sweeps, as lists of jobs (DESIGN.md section 7,
//! "Runs as jobs"): each impact, and each load of a scratch, is a pure function of its inputs, run
//! through [`crate::jobs::run_jobs`] and cached under their hash. A rerun skips finished jobs; the
//! same list runs side by side on a machine's cores, as a Slurm array or under mpirun.
//!
//! A sweep is the Cartesian product of its lists (an empty list keeps the base value): impacts over
//! `mu_a`, `hardness`, `speed` and `angle_deg` (outermost first), scratches over `mu_a` and `hardness`,
//! each then over its loads.

use serde::{Deserialize, Serialize};

use super::impact::{run_impact, ImpactConfig, ImpactResult, RunSettings, Shot};
use super::model::{PlasticModel, Projectile};
use super::scratch::{run_scratch_load, Indent, ScratchConfig, ScratchResult, ScratchRun, Slide};
use crate::error::{DemError, Result};
use crate::io::progress::ProgressFile;
use crate::jobs::{run_jobs, Collected, JobCache, RunJobs};

/// What an impact sweep varies.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ImpactSweep {
    /// Impact angles (degrees).
    pub angle_deg: Vec<f64>,
    /// Impact speeds (m/s).
    pub speed: Vec<f64>,
    /// Hardness H (Pa).
    pub hardness: Vec<f64>,
    /// mu_a.
    pub mu_a: Vec<f64>,
}

/// An impact config file: [`ImpactConfig`]'s sections and an optional `[sweep]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ImpactFile {
    #[serde(default)]
    pub model: PlasticModel,
    pub projectile: Projectile,
    pub impact: Shot,
    #[serde(default)]
    pub run: RunSettings,
    #[serde(default)]
    pub sweep: Option<ImpactSweep>,
}

fn or_base(list: &[f64], base: f64) -> Vec<f64> {
    if list.is_empty() {
        vec![base]
    } else {
        list.to_vec()
    }
}

impl ImpactFile {
    /// The impact the file describes without its sweep.
    pub fn base(&self) -> ImpactConfig {
        ImpactConfig {
            model: self.model,
            projectile: self.projectile,
            impact: self.impact,
            run: self.run,
        }
    }

    /// Every impact of the file (one without a sweep), each validated.
    pub fn jobs(&self) -> Result<Vec<ImpactConfig>> {
        let base = self.base();
        let sw = self.sweep.clone().unwrap_or_default();
        let mut jobs = Vec::new();
        for &mu_a in &or_base(&sw.mu_a, base.model.mu_a) {
            for &h in &or_base(&sw.hardness, base.model.hardness) {
                for &v in &or_base(&sw.speed, base.impact.speed) {
                    for &a in &or_base(&sw.angle_deg, base.impact.angle_deg) {
                        let mut c = base.clone();
                        c.model.mu_a = mu_a;
                        c.model.hardness = h;
                        c.impact.speed = v;
                        c.impact.angle_deg = a;
                        c.validate().map_err(|e| with_job(e, &c.label()))?;
                        jobs.push(c);
                    }
                }
            }
        }
        Ok(jobs)
    }
}

impl ImpactConfig {
    /// A short name of the impact for messages.
    pub fn label(&self) -> String {
        format!(
            "impact V = {} m/s, angle {} deg, H = {} Pa, mu_a = {}",
            self.impact.speed, self.impact.angle_deg, self.model.hardness, self.model.mu_a
        )
    }
}

fn with_job(e: DemError, label: &str) -> DemError {
    match e {
        DemError::InvalidConfig(m) => DemError::InvalidConfig(format!("{label}: {m}")),
        other => other,
    }
}

/// Runs impacts as cached jobs; results in list order (`None`: another shard's, not done yet).
pub fn run_impacts(
    jobs: &[ImpactConfig],
    cache: &JobCache,
    how: &RunJobs,
) -> Result<Collected<ImpactResult>> {
    run_jobs(cache, jobs, how, |cfg, _dir| run_impact(cfg))
}

/// What a scratch sweep varies (each value then runs every load).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ScratchSweep {
    /// mu_a.
    pub mu_a: Vec<f64>,
    /// Hardness H (Pa).
    pub hardness: Vec<f64>,
}

/// A scratch config file: [`ScratchConfig`]'s sections and an optional `[sweep]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScratchFile {
    #[serde(default)]
    pub model: PlasticModel,
    #[serde(default = "default_indenter")]
    pub indenter: Projectile,
    pub indent: Indent,
    #[serde(default)]
    pub slide: Slide,
    #[serde(default = "default_scratch_run")]
    pub run: RunSettings,
    #[serde(default)]
    pub sweep: Option<ScratchSweep>,
}

fn default_indenter() -> Projectile {
    ScratchConfig::default_indenter()
}
fn default_scratch_run() -> RunSettings {
    ScratchConfig::default_run()
}

impl ScratchFile {
    /// The scratch test the file describes without its sweep.
    pub fn base(&self) -> ScratchConfig {
        ScratchConfig {
            model: self.model,
            indenter: self.indenter,
            indent: self.indent.clone(),
            slide: self.slide,
            run: self.run,
        }
    }

    /// The scratch tests of the file, one per sweep value, each validated.
    pub fn tests(&self) -> Result<Vec<ScratchConfig>> {
        let base = self.base();
        let sw = self.sweep.clone().unwrap_or_default();
        let mut tests = Vec::new();
        for &mu_a in &or_base(&sw.mu_a, base.model.mu_a) {
            for &h in &or_base(&sw.hardness, base.model.hardness) {
                let mut c = base.clone();
                c.model.mu_a = mu_a;
                c.model.hardness = h;
                c.validate()
                    .map_err(|e| with_job(e, &format!("scratch H = {h} Pa, mu_a = {mu_a}")))?;
                tests.push(c);
            }
        }
        Ok(tests)
    }
}

/// The jobs of scratch tests: one per test and load, each a config with that single load.
pub fn scratch_jobs(tests: &[ScratchConfig]) -> Vec<ScratchConfig> {
    tests
        .iter()
        .flat_map(|t| {
            t.indent.loads.iter().map(move |&f| {
                let mut c = t.clone();
                c.indent.loads = vec![f];
                c
            })
        })
        .collect()
}

/// Runs scratch tests as cached jobs (one per load, each keeping a progress file in its job
/// directory); one [`ScratchResult`] per test when every job is done (`None` otherwise: another
/// shard's jobs are pending).
pub fn run_scratches(
    tests: &[ScratchConfig],
    cache: &JobCache,
    how: &RunJobs,
) -> Result<Option<Vec<ScratchResult>>> {
    let jobs = scratch_jobs(tests);
    let runs = run_jobs(cache, &jobs, how, |cfg, dir| {
        let file = ProgressFile::new(dir.join("progress.json"));
        run_scratch_load(cfg, cfg.indent.loads[0], Some(&file))
    })?;
    let Some(runs) = runs.into_iter().collect::<Option<Vec<ScratchRun>>>() else {
        return Ok(None);
    };
    let mut runs = runs.into_iter();
    Ok(Some(
        tests
            .iter()
            .map(|t| ScratchResult::collect(runs.by_ref().take(t.indent.loads.len()).collect()))
            .collect(),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    const FILE: &str = r#"
[projectile]
radius = 0.003
density = 2500.0
[impact]
speed = 35.0
angle_deg = 45.0
[sweep]
angle_deg = [30.0, 60.0]
mu_a = [0.15, 0.25]
"#;

    #[test]
    fn a_sweep_is_the_product_of_its_lists() {
        let f: ImpactFile = toml::from_str(FILE).unwrap();
        let jobs = f.jobs().unwrap();
        let got: Vec<(f64, f64, f64)> = jobs
            .iter()
            .map(|j| (j.model.mu_a, j.impact.speed, j.impact.angle_deg))
            .collect();
        assert_eq!(
            got,
            [
                (0.15, 35.0, 30.0),
                (0.15, 35.0, 60.0),
                (0.25, 35.0, 30.0),
                (0.25, 35.0, 60.0)
            ]
        );
        let mut single: ImpactFile = toml::from_str(FILE).unwrap();
        single.sweep = None;
        assert_eq!(single.jobs().unwrap(), vec![single.base()]);
    }

    #[test]
    fn a_bad_sweep_value_names_its_job() {
        let bad = FILE.replace("angle_deg = [30.0, 60.0]", "angle_deg = [30.0, 95.0]");
        let f: ImpactFile = toml::from_str(&bad).unwrap();
        let e = f.jobs().unwrap_err().to_string();
        assert!(e.contains("angle 95") && e.contains("(0, 90]"), "{e}");
        assert!(toml::from_str::<ImpactFile>(&format!("{FILE}speeds = [1.0]\n")).is_err());
    }

    #[test]
    fn scratch_jobs_hold_one_load_each() {
        let f: ScratchFile = toml::from_str(
            "[indent]\nloads = [1000.0, 2000.0]\n[sweep]\nmu_a = [0.25, 0.4]\n",
        )
        .unwrap();
        let tests = f.tests().unwrap();
        assert_eq!(tests.len(), 2);
        let jobs = scratch_jobs(&tests);
        let got: Vec<(f64, Vec<f64>)> = jobs
            .iter()
            .map(|j| (j.model.mu_a, j.indent.loads.clone()))
            .collect();
        assert_eq!(
            got,
            [
                (0.25, vec![1000.0]),
                (0.25, vec![2000.0]),
                (0.4, vec![1000.0]),
                (0.4, vec![2000.0])
            ]
        );
    }
}
