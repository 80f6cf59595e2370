//! One calibration end to end: checked config -> sample (made once, saved, reloaded on resume) ->
//! executor -> card, history (JSON, CSV) and a `cgdem patch` config that re-runs the patch tests with
//! the calibrated multipliers.

use std::fmt::Write as _;
use std::path::Path;

use dem::sample::Sample;
use dem::sample::{make_sample, SampleSpec};
use dem::scenario::patch::suite::PatchKind;
use dem::scenario::patch::PatchSuite;
use dem::Parallelism;

use crate::card::{CalibratedCard, Provenance};
use crate::config::CalibrationConfig;
use crate::error::{CalibrateError, Result};
use crate::executor::{Checkpoint, Executor, Record};
use crate::patch_problem::{PatchProblem, Properties, Target};

/// What a calibration returns.
#[derive(Debug, Clone)]
pub struct Outcome {
    pub card: CalibratedCard,
    pub checkpoint: Checkpoint,
    pub problem: PatchProblem,
}

/// Builds the problem of `cfg` (making or reloading `out/sample.json`).
pub fn problem(cfg: &CalibrationConfig, out: &Path, par: Parallelism) -> Result<PatchProblem> {
    let p = cfg.prepare()?;
    let path = out.join("sample.json");
    let sample = if path.exists() {
        Sample::load(&path)?
    } else {
        tracing::info!("making the sample");
        let s = make_sample(&p.sample, &p.model, &cfg.relax, par)?;
        s.save(&path)?;
        s
    };
    Ok(PatchProblem {
        sample,
        model: p.model,
        target: p.target,
        targets: p.targets,
        unknowns: p.unknowns,
        tests: p.tests,
    })
}

/// Runs (or resumes) the calibration of `cfg` with all its files in `out`; `stop_after` simulates a
/// kill after that many iterations (tests).
pub fn calibrate(
    cfg: &CalibrationConfig,
    out: &Path,
    par: Parallelism,
    stop_after: Option<usize>,
) -> Result<Outcome> {
    let t0 = std::time::Instant::now();
    // Refusals and config errors come before any file or simulation.
    let p = cfg.prepare()?;
    std::fs::create_dir_all(out).map_err(|e| CalibrateError::io(out, e))?;
    let prob = problem(cfg, out, par)?;
    let mut path = cfg.clone();
    // Budget and tolerance only decide where the run stops (see `Executor::new`).
    path.solver.max_iterations = 0;
    path.solver.tolerance = 0.0;
    let description =
        toml::to_string(&path).map_err(|e| CalibrateError::InvalidConfig(e.to_string()))?;
    let x0 = vec![0.0; prob.unknowns.len()];
    let mut ex = Executor::new(&prob, x0, cfg.solver, &description).checkpoint_dir(out);
    if let Some(k) = stop_after {
        ex = ex.stop_after(k);
    }
    let fp = ex.fingerprint().to_string();
    let cp = ex.run()?;
    let r0 = &cp.r0;
    let model = prob.model_at(&cp.state.x);
    // With re-equilibration the tests ran on the sample relaxed with the calibrated model: save it,
    // so that the card and `patch.toml` reproduce the calibrated properties.
    let sample_file = if prob.tests.reequilibrate.is_some() {
        let s = prob
            .sample_for(&model)
            .map_err(|e| CalibrateError::StartFailed(format!("calibrated sample: {e}")))?;
        s.save(&out.join("sample-calibrated.json"))?;
        "sample-calibrated.json"
    } else {
        "sample.json"
    };
    let card = CalibratedCard {
        units: if cfg.material_si.is_some() {
            "nano"
        } else {
            "reduced"
        }
        .into(),
        model,
        material_si: cfg.material_si.clone(),
        sample: p.sample,
        sample_file: sample_file.into(),
        relax: cfg.relax,
        tests: p.tests,
        targets: targets(&prob),
        uncalibrated: prob.properties_of(r0),
        calibrated: prob.properties_of(&cp.state.r),
        provenance: Provenance {
            tool: format!("cgdem calibrate {}", env!("CARGO_PKG_VERSION")),
            fingerprint: fp,
            status: cp.state.status.clone(),
            iterations: cp.state.iteration,
            evaluations: cp.state.evaluations,
            wall_seconds: t0.elapsed().as_secs_f64(),
            notes: p
                .design_poisson_ratio
                .map(|nu| {
                    format!(
                        "model.material.poisson_ratio = {nu} is a design value (A_N, A_T of eqs 15-16 \
                         are computed from it); the target nu is in [targets]: the closed form \
                         gives k_T = 0 near nu = 1/4, which multipliers cannot leave"
                    )
                })
                .into_iter()
                .chain([
                "the sample was made once with the first-guess multipliers and kept fixed; \
                 reuse sample_file to reproduce the calibrated properties"
                    .to_string(),
            ])
            .collect(),
        },
    };
    card.write(&out.join("card.toml"))?;
    write_history(out, &cp, &prob)?;
    write_patch_config(out, &card)?;
    Ok(Outcome {
        card,
        checkpoint: cp,
        problem: prob,
    })
}

fn targets(p: &PatchProblem) -> Properties {
    let r = vec![0.0; p.targets.len()];
    p.properties_of(&r)
}

/// Re-runs the patch tests of `problem` with the card's model (no cache): the verification.
pub fn verify(problem: &PatchProblem, card: &CalibratedCard) -> Result<Properties> {
    let model = card.pair_model()?;
    problem
        .measure(&model)
        .map_err(|e| CalibrateError::StartFailed(format!("verification: {e}")))
}

/// `history.json` (the checkpoint's records with residual names) and `history.csv` (one line per
/// iteration: accepted, lambda, cost, residuals, multipliers).
pub fn write_history(out: &Path, cp: &Checkpoint, prob: &PatchProblem) -> Result<()> {
    let json = out.join("history.json");
    let bytes = serde_json::to_vec_pretty(&serde_json::json!({
        "residual_names": cp.residual_names,
        "unknowns": prob.unknowns.iter().map(|u| u.name()).collect::<Vec<_>>(),
        "start_residuals": cp.r0,
        "final_state": cp.state,
        "history": cp.history,
    }))
    .map_err(|e| CalibrateError::format(&json, e))?;
    dem::io::checkpoint::write_atomic(&json, &bytes)?;
    let mut csv =
        String::from("iteration,accepted,failed,lambda,cost,cost_trial,evaluations,seconds");
    for n in &cp.residual_names {
        let _ = write!(csv, ",r_{n}");
    }
    for u in &prob.unknowns {
        let _ = write!(csv, ",{}", u.name());
    }
    csv.push('\n');
    let line = |csv: &mut String, rec: &Record, x: &[f64]| {
        let _ = write!(
            csv,
            "{},{},{},{:e},{:e},{},{},{:.1}",
            rec.iteration,
            rec.accepted,
            rec.failure.is_some(),
            rec.lambda,
            rec.cost,
            rec.cost_trial.map_or(String::new(), |c| format!("{c:e}")),
            rec.evaluations,
            rec.seconds
        );
        for v in &rec.r {
            let _ = write!(csv, ",{v:e}");
        }
        for v in x {
            let _ = write!(csv, ",{}", v.exp());
        }
        csv.push('\n');
    };
    let mut x = vec![0.0; prob.unknowns.len()];
    for rec in &cp.history {
        if rec.accepted {
            x.clone_from(&rec.x_trial);
        }
        line(&mut csv, rec, &x);
    }
    dem::io::checkpoint::write_atomic(&out.join("history.csv"), csv.as_bytes())?;
    Ok(())
}

/// `patch.toml`: a `cgdem patch` campaign on the saved sample with the calibrated multipliers.
fn write_patch_config(out: &Path, card: &CalibratedCard) -> Result<()> {
    let has = |t: Target| card.targets.get(t).is_some();
    let mut tests = Vec::new();
    if has(Target::YoungModulus) || has(Target::PoissonRatio) {
        tests.push(PatchKind::Elastic);
    }
    if has(Target::TensileStrength) || has(Target::SurfaceEnergy) {
        tests.push(PatchKind::Tensile);
    }
    if has(Target::ShearStrength) {
        tests.push(PatchKind::Shear);
    }
    let suite = PatchSuite {
        material: card.model.material.clone(),
        scale: card.model.scale,
        sample: SampleSpec::File {
            path: out.join(&card.sample_file),
        },
        relax: card.relax,
        tests,
        elastic: card.tests.elastic,
        tensile: card.tests.tensile,
        shear: card.tests.shear,
        sweep: Default::default(),
        save_samples: false,
    };
    let text =
        toml::to_string_pretty(&suite).map_err(|e| CalibrateError::InvalidConfig(e.to_string()))?;
    dem::io::checkpoint::write_atomic(&out.join("patch.toml"), text.as_bytes())?;
    Ok(())
}
