//! Relaxed boxes as jobs (DESIGN.md section 7, "Runs as jobs"): a box relaxed as in paper 000 section
//! 3.2 is a pure function of its recipe, its pair model and the relaxation settings, so it is stored
//! once in a samples cache under the key of those three and read by every run that needs it: the
//! runs of a d* search at one seed, and a sliding run beside the strength job that measures its
//! material's tau_m on the same box. A list of runs relaxes its distinct boxes first, as a job list of
//! their own ([`relax_all`]), so that no two runs relax the same box at once (locally side by side, or
//! as the ranks of a cluster run).

use std::path::Path;

use dem::io::progress::{self, ProgressFile};
use dem::jobs::{run_jobs, JobCache, RunJobs};
use dem::material::PairModel;
use dem::sample::{make_sample_resumable, RelaxConfig, Sample, SampleSpec};
use dem::Parallelism;
use serde::{Deserialize, Serialize};

use crate::error::Result;

/// How long the relaxation took, and of what.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SampleRecord {
    pub particles: usize,
    pub seconds: f64,
    pub converged: bool,
}

/// What identifies a relaxed box: the recipe, the model and the relaxation (the key of its job).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SampleJob<'a> {
    pub recipe: SampleSpec,
    pub model: &'a PairModel,
    pub relax: RelaxConfig,
}

impl SampleJob<'_> {
    /// Relaxes the box into `dir` (`sample.json`; an interrupted relaxation resumes from its progress
    /// file there): the job function of a samples cache.
    pub fn relax_into(&self, dir: &Path, par: Parallelism) -> Result<SampleRecord> {
        let t = std::time::Instant::now();
        let p = ProgressFile::new(dir.join("relax.progress.json"));
        let sample = make_sample_resumable(&self.recipe, self.model, &self.relax, par, Some(&p))?;
        sample.save(&dir.join("sample.json"))?;
        progress::remove(&p.path)?;
        Ok(SampleRecord {
            particles: sample.particles.len(),
            seconds: t.elapsed().as_secs_f64(),
            converged: sample.relaxation.as_ref().is_some_and(|r| r.converged),
        })
    }
}

/// The relaxed box of `job` from `samples`, relaxed and stored first if the cache does not hold it.
pub fn relaxed(
    samples: &JobCache,
    job: &SampleJob,
    par: Parallelism,
) -> Result<(Sample, SampleRecord)> {
    let one = RunJobs {
        at_once: 1,
        ..RunJobs::default()
    };
    let record = run_jobs(samples, std::slice::from_ref(job), &one, |j, dir| {
        j.relax_into(dir, par)
    })?
    .pop()
    .flatten()
    .expect("a whole-list run returns every result");
    let dir = samples.dir(&JobCache::key(job)?)?;
    Ok((Sample::load(&dir.join("sample.json"))?, record))
}

/// Relaxes the distinct boxes of `jobs` that `samples` does not hold yet, as one job list run as `how`
/// says (each box single-threaded when several run side by side, else with `par`). Returns the
/// records in the order of the distinct boxes; `None` where another (non-concurrent) shard's box is
/// not done yet.
pub fn relax_all(
    samples: &JobCache,
    jobs: &[SampleJob],
    how: &RunJobs,
    par: Parallelism,
) -> Result<Vec<Option<SampleRecord>>> {
    let par = if how.at_once > 1 {
        Parallelism::Sequential
    } else {
        par
    };
    run_jobs(samples, &distinct(jobs), how, |job, dir| {
        job.relax_into(dir, par)
    })
}

/// The boxes of `jobs`, each once, in order of first appearance (runs that share a box list it
/// once; the job list of a cache must not hold one key twice).
pub fn distinct<'b, 'a>(jobs: &'b [SampleJob<'a>]) -> Vec<&'b SampleJob<'a>> {
    let mut out: Vec<&SampleJob> = Vec::new();
    for j in jobs {
        if !out.contains(&j) {
            out.push(j);
        }
    }
    out
}
