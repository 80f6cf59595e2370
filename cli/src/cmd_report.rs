//! `cgdem report --profile quick|paper --out DIR`: the validation report (`validation::report`):
//! `DIR/report.html` (self-contained), `DIR/summary.csv`, `DIR/figures/` (SVG, PNG and the CSV behind
//! each), `DIR/provenance.json`. Cases are cached by their inputs (`DIR/cache`, or `--cache`): a rerun
//! reuses them, and a report stopped by Ctrl-C continues where it stopped.

use std::path::PathBuf;
use std::sync::Mutex;

use anyhow::{bail, Context as _, Result};
use clap::{Args, ValueEnum};
use validation::report::{self, MdSetup, Observer, Options, Profile};

#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum ProfileArg {
    /// Smaller samples and fewer cases (about 7 minutes on 2 cores for the sections on main).
    Quick,
    /// The papers' sizes (hours).
    Paper,
}

/// Arguments of `cgdem report`.
#[derive(Debug, Args)]
pub struct ReportArgs {
    #[arg(long, value_enum, default_value = "quick")]
    pub profile: ProfileArg,
    /// Output directory.
    #[arg(long, default_value = "out/report")]
    pub out: PathBuf,
    /// Case cache [default: OUT/cache].
    #[arg(long)]
    pub cache: Option<PathBuf>,
    /// Only these sections (comma separated ids; the page lists them all).
    #[arg(long, value_delimiter = ',')]
    pub only: Option<Vec<String>>,
}

/// A progress bar per list of cases (the CLI's one bar), and a line per section.
struct Bar {
    bar: Mutex<Option<crate::progress::Bar>>,
}

impl Bar {
    fn finish(&self) {
        if let Ok(mut b) = self.bar.lock() {
            if let Some(b) = b.take() {
                b.finish();
            }
        }
    }
}

impl Observer for Bar {
    fn section(&self, id: &str, _title: &str) {
        self.finish();
        eprintln!("section {id}");
    }

    fn cases(&self, what: &str, total: usize, cached: usize) {
        self.finish();
        let b = crate::progress::Bar::new(&format!("  {what}"), "cases");
        b.update(cached as u64, total as u64);
        if let Ok(mut slot) = self.bar.lock() {
            *slot = Some(b);
        }
        if cached > 0 {
            eprintln!("  {what}: {cached} of {total} cases reused from the cache");
        }
    }

    fn case_done(&self, _what: &str) {
        if let Ok(b) = self.bar.lock() {
            if let Some(b) = b.as_ref() {
                b.inc();
            }
        }
    }
}

/// Runs `cgdem report`.
pub fn run(args: ReportArgs, threads: usize) -> Result<()> {
    let profile = match args.profile {
        ProfileArg::Quick => Profile::Quick,
        ProfileArg::Paper => Profile::Paper,
    };
    let at_once = if threads == 0 {
        std::thread::available_parallelism().map_or(1, |n| n.get())
    } else {
        threads
    };
    if let Some(only) = &args.only {
        report::check_sections(only)?;
    }
    let cache = args.cache.clone();
    let md_cache = cache
        .clone()
        .unwrap_or_else(|| args.out.join("cache"))
        .join("md");
    let opts = Options {
        profile,
        out: args.out.clone(),
        cache,
        only: args.only,
        at_once,
        md: Some(MdSetup {
            exe: std::env::current_exe().context("cannot locate the cgdem executable")?,
            venv: md_bridge::Venv::locate(),
            cache_dir: md_cache,
        }),
    };
    let bar = Bar {
        bar: Mutex::new(None),
    };
    let written = report::run(&opts, &bar);
    bar.finish();
    let w = written.with_context(|| {
        format!(
            "the report stopped; finished cases are kept in the cache: rerun the same command to continue ({})",
            args.out.display()
        )
    })?;
    let count = |v| w.claims().filter(|c| c.verdict() == v).count();
    println!(
        "{} claims: {} pass, {} fail, {} info; {} cases run, {} reused; {:.0} s",
        w.claims().count(),
        count(report::Verdict::Pass),
        count(report::Verdict::Fail),
        count(report::Verdict::Info),
        w.cases_run,
        w.cases_reused,
        w.seconds
    );
    for s in &w.sections {
        println!("  {:<16} {:>7.1} s", s.section.id, s.seconds);
    }
    println!("summary: {}", w.summary.display());
    println!("report: {}", w.html.display());
    let failed = w.failed_sections();
    if !failed.is_empty() {
        for (id, e) in &failed {
            eprintln!("section {id} failed: {e}");
        }
        bail!(
            "{} section(s) failed (the report above shows them)",
            failed.len()
        );
    }
    Ok(())
}
