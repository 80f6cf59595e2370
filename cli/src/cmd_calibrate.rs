//! `cgdem calibrate <calibration.toml> --out DIR`: least-squares calibration of the pair parameters
//! against the patch tests (crate `calibrate`, issue 5). Resumable: rerun the same command after a kill
//! and it continues from `DIR/checkpoint.json`. Writes `card.toml` (the calibrated parameter card),
//! `history.json`, `history.csv`, `sample.json`, `patch.toml` (re-runs the patch tests with
//! `cgdem patch`) and `summary.txt`.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use calibrate::{CalibrationConfig, Properties, Target};
use clap::Args;

/// Arguments of `cgdem calibrate`.
#[derive(Debug, Args)]
pub struct CalibrateArgs {
    /// TOML calibration input (see configs/calibrate-*.toml).
    pub config: PathBuf,
    /// Output directory (also the checkpoint: rerun to resume).
    #[arg(long, default_value = "out/calibrate")]
    pub out: PathBuf,
}

/// The summary table: target, uncalibrated, calibrated (and verified) values with relative errors.
pub(crate) fn table(
    targets: &Properties,
    before: &Properties,
    after: &Properties,
    verified: Option<&Properties>,
) -> String {
    let mut s = format!(
        "{:<17} {:>12} {:>12} {:>8} {:>12} {:>8}",
        "property", "target", "uncalibrated", "error", "calibrated", "error"
    );
    if verified.is_some() {
        s.push_str(&format!(" {:>12} {:>8}", "verified", "error"));
    }
    s.push('\n');
    let err = |v: Option<f64>, t: f64| {
        v.map_or("-".to_string(), |v| format!("{:+.2}%", 100.0 * (v - t) / t))
    };
    let val = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.5e}"));
    for t in [
        Target::YoungModulus,
        Target::PoissonRatio,
        Target::TensileStrength,
        Target::ShearStrength,
        Target::SurfaceEnergy,
    ] {
        let Some(tv) = targets.get(t) else { continue };
        s.push_str(&format!(
            "{:<17} {:>12} {:>12} {:>8} {:>12} {:>8}",
            t.name(),
            format!("{tv:.5e}"),
            val(before.get(t)),
            err(before.get(t), tv),
            val(after.get(t)),
            err(after.get(t), tv)
        ));
        if let Some(v) = verified {
            s.push_str(&format!(" {:>12} {:>8}", val(v.get(t)), err(v.get(t), tv)));
        }
        s.push('\n');
    }
    s
}

/// Runs a calibration into `out` and returns the outcome.
pub(crate) fn run_config(
    cfg: &CalibrationConfig,
    out: &Path,
    threads: usize,
) -> Result<calibrate::Outcome> {
    let o = calibrate::calibrate(cfg, out, crate::parallelism(threads), None)
        .with_context(|| format!("calibrating into {}", out.display()))?;
    let c = &o.card;
    let multipliers = format!(
        "multipliers: k_n {:.4} k_t {:.4} delta_e {:.4} delta_f {:.4} f_mt {:.4}",
        c.model.scale.k_n,
        c.model.scale.k_t,
        c.model.scale.delta_e,
        c.model.scale.delta_f,
        c.model.scale.f_mt
    );
    let text = format!(
        "{}\n{multipliers}\nstatus {:?}, {} iterations, {} evaluations, {:.1} s (this process)\n",
        table(&c.targets, &c.uncalibrated, &c.calibrated, None),
        c.provenance.status,
        c.provenance.iterations,
        c.provenance.evaluations,
        c.provenance.wall_seconds
    );
    print!("{text}");
    std::fs::write(out.join("summary.txt"), &text).context("writing summary.txt")?;
    println!("card: {}", out.join("card.toml").display());
    draw_figure(&o, None, &out.join("calibration.png"))?;
    Ok(o)
}

/// Draws `calibration.png` (errors before and after, and the cost per iteration).
pub(crate) fn draw_figure(
    o: &calibrate::Outcome,
    verified: Option<&calibrate::Properties>,
    path: &Path,
) -> Result<()> {
    use validation::figures::calibration::{cost_series, draw, error_rows};
    let c = &o.card;
    let rows = error_rows(&c.targets, &c.uncalibrated, &c.calibrated, verified);
    draw(path, &rows, &cost_series(&o.checkpoint.history))
        .context("drawing the calibration figure (the card above is complete)")?;
    println!("figure: {}", path.display());
    Ok(())
}

/// Runs `cgdem calibrate`.
pub fn run(args: CalibrateArgs, threads: usize) -> Result<()> {
    let cfg = CalibrationConfig::from_file(&args.config).map_err(|e| {
        // A TOML error gets the unknown key's own line (see crate::config).
        let text = std::fs::read_to_string(&args.config).unwrap_or_default();
        anyhow::anyhow!(
            "{}",
            crate::config::with_key_position(&text, &e.to_string())
        )
        .context(format!("reading {}", args.config.display()))
    })?;
    cfg.prepare()
        .with_context(|| format!("checking {}", args.config.display()))?;
    run_config(&cfg, &args.out, threads)?;
    Ok(())
}
