//! One calibration end to end: checked config -> recipe-level problem (relaxed samples cached under
//! `out/samples/`) -> executor -> verification on fresh samples (cached under `out/verify/`) -> card,
//! history (JSON, CSV) and a `cgdem patch` config that re-measures the card on a sample of its recipe.

use std::fmt::Write as _;
use std::path::Path;

use dem::sample::{Sample, SampleSpec};
use dem::scenario::patch::suite::PatchKind;
use dem::scenario::patch::{ModelSource, PatchSuite};
use dem::Parallelism;

use crate::card::{CalibratedCard, Provenance};
use crate::config::{CalibrationConfig, Prepared};
use crate::error::{CalibrateError, Result};
use crate::executor::{Checkpoint, Executor, Record};
use crate::patch_problem::{PatchProblem, Properties};
use crate::problem::{EvalFailure, Measured};
use crate::recipe::SampleCache;
use crate::verification::{verify, Verification, VerifyInputs};

/// What a calibration returns.
#[derive(Debug)]
pub struct Outcome {
    pub card: CalibratedCard,
    pub checkpoint: Checkpoint,
    pub problem: PatchProblem,
}

/// Builds the problem of `cfg`, with relaxed samples cached under `out/samples/` (in memory only
/// without `out`).
pub fn problem(cfg: &CalibrationConfig, out: Option<&Path>) -> Result<PatchProblem> {
    problem_of(cfg.prepare()?, cfg, out)
}

fn problem_of(p: Prepared, cfg: &CalibrationConfig, out: Option<&Path>) -> Result<PatchProblem> {
    let d0 = match (p.d0, &p.sample) {
        (Some(d0), _) => d0,
        (None, SampleSpec::File { path }) => Sample::load(path)?.d0,
        (None, _) => unreachable!("generated recipes have a d0"),
    };
    Ok(PatchProblem {
        samples: p.samples,
        relax: cfg.relax,
        cache: SampleCache::new(out.map(|o| o.join("samples"))),
        d0,
        model: p.model,
        target: p.target,
        targets: p.targets,
        unknowns: p.unknowns,
        tests: p.tests,
    })
}

/// A rayon pool of `par`'s threads (one for `Sequential`).
pub fn pool(par: Parallelism) -> Result<rayon::ThreadPool> {
    let n = par.threads();
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build()
        .map_err(|e| CalibrateError::InvalidConfig(format!("cannot start {n} threads: {e}")))
}

/// Runs (or resumes) the calibration of `cfg` with all its files in `out`, its evaluations on `par`'s
/// threads; `stop_after` simulates a kill after that many iterations (tests).
pub fn calibrate(
    cfg: &CalibrationConfig,
    out: &Path,
    par: Parallelism,
    stop_after: Option<usize>,
) -> Result<Outcome> {
    // Refusals and config errors come before any file or simulation.
    let p = cfg.prepare()?;
    std::fs::create_dir_all(out).map_err(|e| CalibrateError::io(out, e))?;
    let prob = problem_of(p.clone(), cfg, Some(out))?;
    let mut path = cfg.clone();
    // Budget, tolerance and the verification only decide where the run stops and what is measured
    // after it (see `Executor::new`).
    path.solver.max_iterations = 0;
    path.solver.tolerance = 0.0;
    path.verification = Default::default();
    let description =
        toml::to_string(&path).map_err(|e| CalibrateError::InvalidConfig(e.to_string()))?;
    let x0 = vec![0.0; prob.unknowns.len()];
    let mut ex = Executor::new(&prob, x0, cfg.solver, &description)
        .checkpoint_dir(out)
        .parallelism(par);
    if let Some(k) = stop_after {
        ex = ex.stop_after(k);
    }
    let fp = ex.fingerprint().to_string();
    let cp = ex.run()?;
    let model = prob.model_at(&cp.state.x);
    let t1 = std::time::Instant::now();
    let verification = if cfg.verification.skip || stop_after.is_some() {
        None
    } else {
        tracing::info!(
            target: "stage",
            samples = cfg.verification.samples.len(),
            "verifying the card on fresh samples"
        );
        let inputs = VerifyInputs {
            recipe: &p.sample,
            relax: &cfg.relax,
            tests: &p.tests,
            target: &prob.target,
            d0: prob.d0,
            settings: &cfg.verification,
        };
        let dir = out.join("verify");
        Some(pool(par)?.install(|| verify(&model, inputs, &prob.cache, Some(&dir)))?)
    };
    let verification_seconds = t1.elapsed().as_secs_f64();
    let mut notes: Vec<String> = p
        .design_poisson_ratio
        .map(|nu| {
            format!(
                "model.material.poisson_ratio = {nu} is a design value (A_N, A_T of eqs 15-16 are \
                 computed from it); the target nu is in [targets]: the closed form gives k_T = 0 \
                 near nu = 1/4, which multipliers cannot leave"
            )
        })
        .into_iter()
        .collect();
    notes.push(format!(
        "recipe-level calibration: every evaluation relaxed {} sample(s) of the recipe with the \
         trial parameters; 'uncalibrated' and 'calibrated' are their means",
        prob.samples.len()
    ));
    let card = CalibratedCard {
        units: if cfg.material_si.is_some() {
            "nano"
        } else {
            "reduced"
        }
        .into(),
        seeds: p.seeds.clone(),
        model,
        material_si: cfg.material_si.clone(),
        sample: p.sample.clone(),
        relax: cfg.relax,
        tests: p.tests,
        targets: targets(&prob),
        uncalibrated: prob.properties_of(&cp.r0),
        calibrated: prob.properties_of(&cp.state.r),
        verification,
        provenance: Provenance {
            tool: format!("cgdem calibrate {}", env!("CARGO_PKG_VERSION")),
            fingerprint: fp,
            status: cp.state.status.clone(),
            iterations: cp.state.iteration,
            evaluations: cp.state.evaluations,
            wall_seconds: cp.state.wall_seconds + verification_seconds,
            verification_seconds,
            notes,
        },
    };
    if stop_after.is_none() {
        card.write(&out.join("card.toml"))?;
        write_patch_config(out, &card, &cfg.verification)?;
    }
    write_history(out, &cp, &prob)?;
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

/// Re-measures the card's model on the calibration's own samples (from the sample cache, no
/// evaluation cache) on `par`'s threads: the mean properties, which equal the card's `calibrated`
/// bit for bit (the evaluations are deterministic).
pub fn remeasure(
    problem: &PatchProblem,
    card: &CalibratedCard,
    par: Parallelism,
) -> Result<Properties> {
    let model = card.pair_model()?;
    let rows = pool(par)?
        .install(|| problem.measure(&model))
        .map_err(|EvalFailure(e)| CalibrateError::StartFailed(format!("re-measurement: {e}")))?;
    let rows = rows
        .iter()
        .map(|p| problem.residuals_of(p))
        .collect::<std::result::Result<Vec<_>, _>>()
        .map_err(|EvalFailure(e)| CalibrateError::StartFailed(e))?;
    Ok(problem.properties_of(&Measured::mean_of(rows).r))
}

/// The verification of a card on fresh samples, outside a calibration (e.g. with other settings).
pub fn verify_card(
    problem: &PatchProblem,
    card: &CalibratedCard,
    settings: &crate::recipe::VerifySettings,
    dir: Option<&Path>,
    par: Parallelism,
) -> Result<Verification> {
    let model = card.pair_model()?;
    let inputs = VerifyInputs {
        recipe: &card.sample,
        relax: &card.relax,
        tests: &card.tests,
        target: &problem.target,
        d0: problem.d0,
        settings,
    };
    pool(par)?.install(|| verify(&model, inputs, &problem.cache, dir))
}

/// `history.json` (the checkpoint's records with residual names) and `history.csv` (one line per
/// iteration: accepted, lambda or radius, cost, residuals, their noise, multipliers).
pub fn write_history(out: &Path, cp: &Checkpoint, prob: &PatchProblem) -> Result<()> {
    let json = out.join("history.json");
    let bytes = serde_json::to_vec_pretty(&serde_json::json!({
        "residual_names": cp.residual_names,
        "unknowns": prob.unknowns.iter().map(|u| u.name()).collect::<Vec<_>>(),
        "start_residuals": cp.r0,
        "start_noise": cp.noise0,
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
    for n in &cp.residual_names {
        let _ = write!(csv, ",noise_{n}");
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
        for k in 0..rec.r.len() {
            let _ = match rec.noise_trial.get(k) {
                Some(v) => write!(csv, ",{v:e}"),
                None => write!(csv, ","),
            };
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

/// `patch.toml`: a `cgdem patch` campaign that re-measures the card (`[model] card`) on the first
/// verification sample of its recipe, with the calibration's test settings and the tensile test run
/// to separation. Change `[sample] seed` (or pass `--seed`) to measure it on another sample.
fn write_patch_config(
    out: &Path,
    card: &CalibratedCard,
    verification: &crate::recipe::VerifySettings,
) -> Result<()> {
    let sample = match verification.samples.first() {
        Some(v) => card.sample.with_seed(v.seed).resized(v.length, v.width)?,
        None => card.sample.clone(),
    };
    let mut tensile = card.tests.tensile;
    tensile.post_peak_strain = verification.post_peak_strain;
    let suite = PatchSuite {
        material: card.model.material.clone(),
        scale: card.model.scale,
        model: Some(ModelSource {
            card: "card.toml".into(),
            pair_model: None,
        }),
        sample,
        relax: card.relax,
        tests: vec![PatchKind::Elastic, PatchKind::Tensile, PatchKind::Shear],
        elastic: card.tests.elastic,
        tensile,
        shear: card.tests.shear,
        compaction: Default::default(),
        sweep: Default::default(),
        save_samples: false,
    };
    let text =
        toml::to_string_pretty(&suite).map_err(|e| CalibrateError::InvalidConfig(e.to_string()))?;
    dem::io::checkpoint::write_atomic(&out.join("patch.toml"), text.as_bytes())?;
    Ok(())
}
