//! The options every command that runs a list of cached jobs shares (`cgdem impact`, `cgdem scratch`,
//! `cgdem dstar`, `cgdem sliding`): how many jobs run side by side, which share of the list this
//! process takes, and (where the command does not keep its cache under its output) where the cache is
//! (DESIGN.md section 7, `dem::jobs`).

use std::path::{Path, PathBuf};

use anyhow::Result;
use clap::Args;
use dem::jobs::{JobCache, RunJobs, Shard};

/// Concurrency and shard of a list of jobs.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// Jobs run side by side (default: the machine's cores; side by side, each job is
    /// single-threaded; `cgdem sliding` with --jobs 1 gives each job --threads).
    #[arg(long)]
    pub jobs: Option<usize>,
    /// This task's share, i/n (a Slurm array: --shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT);
    /// under mpirun or srun the rank comes from the launcher. A task runs its share and exits; a
    /// final run of the same command finds every job cached and writes the outputs.
    #[arg(long)]
    pub shard: Option<String>,
}

impl RunArgs {
    /// How the list runs.
    pub fn resolve(&self) -> Result<RunJobs> {
        let mut how = RunJobs::default();
        if let Some(n) = self.jobs {
            how.at_once = n.max(1);
        }
        how.shard = match &self.shard {
            Some(s) => Shard::parse(s)?,
            None => Shard::from_env(),
        };
        Ok(how)
    }
}

/// Cache, concurrency and shard of a list of jobs.
#[derive(Debug, Args)]
pub struct JobArgs {
    /// Job cache (default OUT/jobs). Finished jobs are kept there by their inputs: a rerun, or
    /// another config sharing jobs, reuses them.
    #[arg(long)]
    pub cache: Option<PathBuf>,
    #[command(flatten)]
    pub run: RunArgs,
}

impl JobArgs {
    /// The cache (under `out` unless given) and how the list runs.
    pub fn resolve(&self, out: &Path) -> Result<(JobCache, RunJobs)> {
        let cache = JobCache::new(self.cache.clone().unwrap_or_else(|| out.join("jobs")));
        Ok((cache, self.run.resolve()?))
    }
}
