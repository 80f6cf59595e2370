//! Runs as jobs (DESIGN.md section 7): a scenario run is a pure function of its inputs (config, card,
//! seed), so its result is stored under a key made from those inputs, and a sweep or a search is a list
//! of such jobs. The same list runs:
//! - locally, several jobs side by side on the machine's cores ([`RunJobs::at_once`]); every job's
//!   engine is single-threaded then, and results are bit-identical to any other arrangement, because
//!   the engine is deterministic for any thread count;
//! - on a cluster under `mpirun -np N` or `srun` (one allocation, N tasks): every task runs the same
//!   command, takes the jobs whose index modulo N is its rank ([`Shard::from_env`]), and waits for the
//!   others' results to appear in the shared cache before the next round of a search;
//! - as a Slurm job array (`--shard i/n` from `SLURM_ARRAY_TASK_ID`): the task runs its share of the
//!   pending jobs and exits; a final run of the same command finds everything cached and writes the
//!   results.
//!
//! No scheduler and no network code: the partition is static and results meet in the file system.
//!
//! Layout of a cache: `<root>/<key>/inputs.json` (what the job was), `<root>/<key>/result.json` (what it
//! gave; its presence marks the job done), `<root>/<key>/ran_by` (the shard index and count that ran
//! it), `<root>/<key>/failed` (the error of a failed attempt: ranks waiting for the job stop and report
//! it instead of waiting forever; the next attempt removes it) and whatever the job writes in
//! `<root>/<key>/` (progress files, dumps, figures). Keys are the first 16 bytes of the SHA-256 of the inputs' JSON (shortest
//! round-trip floats, so equal inputs give equal keys on every machine).

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use rayon::prelude::*;
use serde::de::DeserializeOwned;
use serde::Serialize;
use sha2::{Digest, Sha256};

use crate::error::{DemError, Result};
use crate::io::checkpoint::write_atomic;

/// A directory of finished jobs, keyed by their inputs.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct JobCache {
    root: PathBuf,
}

/// What identifies one job: the hex key and the inputs it was made from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct JobKey(pub String);

impl std::fmt::Display for JobKey {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

fn to_json(v: &impl Serialize, what: &str) -> Result<Vec<u8>> {
    serde_json::to_vec_pretty(v)
        .map_err(|e| DemError::InvalidConfig(format!("cannot serialise the {what}: {e}")))
}

impl JobCache {
    /// A cache rooted at `root` (created on first use).
    pub fn new(root: impl Into<PathBuf>) -> Self {
        JobCache { root: root.into() }
    }

    /// The cache's directory.
    pub fn root(&self) -> &Path {
        &self.root
    }

    /// The key of a job with these inputs: a hash of their JSON, so that equal inputs share a result.
    pub fn key(inputs: &impl Serialize) -> Result<JobKey> {
        let json = serde_json::to_vec(inputs)
            .map_err(|e| DemError::InvalidConfig(format!("cannot serialise job inputs: {e}")))?;
        let digest = Sha256::digest(&json);
        Ok(JobKey(
            digest[..16].iter().map(|b| format!("{b:02x}")).collect(),
        ))
    }

    /// The working directory of a job (created): progress files, dumps and figures go there.
    pub fn dir(&self, key: &JobKey) -> Result<PathBuf> {
        let d = self.root.join(&key.0);
        std::fs::create_dir_all(&d).map_err(|e| DemError::io(&d, e))?;
        Ok(d)
    }

    fn result_path(&self, key: &JobKey) -> PathBuf {
        self.root.join(&key.0).join("result.json")
    }

    fn failure_path(&self, key: &JobKey) -> PathBuf {
        self.root.join(&key.0).join("failed")
    }

    /// The error of the job's last failed attempt, if its folder holds one.
    pub fn failure(&self, key: &JobKey) -> Option<String> {
        std::fs::read_to_string(self.failure_path(key)).ok()
    }

    /// Whether the job has a stored result.
    pub fn is_done(&self, key: &JobKey) -> bool {
        self.result_path(key).is_file()
    }

    /// The stored result of a job, if it has one. A result that cannot be read is an error naming the
    /// file (a damaged cache is not silently recomputed over: the user decides).
    pub fn get<R: DeserializeOwned>(&self, key: &JobKey) -> Result<Option<R>> {
        let path = self.result_path(key);
        let bytes = match std::fs::read(&path) {
            Ok(b) => b,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(e) => return Err(DemError::io(&path, e)),
        };
        serde_json::from_slice(&bytes)
            .map(Some)
            .map_err(|e| DemError::Format {
                path: path.display().to_string(),
                reason: format!("{e} (remove the job's directory to run it again)"),
            })
    }

    /// Stores a job's inputs and result (atomically: a reader sees the whole file or none).
    pub fn put<I: Serialize, R: Serialize>(
        &self,
        key: &JobKey,
        inputs: &I,
        result: &R,
    ) -> Result<()> {
        let d = self.dir(key)?;
        write_atomic(&d.join("inputs.json"), &to_json(inputs, "job inputs")?)?;
        write_atomic(&self.result_path(key), &to_json(result, "job result")?)
    }
}

/// This process's share of a job list: jobs whose index modulo `count` is `index`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
    /// Whether the other shards run at the same time (mpirun, srun), so a search may wait for their
    /// results; false for a Slurm array task, which runs its share of the pending jobs and returns.
    pub concurrent: bool,
}

impl Default for Shard {
    fn default() -> Self {
        Shard::whole()
    }
}

impl Shard {
    /// The whole list (one process).
    pub fn whole() -> Self {
        Shard {
            index: 0,
            count: 1,
            concurrent: true,
        }
    }

    /// Parses `i/n` (a Slurm array task: `--shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT`).
    pub fn parse(s: &str) -> Result<Self> {
        let bad = || {
            DemError::InvalidConfig(format!(
                "shard '{s}' must be i/n with 0 <= i < n (e.g. --shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT)"
            ))
        };
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let (index, count): (usize, usize) = (
            i.trim().parse().map_err(|_| bad())?,
            n.trim().parse().map_err(|_| bad())?,
        );
        if count == 0 || index >= count {
            return Err(bad());
        }
        Ok(Shard {
            index,
            count,
            concurrent: false,
        })
    }

    /// The rank and size a launcher gives this process: MPICH's and Intel MPI's `PMI_RANK`/`PMI_SIZE`,
    /// Open MPI's `OMPI_COMM_WORLD_RANK`/`OMPI_COMM_WORLD_SIZE`, or Slurm's `SLURM_PROCID`/`SLURM_NTASKS`
    /// under `srun`; the whole list otherwise. The binary needs no MPI library: the launcher only
    /// starts N copies, and the shared cache is where their results meet.
    pub fn from_env() -> Self {
        Self::from_vars(|k| std::env::var(k).ok())
    }

    fn from_vars(get: impl Fn(&str) -> Option<String>) -> Self {
        let pairs = [
            ("PMI_RANK", "PMI_SIZE"),
            ("OMPI_COMM_WORLD_RANK", "OMPI_COMM_WORLD_SIZE"),
            ("SLURM_PROCID", "SLURM_NTASKS"),
        ];
        for (r, s) in pairs {
            let parsed = (
                get(r).and_then(|v| v.parse::<usize>().ok()),
                get(s).and_then(|v| v.parse::<usize>().ok()),
            );
            if let (Some(index), Some(count)) = parsed {
                if count > 0 && index < count {
                    return Shard {
                        index,
                        count,
                        concurrent: true,
                    };
                }
            }
        }
        Shard::whole()
    }

    /// Whether job `j` of a list is this shard's.
    pub fn owns(&self, j: usize) -> bool {
        j % self.count == self.index
    }

    /// Whether this process writes the collected outputs (rank 0; every process when alone).
    pub fn is_leader(&self) -> bool {
        self.index == 0
    }
}

/// How a list of jobs runs on this process.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RunJobs {
    /// Jobs side by side (each single-threaded); default: the cores of the machine.
    pub at_once: usize,
    /// This process's share.
    pub shard: Shard,
    /// How often to look for the other shards' results while waiting.
    pub poll: Duration,
}

impl Default for RunJobs {
    fn default() -> Self {
        RunJobs {
            at_once: std::thread::available_parallelism().map_or(1, |n| n.get()),
            shard: Shard::whole(),
            poll: Duration::from_secs(2),
        }
    }
}

/// The outcome of running a list: every result when all are in the cache, or `None` where a job is
/// another (non-concurrent) shard's and not done yet.
pub type Collected<R> = Vec<Option<R>>;

/// Runs this shard's pending jobs of `jobs` (those without a cached result), `at_once` at a time, each
/// through `run(inputs, job_dir)`, storing each result as it finishes; then, when the shards run
/// concurrently, waits for the other shards' results. Returns the results in list order. A job that
/// fails stops the list with its error once the jobs already started have finished (their results are
/// kept), so nothing computed is lost. The jobs' error type is the caller's (any that an engine error
/// converts into).
pub fn run_jobs<I, R, E, F>(
    cache: &JobCache,
    jobs: &[I],
    how: &RunJobs,
    run: F,
) -> std::result::Result<Collected<R>, E>
where
    I: Serialize + Sync,
    R: Serialize + DeserializeOwned + Send,
    E: From<DemError> + std::fmt::Display + Send,
    F: Fn(&I, &Path) -> std::result::Result<R, E> + Sync,
{
    let keys: Vec<JobKey> = jobs.iter().map(JobCache::key).collect::<Result<_>>()?;
    let mine: Vec<usize> = (0..jobs.len())
        .filter(|&j| how.shard.owns(j) && !cache.is_done(&keys[j]))
        .collect();
    let one = |j: usize| -> std::result::Result<(), E> {
        let dir = cache.dir(&keys[j])?;
        crate::io::progress::remove(&cache.failure_path(&keys[j]))?;
        let t = Instant::now();
        let result = match run(&jobs[j], &dir) {
            Ok(r) => r,
            Err(e) => {
                // Best effort: the ranks that wait for this job read why it will never come.
                let _ = write_atomic(&cache.failure_path(&keys[j]), e.to_string().as_bytes());
                return Err(e);
            }
        };
        cache.put(&keys[j], &jobs[j], &result)?;
        // Provenance: which shard of how many ran the job (a cluster run's ranks show here).
        let ran_by = format!("{} {}\n", how.shard.index, how.shard.count);
        write_atomic(&dir.join("ran_by"), ran_by.as_bytes())?;
        tracing::debug!(job = %keys[j], seconds = %crate::io::Sig(t.elapsed().as_secs_f64(), 3), "job done");
        Ok(())
    };
    if how.at_once <= 1 || mine.len() <= 1 {
        mine.iter().try_for_each(|&j| one(j))?;
    } else {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(how.at_once.min(mine.len()))
            .build()
            .map_err(|e| DemError::InvalidConfig(format!("cannot start job threads: {e}")))?;
        // Every job runs to its end or error; the first error in list order is reported.
        let outcomes: Vec<std::result::Result<(), E>> =
            pool.install(|| mine.par_iter().with_max_len(1).map(|&j| one(j)).collect());
        outcomes
            .into_iter()
            .collect::<std::result::Result<(), E>>()?;
    }
    let mut waited = false;
    loop {
        let results: Collected<R> = keys.iter().map(|k| cache.get(k)).collect::<Result<_>>()?;
        let missing = results.iter().filter(|r| r.is_none()).count();
        if missing == 0 || !how.shard.concurrent || how.shard.count == 1 {
            return Ok(results);
        }
        if let Some((k, reason)) = keys
            .iter()
            .zip(&results)
            .filter(|(_, r)| r.is_none())
            .find_map(|(k, _)| cache.failure(k).map(|f| (k, f)))
        {
            return Err(DemError::JobFailed {
                key: k.0.clone(),
                reason,
            }
            .into());
        }
        if crate::interrupt::requested() {
            return Err(DemError::Interrupted { step: 0 }.into());
        }
        if !waited {
            tracing::info!(
                missing,
                "waiting for the other ranks' jobs to reach the cache {}",
                cache.root().display()
            );
            waited = true;
        }
        std::thread::sleep(how.poll);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    fn scratch(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("cgdem-jobs-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        d
    }

    #[test]
    fn keys_follow_the_inputs_exactly() {
        let a = JobCache::key(&(1.0f64, "x")).unwrap();
        assert_eq!(a, JobCache::key(&(1.0f64, "x")).unwrap());
        assert_ne!(a, JobCache::key(&(1.0f64 + f64::EPSILON, "x")).unwrap());
        assert_eq!(a.0.len(), 32);
    }

    #[test]
    fn cached_jobs_are_not_run_again_and_order_is_kept() {
        let cache = JobCache::new(scratch("order"));
        let calls = AtomicUsize::new(0);
        let square = |x: &u64, dir: &Path| -> Result<u64> {
            assert!(dir.is_dir());
            calls.fetch_add(1, Ordering::Relaxed);
            Ok(x * x)
        };
        let how = RunJobs {
            at_once: 2,
            ..RunJobs::default()
        };
        let r = run_jobs(&cache, &[3u64, 1, 2], &how, square).unwrap();
        assert_eq!(r, vec![Some(9), Some(1), Some(4)]);
        let r = run_jobs(&cache, &[2u64, 5], &how, square).unwrap();
        assert_eq!(r, vec![Some(4), Some(25)]);
        assert_eq!(calls.load(Ordering::Relaxed), 4);
        std::fs::remove_dir_all(cache.root()).unwrap();
    }

    #[test]
    fn an_array_task_runs_its_share_and_leaves_the_rest() {
        let cache = JobCache::new(scratch("shard"));
        let how = |i| RunJobs {
            at_once: 1,
            shard: Shard::parse(&format!("{i}/2")).unwrap(),
            ..RunJobs::default()
        };
        let id = |x: &u64, _: &Path| -> Result<u64> { Ok(*x) };
        let r = run_jobs(&cache, &[10u64, 11, 12], &how(1), id).unwrap();
        assert_eq!(r, vec![None, Some(11), None]);
        let r = run_jobs(&cache, &[10u64, 11, 12], &how(0), id).unwrap();
        assert_eq!(r, vec![Some(10), Some(11), Some(12)]);
        std::fs::remove_dir_all(cache.root()).unwrap();
    }

    #[test]
    fn a_rank_waiting_for_a_failed_job_reports_it_instead_of_waiting() {
        let cache = JobCache::new(scratch("failed-rank"));
        let jobs = [1u64, 2];
        // Rank 1 of 2 runs job 1 (index 1) and fails; rank 0 then finds the failure while waiting.
        let fail = |x: &u64, _: &Path| -> Result<u64> {
            Err(DemError::InvalidConfig(format!("job {x} cannot run")))
        };
        let rank = |i| RunJobs {
            at_once: 1,
            shard: Shard {
                index: i,
                count: 2,
                concurrent: true,
            },
            poll: Duration::from_millis(5),
        };
        assert!(run_jobs(&cache, &jobs, &rank(1), fail).is_err());
        let ok = |x: &u64, _: &Path| -> Result<u64> { Ok(*x) };
        let e = run_jobs(&cache, &jobs, &rank(0), ok).unwrap_err();
        assert!(
            matches!(e, DemError::JobFailed { .. }) && e.to_string().contains("job 2 cannot run"),
            "{e}"
        );
        // The owner's next attempt clears the mark and runs the job.
        assert_eq!(
            run_jobs(&cache, &jobs, &rank(1), ok).unwrap(),
            [Some(1), Some(2)]
        );
        assert!(cache.failure(&JobCache::key(&2u64).unwrap()).is_none());
        std::fs::remove_dir_all(cache.root()).unwrap();
    }

    #[test]
    fn a_failed_job_keeps_the_finished_ones() {
        let cache = JobCache::new(scratch("fail"));
        let how = RunJobs {
            at_once: 1,
            ..RunJobs::default()
        };
        let f = |x: &u64, _: &Path| -> Result<u64> {
            if *x == 2 {
                Err(DemError::InvalidConfig("two".into()))
            } else {
                Ok(*x)
            }
        };
        assert!(run_jobs(&cache, &[1u64, 2, 3], &how, f).is_err());
        assert!(cache.is_done(&JobCache::key(&1u64).unwrap()));
        std::fs::remove_dir_all(cache.root()).unwrap();
    }

    #[test]
    fn shards_come_from_the_launcher_or_from_i_over_n() {
        let env = |pairs: &'static [(&'static str, &'static str)]| {
            move |k: &str| {
                pairs
                    .iter()
                    .find(|(n, _)| *n == k)
                    .map(|(_, v)| v.to_string())
            }
        };
        let s = Shard::from_vars(env(&[("PMI_RANK", "1"), ("PMI_SIZE", "2")]));
        assert_eq!((s.index, s.count, s.concurrent), (1, 2, true));
        let s = Shard::from_vars(env(&[("SLURM_PROCID", "3"), ("SLURM_NTASKS", "4")]));
        assert_eq!((s.index, s.count), (3, 4));
        assert_eq!(
            Shard::from_vars(env(&[("PMI_RANK", "5"), ("PMI_SIZE", "2")])),
            Shard::whole()
        );
        assert_eq!(Shard::from_vars(env(&[])), Shard::whole());
        assert!(Shard::parse("2/2").is_err());
        assert!(Shard::parse("a/2").is_err());
        assert!(Shard::parse("1").is_err());
        let s = Shard::parse("1/3").unwrap();
        assert!(s.owns(4) && !s.owns(3) && !s.concurrent);
    }
}
