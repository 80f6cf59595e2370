//! One junction run as the workbench runs it (`cgdem junction CONFIG --out DIR`, and every run of a d*
//! search): the config file (units, material source, junction settings), the relaxed sample shared by
//! every run of the same recipe and seed, the run itself (resumable), and its outputs:
//! - `verdict.json`: `outcome` (`plastic_smoothing` or `wear_particle`) beside its evidence, the
//!   material's source and d* of eq 22, and the run's cost;
//! - `force.csv`: the pair force on the top wall against time and slide distance;
//! - `frames.json`: the junction members' unwrapped positions, frame by frame;
//! - `junction.dump`: LAMMPS-style frames (OVITO) with `body` and `junction` columns;
//! - `snapshot.png` (first and last frame, side view through the junction) and `force.png`.

use std::path::Path;

use calibrate::{MaterialSource, ResolvedMaterial, Units};
use dem::io::checkpoint::write_atomic;
use dem::io::progress::{self, ProgressFile};
use dem::jobs::JobCache;
use dem::material::{ForceLaw, PairModel};
use dem::sample::{Sample, SampleSpec};
use dem::scenario::junction::{run_resumable, JunctionConfig, JunctionResult};
use dem::Parallelism;
use serde::{Deserialize, Serialize};
use wear::outcome::Detachment;
use wear::Outcome;

use super::json;
pub use super::samples::{SampleJob, SampleRecord};
use crate::error::{Result, ValidationError};
use crate::figures::junction::{draw_force, draw_snapshots};

/// A junction config file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JunctionFile {
    /// Units of every number in the file; default nano (nm, ns, MPa, m/s), the paper's silica runs.
    #[serde(default = "nano")]
    pub units: Units,
    /// Where the material comes from (see `calibrate::source`).
    pub material: MaterialSource,
    /// The run; default the paper's silica set-up (D = 20 nm, d0 = 6 nm).
    #[serde(default)]
    pub junction: JunctionConfig,
}

fn nano() -> Units {
    Units::Nano
}

impl JunctionFile {
    /// Resolves the material (relative paths from `base`, the config's folder) and checks the
    /// junction settings.
    pub fn resolve(&self, base: &Path) -> Result<ResolvedMaterial> {
        let m = self
            .material
            .resolve(base, self.units, ForceLaw::Cohesive)?;
        self.junction.validate()?;
        check_monolayer(&self.material, &self.junction)?;
        Ok(m)
    }
}

/// A monolayer material goes with a monolayer junction of the same d0, and the other way round: the
/// material's closed form is for that layer.
pub fn check_monolayer(material: &MaterialSource, junction: &JunctionConfig) -> Result<()> {
    let bad = |reason: String| {
        Err(ValidationError::Config {
            path: "[material] / [junction.monolayer]".into(),
            reason,
        })
    };
    match (&material.monolayer, &junction.monolayer) {
        (Some(m), Some(_)) if (m.d0 - junction.d0).abs() > 1e-12 * m.d0 => bad(format!(
            "the monolayer material is matched for d0 = {} but the junction has d0 = {}",
            m.d0, junction.d0
        )),
        (Some(_), None) => bad(
            "a monolayer material needs [junction.monolayer] (its pair parameters hold for the \
             planar hex layer only)"
                .into(),
        ),
        (None, Some(_)) => bad(
            "[junction.monolayer] needs a [material.monolayer] matched to its layer (a 3D card's \
             parameters do not give its properties to a monolayer)"
                .into(),
        ),
        _ => Ok(()),
    }
}

/// The recipe of a junction's relaxed box: the config's lengths and size distribution, d0 in units of
/// the material's d_c (eq 18); a quasi-2D junction's hex monolayer of the config's x-y lengths.
pub fn recipe(cfg: &JunctionConfig, model: &PairModel) -> SampleSpec {
    let d_c = model.material.critical_diameter();
    let d0 = cfg.d0;
    if let Some(m) = &cfg.monolayer {
        return SampleSpec::HexMonolayer {
            d0_over_dc: d0 / d_c,
            l_over_d0: cfg.lengths[0] / d0,
            h_over_d0: cfg.lengths[1] / d0,
            w_over_d0: m.thickness_over_d0,
            polydispersity: m.polydispersity,
            seed: cfg.seed,
        };
    }
    SampleSpec::Amorphous {
        d0_over_dc: d0 / d_c,
        l_over_d0: cfg.lengths[0] / d0,
        w_over_d0: cfg.lengths[2] / d0,
        h_over_d0: Some(cfg.lengths[1] / d0),
        ds_over_d0: cfg.ds_over_d0,
        dl_over_d0: cfg.dl / d0,
        dl_over_l: None,
        seed: cfg.seed,
        insert_fraction: cfg.insert_fraction,
    }
}

impl<'a> SampleJob<'a> {
    /// The relaxed box of `cfg` for `material` (relaxed as its card requires).
    pub fn junction(cfg: &JunctionConfig, material: &'a ResolvedMaterial) -> Self {
        SampleJob {
            recipe: recipe(cfg, &material.model),
            model: &material.model,
            relax: material.relax_for(cfg.relax),
        }
    }
}

/// The relaxed box of `cfg` for `material`, from the sample cache `samples` (relaxed and stored on
/// first use; every D of a search shares it).
pub fn relaxed_sample(
    samples: &JobCache,
    cfg: &JunctionConfig,
    material: &ResolvedMaterial,
    par: Parallelism,
) -> Result<(Sample, SampleRecord)> {
    super::samples::relaxed(samples, &SampleJob::junction(cfg, material), par)
}

/// The small record of a run that searches and reports keep (the rest stays in its folder).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JunctionSummary {
    pub diameter: f64,
    pub d0: f64,
    pub seed: u64,
    pub outcome: Outcome,
    pub turn: f64,
    pub rigidity: f64,
    pub force_late_over_peak: Option<f64>,
    pub detachment: Option<Detachment>,
    pub particles: usize,
    pub junction_members: usize,
    pub steps: u64,
    pub dt: f64,
    pub slide: f64,
    pub run_seconds: f64,
    pub relax_seconds: f64,
    /// The top wall's largest descent over the run, over the junction height H: a junction squashed
    /// flat gives at most 1, and beyond `max_descent_over_height` the run stops as a collapse (none in
    /// summaries written before it was recorded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wall_descent_over_height: Option<f64>,
}

/// What `verdict.json` holds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct VerdictFile {
    pub outcome: Outcome,
    pub evidence: wear::Verdict,
    pub thresholds: wear::ClassifyParams,
    pub junction: JunctionConfig,
    pub units: Units,
    pub length_unit: String,
    /// Where the pair model came from.
    pub material: String,
    /// d* of eq 22 from the material's target properties, in the length unit.
    pub dstar_eq22_target: f64,
    /// The calibrated card's verification, when the material came from one (as the card has it).
    pub card_verification: Option<serde_json::Value>,
    pub summary: JunctionSummary,
}

/// Runs the junction of `cfg` with `material` into `out` (resumable: a progress file is kept there
/// until the run is done), with relaxed samples from `samples`. `report(step, total)` follows the run.
pub fn run_junction(
    cfg: &JunctionConfig,
    material: &ResolvedMaterial,
    samples: &JobCache,
    out: &Path,
    par: Parallelism,
    report: &mut dyn FnMut(u64, u64),
) -> Result<JunctionSummary> {
    std::fs::create_dir_all(out).map_err(|e| ValidationError::io(out, e))?;
    let (sample, record) = relaxed_sample(samples, cfg, material, par)?;
    let progress = ProgressFile::new(out.join("junction.progress.json"));
    let dump = (cfg.dump_frames > 0).then(|| out.join("junction.dump"));
    let r = run_resumable(
        &sample,
        &material.model,
        cfg,
        par,
        dump.as_deref(),
        Some(&progress),
        report,
    )?;
    let summary = JunctionSummary {
        diameter: cfg.diameter,
        d0: cfg.d0,
        seed: cfg.seed,
        outcome: r.outcome,
        turn: r.verdict.turn,
        rigidity: r.verdict.rigidity,
        force_late_over_peak: r.verdict.force_late_over_peak,
        detachment: r.verdict.detachment.clone(),
        particles: r.particles,
        junction_members: r.junction_members,
        steps: r.steps,
        dt: r.dt,
        slide: r.slide,
        run_seconds: r.wall_seconds,
        relax_seconds: record.seconds,
        wall_descent_over_height: Some(r.largest_wall_descent() / cfg.height()),
    };
    write_outputs(out, cfg, material, &r, &summary)?;
    progress::remove(&progress.path)?;
    Ok(summary)
}

fn write_outputs(
    out: &Path,
    cfg: &JunctionConfig,
    material: &ResolvedMaterial,
    r: &JunctionResult,
    summary: &JunctionSummary,
) -> Result<()> {
    let t = &material.target;
    let dstar = wear::scales::critical_junction_size(
        t.surface_energy,
        t.young_modulus,
        t.poisson_ratio,
        t.shear_strength,
    );
    let verification = material
        .card
        .as_ref()
        .and_then(|c| serde_json::to_value(c).ok())
        .and_then(|v| v.get("verification").cloned());
    let verdict = VerdictFile {
        outcome: r.outcome,
        evidence: r.verdict.clone(),
        thresholds: cfg.classify,
        junction: cfg.clone(),
        units: material.units,
        length_unit: material.units.length_name().into(),
        material: material.description.clone(),
        dstar_eq22_target: dstar,
        card_verification: verification,
        summary: summary.clone(),
    };
    json(&out.join("verdict.json"), &verdict)?;
    json(&out.join("frames.json"), &r.frames)?;
    let csv = out.join("force.csv");
    let mut text = String::from("step,time,slide,force_x,force_y,force_z\n");
    for s in &r.force {
        text.push_str(&format!(
            "{},{},{},{},{},{}\n",
            s.step, s.time, s.displacement[0], s.force[0], s.force[1], s.force[2]
        ));
    }
    write_atomic(&csv, text.as_bytes())?;
    // Reduced configs carry no unit name (sigma for the MD model material, d_c or L elsewhere), so
    // their lengths are printed bare and their axes say "reduced".
    let (units, suffix) = match material.units {
        Units::Nano => (("nm", "pN"), " nm"),
        Units::Reduced => (("reduced", "reduced"), ""),
    };
    let axis_z = 0.5 * (r.first.lo[2] + r.first.hi[2]);
    let views = [
        (
            &r.first,
            format!(
                "start: D = {0}{1}, d0 = {2}{1}",
                cfg.diameter, suffix, cfg.d0
            ),
        ),
        (
            &r.last,
            format!("after {:.1}{} of sliding: {}", r.slide, suffix, r.outcome),
        ),
    ];
    draw_snapshots(
        &out.join("snapshot.png"),
        views,
        axis_z,
        0.5 * cfg.diameter,
        suffix,
    )?;
    draw_force(&out.join("force.png"), &r.force, units)?;
    Ok(())
}
