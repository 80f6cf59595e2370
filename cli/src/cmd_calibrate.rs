//! `cgdem calibrate <calibration.toml> --out DIR`: least-squares calibration of the pair parameters
//! against the patch tests on the recipe's samples (crate `calibrate`, issues 5 and 16), then the
//! card's verification on fresh samples. Resumable: rerun the same command after a kill or a Ctrl-C
//! and it continues from `DIR/checkpoint.json` (evaluations in `DIR/evals/`, relaxed samples in
//! `DIR/samples/`, verification samples in `DIR/verify/`). Writes `card.toml` (the calibrated card,
//! with its `[verification]` table), `history.json`, `history.csv`, `patch.toml` (re-measures the card
//! with `cgdem patch` on a sample of its recipe), `summary.txt` and `calibration.png`.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use calibrate::{CalibrationConfig, Properties, Target, Verification};
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

/// The summary table: target, uncalibrated and calibrated means over the calibration samples, and
/// the verification on fresh samples (mean, its error, spread = largest error of one sample).
pub(crate) fn table(
    targets: &Properties,
    before: &Properties,
    after: &Properties,
    verified: Option<&Verification>,
) -> String {
    let mut s = format!(
        "{:<17} {:>12} {:>12} {:>8} {:>12} {:>8}",
        "property", "target", "uncalibrated", "error", "calibrated", "error"
    );
    if verified.is_some() {
        s.push_str(&format!(
            " {:>12} {:>8} {:>8}",
            "verified", "error", "spread"
        ));
    }
    s.push('\n');
    let pct = |e: f64| format!("{:+.2}%", 100.0 * e);
    let err = |v: Option<f64>, t: f64| v.map_or("-".to_string(), |v| pct((v - t) / t));
    let val = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.5e}"));
    for t in Target::ALL {
        let check = verified.map(|v| v.get(t));
        let Some(tv) = targets.get(t).or(check.map(|c| c.target)) else {
            continue;
        };
        s.push_str(&format!(
            "{:<17} {:>12} {:>12} {:>8} {:>12} {:>8}",
            t.name(),
            format!("{tv:.5e}"),
            val(before.get(t)),
            err(before.get(t), tv),
            val(after.get(t)),
            err(after.get(t), tv)
        ));
        if let Some(c) = check {
            s.push_str(&format!(
                " {:>12} {:>8} {:>8}",
                format!("{:.5e}", c.mean),
                pct(c.mean_error()),
                format!("{:.2}%", 100.0 * c.spread)
            ));
        }
        s.push('\n');
    }
    s
}

/// The verification's samples, failures and d*, under the table.
pub(crate) fn verification_lines(v: &Verification, units: &str) -> String {
    let length = if units == "nano" {
        "nm"
    } else {
        "length units"
    };
    let mut s = format!(
        "verified on {} fresh sample(s) (seeds {:?}): d* (eq 22) {:.4e} {length} from the measured \
         means, {:.4e} {length} from the targets\n",
        v.samples.len(),
        v.seeds,
        v.dstar,
        v.dstar_target
    );
    for sample in &v.samples {
        s.push_str(&format!(
            "  {}: {} particles, vf {:.4}{}{}{}\n",
            calibrate::recipe::describe(&sample.spec),
            sample.particles,
            sample.volume_fraction,
            sample.deep_overlaps.map_or(String::new(), |d| format!(
                ", {d:.3} deep overlaps per particle"
            )),
            sample.compaction.map_or(String::new(), |c| format!(
                ", compaction under shear {:.2} %",
                100.0 * c
            )),
            match (&sample.failure, sample.separated) {
                (Some(f), _) => format!(", FAILED: {f}"),
                (None, true) => String::new(),
                (None, false) =>
                    ", tensile test not separated (surface energy a lower bound)".into(),
            }
        ));
    }
    if let Some(c) = &v.compaction {
        s.push_str(&format!(
            "{}: {}\n",
            if c.holds() {
                "holds under shear"
            } else {
                "COLLAPSES under shear"
            },
            c.describe()
        ));
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
    let mut text = format!(
        "{}\n{multipliers}\nstatus {:?}, {} iterations, {} evaluations ({} sample(s) each), {:.1} s (over every run of it)\n",
        table(
            &c.targets,
            &c.uncalibrated,
            &c.calibrated,
            c.verification.as_ref()
        ),
        c.provenance.status,
        c.provenance.iterations,
        c.provenance.evaluations,
        o.problem.samples.len(),
        c.provenance.wall_seconds
    );
    if let Some(v) = &c.verification {
        text.push_str(&verification_lines(v, &c.units));
    }
    print!("{text}");
    std::fs::write(out.join("summary.txt"), &text).context("writing summary.txt")?;
    println!("card: {}", out.join("card.toml").display());
    draw_figure(&o, &out.join("calibration.png"))?;
    Ok(o)
}

/// Draws `calibration.png` (errors before and after, verified, and the cost per iteration).
pub(crate) fn draw_figure(o: &calibrate::Outcome, path: &Path) -> Result<()> {
    use validation::figures::calibration::{cost_series, draw, error_rows};
    let c = &o.card;
    let verified = c.verification.as_ref().map(Verification::means);
    let verified_targets = c.verification.as_ref().map(Verification::targets);
    let rows = error_rows(
        &c.targets,
        &c.uncalibrated,
        &c.calibrated,
        verified.as_ref(),
        verified_targets.as_ref(),
    );
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
