//! One sliding run, or a grid of them, as the workbench runs it (`cgdem sliding CONFIG --out DIR`,
//! paper 004): the config file, the relaxed sample (a job of `DIR/samples/`, resumable, relaxed once
//! for the run and its strength tests), the run (resumable), and its outputs:
//! - `summary.json`: `rho_tbl` (over rho_0), `h_tbl` (over H), `p_t`, `p_n`, `regime`, `tau_m` (over
//!   E, measured on the run's own relaxed box with the patch-test rig unless the config gives it, and
//!   `tau_m_how`), `p_t_over_tau_m`, the layer's `agitation` (over v0), where the TBL first lay
//!   against a rigid body (`body_reached_at_l`) and the measures of the `interior` phase (TBL inside
//!   the material, paper 004's first stationary phase), with the material (sigma_m, gamma, d*), the
//!   cost and the settings;
//! - `profiles.csv`: the steady profiles over y / H (velocity over v0, density over rho_0 raw and
//!   Savitzky-Golay filtered, the fitted Gaussian, agitation over v0);
//! - `windows.csv`: h_TBL / H, rho_TBL / rho_0 and the TBL's boundaries over H per window against
//!   the slide (Fig. 5); `summary.json`'s `body_reached_at_l` and `interior` come from them;
//! - `force.csv`: the horizontal and normal pair forces on the two bodies and p_T;
//! - `wear_particles.csv`: per window, the layer's wear particles (loose clusters of at least
//!   `wear_particle_members`: their count, the largest's members, fraction and equivalent diameter
//!   over L) and its detached fraction (`wear::tbl::wear_particles`); `summary.json`'s
//!   `wear_particles` summarises them;
//! - `sliding.dump`: LAMMPS-style frames (OVITO) with `half` and `height0` columns;
//! - `profiles.png`, `h_tbl.png`, `snapshot.png`, `wear_particles.png` (see
//!   [`crate::figures::sliding`]).
//!
//! The strength tests (tau_m and sigma_t, [`dem::scenario::sliding::measure_strength`]) are jobs of
//! their own in `DIR/strength/<key>/` (`strength.json`, `strength.csv`, `strength.png`), keyed by
//! the material and the box only ([`SlidingConfig::material_test`]): the runs of a grid that share a
//! material share one measurement, on the box they slide (one relaxation in `DIR/samples/<key>/`,
//! [`super::samples`]).
//!
//! A grid (`[[grid]]` entries, each a p_N, sigma_m and d*) is a list of [`dem::jobs`] jobs: each run
//! in `DIR/runs/<key>/` with its own outputs, side by side or sharded, and `DIR/grid.csv`.

use std::fmt::Write as _;
use std::path::Path;

use dem::io::checkpoint::write_atomic;
use dem::io::progress::{self, ProgressFile};
use dem::jobs::{run_jobs, JobCache, RunJobs};
use dem::material::PairModel;
use dem::scenario::sliding::{
    measure_strength, run_resumable, MaterialStrength, SlidingConfig, SlidingResult,
};
use dem::Parallelism;
use serde::{Deserialize, Serialize};
use wear::tbl::Regime;

use super::json;
use super::samples::{relax_all, relaxed, SampleJob};
use crate::error::{Result, ValidationError};
use crate::figures::sliding::{
    draw_h_tbl, draw_profiles, draw_snapshot, draw_strength, draw_wear_particles,
};

/// Bumped when the strength tests' code changes what they give (retires cached measurements).
// 2: the shear test runs on past the peak and the output carries the flow stress.
// 3: the shear strain from the unwrapped top wall (a wall crossing the periodic boundary made it jump
//    by -L / l0, so a test could run on past its stop and mix wrapped strains into the flow window).
const STRENGTH_VERSION: u32 = 3;

/// One point of a grid: the settings that differ from the file's `[sliding]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GridPoint {
    /// p_N (units of E).
    pub pressure: f64,
    /// sigma_m (units of E).
    pub strength: f64,
    /// d* (units of L).
    pub d_star: f64,
}

/// A sliding config file: `[sliding]` (every key optional, defaults the paper's), and optionally a
/// grid of runs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SlidingFile {
    #[serde(default)]
    pub sliding: SlidingConfig,
    /// Runs of a grid (none: one run of `[sliding]`).
    #[serde(default)]
    pub grid: Vec<GridPoint>,
}

impl SlidingFile {
    /// The config of every run (one without a grid), each validated.
    pub fn runs(&self) -> Result<Vec<SlidingConfig>> {
        let runs: Vec<SlidingConfig> = if self.grid.is_empty() {
            vec![self.sliding.clone()]
        } else {
            self.grid
                .iter()
                .map(|g| {
                    let mut c = self.sliding.clone();
                    c.pressure = g.pressure;
                    c.material.strength = g.strength;
                    c.material.d_star = Some(g.d_star);
                    c.material.surface_energy = None;
                    c
                })
                .collect()
        };
        for c in &runs {
            c.validate()?;
        }
        Ok(runs)
    }
}

/// The interior phase of a run, in the summary's units.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct InteriorSummary {
    pub windows: usize,
    pub p_t: f64,
    pub rho_tbl: f64,
    pub h_tbl: f64,
    pub p_t_over_tau_m: f64,
    pub p_t_over_tau_flow: Option<f64>,
}

/// What `summary.json` holds (and a grid's row).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SlidingSummary {
    /// rho_TBL / rho_0 of the steady profile.
    pub rho_tbl: f64,
    /// Mean h_TBL / H of the steady windows.
    pub h_tbl: f64,
    /// Mean p_T and the applied p_N (units of E).
    pub p_t: f64,
    pub p_n: f64,
    pub regime: Regime,
    /// Steady windows whose TBL lies against a rigid body, and the slide over L at which the run's
    /// TBL first did (none: it never did). Paper 004 drops that phase as unphysical.
    #[serde(default)]
    pub steady_windows_at_body: usize,
    #[serde(default)]
    pub body_reached_at_l: Option<f64>,
    /// The interior phase (`dem::scenario::sliding` docs): windows after the start-up whose TBL lies
    /// inside the material, paper 004's "first stationary phase"; their count, mean p_T (E), mean
    /// rho_TBL / rho_0 and h_TBL / H, and p_T over tau_m and tau_flow (none without such windows).
    #[serde(default)]
    pub interior: Option<InteriorSummary>,
    /// tau_m over E, how it was found (measured or given), tau_m / sigma_m, the measured tensile
    /// strength sigma_t over E (none when tau_m was given), p_T / tau_m (about 1 in a shear band,
    /// paper 004 section 3) and p_T over tau_m rho_TBL / rho_0 (about 1 in the mixed regime).
    pub tau_m: f64,
    pub tau_m_how: String,
    pub tau_m_over_sigma_m: f64,
    pub sigma_t: Option<f64>,
    pub p_t_over_tau_m: f64,
    pub p_t_over_tau_rho: f64,
    /// The flow stress after the shear peak over E, tau_flow / sigma_m and p_T / tau_flow (none when
    /// tau_m was given or the shear test stopped too soon after its peak; `dem::scenario::sliding::
    /// flow_stress`): the steady layer is sheared, re-bonded material, which flows at this stress.
    #[serde(default)]
    pub tau_flow: Option<f64>,
    #[serde(default)]
    pub tau_flow_over_sigma_m: Option<f64>,
    #[serde(default)]
    pub p_t_over_tau_flow: Option<f64>,
    /// The steady TBL's agitation over v0: the root mean square velocity fluctuation per component
    /// about the mean flow in the layer's bins (`wear::tbl::layer_agitation`); none without a layer.
    /// The layer's shear stress falls as it rises (docs/sliding.md).
    #[serde(default)]
    pub agitation: Option<f64>,
    /// The layer's wear particles (Fig. 3a and 3c; `dem::scenario::sliding::WearSummary`, lengths
    /// over L): loose clusters of at least `wear_particle_members` particles; none for older runs.
    #[serde(default)]
    pub wear_particles: Option<dem::scenario::sliding::WearSummary>,
    pub strength: f64,
    pub surface_energy: f64,
    pub d_star: f64,
    pub d_m_over_d0: f64,
    pub d0_over_l: f64,
    pub distance_over_l: f64,
    pub particles: usize,
    pub steps: u64,
    pub dt: f64,
    pub steady_windows: usize,
    pub run_seconds: f64,
    /// Neighbour-list builds of the run, and how many were local (`sliding.local_rebuilds`).
    #[serde(default)]
    pub neighbour_builds: u64,
    #[serde(default)]
    pub local_builds: u64,
    /// What relaxing the run's box took when it was relaxed (once, in the samples cache, for the run
    /// and its strength job alike).
    pub relax_seconds: f64,
}

/// The shear strength a run is compared with: measured on its material, or given by its config.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShearStrength {
    /// tau_m and, when measured, sigma_t (engine units).
    pub tau_m: f64,
    pub sigma_t: Option<f64>,
    /// The flow stress after the shear peak (engine units), when measured (none when given, or when
    /// the shear test stopped too soon after its peak).
    #[serde(default)]
    pub tau_flow: Option<f64>,
    /// How it was found, in one line.
    pub how: String,
}

impl ShearStrength {
    fn given(cfg: &SlidingConfig) -> Option<Self> {
        cfg.given_shear_strength().map(|tau_m| ShearStrength {
            tau_m,
            sigma_t: None,
            tau_flow: None,
            how: format!(
                "given: shear_strength_over_strength = {} (not measured)",
                cfg.shear_strength_over_strength.unwrap_or_default()
            ),
        })
    }

    /// The strengths a strength job measured.
    pub fn measured(m: &MaterialStrength) -> Self {
        ShearStrength {
            tau_m: m.tau_m,
            sigma_t: Some(m.sigma_t),
            tau_flow: m.tau_flow.map(|f| f.mean),
            how: m.how.clone(),
        }
    }
}

/// The inputs of a strength job (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StrengthJob {
    pub version: u32,
    pub sliding: SlidingConfig,
}

impl StrengthJob {
    /// The strength job of a run (its material and box).
    pub fn of(cfg: &SlidingConfig) -> Self {
        StrengthJob {
            version: STRENGTH_VERSION,
            sliding: cfg.material_test(),
        }
    }
}

/// Measures tau_m and sigma_t of the job's material in `dir` (resumable from the progress files
/// there) on its relaxed box from `samples` (the box its runs slide), writing `strength.json`,
/// `strength.csv` and `strength.png`.
pub fn run_strength_job(
    job: &StrengthJob,
    samples: &JobCache,
    dir: &Path,
    par: Parallelism,
) -> Result<MaterialStrength> {
    let cfg = &job.sliding;
    cfg.validate()?;
    std::fs::create_dir_all(dir).map_err(|e| ValidationError::io(dir, e))?;
    let model = cfg.model()?;
    let (sample, _) = relaxed(samples, &SampleJob::sliding(cfg, &model)?, par)?;
    let m = measure_strength(&sample, cfg, &cfg.strength_tests, par, Some(dir))?;
    json(&dir.join("strength.json"), &m)?;
    let mut csv = String::from("test,strain,stress,sigma_yy\n");
    for (test, p) in [("shear", &m.shear), ("tensile", &m.tensile)] {
        for (e, s, n) in &p.curve {
            writeln!(csv, "{test},{e},{s},{n}").expect("writing to a String");
        }
    }
    write_atomic(&dir.join("strength.csv"), csv.as_bytes())?;
    draw_strength(&dir.join("strength.png"), &m)?;
    tracing::info!(
        target: "stage",
        sigma_m = cfg.material.strength,
        tau_m = m.tau_m,
        tau_over_sigma_m = m.tau_over_sigma_m(),
        sigma_t = m.sigma_t,
        "sliding material strength (patch tests)"
    );
    Ok(m)
}

/// The shear strength of every run of `runs`: given by its config, or measured as a strength job in
/// `root` (one job per distinct material, run as `how` says) on the relaxed box from `samples`
/// (relaxed there first if missing: see [`relax_boxes`]); `None` where another shard's job is not
/// done yet.
pub fn shear_strengths(
    runs: &[SlidingConfig],
    samples: &JobCache,
    root: &Path,
    how: &RunJobs,
    par: Parallelism,
) -> Result<Vec<Option<ShearStrength>>> {
    let mut jobs: Vec<StrengthJob> = Vec::new();
    for c in runs {
        let j = StrengthJob::of(c);
        if c.given_shear_strength().is_none() && !jobs.contains(&j) {
            jobs.push(j);
        }
    }
    let cache = JobCache::new(root);
    let measured = run_jobs(&cache, &jobs, how, |job, dir| {
        run_strength_job(job, samples, dir, par)
    })?;
    Ok(runs
        .iter()
        .map(|c| {
            ShearStrength::given(c).or_else(|| {
                let j = StrengthJob::of(c);
                let k = jobs.iter().position(|x| *x == j)?;
                measured[k].as_ref().map(ShearStrength::measured)
            })
        })
        .collect())
}

/// Relaxes the sample and runs `cfg` into `out` (both resumable from their progress files there),
/// its shear strength measured first in `out/strength/` (or given by the config).
pub fn run_sliding(
    cfg: &SlidingConfig,
    out: &Path,
    par: Parallelism,
    report: &mut dyn FnMut(u64, u64),
) -> Result<SlidingSummary> {
    cfg.validate()?;
    let how = RunJobs {
        at_once: 1,
        ..RunJobs::default()
    };
    let samples = samples_cache(out);
    let tau = shear_strengths(
        std::slice::from_ref(cfg),
        &samples,
        &out.join("strength"),
        &how,
        par,
    )?
    .pop()
    .flatten()
    .ok_or_else(|| {
        ValidationError::Dem(dem::DemError::InvalidConfig(
            "sliding: the strength job gave no result".into(),
        ))
    })?;
    run_sliding_with(cfg, &tau, &samples, out, par, report)
}

impl<'a> SampleJob<'a> {
    /// The relaxed box of a sliding run (or of its material's strength job: the same recipe, model
    /// and relaxation, so both read one box and it is relaxed once).
    pub fn sliding(cfg: &SlidingConfig, model: &'a PairModel) -> Result<Self> {
        Ok(SampleJob {
            recipe: cfg.recipe()?,
            model,
            relax: cfg.relax,
        })
    }
}

/// Where a sliding run or grid in `out` keeps its relaxed boxes.
pub fn samples_cache(out: &Path) -> JobCache {
    JobCache::new(out.join("samples"))
}

/// The pair model of each of `runs` (what their boxes' jobs borrow).
pub fn models(runs: &[SlidingConfig]) -> Result<Vec<PairModel>> {
    Ok(runs.iter().map(|c| c.model()).collect::<dem::Result<_>>()?)
}

/// The box job of each of `runs`, with `models` from [`models`] (runs of one material repeat a box:
/// [`super::samples::distinct`] lists each once).
pub fn box_jobs<'a>(runs: &[SlidingConfig], models: &'a [PairModel]) -> Result<Vec<SampleJob<'a>>> {
    runs.iter()
        .zip(models)
        .map(|(c, m)| SampleJob::sliding(c, m))
        .collect()
}

/// Relaxes the distinct boxes of `runs` into `samples` (a job list run as `how` says), before their
/// strength jobs and runs read them. Returns whether every box is there (`false`: another
/// non-concurrent shard's box is not done yet).
pub fn relax_boxes(
    runs: &[SlidingConfig],
    samples: &JobCache,
    how: &RunJobs,
    par: Parallelism,
) -> Result<bool> {
    let models = models(runs)?;
    Ok(relax_all(samples, &box_jobs(runs, &models)?, how, par)?
        .iter()
        .all(Option::is_some))
}

/// [`run_sliding`] with the shear strength `tau` already found.
pub fn run_sliding_with(
    cfg: &SlidingConfig,
    tau: &ShearStrength,
    samples: &JobCache,
    out: &Path,
    par: Parallelism,
    report: &mut dyn FnMut(u64, u64),
) -> Result<SlidingSummary> {
    cfg.validate()?;
    std::fs::create_dir_all(out).map_err(|e| ValidationError::io(out, e))?;
    let model = cfg.model()?;
    // Eq 11: pairs larger than d_m = d* / 8 break at delta_e, where gamma no longer enters (see
    // `dem::scenario::sliding`). Pairs' radii sums r_i + r_j span [0.75, 1.25] d0 (diameters in
    // [0.75, 1.25] d0): d_m below 1.25 d0 leaves some pairs without gamma, below 0.75 d0 all of them.
    let d_m_over_d0 = cfg.d_star()? / 8.0 / cfg.d0();
    if d_m_over_d0 < 1.25 {
        tracing::warn!(
            d_m_over_d0,
            "eq 11 of paper 004 fails for pairs above d_m = d*/8: they break at delta_e and gamma \
             (hence d*) does not enter them{}",
            if d_m_over_d0 < 0.75 {
                " (every pair here: d* has no effect)"
            } else {
                ""
            }
        );
    }
    let (sample, relaxation) = relaxed(samples, &SampleJob::sliding(cfg, &model)?, par)?;
    let relax_seconds = relaxation.seconds;
    let run_progress = ProgressFile::new(out.join("sliding.progress.json"));
    let dump = (cfg.dump_frames > 0).then(|| out.join("sliding.dump"));
    let r = run_resumable(
        &sample,
        &model,
        cfg,
        tau.tau_m,
        par,
        dump.as_deref(),
        Some(&run_progress),
        report,
    )?;
    let summary = SlidingSummary {
        rho_tbl: r.rho_tbl,
        h_tbl: r.h_tbl,
        p_t: r.p_t,
        p_n: r.p_n,
        regime: r.regime,
        steady_windows_at_body: r.steady_windows_at_body,
        body_reached_at_l: r.body_reached_at.map(|x| x / cfg.length),
        interior: r.interior.map(|i| InteriorSummary {
            windows: i.windows,
            p_t: i.p_t / cfg.young_modulus,
            rho_tbl: i.rho_tbl,
            h_tbl: i.h_tbl,
            p_t_over_tau_m: i.p_t / r.tau_m,
            p_t_over_tau_flow: tau.tau_flow.map(|t| i.p_t / t),
        }),
        tau_m: r.tau_m / cfg.young_modulus,
        tau_m_how: tau.how.clone(),
        tau_m_over_sigma_m: r.tau_m / cfg.material.strength,
        sigma_t: tau.sigma_t.map(|s| s / cfg.young_modulus),
        p_t_over_tau_m: r.p_t / r.tau_m,
        p_t_over_tau_rho: r.p_t / (r.tau_m * r.rho_tbl),
        tau_flow: tau.tau_flow.map(|t| t / cfg.young_modulus),
        tau_flow_over_sigma_m: tau.tau_flow.map(|t| t / cfg.material.strength),
        p_t_over_tau_flow: tau.tau_flow.map(|t| r.p_t / t),
        agitation: r.layer.agitation,
        wear_particles: r.wear_summary,
        strength: cfg.material.strength,
        surface_energy: cfg.surface_energy()?,
        d_star: r.d_star,
        d_m_over_d0: r.d_m_over_d0,
        d0_over_l: cfg.d0_over_l,
        distance_over_l: cfg.distance_over_l,
        particles: r.particles,
        steps: r.steps,
        dt: r.dt,
        steady_windows: r.steady_windows,
        run_seconds: r.wall_seconds,
        neighbour_builds: r.neighbour_builds,
        local_builds: r.local_builds,
        relax_seconds,
    };
    write_outputs(out, cfg, &r, &summary)?;
    progress::remove(&run_progress.path)?;
    Ok(summary)
}

/// Runs every config of a grid as cached jobs under `out/runs/` (their relaxed boxes in
/// `out/samples/`, their strength jobs in `out/strength/`) and writes `out/grid.csv`; `None` where
/// another (non-concurrent) shard's job is not done yet.
///
/// Each job's engine steps on one thread when jobs run side by side (`how.at_once > 1`: the cores are
/// the jobs'), and with `par` when they run one at a time (a cluster task given several cores for
/// its share: `--jobs 1 --threads N`). Either way the same bits (the engine is deterministic for any
/// thread count), so the cache is shared by both arrangements.
pub fn run_grid(
    runs: &[SlidingConfig],
    out: &Path,
    how: &RunJobs,
    par: Parallelism,
) -> Result<Vec<Option<SlidingSummary>>> {
    let par = if how.at_once > 1 {
        Parallelism::Sequential
    } else {
        par
    };
    let samples = samples_cache(out);
    // Boxes, then strength jobs, then runs, each a job list: a stage waits for the whole stage before
    // it. A Slurm array's task that finds another task's box or strength job missing leaves its runs
    // pending and exits cleanly, so that the next stage's array (submitted `afterok`) starts; a
    // failure here would break that chain (scripts/slurm-grid).
    let taus = if relax_boxes(runs, &samples, how, par)? {
        shear_strengths(runs, &samples, &out.join("strength"), how, par)?
            .into_iter()
            .collect::<Option<Vec<ShearStrength>>>()
    } else {
        None
    };
    let results = match taus {
        Some(taus) => {
            let cache = JobCache::new(out.join("runs"));
            run_jobs(&cache, runs, how, |cfg, dir| {
                let k = runs
                    .iter()
                    .position(|c| c == cfg)
                    .expect("a run of the list");
                run_sliding_with(cfg, &taus[k], &samples, dir, par, &mut |_, _| {})
            })?
        }
        None => vec![None; runs.len()],
    };
    let mut csv = String::from(
        "p_n,strength,d_star,rho_tbl,h_tbl,p_t,tau_m,p_t_over_tau_m,p_t_over_tau_rho,tau_flow,p_t_over_tau_flow,agitation,regime,body_reached_at_l,interior_windows,interior_p_t_over_tau_m,interior_p_t_over_tau_flow,particles,run_seconds,key\n",
    );
    for (cfg, r) in runs.iter().zip(&results) {
        let key = JobCache::key(cfg)?;
        let line = match r {
            Some(s) => writeln!(
                csv,
                "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
                s.p_n,
                s.strength,
                s.d_star,
                s.rho_tbl,
                s.h_tbl,
                s.p_t,
                s.tau_m,
                s.p_t_over_tau_m,
                s.p_t_over_tau_rho,
                opt(s.tau_flow),
                opt(s.p_t_over_tau_flow),
                opt(s.agitation),
                s.regime.label(),
                opt(s.body_reached_at_l),
                s.interior.as_ref().map_or(0, |i| i.windows),
                opt(s.interior.as_ref().map(|i| i.p_t_over_tau_m)),
                opt(s.interior.as_ref().and_then(|i| i.p_t_over_tau_flow)),
                s.particles,
                s.run_seconds,
                key.0
            ),
            None => writeln!(
                csv,
                "{},{},{},,,,,,,,,,pending,,,,,,,{}",
                cfg.pressure,
                cfg.material.strength,
                cfg.d_star()?,
                key.0
            ),
        };
        line.expect("writing to a String");
    }
    write_atomic(&out.join("grid.csv"), csv.as_bytes())?;
    Ok(results)
}

/// An optional CSV field: empty when absent.
fn opt(v: Option<f64>) -> String {
    v.map_or(String::new(), |v| v.to_string())
}

#[derive(Serialize)]
struct SummaryFile<'a> {
    #[serde(flatten)]
    summary: &'a SlidingSummary,
    config: &'a SlidingConfig,
    layer: &'a wear::tbl::LayerMeasures,
}

fn write_outputs(
    out: &Path,
    cfg: &SlidingConfig,
    r: &SlidingResult,
    summary: &SlidingSummary,
) -> Result<()> {
    json(
        &out.join("summary.json"),
        &SummaryFile {
            summary,
            config: cfg,
            layer: &r.layer,
        },
    )?;
    let centres = r.profile.centres();
    let mut csv = String::from(
        "y_over_h,velocity_over_v0,density_over_rho0,density_filtered,gauss_fit,agitation_over_v0\n",
    );
    for (k, y) in centres.iter().enumerate() {
        let v = opt(r.profile.velocity_over_v0[k]);
        // Empty for a profile summed before the agitation was recorded.
        let a = opt(r.profile.agitation_over_v0.get(k).copied().flatten());
        writeln!(
            csv,
            "{y},{v},{},{},{},{a}",
            r.profile.density[k] / r.rho0,
            r.layer.density_filtered[k],
            r.layer.fit.at(*y)
        )
        .expect("writing to a String");
    }
    write_atomic(&out.join("profiles.csv"), csv.as_bytes())?;
    let mut csv = String::from("step,time,slide_over_l,height,h_tbl,rho_tbl,tbl_lo,tbl_hi\n");
    for w in &r.windows {
        writeln!(
            csv,
            "{},{},{},{},{},{},{},{}",
            w.step,
            w.time,
            w.slide / cfg.length,
            w.height,
            opt(w.h_tbl),
            opt(w.rho_tbl),
            opt(w.bounds.map(|b| b.lo)),
            opt(w.bounds.map(|b| b.hi))
        )
        .expect("writing to a String");
    }
    write_atomic(&out.join("windows.csv"), csv.as_bytes())?;
    let mut csv = String::from(
        "step,slide_over_l,wear_particles,largest_members,largest_fraction,largest_diameter_over_l,detached\n",
    );
    for w in &r.wear {
        let p = &w.particles;
        writeln!(
            csv,
            "{},{},{},{},{},{},{}",
            w.step,
            w.slide / cfg.length,
            p.count,
            p.largest,
            p.largest_fraction,
            p.largest_diameter / cfg.length,
            p.detached
        )
        .expect("writing to a String");
    }
    write_atomic(&out.join("wear_particles.csv"), csv.as_bytes())?;
    let mut csv = String::from("step,time,slide,fx_top,fy_top,fx_bottom,fy_bottom,p_t\n");
    for (a, b) in r.force_top.iter().zip(&r.force_bottom) {
        writeln!(
            csv,
            "{},{},{},{},{},{},{},{}",
            a.step,
            a.time,
            a.displacement[0],
            a.force[0],
            a.force[1],
            b.force[0],
            b.force[1],
            wear::tbl::shear_traction(a.force[0], b.force[0], r.area)
        )
        .expect("writing to a String");
    }
    write_atomic(&out.join("force.csv"), csv.as_bytes())?;
    draw_profiles(&out.join("profiles.png"), r)?;
    draw_h_tbl(&out.join("h_tbl.png"), r, cfg.length, cfg.regime.window)?;
    draw_snapshot(&out.join("snapshot.png"), r)?;
    draw_wear_particles(
        &out.join("wear_particles.png"),
        r,
        cfg.length,
        cfg.wear_particle_members,
    )?;
    Ok(())
}
