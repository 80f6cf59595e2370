//! The automatic d* search (`cgdem dstar CONFIG --out DIR`): bisection on the junction diameter D
//! between a plastic and a debris outcome, several seeds per D ([`wear::dstar`] decides the probes),
//! every run a cached job ([`dem::jobs`]): a rerun or a wider search reuses the finished runs, an
//! interrupted one resumes (the run in progress from its own progress file), and under `mpirun -np N`
//! or `srun` every rank takes its share of each round.
//!
//! The bracket is reported beside d* of eq 22 computed two ways: from the target properties, and from
//! the properties the DEM material actually has on the search's own recipe (patch tests on the first
//! seed's relaxed box: E, nu, the tensile and shear strengths, and the surface energy as half the
//! fracture energy of the tensile test, which calibration notes found up to twice gamma).
//!
//! Outputs: `DIR/dstar.json` (`bracket` [lower, upper] in the config's length unit, the runs behind
//! it, both d* of eq 22 and the measured properties), `DIR/runs.csv`, `DIR/outcomes.png`, and one
//! folder per run under `DIR/runs/<key>/` with the run's own outputs (verdict, force, snapshot).

use std::path::{Path, PathBuf};

use calibrate::{MaterialSource, ResolvedMaterial, Units};
use dem::io::checkpoint::write_atomic;
use dem::io::progress::{self, ProgressFile};
use dem::jobs::{run_jobs, JobCache, RunJobs};
use dem::material::{ForceLaw, PairModel};
use dem::scenario::junction::JunctionConfig;
use dem::scenario::patch::{
    elastic, strength_resumable, ElasticConfig, StrengthConfig, StrengthMode,
};
use dem::Parallelism;
use serde::{Deserialize, Serialize};
use wear::dstar::{next_step, Bracket, Probe, SearchSettings, Step};

use super::junction::{relaxed_sample, run_junction, JunctionSummary};
use super::samples::{relax_all, SampleJob};
use crate::error::{Result, ValidationError};
use crate::figures::dstar::{draw_outcomes, OutcomeRow};

/// A d* search config file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DstarFile {
    /// Units of every number in the file; default nano (nm, ns, MPa, m/s).
    #[serde(default = "nano")]
    pub units: Units,
    /// Where the material comes from (see `calibrate::source`).
    pub material: MaterialSource,
    /// Every setting of the runs but the diameter and the seed; default the paper's silica set-up.
    #[serde(default)]
    pub junction: JunctionConfig,
    pub search: SearchConfig,
}

fn nano() -> Units {
    Units::Nano
}

/// What the search varies.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SearchConfig {
    /// Starting range [D expected plastic, D expected to detach], in the length unit.
    pub range: [f64; 2],
    /// Seeds run at every D (one relaxed box each); default [1, 2]: two seeds at each bound.
    #[serde(default = "d_seeds")]
    pub seeds: Vec<u64>,
    /// Stop when (upper - lower) / centre is at most this; default 0.15.
    #[serde(default = "d_width")]
    pub relative_width: f64,
    /// Smallest and largest D allowed; default from the geometry (a junction at least d0 tall, and the
    /// largest D whose solids keep half a d0 between walls and junction, below the box width; four
    /// times the range's top when the box grows with D).
    #[serde(default)]
    pub limits: Option<[f64; 2]>,
    /// Most rounds of probes; default 8.
    #[serde(default = "d_rounds")]
    pub max_rounds: usize,
    /// Grow the box with D: each length at least this factor times D (x, y, z); default none (the
    /// junction's box for every D). Paper 000's box is [3, 2, 2] D at D = 20 nm.
    #[serde(default)]
    pub box_over_diameter: Option<[f64; 3]>,
    /// Slide at least this many diameters (the duration grows with D); default none. A detached
    /// particle of diameter ~D turns by ~slide / D rad, so 4 D clears the classifier's 2 rad.
    #[serde(default)]
    pub slide_over_diameter: Option<f64>,
    /// Measure the material's properties on the first seed's box for d* of eq 22; default true.
    #[serde(default = "yes")]
    pub measure: bool,
}

fn d_seeds() -> Vec<u64> {
    vec![1, 2]
}
fn d_width() -> f64 {
    0.15
}
fn d_rounds() -> usize {
    8
}
fn yes() -> bool {
    true
}

impl DstarFile {
    /// Resolves the material (relative paths from `base`, the config's folder) and checks the
    /// search settings.
    pub fn resolve(&self, base: &Path) -> Result<ResolvedMaterial> {
        let m = self
            .material
            .resolve(base, self.units, ForceLaw::Cohesive)?;
        self.junction.validate()?;
        super::junction::check_monolayer(&self.material, &self.junction)?;
        self.settings()?;
        Ok(m)
    }

    /// The search settings, with the geometry's limits when none are given.
    pub fn settings(&self) -> Result<SearchSettings> {
        let j = &self.junction;
        if self.search.seeds.is_empty() {
            return Err(ValidationError::Config {
                path: "[search]".into(),
                reason: "seeds must hold at least one seed".into(),
            });
        }
        let limits = self.search.limits.unwrap_or_else(|| {
            // Smallest D: a junction at least a particle tall (H >= d0), so that every run of the
            // search holds members whatever its seed (a single run may go down to 1.5 d0).
            let smallest = (j.min_diameter_over_d0 * j.d0).max(j.d0 / j.height_over_diameter);
            if self.search.box_over_diameter.is_some() {
                // The box grows with D: no geometric ceiling, four times the starting range's top.
                return [smallest, 4.0 * self.search.range[1]];
            }
            // Largest D: narrower than both periodic lengths, and solids (L_y - D h) / 2 thick enough
            // for the walls plus half a d0.
            let by_walls =
                (j.lengths[1] - 2.0 * (j.wall_thickness() + 0.5 * j.d0)) / j.height_over_diameter;
            let by_width = 0.95 * j.lengths[0].min(j.lengths[2]);
            [smallest, by_walls.min(by_width)]
        });
        if let Some(f) = self.search.box_over_diameter {
            if !f.iter().all(|v| v.is_finite() && *v > 0.0) {
                return Err(ValidationError::Config {
                    path: "[search]".into(),
                    reason: format!("box_over_diameter {f:?} must hold three positive factors"),
                });
            }
        }
        if let Some(k) = self.search.slide_over_diameter {
            if !(k.is_finite() && k > 0.0) {
                return Err(ValidationError::Config {
                    path: "[search]".into(),
                    reason: format!("slide_over_diameter {k} must be positive"),
                });
            }
        }
        let s = SearchSettings {
            range: self.search.range,
            limits,
            relative_width: self.search.relative_width,
            widen: 1.5,
            max_rounds: self.search.max_rounds,
        };
        s.validate()?;
        Ok(s)
    }
}

impl DstarFile {
    /// The run at diameter `d` with `seed`: the junction's settings, its box and sliding time grown
    /// with D when the search says so.
    pub fn run_config(&self, d: f64, seed: u64) -> JunctionConfig {
        let mut j = JunctionConfig {
            diameter: d,
            seed,
            ..self.junction.clone()
        };
        if let Some(f) = self.search.box_over_diameter {
            for a in 0..3 {
                j.lengths[a] = j.lengths[a].max(f[a] * d);
            }
        }
        if let Some(k) = self.search.slide_over_diameter {
            j.duration = j.duration.max(k * d / j.velocity);
        }
        j
    }
}

/// One run of the search: the junction settings with its D and seed, and the model (the job's key).
#[derive(Debug, Clone, PartialEq, Serialize)]
struct RunJob<'a> {
    junction: JunctionConfig,
    model: &'a PairModel,
}

/// The material's properties measured on the search's recipe, engine units.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Measured {
    pub young_modulus: f64,
    pub poisson_ratio: f64,
    pub tensile_strength: f64,
    pub shear_strength: f64,
    /// Half the fracture energy of the tensile test (None if the sample did not separate).
    pub surface_energy: Option<f64>,
    pub seed: u64,
    pub particles: usize,
    pub seconds: f64,
}

/// What `dstar.json` holds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DstarResult {
    /// [lower, upper]: largest all-plastic D below the smallest all-debris D (null where missing).
    pub bracket: [Option<f64>; 2],
    pub converged: bool,
    pub reason: String,
    pub length_unit: String,
    pub material: String,
    pub seeds: Vec<u64>,
    pub d0: f64,
    /// D with split seeds inside the bracket, and all-plastic D above it.
    pub split: Vec<f64>,
    pub non_monotonic: Vec<f64>,
    /// d* of eq 22 from the target properties.
    pub dstar_eq22_target: f64,
    /// d* of eq 22 from the measured E, nu, sigma_T and surface energy.
    pub dstar_eq22_measured: Option<f64>,
    /// d* of eq 22 from the measured E, nu and sigma_T with the target surface energy: which part of
    /// the difference the strengths and stiffness explain.
    pub dstar_eq22_measured_target_gamma: Option<f64>,
    pub measured: Option<Measured>,
    pub runs: Vec<JunctionSummary>,
    /// Folder of each run, relative to the output directory.
    pub run_dirs: Vec<String>,
    pub rounds: usize,
    /// Wall time of every run and relaxation that this search's cache holds (s).
    pub cost_seconds: f64,
}

/// Runs (or continues) the search of `file` into `out`.
pub fn search(
    file: &DstarFile,
    material: &ResolvedMaterial,
    out: &Path,
    how: &RunJobs,
    par: Parallelism,
) -> Result<DstarResult> {
    let settings = file.settings()?;
    std::fs::create_dir_all(out).map_err(|e| ValidationError::io(out, e))?;
    let samples = JobCache::new(out.join("samples"));
    let base = &file.junction;
    let seeds = &file.search.seeds;
    // The base box of the first seed carries the measurement of the material's properties.
    let measure_box = JunctionConfig {
        seed: seeds[0],
        ..base.clone()
    };
    let mut box_seconds = 0.0;
    let mut probes: Vec<Probe> = Vec::new();
    let mut summaries: Vec<(JunctionSummary, String)> = Vec::new();
    let mut rounds = 0;
    let (converged, reason) = loop {
        match next_step(&settings, &probes, rounds)? {
            Step::Done { converged, reason } => break (converged, reason),
            Step::Probe(sizes) => {
                tracing::info!(
                    target: "stage",
                    round = rounds + 1,
                    ?sizes,
                    runs = sizes.len() * seeds.len(),
                    "d* search round"
                );
                let batch = run_sizes(file, material, out, &sizes, seeds, how, par)?;
                box_seconds += batch.box_seconds;
                for (d, chunk) in sizes.iter().zip(batch.runs.chunks(seeds.len())) {
                    let outcomes = chunk.iter().map(|s| s.0.outcome).collect();
                    probes.push(Probe { size: *d, outcomes });
                }
                summaries.extend(batch.runs);
                rounds += 1;
            }
        }
    };
    let b = Bracket::of(&probes);
    let measured = if file.search.measure {
        Some(measure(&samples, &measure_box, material, out, par)?)
    } else {
        None
    };
    let t = &material.target;
    let eq22 = |gamma: f64, e: f64, nu: f64, st: f64| {
        wear::scales::critical_junction_size(gamma, e, nu, st)
    };
    let dstar_measured = measured.as_ref().and_then(|m| {
        m.surface_energy
            .map(|g| eq22(g, m.young_modulus, m.poisson_ratio, m.shear_strength))
    });
    let dstar_measured_target_gamma = measured.as_ref().map(|m| {
        eq22(
            t.surface_energy,
            m.young_modulus,
            m.poisson_ratio,
            m.shear_strength,
        )
    });
    summaries.sort_by(|a, b| {
        a.0.diameter
            .total_cmp(&b.0.diameter)
            .then(a.0.seed.cmp(&b.0.seed))
    });
    let result = DstarResult {
        bracket: [b.lower, b.upper],
        converged,
        reason,
        length_unit: material.units.length_name().into(),
        material: material.description.clone(),
        seeds: seeds.clone(),
        d0: base.d0,
        split: b.split.clone(),
        non_monotonic: b.non_monotonic.clone(),
        dstar_eq22_target: eq22(
            t.surface_energy,
            t.young_modulus,
            t.poisson_ratio,
            t.shear_strength,
        ),
        dstar_eq22_measured: dstar_measured,
        dstar_eq22_measured_target_gamma: dstar_measured_target_gamma,
        measured,
        cost_seconds: summaries.iter().map(|s| s.0.run_seconds).sum::<f64>() + box_seconds,
        run_dirs: summaries.iter().map(|s| s.1.clone()).collect(),
        runs: summaries.into_iter().map(|s| s.0).collect(),
        rounds,
    };
    if how.shard.is_leader() {
        write_outputs(out, &result)?;
    }
    Ok(result)
}

/// The runs of one batch (every size with every seed, size-major), each with its folder relative to
/// the search's output directory, and the relaxation time of the boxes it had to relax.
#[derive(Debug)]
pub struct Batch {
    pub runs: Vec<(JunctionSummary, String)>,
    pub box_seconds: f64,
}

/// Runs (or reads from the search's job cache in `out`) every size of `sizes` with every seed of
/// `seeds`: the jobs a search round runs, so that runs added later (more seeds at the sizes around
/// the transition) share the cache with the search's own.
pub fn run_sizes(
    file: &DstarFile,
    material: &ResolvedMaterial,
    out: &Path,
    sizes: &[f64],
    seeds: &[u64],
    how: &RunJobs,
    par: Parallelism,
) -> Result<Batch> {
    std::fs::create_dir_all(out).map_err(|e| ValidationError::io(out, e))?;
    let samples = JobCache::new(out.join("samples"));
    let runs = JobCache::new(out.join("runs"));
    let model = &material.model;
    // Jobs side by side run single-threaded; one at a time, a job takes the threads asked for.
    let job_par = if how.at_once > 1 {
        Parallelism::Sequential
    } else {
        par
    };
    let jobs: Vec<RunJob> = sizes
        .iter()
        .flat_map(|&d| {
            seeds.iter().map(move |&seed| RunJob {
                junction: file.run_config(d, seed),
                model,
            })
        })
        .collect();
    // The relaxed boxes first, each once, so that no two runs relax the same box at once.
    let box_jobs: Vec<SampleJob> = jobs
        .iter()
        .map(|j| SampleJob::junction(&j.junction, material))
        .collect();
    let records = relax_all(&samples, &box_jobs, how, par)?;
    if records.iter().any(|r| r.is_none()) {
        return Err(shard_done(out));
    }
    let box_seconds = records.iter().flatten().map(|r| r.seconds).sum::<f64>();
    let results = run_jobs(&runs, &jobs, how, |job, dir| {
        run_junction(
            &job.junction,
            material,
            &samples,
            dir,
            job_par,
            &mut |_, _| {},
        )
    })?;
    if results.iter().any(|r| r.is_none()) {
        return Err(shard_done(out));
    }
    let mut batch = Vec::new();
    for (job, r) in jobs.iter().zip(results) {
        let key = JobCache::key(job)?;
        batch.push((r.expect("checked above"), format!("runs/{key}")));
    }
    Ok(Batch {
        runs: batch,
        box_seconds,
    })
}

/// Patch tests of the material on the relaxed box of `cfg` (cached as a job in `out/measured`).
fn measure(
    samples: &JobCache,
    cfg: &JunctionConfig,
    material: &ResolvedMaterial,
    out: &Path,
    par: Parallelism,
) -> Result<Measured> {
    let model = &material.model;
    let cache = JobCache::new(out.join("measured"));
    // Tension continues to complete separation (amorphous bonds re-form behind the crack), so that
    // half the fracture energy is the material's surface energy.
    let tensile = StrengthConfig {
        post_peak_strain: 1.0,
        max_strain: 2.0,
        ..StrengthConfig::paper(StrengthMode::Tensile)
    };
    let shear = StrengthConfig::paper(StrengthMode::Shear);
    let key = JobCache::key(&(cfg, model, &tensile, &shear))?;
    if let Some(m) = cache.get::<Measured>(&key)? {
        return Ok(m);
    }
    let t = std::time::Instant::now();
    let (sample, _) = relaxed_sample(samples, cfg, material, par)?;
    tracing::info!(
        target: "stage",
        particles = sample.particles.len(),
        "measuring the material on the search's recipe"
    );
    let dir = cache.dir(&key)?;
    if cfg.monolayer.is_some() {
        // The planar layer's own measures (2D: force per length), not the 3D patch tests.
        let m2 = dem::scenario::monolayer::measure(
            &sample,
            model,
            &dem::scenario::monolayer::MeasureConfig::default(),
            par,
        )?;
        let p = m2.properties;
        let m = Measured {
            young_modulus: p.young_modulus,
            poisson_ratio: p.poisson_ratio,
            tensile_strength: p.tensile_strength,
            shear_strength: p.shear_strength,
            surface_energy: Some(p.surface_energy),
            seed: cfg.seed,
            particles: sample.particles.len(),
            seconds: t.elapsed().as_secs_f64(),
        };
        cache.put(&key, &(cfg, model), &m)?;
        return Ok(m);
    }
    let e = elastic(&sample, model, &ElasticConfig::default(), par)?;
    let p = |name: &str| ProgressFile::new(dir.join(format!("{name}.progress.json")));
    let (pt, ps) = (p("tensile"), p("shear"));
    let ten = strength_resumable(&sample, model, &tensile, par, Some(&pt))?;
    let sh = strength_resumable(&sample, model, &shear, par, Some(&ps))?;
    let m = Measured {
        young_modulus: e.young_modulus,
        poisson_ratio: e.poisson_ratio,
        tensile_strength: ten.strength,
        shear_strength: sh.strength,
        surface_energy: ten
            .fracture
            .filter(|f| f.separated)
            .map(|f| f.surface_energy),
        seed: cfg.seed,
        particles: sample.particles.len(),
        seconds: t.elapsed().as_secs_f64(),
    };
    cache.put(&key, &(cfg, model), &m)?;
    progress::remove(&pt.path)?;
    progress::remove(&ps.path)?;
    Ok(m)
}

/// What a Slurm array task reports once its share of a round is done: a later run collects.
fn shard_done(out: &Path) -> ValidationError {
    ValidationError::ShardDone(out.display().to_string())
}

fn write_outputs(out: &Path, r: &DstarResult) -> Result<()> {
    let path = out.join("dstar.json");
    let bytes = serde_json::to_vec_pretty(r).map_err(|e| ValidationError::Config {
        path: path.display().to_string(),
        reason: e.to_string(),
    })?;
    write_atomic(&path, &bytes)?;
    let mut csv = String::from(
        "diameter,seed,outcome,turn,rigidity,debris_fraction,force_late_over_peak,particles,junction_members,run_seconds,dir\n",
    );
    for (s, dir) in r.runs.iter().zip(&r.run_dirs) {
        csv.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{},{}\n",
            s.diameter,
            s.seed,
            serde_json::to_value(s.outcome)
                .ok()
                .and_then(|v| v.as_str().map(String::from))
                .unwrap_or_default(),
            s.turn,
            s.rigidity,
            s.detachment
                .as_ref()
                .map_or(f64::NAN, |d| d.debris_fraction),
            s.force_late_over_peak.unwrap_or(f64::NAN),
            s.particles,
            s.junction_members,
            s.run_seconds,
            dir
        ));
    }
    write_atomic(&out.join("runs.csv"), csv.as_bytes())?;
    let rows: Vec<OutcomeRow> = r
        .seeds
        .iter()
        .map(|&seed| OutcomeRow {
            label: format!("DEM d0 = {} {}, seed {seed}", r.d0, r.length_unit),
            points: r
                .runs
                .iter()
                .filter(|s| s.seed == seed)
                .map(|s| (s.diameter, s.outcome))
                .collect(),
        })
        .collect();
    let mut refs = vec![("eq 22, target properties".to_string(), r.dstar_eq22_target)];
    if let Some(d) = r.dstar_eq22_measured_target_gamma {
        refs.push((
            "eq 22, measured E, nu, sigma_T, target gamma".to_string(),
            d,
        ));
    }
    if let Some(d) = r.dstar_eq22_measured {
        refs.push(("eq 22, measured properties".to_string(), d));
    }
    draw_outcomes(
        &out.join("outcomes.png"),
        &format!("junction diameter D ({})", r.length_unit),
        &rows,
        &[("DEM bracket".to_string(), r.bracket)],
        &refs,
    )?;
    Ok(())
}

/// The output directory's conventional place for a search's runs (for the report).
pub fn runs_dir(out: &Path) -> PathBuf {
    out.join("runs")
}
