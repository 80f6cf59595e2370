//! `cgdem compare CONFIG --out DIR`: DEM against MD on the 2D LJ model material (issue 17), see
//! `validation::compare`. MD runs are worker jobs in the MD cache (default `<repo>/runs/md-cache`,
//! shared with `cgdem md`), DEM runs are the dstar searches' jobs under DIR: a rerun reads them all,
//! an interrupted comparison resumes after the runs it finished.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use dem::jobs::RunJobs;
use md_bridge::job::RunOptions;
use md_bridge::Venv;
use validation::compare::{compare, CompareFile, CompareRun};

/// Arguments of `cgdem compare`.
#[derive(Debug, Args)]
pub struct CompareArgs {
    /// TOML comparison config (configs/compare-model.toml).
    pub config: PathBuf,
    /// Output directory (compare.json, compare.svg/.png, compare.md, the DEM searches).
    #[arg(long, default_value = "out/compare")]
    pub out: PathBuf,
    /// Runs side by side (default: one per core): DEM runs, each single-threaded, and the MD runs of
    /// a search round or of the scan, jobs / np worker processes of np ranks each.
    #[arg(long)]
    pub jobs: Option<usize>,
    /// MPI ranks of each MD run (1: the runs of the comparison's cost table are single-process).
    #[arg(long, default_value_t = 1)]
    pub np: u32,
    /// MD job cache (default: runs/md-cache in the repository).
    #[arg(long)]
    pub md_cache: Option<PathBuf>,
}

/// Runs `cgdem compare`.
pub fn run(args: CompareArgs, threads: usize) -> Result<()> {
    let file: CompareFile = crate::config::read(&args.config)?;
    let base = args.config.parent().unwrap_or(std::path::Path::new("."));
    let mut dem = RunJobs::default();
    if let Some(n) = args.jobs {
        dem.at_once = n.max(1);
    }
    let how = CompareRun {
        md: RunOptions {
            exe: std::env::current_exe().context("cannot locate the cgdem executable")?,
            np: args.np,
            cache_dir: args
                .md_cache
                .clone()
                .unwrap_or_else(|| md_bridge::venv::repo_root().join("runs/md-cache")),
            venv: Venv::locate(),
            reuse_cache: true,
        },
        dem,
        par: crate::parallelism(threads),
        base,
    };
    let r = compare(&file, &how, &args.out, &mut |m, cached| {
        eprintln!(
            "MD D = {} sigma, seed {}: {:?}, turn {:.2} rad, rigidity {:.2} ({}, {:.1} s)",
            m.diameter,
            m.seed,
            m.outcome,
            m.turn,
            m.rigidity,
            if cached { "cached" } else { "ran" },
            m.wall_seconds
        );
    })
    .with_context(|| {
        if dem::interrupt::requested() {
            format!(
                "comparing {}: interrupted; every finished run is cached, the same command resumes \
                 after them",
                args.config.display()
            )
        } else {
            format!("comparing {}", args.config.display())
        }
    })?;
    let show = |b: &[Option<f64>; 2]| {
        let f = |v: Option<f64>| v.map_or("-".to_string(), |x| format!("{x}"));
        format!("({}, {}]", f(b[0]), f(b[1]))
    };
    println!("d* of eq 22 (MD card): {:.1} sigma", r.dstar_theory);
    println!(
        "MD bracket {} sigma ({}; {} runs, {:.0} s)",
        show(&r.md_bracket),
        r.md.reason,
        r.md.runs.len(),
        r.md_cost_seconds
    );
    for (e, a) in r.dem.iter().zip(&r.agreement) {
        println!(
            "DEM d0 = {} sigma: bracket {} sigma ({} runs, {:.0} s); overlaps MD: {}, centre ratio DEM/MD {}",
            e.d0,
            show(&e.bracket),
            e.runs.len(),
            e.cost_seconds,
            a.overlap.map_or("-", |o| if o { "yes" } else { "no" }),
            a.centre_ratio.map_or("-".to_string(), |c| format!("{c:.2}"))
        );
    }
    if r.md_detachment.is_some() {
        println!(
            "MD detachment: {}",
            validation::compare::summary::d50_words(r.md_detachment.as_ref())
        );
    }
    for e in r.dem.iter().filter(|e| e.detachment.is_some()) {
        let q = r.d50_ratios.iter().find(|q| q.d0 == e.d0);
        println!(
            "DEM d0 = {} sigma detachment: {}; D50 / d0 {}, DEM D50 / MD D50 {}",
            e.d0,
            validation::compare::summary::d50_words(e.detachment.as_ref()),
            q.and_then(|q| q.d50_over_d0)
                .map_or("-".to_string(), |x| format!("{x:.1}")),
            q.and_then(|q| q.ratio)
                .map_or("-".to_string(), |x| format!("{x:.2}"))
        );
    }
    for c in &r.cost_ratios {
        println!(
            "cost at D = {} sigma, d0 = {}: MD {:.1} s / DEM {:.1} s = {:.3} ({})",
            c.diameter, c.d0, c.md_seconds, c.dem_seconds, c.ratio, c.how
        );
    }
    println!("wrote {}", args.out.join("compare.json").display());
    Ok(())
}
