//! `cgdem impact CONFIG --out DIR`: impacts of a rigid sphere on the plastic-wear surface of paper 001
//! (sections 4.1-4.2, 4.4). The TOML is [`dem::scenario::plastic::ImpactFile`]: one impact, or a
//! `[sweep]` of angles, speeds, hardness, mu_a and landing points, each impact a cached job.
//!
//! Outputs in DIR: for one impact, `impact.json` (inputs in SI, wear volume, COR, deviation angle,
//! energy terms and their time series) and `fig12` (energies against time); for a sweep, `sweep.json`
//! (the sweep points, means over landing points, and every run without its time series) and the
//! figures the sweep calls for (Fig. 4 for normal impacts over H or V, Figs. 5-7 over angles, Fig. 12
//! for up to six single impacts). Figures are PNG, SVG and the CSV they plot.

use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

use anyhow::{Context, Result};
use clap::Args;
use dem::jobs::JobCache;
use dem::scenario::plastic::{run_impacts, ImpactFile, ImpactResult};
use validation::figures::plastic::{fig12, impact_figures, write_all};

use crate::job_args::JobArgs;

/// Arguments of `cgdem impact`.
#[derive(Debug, Args)]
pub struct ImpactArgs {
    /// TOML impact or sweep (see configs/impact-*.toml).
    pub config: PathBuf,
    /// Output directory.
    #[arg(long, default_value = "out/impact")]
    pub out: PathBuf,
    #[command(flatten)]
    pub jobs: JobArgs,
}

/// Runs `cgdem impact`.
pub fn run(args: ImpactArgs) -> Result<()> {
    let file: ImpactFile = crate::config::read(&args.config)?;
    let jobs = file.jobs()?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let (cache, how) = args.jobs.resolve(&args.out)?;
    let pending = jobs
        .iter()
        .filter(|j| JobCache::key(j).is_ok_and(|k| !cache.is_done(&k)))
        .count();
    eprintln!(
        "{} impacts, {} cached, {pending} to run (cache {})",
        jobs.len(),
        jobs.len() - pending,
        cache.root().display()
    );
    let count = AtomicUsize::new(0);
    let done = |cfg: &dem::scenario::plastic::ImpactConfig, r: &ImpactResult| {
        let k = count.fetch_add(1, Ordering::Relaxed) + 1;
        eprintln!(
            "[{k}/{pending}] {}: W_V {:.4e} m^3, COR {:.4}",
            cfg.label(),
            r.wear_volume,
            r.cor
        );
    };
    let results = run_impacts(&jobs, &cache, &how, &done)?;
    let Some(runs) = results.into_iter().collect::<Option<Vec<ImpactResult>>>() else {
        println!(
            "this shard's impacts are done; run the command again once every shard has finished"
        );
        return Ok(());
    };
    if !how.shard.is_leader() {
        return Ok(());
    }
    let mut figures = Vec::new();
    if file.sweep.is_none() {
        let r = &runs[0];
        write_json(&args.out.join("impact.json"), r)?;
        println!(
            "wear volume {:.4e} m^3 (eq 16: {:.4e}), COR {:.4}, deviation {:.3} deg, energy balance within {:.2e}",
            r.wear_volume,
            r.reference_wear_volume,
            r.cor,
            r.deviation_deg,
            r.energy.max_balance_error
        );
        println!("results: {}", args.out.join("impact.json").display());
        figures.push(fig12(&runs));
    } else {
        let points = file.points(&runs);
        for p in &points {
            println!(
                "V {:>6} m/s  angle {:>5} deg  H {:.3e} Pa  mu_a {:<5} W_V {:.4e} m^3 (sd {:.1e})  COR {:.4}  deviation {:7.3} deg",
                p.speed, p.angle_deg, p.hardness, p.mu_a, p.wear_volume, p.wear_volume_sd, p.cor, p.deviation_deg
            );
        }
        let light: Vec<ImpactResult> = runs
            .iter()
            .map(|r| ImpactResult {
                series: Default::default(),
                ..r.clone()
            })
            .collect();
        write_json(
            &args.out.join("sweep.json"),
            &serde_json::json!({ "points": points, "runs": light }),
        )?;
        println!("results: {}", args.out.join("sweep.json").display());
        figures.extend(impact_figures(&points, &file.base()));
        if runs.len() <= 6 {
            figures.push(fig12(&runs));
        }
    }
    let files = write_all(&figures, &args.out)
        .context("drawing the figures (the results above are complete)")?;
    for f in files {
        println!("figure: {} (and .svg, .csv)", f.png.display());
    }
    Ok(())
}

/// Writes `value` as pretty JSON.
pub fn write_json(path: &std::path::Path, value: &impl serde::Serialize) -> Result<()> {
    let text = serde_json::to_string_pretty(value)?;
    std::fs::write(path, text).with_context(|| format!("writing {}", path.display()))
}
