//! Config files of impacts and scratches, with optional sweeps, as lists of jobs (DESIGN.md section 7,
//! "Runs as jobs"): each impact, and each load of a scratch, is a pure function of its inputs, run
//! through [`crate::jobs::run_jobs`] and cached under their hash. A rerun skips finished jobs; the
//! same list runs side by side on a machine's cores, as a Slurm array or under mpirun.
//!
//! A sweep is the Cartesian product of its lists (an empty list keeps the base value): impacts over
//! `mu_a`, `hardness`, `speed`, `angle_deg` and `aims` landing points (outermost first), scratches
//! over `mu_a` and `hardness`, each then over its loads.
//!
//! Decision (landing points): a 3 mm projectile (Figs. 5-7) meets three to six surface spheres, and
//! which ones depends on where it lands in the cell of the grid: one impact onto a sphere and one onto
//! a hollow between three differ by a factor of two in wear volume. The paper does not say where its
//! projectiles landed. A sweep point is the mean over `aims` landing points spread over the cell by
//! the R2 low-discrepancy sequence (the first on a sphere, the base `aim_offset`), with the spread
//! reported beside it, as an erosion experiment averages over many particles.

use serde::{Deserialize, Serialize};

use super::impact::{run_impact, ImpactConfig, ImpactResult, RunSettings, Shot};
use super::model::{PlasticModel, Projectile};
use super::scratch::{run_scratch_load, Indent, ScratchConfig, ScratchResult, ScratchRun, Slide};
use super::surface::SurfaceSpec;
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
    /// Landing points per sweep point, spread over the grid's cell; default (0) one, the base aim.
    pub aims: usize,
}

/// Landing point `k` of the R2 sequence in the cell of `spec`'s grid (m, from the base aim): k = 0 is
/// the base aim itself.
pub fn aim_in_cell(spec: &SurfaceSpec, k: usize) -> [f64; 2] {
    // R2 (Roberts 2018): the plastic number's powers give the most even 2D sequence.
    const A1: f64 = 0.754_877_666_246_692_7;
    const A2: f64 = 0.569_840_290_998_053_2;
    let (u, v) = ((k as f64 * A1).fract(), (k as f64 * A2).fract());
    let a_s = spec.length * spec.width / spec.spheres as f64;
    let s = (a_s / 0.75f64.sqrt()).sqrt();
    [u * s + 0.5 * v * s, v * s * 0.75f64.sqrt()]
}

/// The mean of an impact sweep point over its landing points (SI).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ImpactPoint {
    pub speed: f64,
    pub angle_deg: f64,
    pub hardness: f64,
    pub mu_a: f64,
    /// Landing points averaged.
    pub aims: usize,
    /// Means and standard deviations over the landing points.
    pub wear_volume: f64,
    pub wear_volume_sd: f64,
    pub wear_volume_normal: f64,
    pub wear_volume_scratch: f64,
    pub reference_wear_volume: f64,
    pub cor: f64,
    pub cor_sd: f64,
    pub deviation_deg: f64,
    pub deviation_sd: f64,
    pub crater_depth: f64,
    /// The largest energy-balance error of the runs.
    pub max_balance_error: f64,
}

impl ImpactPoint {
    /// The mean of the impacts of one sweep point.
    pub fn of(runs: &[ImpactResult]) -> ImpactPoint {
        let n = runs.len().max(1) as f64;
        let mean = |f: &dyn Fn(&ImpactResult) -> f64| runs.iter().map(f).sum::<f64>() / n;
        let sd = |f: &dyn Fn(&ImpactResult) -> f64| {
            let m = mean(f);
            (runs.iter().map(|r| (f(r) - m).powi(2)).sum::<f64>() / n).sqrt()
        };
        let r0 = &runs[0];
        ImpactPoint {
            speed: r0.speed,
            angle_deg: r0.angle_deg,
            hardness: r0.hardness,
            mu_a: r0.mu_a,
            aims: runs.len(),
            wear_volume: mean(&|r| r.wear_volume),
            wear_volume_sd: sd(&|r| r.wear_volume),
            wear_volume_normal: mean(&|r| r.wear_volume_normal),
            wear_volume_scratch: mean(&|r| r.wear_volume_scratch),
            reference_wear_volume: r0.reference_wear_volume,
            cor: mean(&|r| r.cor),
            cor_sd: sd(&|r| r.cor),
            deviation_deg: mean(&|r| r.deviation_deg),
            deviation_sd: sd(&|r| r.deviation_deg),
            crater_depth: mean(&|r| r.crater_depth),
            max_balance_error: runs
                .iter()
                .map(|r| r.energy.max_balance_error)
                .fold(0.0, f64::max),
        }
    }
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

    /// Landing points per sweep point (at least one).
    pub fn aims(&self) -> usize {
        self.sweep.as_ref().map_or(1, |s| s.aims.max(1))
    }

    /// Every impact of the file (one without a sweep), each validated, landing points innermost.
    pub fn jobs(&self) -> Result<Vec<ImpactConfig>> {
        let base = self.base();
        let sw = self.sweep.clone().unwrap_or_default();
        let mut jobs = Vec::new();
        for &mu_a in &or_base(&sw.mu_a, base.model.mu_a) {
            for &h in &or_base(&sw.hardness, base.model.hardness) {
                for &v in &or_base(&sw.speed, base.impact.speed) {
                    for &a in &or_base(&sw.angle_deg, base.impact.angle_deg) {
                        for k in 0..self.aims() {
                            let mut c = base.clone();
                            c.model.mu_a = mu_a;
                            c.model.hardness = h;
                            c.impact.speed = v;
                            c.impact.angle_deg = a;
                            let d = aim_in_cell(&c.model.surface, k);
                            c.impact.aim_offset[0] += d[0];
                            c.impact.aim_offset[1] += d[1];
                            c.validate().map_err(|e| with_job(e, &c.label()))?;
                            jobs.push(c);
                        }
                    }
                }
            }
        }
        Ok(jobs)
    }

    /// The sweep points of the results of [`ImpactFile::jobs`] (in that order): means over the
    /// landing points.
    pub fn points(&self, runs: &[ImpactResult]) -> Vec<ImpactPoint> {
        runs.chunks(self.aims()).map(ImpactPoint::of).collect()
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
/// `done` hears of each job this process finishes (for a progress line).
pub fn run_impacts(
    jobs: &[ImpactConfig],
    cache: &JobCache,
    how: &RunJobs,
    done: &(dyn Fn(&ImpactConfig, &ImpactResult) + Sync),
) -> Result<Collected<ImpactResult>> {
    run_jobs(cache, jobs, how, |cfg, _dir| {
        let r = run_impact(cfg)?;
        done(cfg, &r);
        Ok(r)
    })
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
/// `done` hears of each job this process finishes.
pub fn run_scratches(
    tests: &[ScratchConfig],
    cache: &JobCache,
    how: &RunJobs,
    done: &(dyn Fn(&ScratchConfig, &ScratchRun) + Sync),
) -> Result<Option<Vec<ScratchResult>>> {
    let jobs = scratch_jobs(tests);
    let runs = run_jobs(cache, &jobs, how, |cfg, dir| {
        let file = ProgressFile::new(dir.join("progress.json"));
        let r = run_scratch_load(cfg, cfg.indent.loads[0], Some(&file))?;
        done(cfg, &r);
        Ok(r)
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
    fn landing_points_fill_the_cell_and_start_on_a_sphere() {
        let spec = SurfaceSpec::default();
        assert_eq!(aim_in_cell(&spec, 0), [0.0, 0.0]);
        let s = (spec.length * spec.width / spec.spheres as f64 / 0.75f64.sqrt()).sqrt();
        let dy = s * 0.75f64.sqrt();
        // 64 points: every quarter of the cell (in its own coordinates) holds 12 to 20 of them.
        let mut quarters = [0usize; 4];
        for k in 0..64 {
            let [x, y] = aim_in_cell(&spec, k);
            let v = y / dy;
            let u = (x - 0.5 * v * s) / s;
            assert!((0.0..1.0).contains(&u) && (0.0..1.0).contains(&v));
            quarters[usize::from(u >= 0.5) + 2 * usize::from(v >= 0.5)] += 1;
        }
        assert!(
            quarters.iter().all(|&q| (12..=20).contains(&q)),
            "{quarters:?}"
        );
        let f: ImpactFile = toml::from_str(&format!("{FILE}aims = 3\n")).unwrap();
        let jobs = f.jobs().unwrap();
        assert_eq!(jobs.len(), 12);
        assert_eq!(jobs[0].impact.aim_offset, [0.0, 0.0]);
        assert_eq!(jobs[1].impact.aim_offset, aim_in_cell(&spec, 1));
        assert_eq!(jobs[3].impact.aim_offset, [0.0, 0.0]);
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
        let f: ScratchFile =
            toml::from_str("[indent]\nloads = [1000.0, 2000.0]\n[sweep]\nmu_a = [0.25, 0.4]\n")
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
