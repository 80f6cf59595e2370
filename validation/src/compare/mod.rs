//! DEM against MD on one machine (`cgdem compare CONFIG --out DIR`): the critical junction size d*
//! of the 2D LJ model material found by the same bisection on both sides ([`wear::dstar`]), the MD
//! side through cached MD worker jobs ([`md`]), the DEM side through the d* searches of the dstar
//! configs the compare config names (one per discretisation d0, [`crate::wear::dstar::search`] and
//! its job cache), set beside d* of paper 000 eq 22 from the MD-measured model card.
//!
//! Outputs: `DIR/compare.json` ([`CompareResult`]: `md_bracket` and every `dem[i].bracket` in sigma,
//! `dstar_theory`, every run's verdict and cost, the MD/DEM cost ratio for the same junction, both
//! materials' properties side by side), `DIR/compare.svg` and `.png` (the wear fraction per size
//! and side against D / d*_theory, the fitted P(wear | D) and D50, the brackets), `DIR/outcomes.svg`
//! and `.png` (every run's outcome, one row per seed and side), `DIR/compare.md`. With `[scan]`
//! ([`scan`]) each side runs more seeds at the sizes around its transition and gets D50 from a
//! logistic fit. Every run is a cached job, so a rerun reads them all in seconds and an interrupted
//! comparison resumes after its finished runs.

pub mod md;
pub mod scan;
pub mod summary;

use std::path::{Path, PathBuf};

use calibrate::Units;
use dem::jobs::RunJobs;
use dem::Parallelism;
use md_bridge::job::{run_job, Job, JobOutput, RunOptions};
use md_bridge::model::{ModelConfig, ModelResult};
use serde::{Deserialize, Serialize};

use crate::error::{Result, ValidationError};
use crate::wear::dstar::{run_sizes, search as dem_search, DstarFile, DstarResult};
pub use summary::{CompareResult, DemEntry};

/// A comparison config file (`configs/compare-model.toml`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CompareFile {
    /// The model material's measurements (`cgdem md model`): its card gives d* of eq 22.
    #[serde(default = "model_13")]
    pub model: ModelConfig,
    /// The MD d* search.
    pub md: md::MdSearchConfig,
    /// One DEM d* search per discretisation (may be empty: the MD side alone).
    #[serde(default)]
    pub dem: Vec<DemSearchRef>,
    /// More seeds at the sizes around each side's transition and the fit of P(wear | D) (D50);
    /// default none (the bisection alone).
    #[serde(default)]
    pub scan: Option<scan::ScanConfig>,
}

/// The model material of issue 17: cut-off 1.3 sigma, d* of eq 22 about 25 sigma.
fn model_13() -> ModelConfig {
    ModelConfig {
        cutoff: 1.3,
        ..ModelConfig::default()
    }
}

/// A DEM d* search: a `cgdem dstar` config, run into its own folder.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DemSearchRef {
    /// The dstar config, relative to the compare config's folder.
    pub config: PathBuf,
    /// Its output folder (the search's job cache), relative to the compare output folder; default
    /// `dem/<config file stem>`.
    #[serde(default)]
    pub out: Option<PathBuf>,
    /// This discretisation's scan seeds in place of `[scan] seeds` (fewer where its runs near the
    /// transition cost minutes each); default the `[scan]` ones.
    #[serde(default)]
    pub scan_seeds: Option<Vec<u64>>,
    /// Whether its scan steps outside the bracket, in place of `[scan] outside`; default the
    /// `[scan]` one.
    #[serde(default)]
    pub scan_outside: Option<bool>,
    /// More sizes for its scan (the dstar config's length unit), where the search left a gap the
    /// transition may sit in; default none.
    #[serde(default)]
    pub scan_extra_sizes: Vec<f64>,
}

impl DemSearchRef {
    /// The scan of this discretisation: `[scan]` with this entry's overrides.
    pub fn scan(&self, sc: &scan::ScanConfig) -> scan::ScanConfig {
        scan::ScanConfig {
            seeds: self.scan_seeds.clone().unwrap_or_else(|| sc.seeds.clone()),
            outside: self.scan_outside.unwrap_or(sc.outside),
            fit: sc.fit,
        }
    }
}

impl CompareFile {
    /// Checks what can be checked before any run.
    pub fn validate(&self) -> Result<()> {
        self.model.validate()?;
        self.md.settings()?;
        if self.md.junction.cutoff != self.model.cutoff {
            return Err(ValidationError::Config {
                path: "[md.junction]".into(),
                reason: format!(
                    "cutoff {} differs from the model card's {}: the junctions must be of the \
                     measured material",
                    self.md.junction.cutoff, self.model.cutoff
                ),
            });
        }
        Ok(())
    }
}

/// How the comparison runs its jobs.
#[derive(Debug)]
pub struct CompareRun<'a> {
    /// MD worker launch (executable, ranks, cache).
    pub md: RunOptions,
    /// Jobs side by side: the DEM cases, and the MD runs of a search round or of the scan (as many
    /// worker processes as fit `at_once` cores with `md.np` ranks each).
    pub dem: RunJobs,
    pub par: Parallelism,
    /// The compare config's folder (relative paths start there).
    pub base: &'a Path,
}

/// Runs (or reads from the caches) the model card, the MD search and every DEM search, and writes
/// the outputs into `out`.
/// `report(run, cached)` hears of every MD run, batch by batch (a search round, the scan).
pub fn compare(
    file: &CompareFile,
    how: &CompareRun,
    out: &Path,
    report: &mut dyn FnMut(&md::MdRun, bool),
) -> Result<CompareResult> {
    file.validate()?;
    std::fs::create_dir_all(out).map_err(|e| ValidationError::io(out, e))?;
    // Every DEM config is read and checked before the first run, so a bad one costs nothing.
    let mut searches = Vec::new();
    for r in &file.dem {
        let path = how.base.join(&r.config);
        let config_err = |reason: String| ValidationError::Config {
            path: path.display().to_string(),
            reason,
        };
        let text = std::fs::read_to_string(&path).map_err(|e| config_err(e.to_string()))?;
        let df: DstarFile = toml::from_str(&text).map_err(|e| config_err(e.to_string()))?;
        let material = df
            .resolve(path.parent().unwrap_or(Path::new(".")))
            .map_err(|e| config_err(e.to_string()))?;
        let dir =
            out.join(r.out.clone().unwrap_or_else(|| {
                PathBuf::from("dem").join(path.file_stem().unwrap_or_default())
            }));
        searches.push((r, df, material, dir));
    }
    match &file.scan {
        Some(sc) => {
            sc.validate(&[("[md]".into(), &file.md.seeds)])?;
            for (r, df, _, _) in &searches {
                let name = r.config.display().to_string();
                r.scan(sc).validate(&[(name.clone(), &df.search.seeds)])?;
                let limits = df.settings()?.limits;
                if let Some(d) = r
                    .scan_extra_sizes
                    .iter()
                    .find(|d| !(d.is_finite() && limits[0] <= **d && **d <= limits[1]))
                {
                    return Err(ValidationError::Config {
                        path: name,
                        reason: format!(
                            "scan_extra_sizes: {d} lies outside the search's limits {limits:?}"
                        ),
                    });
                }
            }
        }
        None => {
            if let Some(r) = file.dem.iter().find(|r| {
                r.scan_seeds.is_some() || r.scan_outside.is_some() || !r.scan_extra_sizes.is_empty()
            }) {
                return Err(ValidationError::Config {
                    path: r.config.display().to_string(),
                    reason: "scan_seeds, scan_outside and scan_extra_sizes need a [scan] section"
                        .into(),
                });
            }
        }
    }
    let (card, card_seconds) = model_card(&file.model, &how.md)?;
    tracing::info!(d_star = card.d_star, "model card");
    let md_at_once = (how.dem.at_once / how.md.np.max(1) as usize).max(1);
    let md = md::search(&file.md, &how.md, md_at_once, report)?;
    let md_detachment = match &file.scan {
        Some(sc) => Some(md_scan(file, sc, &md, &how.md, md_at_once, report)?),
        None => None,
    };
    let mut dem = Vec::new();
    for (r, df, material, dir) in &searches {
        tracing::info!(config = %r.config.display(), out = %dir.display(), "DEM d* search");
        let res: DstarResult = dem_search(df, material, dir, &how.dem, how.par)?;
        let to_sigma = match df.units {
            Units::Reduced => 1.0,
            Units::Nano => 1.0 / file.model.sigma_nm,
        };
        let detachment = match &file.scan {
            Some(sc) => Some(dem_scan(df, material, dir, (r, sc), &res, to_sigma, how)?),
            None => None,
        };
        let mut e = DemEntry::new(&r.config, dir, to_sigma, res);
        e.detachment = detachment;
        dem.push(e);
    }
    let result = CompareResult::new(&card, card_seconds, md, md_detachment, dem);
    summary::write_outputs(out, &result)?;
    Ok(result)
}

/// The MD side's scan: the scan seeds at the sizes around the MD transition, `at_once` workers at a
/// time (each a cached job), and the fit over every MD run.
fn md_scan(
    file: &CompareFile,
    sc: &scan::ScanConfig,
    md: &md::MdSearch,
    opts: &RunOptions,
    at_once: usize,
    report: &mut dyn FnMut(&md::MdRun, bool),
) -> Result<scan::Detachment> {
    let mut visited: Vec<f64> = md.runs.iter().map(|r| r.diameter).collect();
    visited.dedup();
    let sizes = scan::scan_sizes(
        &visited,
        &md.bracket,
        &md.split,
        &md.non_monotonic,
        file.md.settings()?.limits,
        sc.outside,
    );
    tracing::info!(?sizes, seeds = ?sc.seeds, "MD detachment scan");
    let trial = |r: &md::MdRun, scan: bool| scan::Trial {
        diameter: r.diameter,
        seed: r.seed,
        outcome: r.outcome,
        scan,
        seconds: r.wall_seconds,
    };
    let mut trials: Vec<scan::Trial> = md.runs.iter().map(|r| trial(r, false)).collect();
    // The search's runs at a scanned size are already in; the scan adds its own seeds there.
    let jobs: Vec<_> = sizes
        .iter()
        .flat_map(|&d| {
            sc.seeds
                .iter()
                .map(move |&seed| file.md.run_config(d, seed))
        })
        .collect();
    for (r, cached) in md::run_many(&jobs, opts, at_once, "MD detachment scan")? {
        report(&r, cached);
        trials.push(trial(&r, true));
    }
    scan::Detachment::new(sizes, sc.seeds.clone(), trials, &sc.fit)
}

/// A DEM side's scan: the scan seeds at the sizes around its transition, through the search's own
/// job cache, and the fit over every run of the search and the scan (sigma).
fn dem_scan(
    df: &DstarFile,
    material: &calibrate::ResolvedMaterial,
    dir: &Path,
    (entry, sc): (&DemSearchRef, &scan::ScanConfig),
    res: &DstarResult,
    to_sigma: f64,
    how: &CompareRun,
) -> Result<scan::Detachment> {
    // This entry's seeds and steps, and its extra sizes.
    let sc = &entry.scan(sc);
    let extra = &entry.scan_extra_sizes;
    let mut visited: Vec<f64> = res.runs.iter().map(|r| r.diameter).collect();
    visited.dedup();
    let mut sizes = scan::scan_sizes(
        &visited,
        &res.bracket,
        &res.split,
        &res.non_monotonic,
        df.settings()?.limits,
        sc.outside,
    );
    sizes.extend_from_slice(extra);
    sizes.sort_by(f64::total_cmp);
    sizes.dedup();
    tracing::info!(?sizes, seeds = ?sc.seeds, out = %dir.display(), "DEM detachment scan");
    let batch = run_sizes(df, material, dir, &sizes, &sc.seeds, &how.dem, how.par)?;
    let trial = |r: &crate::wear::junction::JunctionSummary, scan: bool| scan::Trial {
        diameter: r.diameter * to_sigma,
        seed: r.seed,
        outcome: r.outcome,
        scan,
        seconds: r.run_seconds,
    };
    let trials = res
        .runs
        .iter()
        .map(|r| trial(r, false))
        .chain(batch.runs.iter().map(|(r, _)| trial(r, true)))
        .collect();
    let sigma = sizes.iter().map(|d| d * to_sigma).collect();
    scan::Detachment::new(sigma, sc.seeds.clone(), trials, &sc.fit)
}

/// The model material's card (a cached MD job) and the wall time it took.
pub fn model_card(cfg: &ModelConfig, opts: &RunOptions) -> Result<(ModelResult, f64)> {
    let (rec, _) = run_job(&Job::Model(cfg.clone()), opts)?;
    match rec.output {
        JobOutput::Model(r) => Ok((*r, rec.provenance.wall_seconds)),
        other => Err(ValidationError::Report(format!(
            "model job returned {other:?}, not a model card"
        ))),
    }
}
