//! DEM against MD on one machine (`cgdem compare CONFIG --out DIR`): the critical junction size d*
//! of the 2D LJ model material found by the same bisection on both sides ([`wear::dstar`]), the MD
//! side through cached MD worker jobs ([`md`]), the DEM side through the d* searches of the dstar
//! configs the compare config names (one per discretisation d0, [`crate::wear::dstar::search`] and
//! its job cache), set beside d* of paper 000 eq 22 from the MD-measured model card.
//!
//! Outputs: `DIR/compare.json` ([`CompareResult`]: `md_bracket` and every `dem[i].bracket` in sigma,
//! `dstar_theory`, every run's verdict and cost, the MD/DEM cost ratio for the same junction, both
//! materials' properties side by side), `DIR/compare.svg` and `.png` (outcome against D / d*_theory),
//! `DIR/properties.md` (the properties table). Every run is a cached job, so a rerun reads them
//! all in seconds and an interrupted comparison resumes after its finished runs.

pub mod md;
pub mod summary;

use std::path::{Path, PathBuf};

use calibrate::Units;
use dem::jobs::RunJobs;
use dem::Parallelism;
use md_bridge::job::{run_job, Job, JobOutput, RunOptions};
use md_bridge::model::{ModelConfig, ModelResult};
use serde::{Deserialize, Serialize};

use crate::error::{Result, ValidationError};
use crate::wear::dstar::{search as dem_search, DstarFile, DstarResult};
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
    /// DEM jobs side by side.
    pub dem: RunJobs,
    pub par: Parallelism,
    /// The compare config's folder (relative paths start there).
    pub base: &'a Path,
}

/// Runs (or reads from the caches) the model card, the MD search and every DEM search, and writes
/// the outputs into `out`.
/// `report(run, cached)` hears of every MD run as it ends.
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
    let (card, card_seconds) = model_card(&file.model, &how.md)?;
    tracing::info!(d_star = card.d_star, "model card");
    let md = md::search(&file.md, &how.md, report)?;
    let mut dem = Vec::new();
    for (r, df, material, dir) in &searches {
        tracing::info!(config = %r.config.display(), out = %dir.display(), "DEM d* search");
        let res: DstarResult = dem_search(df, material, dir, &how.dem, how.par)?;
        let to_sigma = match df.units {
            Units::Reduced => 1.0,
            Units::Nano => 1.0 / file.model.sigma_nm,
        };
        dem.push(DemEntry::new(&r.config, dir, to_sigma, res));
    }
    let result = CompareResult::new(&card, card_seconds, md, dem);
    summary::write_outputs(out, &result)?;
    Ok(result)
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
