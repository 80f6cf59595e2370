//! `cgdem scratch CONFIG --out DIR`: scratch tests on the plastic-wear surface of paper 001 (sections
//! 3.1, 4.3, 4.4). The TOML is [`dem::scenario::plastic::ScratchFile`]: indentation speed and loads,
//! slide, and an optional `[sweep]` of mu_a and hardness; every load is a cached job that keeps a
//! progress file (Ctrl-C, then the same command, resumes it).
//!
//! Outputs in DIR: `scratch.json` (for one test: `loads`, `wear_per_distance` per load, the shear
//! hardness fit and every run with its series; for a sweep: `tests`, one such object each) and the
//! figures: Fig. 10 (wear per distance against load), Fig. 3 (threshold and shear hardness), Fig. 13
//! (energies against the external work) and Figs. 8-9 (indentation and slide) as PNG, SVG and CSV.

use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

use anyhow::{Context, Result};
use clap::Args;
use dem::jobs::JobCache;
use dem::scenario::plastic::{run_scratches, scratch_jobs, ScratchConfig, ScratchFile, ScratchRun};
use validation::figures::plastic::{scratch_figures, write_all};

use crate::cmd_impact::write_json;
use crate::job_args::JobArgs;

/// Arguments of `cgdem scratch`.
#[derive(Debug, Args)]
pub struct ScratchArgs {
    /// TOML scratch test (see configs/scratch*.toml).
    pub config: PathBuf,
    /// Output directory.
    #[arg(long, default_value = "out/scratch")]
    pub out: PathBuf,
    #[command(flatten)]
    pub jobs: JobArgs,
}

/// Runs `cgdem scratch`.
pub fn run(args: ScratchArgs) -> Result<()> {
    let file: ScratchFile = crate::config::read(&args.config)?;
    let tests = file.tests()?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let (cache, how) = args.jobs.resolve(&args.out)?;
    let jobs = scratch_jobs(&tests);
    let pending = jobs
        .iter()
        .filter(|j| JobCache::key(j).is_ok_and(|k| !cache.is_done(&k)))
        .count();
    eprintln!(
        "{} scratches, {} cached, {pending} to run (cache {}; an interrupted one resumes)",
        jobs.len(),
        jobs.len() - pending,
        cache.root().display()
    );
    let count = AtomicUsize::new(0);
    let done = |cfg: &ScratchConfig, r: &ScratchRun| {
        let k = count.fetch_add(1, Ordering::Relaxed) + 1;
        eprintln!(
            "[{k}/{pending}] load {} N, mu_a {}: {:.4e} m^3/m, F_x {:.1} N",
            cfg.indent.loads[0], cfg.model.mu_a, r.wear_per_distance, r.lateral_force
        );
    };
    let Some(results) = run_scratches(&tests, &cache, &how, &done)? else {
        println!(
            "this shard's scratches are done; run the command again once every shard has finished"
        );
        return Ok(());
    };
    if !how.shard.is_leader() {
        return Ok(());
    }
    for t in &results {
        for r in &t.runs {
            println!(
                "mu_a {:<5} H {:.3e} Pa  load {:>9.1} N  wear/distance {:.4e} m^3/m  F_x {:9.1} N  A_z {:.4e} m^2  depth {:.4e} m  balance {:.1e}",
                r.mu_a, r.hardness, r.load, r.wear_per_distance, r.lateral_force, r.contact_area, r.depth, r.energy.max_balance_error
            );
        }
        if let Some(h) = &t.shear_hardness {
            println!(
                "shear hardness dF_x/dA_z = {:.4e} Pa (mu_a H = {:.4e} Pa), threshold load {:.1} N",
                h.slope, h.reference, h.threshold_load
            );
        }
    }
    let path = args.out.join("scratch.json");
    if results.len() == 1 {
        write_json(&path, &results[0])?;
    } else {
        write_json(&path, &serde_json::json!({ "tests": results }))?;
    }
    println!("results: {}", path.display());
    let files = write_all(&scratch_figures(&results), &args.out)
        .context("drawing the figures (the results above are complete)")?;
    for f in files {
        println!("figure: {} (and .svg, .csv)", f.png.display());
    }
    Ok(())
}
