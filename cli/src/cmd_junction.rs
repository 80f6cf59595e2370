//! `cgdem junction <config.toml> --out DIR`: one junction shear run of paper 000 section 4 (see
//! `validation::wear::junction` for the file and its outputs). The relaxed sample is cached in
//! `--samples` (default `DIR/../samples`, so that neighbouring runs of the same recipe and seed share
//! it); rerunning after Ctrl-C or a crash continues the run from its progress file.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use dem::jobs::JobCache;
use validation::wear::junction::{run_junction, JunctionFile};

/// Arguments of `cgdem junction`.
#[derive(Debug, Args)]
pub struct JunctionArgs {
    /// TOML junction config (see configs/junction-*.toml).
    pub config: PathBuf,
    /// Output directory.
    #[arg(long, default_value = "out/junction")]
    pub out: PathBuf,
    /// Cache of relaxed samples (default: `samples/` beside the output directory).
    #[arg(long)]
    pub samples: Option<PathBuf>,
    /// Seed of the relaxed sample, in place of the config's `[junction] seed` (a new packing of the
    /// same recipe: run several to see how far an outcome depends on the draw).
    #[arg(long)]
    pub seed: Option<u64>,
}

/// Runs `cgdem junction`.
pub fn run(args: JunctionArgs, threads: usize) -> Result<()> {
    let mut file: JunctionFile = crate::config::read(&args.config)?;
    if let Some(seed) = args.seed {
        file.junction.seed = seed;
    }
    let base = args.config.parent().unwrap_or(std::path::Path::new("."));
    let material = file
        .resolve(base)
        .with_context(|| format!("in {}", args.config.display()))?;
    let cfg = &file.junction;
    let unit = material.units.length_name();
    tracing::info!(
        D = cfg.diameter,
        d0 = cfg.d0,
        seed = cfg.seed,
        "junction shear ({unit}); material: {}",
        material.description
    );
    let samples = args.samples.clone().unwrap_or_else(|| {
        args.out
            .parent()
            .map_or_else(|| PathBuf::from("samples"), |p| p.join("samples"))
    });
    let bar = crate::progress::Bar::new("junction", "steps");
    let s = run_junction(
        cfg,
        &material,
        &JobCache::new(&samples),
        &args.out,
        crate::parallelism(threads),
        &mut |step, total| bar.update(step, total),
    )?;
    bar.finish();
    println!(
        "{}: D = {} {unit}, d0 = {} {unit}, seed {}: turn {:.2} rad, rigidity {:.2}, debris {} \
         ({} particles, {} junction members, {} steps, {:.1} s + {:.1} s relaxation)",
        s.outcome,
        s.diameter,
        s.d0,
        s.seed,
        s.turn,
        s.rigidity,
        s.detachment.as_ref().map_or("-".into(), |d| format!(
            "{:.0} %",
            100.0 * d.debris_fraction
        )),
        s.particles,
        s.junction_members,
        s.steps,
        s.run_seconds,
        s.relax_seconds
    );
    println!("wrote {}", args.out.join("verdict.json").display());
    Ok(())
}
