//! The MD side of the comparison: the d* search of the 2D LJ model material, the same bisection as
//! the DEM side ([`wear::dstar::next_step`] over probes of several seeds), each run an MD junction job
//! ([`md_bridge::junction`]) run by a worker process and cached by [`md_bridge::job::run_job`]: a rerun
//! reads every finished run from the cache, an interrupted search resumes after its finished runs
//! (the run in progress starts over: LAMMPS is not checkpointed mid-run).
//!
//! What a seed varies (decision): the MD crystal has no disorder, so a seed that only drew the thermal
//! velocities (T = 0.01 epsilon/k_B) would repeat almost the same junction. A seed here also places
//! the junction at its own lateral offset in the lattice ([`lattice_offset`]), so the junction's
//! edges cut the lattice columns differently: two seeds are two junctions of the same width, as two
//! DEM packings are.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;

use md_bridge::job::{run_job, Job, JobOutput, RunOptions};
use md_bridge::junction::JunctionConfig;
use serde::{Deserialize, Serialize};
use wear::dstar::{next_step, Bracket, Probe, SearchSettings, Step};
use wear::Outcome;

use crate::error::{Result, ValidationError};

/// The MD search: the junction set-up (all but width, seed and offset) and what the search varies.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MdSearchConfig {
    /// Every junction setting but `width`, `seed` and `lattice_offset`, which the search sets.
    #[serde(default)]
    pub junction: JunctionConfig,
    /// Starting range [D expected plastic, D expected to detach] (sigma).
    pub range: [f64; 2],
    /// Smallest and largest D (sigma); default [8, 4 x range top]: a junction at least 4 sigma tall.
    #[serde(default)]
    pub limits: Option<[f64; 2]>,
    /// Seeds run at every D; default [1, 2]: two seeds at each bound.
    #[serde(default = "d_seeds")]
    pub seeds: Vec<u64>,
    /// Stop when (upper - lower) / centre is at most this; default 0.2 (issue 17's acceptance).
    #[serde(default = "d_width")]
    pub relative_width: f64,
    /// Most rounds of probes; default 6 (each MD round costs minutes per run).
    #[serde(default = "d_rounds")]
    pub max_rounds: usize,
}

fn d_seeds() -> Vec<u64> {
    vec![1, 2]
}
fn d_width() -> f64 {
    0.2
}
fn d_rounds() -> usize {
    6
}

/// The junction's lateral offset in the lattice for `seed`, a fraction of the lattice spacing in
/// [0, 1): the golden-ratio sequence, so that any few seeds spread over the cell (seeds 1 and 2 give
/// 0.618 and 0.236).
pub fn lattice_offset(seed: u64) -> f64 {
    let phi = 0.5 * (5f64.sqrt() - 1.0);
    let v = (seed as f64 * phi).fract();
    // Three decimals: readable job files, and the value cannot round up to 1.
    (v * 1000.0).floor() / 1000.0
}

impl MdSearchConfig {
    /// The search settings (the bisection's own checks included).
    pub fn settings(&self) -> Result<SearchSettings> {
        if self.seeds.is_empty() {
            return Err(ValidationError::Config {
                path: "[md]".into(),
                reason: "seeds must hold at least one seed".into(),
            });
        }
        let s = SearchSettings {
            range: self.range,
            limits: self.limits.unwrap_or([8.0, 4.0 * self.range[1]]),
            relative_width: self.relative_width,
            widen: 1.5,
            max_rounds: self.max_rounds,
        };
        s.validate()?;
        Ok(s)
    }

    /// The job at width `d` with `seed`.
    pub fn run_config(&self, d: f64, seed: u64) -> JunctionConfig {
        JunctionConfig {
            width: d,
            seed,
            lattice_offset: lattice_offset(seed),
            ..self.junction.clone()
        }
    }
}

/// One MD run of the search.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MdRun {
    /// Junction width D (sigma).
    pub diameter: f64,
    pub seed: u64,
    pub lattice_offset: f64,
    pub outcome: Outcome,
    pub turn: f64,
    pub rigidity: f64,
    pub debris_fraction: Option<f64>,
    pub force_late_over_peak: Option<f64>,
    pub atoms: u64,
    pub junction_atoms: usize,
    /// Wall time of the worker run (s), as its cache record holds it.
    pub wall_seconds: f64,
    /// MPI ranks of the run.
    pub ranks: u32,
    /// The job's cache key (its folder in the MD cache).
    pub job: String,
}

/// The MD search's outcome.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MdSearch {
    /// [lower, upper] in sigma: largest all-plastic D below the smallest all-debris D.
    pub bracket: [Option<f64>; 2],
    pub converged: bool,
    pub reason: String,
    pub split: Vec<f64>,
    pub non_monotonic: Vec<f64>,
    pub seeds: Vec<u64>,
    pub rounds: usize,
    /// Every run, by D then seed.
    pub runs: Vec<MdRun>,
    /// Sum of the runs' wall times (s).
    pub cost_seconds: f64,
}

/// Runs (or reads from the MD cache) the search, the runs of a round (its sizes times the seeds, which
/// do not depend on each other) `at_once` workers at a time; `report(run, cached)` hears of every
/// run, in the round's order, when the round ends.
pub fn search(
    cfg: &MdSearchConfig,
    opts: &RunOptions,
    at_once: usize,
    report: &mut dyn FnMut(&MdRun, bool),
) -> Result<MdSearch> {
    let settings = cfg.settings()?;
    cfg.run_config(settings.range[0], cfg.seeds[0]).validate()?;
    let mut probes: Vec<Probe> = Vec::new();
    let mut runs: Vec<MdRun> = Vec::new();
    let mut rounds = 0;
    let (converged, reason) = loop {
        match next_step(&settings, &probes, rounds)? {
            Step::Done { converged, reason } => break (converged, reason),
            Step::Probe(sizes) => {
                tracing::info!(round = rounds + 1, ?sizes, "MD d* search round");
                let jobs: Vec<JunctionConfig> = sizes
                    .iter()
                    .flat_map(|&d| cfg.seeds.iter().map(move |&seed| cfg.run_config(d, seed)))
                    .collect();
                let done = run_many(&jobs, opts, at_once, "MD d* search")?;
                let mut done = done.into_iter();
                for &d in &sizes {
                    let mut outcomes = Vec::new();
                    for (r, cached) in done.by_ref().take(cfg.seeds.len()) {
                        report(&r, cached);
                        outcomes.push(r.outcome);
                        runs.push(r);
                    }
                    probes.push(Probe { size: d, outcomes });
                }
                rounds += 1;
            }
        }
    };
    let b = Bracket::of(&probes);
    runs.sort_by(|a, b| a.diameter.total_cmp(&b.diameter).then(a.seed.cmp(&b.seed)));
    Ok(MdSearch {
        bracket: [b.lower, b.upper],
        converged,
        reason,
        split: b.split,
        non_monotonic: b.non_monotonic,
        seeds: cfg.seeds.clone(),
        rounds,
        cost_seconds: runs.iter().map(|r| r.wall_seconds).sum(),
        runs,
    })
}

/// A finished MD run and whether it came from the cache.
type Ran = (MdRun, bool);

/// Runs the junction jobs of `jobs` (or reads them from the MD cache), `at_once` worker processes at
/// a time, each job as [`run_one`] runs it alone: the same request, hence the same cached record, for
/// any `at_once`. Results in list order. A Ctrl-C stops the list before its next job starts, and an
/// error stops it once the jobs already started have ended; the finished runs are cached either way,
/// and the same command resumes after them (`what` names the list in that message).
pub(crate) fn run_many(
    jobs: &[JunctionConfig],
    opts: &RunOptions,
    at_once: usize,
    what: &str,
) -> Result<Vec<Ran>> {
    let next = AtomicUsize::new(0);
    let slots: Vec<Mutex<Option<Result<Ran>>>> = jobs.iter().map(|_| Mutex::new(None)).collect();
    let failed = AtomicBool::new(false);
    let worker = || loop {
        if failed.load(Ordering::Relaxed) || dem::interrupt::requested() {
            return;
        }
        let k = next.fetch_add(1, Ordering::Relaxed);
        let Some(job) = jobs.get(k) else { return };
        let r = run_one(job, opts);
        if r.is_err() {
            failed.store(true, Ordering::Relaxed);
        }
        if let Ok(mut slot) = slots[k].lock() {
            *slot = Some(r);
        }
    };
    std::thread::scope(|s| {
        for _ in 1..at_once.clamp(1, jobs.len().max(1)) {
            s.spawn(worker);
        }
        worker();
    });
    let mut out = Vec::with_capacity(jobs.len());
    for slot in slots {
        match slot.into_inner().ok().flatten() {
            Some(r) => out.push(r?),
            // Jobs start in list order, so an unstarted one follows every error: only a Ctrl-C
            // gets here.
            None => {
                return Err(ValidationError::Report(format!(
                    "{what} interrupted: the finished runs are cached, the same command resumes \
                     after them"
                )))
            }
        }
    }
    Ok(out)
}

pub(crate) fn run_one(j: &JunctionConfig, opts: &RunOptions) -> Result<(MdRun, bool)> {
    let (rec, cached) = run_job(&Job::Junction(j.clone()), opts)?;
    let JobOutput::Junction(r) = &rec.output else {
        return Err(ValidationError::Report(format!(
            "MD job {} returned {:?}, not a junction",
            rec.provenance.input_hash, rec.output
        )));
    };
    let v = &r.verdict;
    let p = &rec.provenance;
    tracing::info!(
        d = j.width,
        seed = j.seed,
        outcome = ?v.outcome,
        turn = v.turn,
        rigidity = v.rigidity,
        seconds = p.wall_seconds,
        cached,
        "MD junction"
    );
    let run = MdRun {
        diameter: j.width,
        seed: j.seed,
        lattice_offset: j.lattice_offset,
        outcome: v.outcome,
        turn: v.turn,
        rigidity: v.rigidity,
        debris_fraction: v.detachment.as_ref().map(|d| d.debris_fraction),
        force_late_over_peak: v.force_late_over_peak,
        atoms: r.n_atoms,
        junction_atoms: r.junction_atoms,
        wall_seconds: p.wall_seconds,
        ranks: p.mpi_ranks,
        job: p.input_hash.clone(),
    };
    Ok((run, cached))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_spread_over_the_cell_and_stay_below_one() {
        assert_eq!(lattice_offset(1), 0.618);
        assert_eq!(lattice_offset(2), 0.236);
        for s in 0..10_000 {
            let o = lattice_offset(s);
            assert!((0.0..1.0).contains(&o), "seed {s}: {o}");
        }
    }

    #[test]
    fn each_seed_gets_its_own_offset_and_the_search_sets_width_and_seed() {
        let cfg = MdSearchConfig {
            junction: JunctionConfig::default(),
            range: [35.0, 50.0],
            limits: None,
            seeds: vec![1, 2],
            relative_width: 0.2,
            max_rounds: 6,
        };
        let (a, b) = (cfg.run_config(42.5, 1), cfg.run_config(42.5, 2));
        assert_eq!((a.width, a.seed, b.seed), (42.5, 1, 2));
        assert_ne!(a.lattice_offset, b.lattice_offset);
        assert!(a.validate().is_ok() && b.validate().is_ok());
        assert_eq!(cfg.settings().unwrap().limits, [8.0, 200.0]);
        let bad = MdSearchConfig {
            seeds: vec![],
            ..cfg
        };
        assert!(bad.settings().is_err());
    }
}
