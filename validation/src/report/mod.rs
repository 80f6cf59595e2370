//! The validation report (`cgdem report --profile quick|paper --out DIR`): every claim of the papers
//! that the workbench reproduces, beside the workbench's own figures, each with a tolerance and a
//! verdict.
//!
//! A report is a list of [`Section`]s ([`sections::all`]). A section is one short module with a
//! `run(&Context) -> Result<SectionOutput>`: it runs its cases through [`Context::jobs`] (a
//! [`dem::jobs::JobCache`] keyed by the cases' inputs, so a rerun reuses every finished case and an
//! interrupted report resumes), and returns claims (rows of the summary), figures (drawn as SVG, PNG
//! and the CSV behind them) and an HTML fragment. [`run`] times each section, then writes
//! `report.html` (self-contained: figures inline as SVG), `summary.csv` and `figures/`.
//!
//! Adding a section: write `sections/<name>.rs` with `pub const SECTION: Section` and its `run`
//! function, and add it to the list in [`sections::all`].

pub mod claim;
pub mod figure;
mod html;
pub mod provenance;
pub mod sections;

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

use dem::jobs::{run_jobs, JobCache, RunJobs, Shard};
use dem::{DemError, Parallelism};
use serde::de::DeserializeOwned;
use serde::Serialize;

pub use claim::{Claim, Tolerance, Verdict};
pub use figure::{Figure, Kind, Panel, Series};

use crate::error::{Result, ValidationError};

/// How big the report's cases are.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Profile {
    /// Smaller samples and fewer cases than the papers: about 7 minutes on 2 cores for the
    /// sections on main; says so on every page and in every figure.
    Quick,
    /// The papers' sizes (hours).
    Paper,
}

impl Profile {
    pub fn name(self) -> &'static str {
        match self {
            Profile::Quick => "quick",
            Profile::Paper => "paper",
        }
    }

    /// The notice shown on every page and figure of a quick report (empty for the paper profile).
    pub fn banner(self) -> &'static str {
        match self {
            Profile::Quick => {
                "QUICK PROFILE: smaller samples and fewer cases than the papers (cgdem report --profile paper for their sizes)"
            }
            Profile::Paper => "",
        }
    }
}

/// How the report reaches LAMMPS: MD jobs run in a worker process (the `cgdem` binary's
/// `md-worker`), cached in their own directory.
#[derive(Debug, Clone)]
pub struct MdSetup {
    pub exe: PathBuf,
    pub venv: md_bridge::Venv,
    pub cache_dir: PathBuf,
}

/// What a report reports back while it runs (the binary draws a progress bar from it).
pub trait Observer: Sync {
    /// A section starts.
    fn section(&self, _id: &str, _title: &str) {}
    /// A list of `total` cases starts, of which `cached` are already in the cache.
    fn cases(&self, _what: &str, _total: usize, _cached: usize) {}
    /// One case finished (run, not reused).
    fn case_done(&self, _what: &str) {}
}

/// An observer that ignores everything.
#[derive(Debug, Default)]
pub struct Silent;
impl Observer for Silent {}

/// Everything a section needs to run.
pub struct Context<'a> {
    pub profile: Profile,
    /// The report's directory.
    pub out: PathBuf,
    pub cache: JobCache,
    /// Cases run side by side (each single-threaded); a lone case gets this many threads.
    pub at_once: usize,
    /// LAMMPS, when the report can reach it (`None`: MD sections fail with the reason).
    pub md: Option<MdSetup>,
    pub observer: &'a dyn Observer,
    ran: AtomicUsize,
    reused: AtomicUsize,
}

impl std::fmt::Debug for Context<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Context")
            .field("profile", &self.profile)
            .field("out", &self.out)
            .field("cache", &self.cache)
            .finish_non_exhaustive()
    }
}

impl Context<'_> {
    /// Runs the cases of `jobs` that the cache does not hold (`at_once` at a time, each through
    /// `run(inputs, job_dir, parallelism)`) and returns every result in list order. An error stops
    /// the list once the cases already started have finished; their results are kept.
    pub fn jobs<I, R, F>(&self, what: &str, jobs: &[I], run: F) -> Result<Vec<R>>
    where
        I: Serialize + Sync,
        R: Serialize + DeserializeOwned + Send,
        F: Fn(&I, &Path, Parallelism) -> Result<R> + Sync,
    {
        let mut cached = 0;
        for j in jobs {
            if self.cache.is_done(&JobCache::key(j)?) {
                cached += 1;
            }
        }
        self.observer.cases(what, jobs.len(), cached);
        self.reused.fetch_add(cached, Ordering::Relaxed);
        let pending = jobs.len() - cached;
        // A lone case gets the threads; several run side by side, one thread each (the engine gives
        // the same bits for any thread count, so a cached result does not depend on this choice).
        let par = if pending <= 1 && self.at_once > 1 {
            Parallelism::Adaptive(self.at_once)
        } else {
            Parallelism::Sequential
        };
        let how = RunJobs {
            at_once: self.at_once.max(1),
            shard: Shard::whole(),
            ..RunJobs::default()
        };
        // run_jobs speaks DemError: a report error is parked here and handed back unchanged.
        let failure: Mutex<Option<ValidationError>> = Mutex::new(None);
        let outcome = run_jobs(&self.cache, jobs, &how, |input, dir| {
            match run(input, dir, par) {
                Ok(r) => {
                    self.ran.fetch_add(1, Ordering::Relaxed);
                    self.observer.case_done(what);
                    Ok(r)
                }
                Err(ValidationError::Dem(e)) => Err(e),
                Err(e) => {
                    let msg = e.to_string();
                    failure.lock().map(|mut f| *f = Some(e)).ok();
                    Err(DemError::InvalidConfig(msg))
                }
            }
        });
        let results = match outcome {
            Ok(r) => r,
            Err(e) => {
                return Err(failure
                    .into_inner()
                    .ok()
                    .flatten()
                    .unwrap_or(ValidationError::Dem(e)))
            }
        };
        results
            .into_iter()
            .map(|r| {
                r.ok_or_else(|| ValidationError::Report(format!("{what}: a case has no result")))
            })
            .collect()
    }

    /// [`Self::jobs`] with the cases started longest first by `cost` (any unit that orders them), and
    /// the results handed back in list order. The job threads take cases from the front of the list
    /// and steal the rest, so a long case listed last starts when the others are done and runs alone
    /// on one core while the others idle; started first, it runs beside all the short ones (the
    /// classic longest-processing-time rule). The cache keys do not depend on the order.
    pub fn jobs_longest_first<I, R, C, F>(
        &self,
        what: &str,
        jobs: &[I],
        cost: C,
        run: F,
    ) -> Result<Vec<R>>
    where
        I: Serialize + Sync,
        R: Serialize + DeserializeOwned + Send,
        C: Fn(&I) -> f64,
        F: Fn(&I, &Path, Parallelism) -> Result<R> + Sync,
    {
        let order = longest_first(jobs, cost);
        let sorted: Vec<&I> = order.iter().map(|&k| &jobs[k]).collect();
        let results = self.jobs(what, &sorted, |job, dir, par| run(job, dir, par))?;
        Ok(in_list_order(&order, results))
    }

    /// The MD set-up, or the reason there is none.
    pub fn md(&self) -> Result<&MdSetup> {
        self.md.as_ref().ok_or_else(|| {
            ValidationError::Report(
                "no LAMMPS set-up was given to the report (run it through `cgdem report`)".into(),
            )
        })
    }
}

/// What a section gives the report.
#[derive(Debug, Default)]
pub struct SectionOutput {
    pub claims: Vec<Claim>,
    pub figures: Vec<Figure>,
    /// HTML fragment shown before the figures (notes, tables); escaped by the section.
    pub html: String,
    /// Provenance entries (LAMMPS version, potential checksum, seeds ...).
    pub provenance: Vec<(String, String)>,
}

/// A section of the report.
#[derive(Debug, Clone, Copy)]
pub struct Section {
    /// Short id (`--only` selects by it; the HTML anchor).
    pub id: &'static str,
    pub title: &'static str,
    pub run: fn(&Context) -> Result<SectionOutput>,
}

/// Options of one report.
#[derive(Debug, Clone)]
pub struct Options {
    pub profile: Profile,
    pub out: PathBuf,
    /// Case cache; default `<out>/cache`.
    pub cache: Option<PathBuf>,
    /// Sections to run (by id); `None`: all.
    pub only: Option<Vec<String>>,
    pub at_once: usize,
    pub md: Option<MdSetup>,
}

/// A section as it ended: its output or its error, and its wall time.
#[derive(Debug)]
pub struct SectionRun {
    pub section: Section,
    pub output: std::result::Result<SectionOutput, String>,
    pub seconds: f64,
}

/// What a finished report returns.
#[derive(Debug)]
pub struct Written {
    pub html: PathBuf,
    pub summary: PathBuf,
    pub sections: Vec<SectionRun>,
    pub cases_run: usize,
    pub cases_reused: usize,
    pub seconds: f64,
}

impl Written {
    /// Every claim with its verdict.
    pub fn claims(&self) -> impl Iterator<Item = &Claim> {
        self.sections
            .iter()
            .filter_map(|s| s.output.as_ref().ok())
            .flat_map(|o| o.claims.iter())
    }

    /// Sections that failed, with their errors.
    pub fn failed_sections(&self) -> Vec<(&'static str, &str)> {
        self.sections
            .iter()
            .filter_map(|s| s.output.as_ref().err().map(|e| (s.section.id, e.as_str())))
            .collect()
    }
}

/// Whether every id of `only` names a section: an error naming the sections otherwise (before
/// anything runs, so a mistyped `--only` is an input error, not a stopped report).
pub fn check_sections(only: &[String]) -> Result<()> {
    let all = sections::all();
    match only
        .iter()
        .find(|id| !all.iter().any(|s| s.id == id.as_str()))
    {
        Some(id) => {
            let ids: Vec<&str> = all.iter().map(|s| s.id).collect();
            Err(ValidationError::Report(format!(
                "no section '{id}'; sections: {}",
                ids.join(", ")
            )))
        }
        None => Ok(()),
    }
}

/// Runs the report: every selected section, timed, then the files. An interrupt (Ctrl-C) stops it
/// with [`DemError::Interrupted`]: the finished cases are in the cache and the next run reuses them.
/// A section that fails otherwise is reported in the page (and as a failing claim) and the others
/// still run.
pub fn run(opts: &Options, observer: &dyn Observer) -> Result<Written> {
    let t0 = Instant::now();
    let all = sections::all();
    if let Some(only) = &opts.only {
        check_sections(only)?;
    }
    let chosen: Vec<Section> = all
        .into_iter()
        .filter(|s| {
            opts.only
                .as_ref()
                .is_none_or(|o| o.iter().any(|id| id == s.id))
        })
        .collect();
    std::fs::create_dir_all(&opts.out).map_err(|e| ValidationError::io(&opts.out, e))?;
    let ctx = Context {
        profile: opts.profile,
        out: opts.out.clone(),
        cache: JobCache::new(opts.cache.clone().unwrap_or_else(|| opts.out.join("cache"))),
        at_once: opts.at_once.max(1),
        md: opts.md.clone(),
        observer,
        ran: AtomicUsize::new(0),
        reused: AtomicUsize::new(0),
    };
    let mut runs = Vec::new();
    for section in chosen {
        observer.section(section.id, section.title);
        let t = Instant::now();
        let output = match (section.run)(&ctx) {
            Ok(o) => Ok(o),
            Err(ValidationError::Dem(DemError::Interrupted { step })) => {
                return Err(ValidationError::Dem(DemError::Interrupted { step }))
            }
            Err(e) => Err(e.to_string()),
        };
        runs.push(SectionRun {
            section,
            output,
            seconds: t.elapsed().as_secs_f64(),
        });
    }
    let prov = provenance::Provenance::gather(&ctx, &runs, t0.elapsed().as_secs_f64());
    let figures_dir = opts.out.join("figures");
    let mut svgs = Vec::new();
    for r in &mut runs {
        let mut drawn = Vec::new();
        if let Ok(o) = &mut r.output {
            for f in &mut o.figures {
                f.banner = opts.profile.banner().to_string();
                drawn.push(f.write(&figures_dir)?);
            }
        }
        svgs.push(drawn);
    }
    let mut csv = String::from(claim::SUMMARY_HEADER);
    csv.push('\n');
    for r in &runs {
        for c in section_claims(r) {
            csv += &c.csv_row();
            csv.push('\n');
        }
    }
    let summary = opts.out.join("summary.csv");
    std::fs::write(&summary, csv).map_err(|e| ValidationError::io(&summary, e))?;
    let html = opts.out.join("report.html");
    let page = html::page(opts.profile, &prov, &runs, &svgs);
    std::fs::write(&html, page).map_err(|e| ValidationError::io(&html, e))?;
    let prov_path = opts.out.join("provenance.json");
    std::fs::write(&prov_path, prov.to_json()).map_err(|e| ValidationError::io(&prov_path, e))?;
    Ok(Written {
        html,
        summary,
        sections: runs,
        cases_run: ctx.ran.load(Ordering::Relaxed),
        cases_reused: ctx.reused.load(Ordering::Relaxed),
        seconds: t0.elapsed().as_secs_f64(),
    })
}

/// A section's claims; a failed section is one failing claim that carries its error.
fn section_claims(r: &SectionRun) -> Vec<Claim> {
    match &r.output {
        Ok(o) => o.claims.clone(),
        Err(e) => vec![Claim::new(
            "workbench",
            r.section.id,
            format!("section ran ({e})"),
            1.0,
            0.0,
            Tolerance::Absolute(0.0),
        )],
    }
}

/// The indices of `jobs` by decreasing `cost`; equal costs (and NaN, compared as the largest) keep
/// list order, so the order is a function of the list alone.
pub(crate) fn longest_first<I>(jobs: &[I], cost: impl Fn(&I) -> f64) -> Vec<usize> {
    let costs: Vec<f64> = jobs.iter().map(cost).collect();
    let mut order: Vec<usize> = (0..jobs.len()).collect();
    order.sort_by(|&a, &b| costs[b].total_cmp(&costs[a]));
    order
}

/// `results[k]` belongs to the case `order[k]` of the list: the results in list order.
fn in_list_order<R>(order: &[usize], results: Vec<R>) -> Vec<R> {
    let mut back: Vec<Option<R>> = std::iter::repeat_with(|| None).take(order.len()).collect();
    for (&k, r) in order.iter().zip(results) {
        back[k] = Some(r);
    }
    back.into_iter().flatten().collect()
}

#[cfg(test)]
mod tests {
    use super::{in_list_order, longest_first};

    #[test]
    fn results_run_in_cost_order_come_back_in_list_order() {
        let cases = ["short", "long", "middle"];
        let order = longest_first(&cases, |c| c.len() as f64);
        let ran: Vec<&str> = order.iter().map(|&k| cases[k]).collect();
        assert_eq!(ran, ["middle", "short", "long"]);
        let results: Vec<String> = ran.iter().map(|c| c.to_uppercase()).collect();
        assert_eq!(in_list_order(&order, results), ["SHORT", "LONG", "MIDDLE"]);
    }

    #[test]
    fn the_costliest_case_comes_first_and_ties_keep_list_order() {
        let costs = [1.0, 8.0, 1.0, 3.0, 8.0];
        assert_eq!(longest_first(&costs, |c| *c), vec![1, 4, 3, 0, 2]);
        assert_eq!(longest_first::<f64>(&[], |c| *c), Vec::<usize>::new());
    }
}
