//! `cgdem dstar <config.toml> --out DIR`: the automatic d* search (see `validation::wear::dstar`).
//! Runs side by side on this machine's cores; under `mpirun -np N` or `srun` every rank takes its share
//! of each round and the ranks meet in DIR's cache; as a Slurm array, `--shard
//! $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT` runs one task's share of the pending round and exits
//! (a final run without `--shard` collects and continues).

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use validation::wear::dstar::{search, DstarFile};

use crate::job_args::RunArgs;

/// Arguments of `cgdem dstar`.
#[derive(Debug, Args)]
pub struct DstarArgs {
    /// TOML search config (see configs/dstar-*.toml).
    pub config: PathBuf,
    /// Output directory (also the cache of every run of the search).
    #[arg(long, default_value = "out/dstar")]
    pub out: PathBuf,
    #[command(flatten)]
    pub run: RunArgs,
}

/// Runs `cgdem dstar`.
pub fn run(args: DstarArgs, threads: usize) -> Result<()> {
    let file: DstarFile = crate::config::read(&args.config)?;
    let base = args.config.parent().unwrap_or(std::path::Path::new("."));
    let material = file
        .resolve(base)
        .with_context(|| format!("in {}", args.config.display()))?;
    let how = args.run.resolve()?;
    let shard = how.shard;
    if shard.count > 1 {
        tracing::info!(
            rank = shard.index,
            of = shard.count,
            "d* search: this process takes its share of every round"
        );
    }
    let r = search(
        &file,
        &material,
        &args.out,
        &how,
        crate::parallelism(threads),
    )?;
    if !shard.is_leader() {
        return Ok(());
    }
    let u = &r.length_unit;
    let show = |v: Option<f64>| v.map_or("-".to_string(), |x| format!("{x}"));
    println!(
        "d* bracket: ({}, {}] {u} ({}; {} runs in {} rounds, {} seeds, {:.0} s of runs and relaxations)",
        show(r.bracket[0]),
        show(r.bracket[1]),
        if r.converged { "converged" } else { "not converged" },
        r.runs.len(),
        r.rounds,
        r.seeds.len(),
        r.cost_seconds
    );
    println!("  {}", r.reason);
    println!(
        "  eq 22: {:.1} {u} from the target properties, {} from the measured ones",
        r.dstar_eq22_target,
        r.dstar_eq22_measured
            .map_or("(not measured)".to_string(), |d| format!("{d:.1} {u}"))
    );
    println!("wrote {}", args.out.join("dstar.json").display());
    Ok(())
}
