//! A patch-test campaign in one typed configuration: which sample (HCP, amorphous or a saved file), which
//! tests, and an optional sweep over d0, nu and s, as in paper 000 Figs. 5-8 and A.4-A.9. The CLI's
//! `cgdem patch <config.toml>` is a thin shell around [`run_suite`].

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::{
    compaction, elastic, strength_resumable, CompactionConfig, CompactionResult, ElasticConfig,
    ElasticResult, StrengthConfig, StrengthMode, StrengthResult,
};
use crate::error::{DemError, Result};
use crate::io::checkpoint::write_atomic;
use crate::io::progress::{self, ProgressFile};
use crate::material::{Material, PairModel, ParamScale};
use crate::sample::stats::{coordination, gap_statistics, Coordination, GapStatistics};
use crate::sample::{make_sample_resumable, RelaxConfig, Sample, SampleSpec};
use crate::sim::Parallelism;

/// The patch tests.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PatchKind {
    Elastic,
    Tensile,
    Shear,
    /// Shear under normal load (not in the default set: the check of a card, not a property).
    Compaction,
}

/// Values swept over (empty: the base value only).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Sweep {
    pub d0_over_dc: Vec<f64>,
    pub poisson_ratio: Vec<f64>,
    pub scaling: Vec<f64>,
}

/// `[model]`: the pair model of a calibrated card (what `cgdem calibrate` writes) instead of
/// `material` and `scale`, to re-measure the card on a sample of one's choosing.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelSource {
    /// The card file; a relative path is taken from the campaign file's folder.
    pub card: PathBuf,
    /// The card's `[model]` table, filled in by whoever reads the card (`cgdem patch`), so that the
    /// report records the model the tests ran with; a campaign file normally leaves it out.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pair_model: Option<PairModel>,
}

/// A campaign of patch tests.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PatchSuite {
    /// Target material; default Table 4 with nu = 0.15, s = 0 (paper 000 section 3). Ignored when
    /// `model` names a card.
    #[serde(default = "d_material")]
    pub material: Material,
    /// Calibration multipliers; default all 1 (the closed-form parameters, eqs 7-13). Ignored when
    /// `model` names a card.
    #[serde(default)]
    pub scale: ParamScale,
    /// The pair model of a calibrated card; default none (`material` and `scale`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub model: Option<ModelSource>,
    pub sample: SampleSpec,
    /// Relaxation of amorphous samples; default the paper's (section 3.2).
    #[serde(default)]
    pub relax: RelaxConfig,
    /// Tests to run; default all three.
    #[serde(default = "d_tests")]
    pub tests: Vec<PatchKind>,
    /// Elastic test settings; default the paper's.
    #[serde(default)]
    pub elastic: ElasticConfig,
    /// Tensile test settings; default the paper's.
    #[serde(default = "d_tensile")]
    pub tensile: StrengthConfig,
    /// Shear test settings; default the paper's.
    #[serde(default = "d_shear")]
    pub shear: StrengthConfig,
    /// Shear-under-load test settings; default [`CompactionConfig::default`].
    #[serde(default)]
    pub compaction: CompactionConfig,
    /// Sweep over d0, nu, s; default none.
    #[serde(default)]
    pub sweep: Sweep,
    /// Save each generated sample next to the results (to reuse with `kind = "file"`); default false.
    #[serde(default)]
    pub save_samples: bool,
}

fn d_material() -> Material {
    Material::table4(0.15)
}
fn d_tests() -> Vec<PatchKind> {
    vec![PatchKind::Elastic, PatchKind::Tensile, PatchKind::Shear]
}
fn d_tensile() -> StrengthConfig {
    StrengthConfig::paper(StrengthMode::Tensile)
}
fn d_shear() -> StrengthConfig {
    StrengthConfig::paper(StrengthMode::Shear)
}

/// Results for one point of the sweep.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PatchCase {
    pub d0_over_dc: Option<f64>,
    pub poisson_ratio: f64,
    pub scaling: f64,
    pub particles: usize,
    pub volume_fraction: f64,
    pub coordination: Coordination,
    /// Pair gaps at rest (paper 000 section 3.2's explanation of the low amorphous strengths).
    #[serde(default)]
    pub gaps: GapStatistics,
    pub sample_seconds: f64,
    pub elastic: Option<ElasticResult>,
    pub tensile: Option<StrengthResult>,
    pub shear: Option<StrengthResult>,
    /// Absent in reports written before the test existed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub compaction: Option<CompactionResult>,
}

/// Results of a campaign.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PatchReport {
    pub config: PatchSuite,
    pub cases: Vec<PatchCase>,
}

/// Runs every case of the campaign; with `out`, writes `report.json` and one CSV per test and case
/// (`case<k>_<test>.csv`), plus the samples when `save_samples`.
pub fn run_suite(suite: &PatchSuite, out: Option<&Path>, par: Parallelism) -> Result<PatchReport> {
    let or_base = |v: &Vec<f64>, base: f64| if v.is_empty() { vec![base] } else { v.clone() };
    let base_d0 = match &suite.sample {
        SampleSpec::Hcp { d0_over_dc, .. }
        | SampleSpec::Amorphous { d0_over_dc, .. }
        | SampleSpec::HexMonolayer { d0_over_dc, .. } => Some(*d0_over_dc),
        SampleSpec::File { .. } => None,
    };
    let d0s: Vec<Option<f64>> = if suite.sweep.d0_over_dc.is_empty() {
        vec![base_d0]
    } else {
        suite.sweep.d0_over_dc.iter().map(|&v| Some(v)).collect()
    };
    let (done, report_path) = match out {
        Some(dir) => (
            finished_cases(dir, suite)?,
            dir.join("report.json").display().to_string(),
        ),
        None => (Vec::new(), String::new()),
    };
    if !done.is_empty() {
        tracing::info!(
            target: "stage",
            cases = done.len(),
            "continuing the campaign of {report_path}: its finished cases are reused"
        );
    }
    let card = match &suite.model {
        None => None,
        Some(ModelSource {
            pair_model: Some(m),
            ..
        }) => Some(m.clone()),
        Some(ModelSource { card, .. }) => {
            return Err(DemError::InvalidConfig(format!(
                "[model] card = {}: the card's model was not read (cgdem patch reads it)",
                card.display()
            )))
        }
    };
    if card.is_some() && !(suite.sweep.scaling.is_empty() && suite.sweep.poisson_ratio.is_empty()) {
        return Err(DemError::InvalidConfig(
            "a card's model is calibrated for its own nu and s: sweep only d0 with [model] card"
                .into(),
        ));
    }
    let material = card.as_ref().map_or(&suite.material, |m| &m.material);
    let (scalings, nus) = (
        or_base(&suite.sweep.scaling, material.scaling),
        or_base(&suite.sweep.poisson_ratio, material.poisson_ratio),
    );
    let total = d0s.len() * scalings.len() * nus.len();
    let mut cases = Vec::new();
    for d0 in &d0s {
        for &s in &scalings {
            for &nu in &nus {
                let k = cases.len();
                if let Some(c) = done.get(k) {
                    if (c.d0_over_dc, c.poisson_ratio, c.scaling) != (*d0, nu, s) {
                        return Err(DemError::Format {
                            path: report_path,
                            reason: format!("its case {k} is not the campaign's case {k}"),
                        });
                    }
                    cases.push(c.clone());
                    continue;
                }
                let model = match &card {
                    Some(m) => m.clone(),
                    None => {
                        let mut m = PairModel::cohesive(Material {
                            poisson_ratio: nu,
                            scaling: s,
                            ..suite.material.clone()
                        });
                        m.scale = suite.scale;
                        m
                    }
                };
                model.validate()?;
                let spec = match d0 {
                    Some(v) if base_d0.is_some() => suite.sample.with_d0(*v)?,
                    _ => suite.sample.clone(),
                };
                tracing::info!(target: "stage", case = k, of = total, d0_over_dc = ?d0, nu, s, "patch case");
                let t = std::time::Instant::now();
                // A relaxed sample is kept beside the report until its case is reported, so that an
                // interrupted case does not relax it again (relaxation is deterministic: same bits).
                let sample_file = out.map(|d| progress_path(d, k, "sample"));
                let sample_key = progress::settings_key(&(&spec, &model, &suite.relax))?;
                let kept = sample_file
                    .as_deref()
                    .and_then(|f| progress::load::<(Sample, f64)>(f, &sample_key));
                let (sample, sample_seconds) = match kept {
                    Some(kept) => {
                        tracing::info!(target: "stage", case = k, "sample taken from its progress file");
                        kept
                    }
                    None => {
                        let relaxing = out.map(|d| ProgressFile::new(progress_path(d, k, "relax")));
                        let sample = make_sample_resumable(
                            &spec,
                            &model,
                            &suite.relax,
                            par,
                            relaxing.as_ref(),
                        )?;
                        let seconds = t.elapsed().as_secs_f64();
                        if let Some(f) = &sample_file {
                            progress::save(f, &sample_key, &(&sample, seconds))?;
                        }
                        if let Some(r) = relaxing {
                            progress::remove(&r.path)?;
                        }
                        (sample, seconds)
                    }
                };
                if let (Some(dir), true) = (out, suite.save_samples) {
                    sample.save(&dir.join(format!("case{k}_sample.json")))?;
                }
                let coord = coordination(&sample.particles, &sample.sim_box, &model, 1e-3)?;
                let gaps = gap_statistics(&sample.particles, &sample.sim_box, &model)?;
                let mut case = PatchCase {
                    d0_over_dc: *d0,
                    poisson_ratio: nu,
                    scaling: s,
                    particles: sample.particles.len(),
                    volume_fraction: sample.volume_fraction(),
                    coordination: coord,
                    gaps,
                    sample_seconds,
                    elastic: None,
                    tensile: None,
                    shear: None,
                    compaction: None,
                };
                // The strength tests keep their progress beside the report, so an interrupted case
                // continues inside its test instead of starting over.
                let progress =
                    |name: &str| out.map(|d| ProgressFile::new(progress_path(d, k, name)));
                let (p_tensile, p_shear) = (progress("tensile"), progress("shear"));
                for kind in &suite.tests {
                    match kind {
                        PatchKind::Elastic => {
                            case.elastic = Some(elastic(&sample, &model, &suite.elastic, par)?)
                        }
                        PatchKind::Tensile => {
                            case.tensile = Some(strength_resumable(
                                &sample,
                                &model,
                                &suite.tensile,
                                par,
                                p_tensile.as_ref(),
                            )?)
                        }
                        PatchKind::Shear => {
                            case.shear = Some(strength_resumable(
                                &sample,
                                &model,
                                &suite.shear,
                                par,
                                p_shear.as_ref(),
                            )?)
                        }
                        PatchKind::Compaction => {
                            case.compaction =
                                Some(compaction(&sample, &model, &suite.compaction, par)?)
                        }
                    }
                }
                if let Some(dir) = out {
                    write_case_curves(dir, k, &case)?;
                }
                cases.push(case);
                if let Some(dir) = out {
                    write_report(
                        dir,
                        &PatchReport {
                            config: suite.clone(),
                            cases: cases.clone(),
                        },
                    )?;
                    for p in [p_tensile, p_shear].into_iter().flatten() {
                        progress::remove(&p.path)?;
                    }
                    if let Some(f) = &sample_file {
                        progress::remove(f)?;
                    }
                }
            }
        }
    }
    Ok(PatchReport {
        config: suite.clone(),
        cases,
    })
}

/// The finished cases of an earlier run of the same campaign in `dir` (its `report.json`, rewritten
/// after every case), so that an interrupted campaign continues where it stopped: cases run in a
/// fixed order, so the first `n` are done. A report of another campaign is refused, not overwritten.
fn finished_cases(dir: &Path, suite: &PatchSuite) -> Result<Vec<PatchCase>> {
    let path = dir.join("report.json");
    let bytes = match std::fs::read(&path) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(cause) => return Err(DemError::io(&path, cause)),
    };
    let report: PatchReport = serde_json::from_slice(&bytes).map_err(|e| DemError::Format {
        path: path.display().to_string(),
        reason: format!("{e} (remove it to start the campaign afresh)"),
    })?;
    if report.config != *suite {
        return Err(DemError::InvalidConfig(format!(
            "{} holds the results of another campaign; choose another output directory, or \
             remove the file to overwrite them",
            path.display()
        )));
    }
    Ok(report.cases)
}

fn write_case_curves(dir: &Path, k: usize, case: &PatchCase) -> Result<()> {
    if let Some(r) = &case.elastic {
        r.curve
            .write_csv(&dir.join(format!("case{k}_elastic.csv")))?;
    }
    if let Some(r) = &case.tensile {
        r.curve
            .write_csv(&dir.join(format!("case{k}_tensile.csv")))?;
    }
    if let Some(r) = &case.shear {
        r.curve.write_csv(&dir.join(format!("case{k}_shear.csv")))?;
    }
    if let Some(r) = &case.compaction {
        r.curve
            .write_csv(&dir.join(format!("case{k}_compaction.csv")))?;
    }
    Ok(())
}

/// Writes `report.json` (pretty, atomically) in `dir`.
pub fn write_report(dir: &Path, report: &PatchReport) -> Result<()> {
    let path = dir.join("report.json");
    let bytes = serde_json::to_vec_pretty(report).map_err(|e| DemError::Format {
        path: path.display().to_string(),
        reason: e.to_string(),
    })?;
    write_atomic(&path, &bytes)
}

/// Where case `k`'s run `name` (its relaxation, relaxed sample or a strength test) keeps its
/// progress inside the campaign directory.
pub fn progress_path(dir: &Path, k: usize, name: &str) -> PathBuf {
    dir.join(format!("case{k}_{name}.progress.json"))
}
