//! `cgdem bench`: DEM throughput in particle-steps per second, against LAMMPS on the same system.
//!
//! Two workloads (`--workload`):
//! - `hcp` (default, [`hcp`]): a periodic HCP packing of equal spheres with 12 contacts each (51 200
//!   spheres by default), the dense and regular case;
//! - `amorphous` ([`amorphous`]): a relaxed amorphous sample of paper 000's silica recipe (d0 = 1.5 nm,
//!   sizes from 0.75 d0 to 5 d0, s = 1/2) of about 6 300 particles, the junction runs' workload: small
//!   and widely polydisperse.
//!
//! cgdem runs the full cohesive force with tangential history at each thread count of `--threads`;
//! LAMMPS runs `pair_style gran/hooke/history` with `fix nve/sphere` at each process count of
//! `--lammps-procs` (under the venv's `mpirun` above one), from a data file of the same particles, with
//! the same time step, skin and number of steps. The figures are loop times (set-up and the first step,
//! which builds the neighbour list, excluded on both sides). Beside the multi-thread figure the bench
//! times as many independent 1-thread copies side by side: what the hardware lets N threads reach at
//! best (they share the memory path and caches), so a speed-up can be read against the machine as well
//! as against the ideal N. Every round measures everything, so each ratio comes from one run; the
//! median of each figure over the rounds ends the output, the headline ratios as bare lines
//! (`speed-up at 2 threads: X.XXx`, `ratio cgdem/LAMMPS per core: X.XXx`,
//! `ratio cgdem 2 threads / LAMMPS 2 processes: X.XXx`).

mod amorphous;
mod hcp;

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use dem::{PairModel, Parallelism, Particles, RunConfig, SimBox, Simulation};
use md_bridge::venv::Venv;
use validation::bench::lammps;

/// What `cgdem bench` times.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Workload {
    /// A periodic HCP packing of equal spheres, 12 contacts each.
    Hcp,
    /// A relaxed amorphous sample of paper 000's silica recipe (sizes 0.75-5 d0).
    Amorphous,
}

#[derive(Debug, Args)]
pub struct BenchArgs {
    /// The system timed.
    #[arg(long, value_enum, default_value_t = Workload::Hcp)]
    workload: Workload,
    /// HCP: lattice cells along x and y (layers along z are 0.8 of that): 40 gives 51 200 spheres.
    #[arg(long, default_value_t = 40)]
    cells: usize,
    /// Amorphous: edge of the cubic box in units of d0; 32.5 gives about 6 300 particles.
    #[arg(long, default_value_t = 32.5)]
    length: f64,
    /// Steps timed on each side [default: 300 for hcp, 1000 for amorphous].
    #[arg(long)]
    steps: Option<u64>,
    /// Thread counts to time, comma separated.
    #[arg(long, default_value = "1,2", value_delimiter = ',')]
    threads: Vec<usize>,
    /// LAMMPS process counts, comma separated; above one LAMMPS runs under the venv's mpirun
    /// [default: 1 for hcp, 1,2 for amorphous].
    #[arg(long, value_delimiter = ',')]
    lammps_procs: Vec<usize>,
    /// Skip the LAMMPS comparison.
    #[arg(long)]
    no_lammps: bool,
    /// Skip the machine's ceiling (independent 1-thread copies run side by side).
    #[arg(long)]
    no_ceiling: bool,
    /// Append the results to this CSV file.
    #[arg(long)]
    csv: Option<PathBuf>,
    /// Rounds of the whole comparison, run one after the other; the median and range of every figure
    /// are printed at the end (single runs vary by ~10 % on a shared machine).
    #[arg(long, default_value_t = 1)]
    repeats: usize,
    /// Write LAMMPS's data file, input and logs into this directory and keep them (by default they
    /// go to a temporary directory, removed at the end).
    #[arg(long)]
    lammps_dir: Option<PathBuf>,
    /// Amorphous: time this saved sample (`cgdem sample`) instead of the recipe's cached one.
    #[arg(long)]
    sample: Option<PathBuf>,
    /// Amorphous: where the relaxed sample is cached (default: runs/bench-cache in the repository).
    #[arg(long)]
    cache: Option<PathBuf>,
}

/// A system ready to time on both sides.
pub(crate) struct Prepared {
    /// What is timed, printed first.
    pub title: String,
    /// What one particle is called in the report lines.
    pub noun: &'static str,
    pub particles: Particles,
    pub sim_box: SimBox,
    pub model: PairModel,
    /// The neighbour-list size cgdem must build, when the workload knows it (the HCP check).
    pub expect_pairs: Option<usize>,
    /// What LAMMPS gets.
    pub lammps: lammps::System,
}

/// One cgdem timing.
struct Timing {
    secs: f64,
    n: usize,
    pairs: usize,
    dt: f64,
    builds: u64,
}

/// One round's figures, rates in particle-steps per second.
#[derive(Debug, Default)]
struct Round {
    /// (threads, rate) of cgdem.
    cgdem: Vec<(usize, f64)>,
    /// (copies, rate of that many independent 1-thread copies side by side over one copy's rate).
    ceiling: Option<(usize, f64)>,
    /// (processes, rate) of LAMMPS.
    lammps: Vec<(usize, f64)>,
}

impl Round {
    fn cgdem(&self, t: usize) -> Option<f64> {
        self.cgdem.iter().find(|c| c.0 == t).map(|c| c.1)
    }
    fn lammps(&self, p: usize) -> Option<f64> {
        self.lammps.iter().find(|c| c.0 == p).map(|c| c.1)
    }
    fn speedup(&self, t: usize) -> Option<f64> {
        Some(self.cgdem(t)? / self.cgdem(1)?)
    }
    /// The speed-up at `t` threads over the machine ceiling of `t` copies: what the machine gave one
    /// thread's work shared against what it gave independent copies in the same round. A host that
    /// runs a lone vCPU faster than two busy ones lowers the speed-up and the ceiling together, so
    /// this figure tells the engine's loss (shared data, joins) from the machine's.
    fn of_ceiling(&self, t: usize) -> Option<f64> {
        let (copies, ceiling) = self.ceiling?;
        (t == copies).then_some(())?;
        Some(self.speedup(t)? / ceiling)
    }
    /// cgdem on `t` threads over LAMMPS on `t` processes (t = 1: per core).
    fn against_lammps(&self, t: usize) -> Option<f64> {
        Some(self.cgdem(t)? / self.lammps(t)?)
    }
}

/// Median and range of one figure over the rounds that have it.
fn spread(values: impl Iterator<Item = f64>) -> Option<(f64, f64, f64)> {
    use md_bridge::bench::{median, range};
    let v: Vec<f64> = values.collect();
    let (lo, hi) = range(&v);
    (!v.is_empty()).then(|| (median(&v), lo, hi))
}

fn parallelism(threads: usize) -> Parallelism {
    if threads <= 1 {
        Parallelism::Sequential
    } else {
        Parallelism::Threads(threads)
    }
}

/// Times `steps` steps after one warm-up step (which builds the neighbour list).
fn time_cgdem(threads: usize, steps: u64, prep: &Prepared) -> Result<Timing> {
    let mut sim = Simulation::new(
        prep.particles.clone(),
        prep.sim_box,
        prep.model.clone(),
        vec![],
        RunConfig::default(),
        parallelism(threads),
    )?;
    sim.step()?;
    let (n, pairs, builds0) = (
        sim.particles.len(),
        sim.neighbors().len(),
        sim.neighbor_builds(),
    );
    let t = Instant::now();
    sim.run(steps)?;
    let secs = t.elapsed().as_secs_f64();
    Ok(Timing {
        secs,
        n,
        pairs,
        dt: sim.dt(),
        builds: sim.neighbor_builds() - builds0,
    })
}

/// The speed-up the machine itself allows: `copies` independent 1-thread runs side by side share
/// nothing but the hardware (memory bandwidth, caches, clocks), so their aggregate rate over one run's
/// rate bounds what `copies` threads on one system can reach.
fn time_copies(copies: usize, steps: u64, prep: &Prepared) -> Result<(f64, usize)> {
    let runs: Vec<Result<Timing>> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..copies)
            .map(|_| s.spawn(|| time_cgdem(1, steps, prep)))
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().unwrap_or_else(|_| bail!("a bench copy panicked")))
            .collect()
    });
    let mut slowest = 0.0f64;
    let mut n = 0;
    for r in runs {
        let t = r?;
        slowest = slowest.max(t.secs);
        n = t.n;
    }
    Ok((slowest, n))
}

/// The project venv, or the reason the comparison cannot run.
fn lammps_venv() -> Result<Venv> {
    let venv = Venv::locate();
    venv.check().context("LAMMPS comparison needs the project venv (run `bash scripts/setup-venv`), or pass --no-lammps")?;
    Ok(venv)
}

pub fn run(mut args: BenchArgs) -> Result<()> {
    if args.repeats == 0 {
        bail!("--repeats must be at least 1");
    }
    if args.threads.is_empty() || args.threads.contains(&0) {
        bail!("--threads must list thread counts of at least 1");
    }
    if args.lammps_procs.is_empty() {
        args.lammps_procs = match args.workload {
            Workload::Hcp => vec![1],
            Workload::Amorphous => vec![1, 2],
        };
    }
    if args.lammps_procs.contains(&0) {
        bail!("--lammps-procs must list process counts of at least 1");
    }
    // Checked before minutes of DEM runs, not after them.
    let venv = if args.no_lammps {
        None
    } else {
        Some(lammps_venv()?)
    };
    let steps = args.steps.unwrap_or(match args.workload {
        Workload::Hcp => 300,
        Workload::Amorphous => 1000,
    });
    let prep = match args.workload {
        Workload::Hcp => hcp::prepare(args.cells)?,
        Workload::Amorphous => amorphous::prepare(&args)?,
    };
    println!("{}", prep.title);
    let dir = args.lammps_dir.clone().unwrap_or_else(|| {
        std::env::temp_dir().join(format!("cgdem-bench-{}", std::process::id()))
    });
    let clean = |dir: &Path| {
        if args.lammps_dir.is_none() {
            std::fs::remove_dir_all(dir).ok();
        }
    };
    let mut rows = Vec::new();
    let mut rounds = Vec::new();
    // Written by the first round (it needs cgdem's time step), then reused: every round runs LAMMPS
    // on the same files.
    let mut lammps_input = None;
    for k in 0..args.repeats {
        if args.repeats > 1 {
            println!("round {} of {}", k + 1, args.repeats);
        }
        let r = round(
            &args,
            steps,
            &prep,
            venv.as_ref(),
            &dir,
            &mut lammps_input,
            &mut rows,
        );
        if r.is_err() {
            clean(&dir);
        }
        rounds.push(r?);
    }
    clean(&dir);
    if args.repeats > 1 {
        summarise(&rounds, &args);
    }
    medians(&rounds, &args);
    if let Some(path) = &args.csv {
        let new = !path.exists();
        let mut f = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(path)?;
        if new {
            writeln!(f, "engine,particles,steps,seconds,particle_steps_per_s")?;
        }
        for (name, n, secs, rate) in rows {
            writeln!(f, "{name},{n},{steps},{secs},{rate}")?;
        }
    }
    Ok(())
}

/// One round of the comparison: cgdem at each thread count, the machine ceiling, LAMMPS at each
/// process count (when `venv` is given, i.e. not with `--no-lammps`).
fn round(
    args: &BenchArgs,
    steps: u64,
    prep: &Prepared,
    venv: Option<&Venv>,
    dir: &Path,
    lammps_input: &mut Option<PathBuf>,
    rows: &mut Vec<(String, usize, f64, f64)>,
) -> Result<Round> {
    let mut r = Round::default();
    let mut dt_used = 0.0;
    let noun = prep.noun;
    for &t in &args.threads {
        let tm = time_cgdem(t, steps, prep)?;
        if let Some(want) = prep.expect_pairs {
            if tm.pairs != want {
                bail!(
                    "packing check failed: {} pairs for {} {noun}, expected {want}",
                    tm.pairs,
                    tm.n
                );
            }
        }
        dt_used = tm.dt;
        let rate = tm.n as f64 * steps as f64 / tm.secs;
        r.cgdem.push((t, rate));
        let speedup = r
            .speedup(t)
            .filter(|_| t > 1)
            .map(|x| format!("  speed-up {x:.2}x"))
            .unwrap_or_default();
        println!(
            "cgdem   {t} thread(s): {} {noun} x {steps} steps in {:.3} s = {rate:.3e} particle-steps/s, {} list builds{speedup}",
            tm.n, tm.secs, tm.builds
        );
        rows.push((format!("cgdem-{t}t"), tm.n, tm.secs, rate));
    }
    let copies = args.threads.iter().copied().max().unwrap_or(1);
    if copies > 1 && !args.no_ceiling {
        let (secs, n) = time_copies(copies, steps, prep)?;
        let rate = (copies * n) as f64 * steps as f64 / secs;
        r.ceiling = r.cgdem(1).map(|r1| (copies, rate / r1));
        let ceiling = r
            .ceiling
            .map(|(_, x)| format!("  machine ceiling {x:.2}x"))
            .unwrap_or_default();
        println!("cgdem   {copies} independent 1-thread copies side by side: {rate:.3e} particle-steps/s in all{ceiling}");
        rows.push((format!("cgdem-{copies}x1t"), copies * n, secs, rate));
    }
    let Some(venv) = venv else {
        println!("(LAMMPS comparison skipped)");
        return Ok(r);
    };
    let input = match lammps_input {
        Some(p) => p.clone(),
        None => lammps_input
            .insert(lammps::write_inputs(
                dir,
                &prep.particles,
                &prep.sim_box,
                &prep.lammps,
                steps,
                dt_used,
            )?)
            .clone(),
    };
    for &procs in &args.lammps_procs {
        let run = lammps::time(venv, &input, steps, procs)?;
        let rate = run.atoms as f64 * steps as f64 / run.secs;
        let what = if procs == 1 {
            "1 process ".to_string()
        } else {
            format!("{procs} processes")
        };
        let builds = run
            .builds
            .map(|b| format!(", {b} list builds"))
            .unwrap_or_default();
        println!(
            "LAMMPS  {what}: {} {noun} x {steps} steps in {:.3} s = {rate:.3e} particle-steps/s (gran/hooke/history, nve/sphere{builds})",
            run.atoms, run.secs
        );
        if procs == 1 {
            if let Some(neigh) = run.neighbors {
                println!("LAMMPS  neighbour list at the end: {neigh} pairs");
            }
        }
        r.lammps.push((procs, rate));
        rows.push((format!("lammps-{procs}p"), run.atoms, run.secs, rate));
    }
    if let Some(x) = r.against_lammps(1) {
        println!("cgdem/LAMMPS per core, this round: {x:.2}x");
    }
    for &t in args.threads.iter().filter(|&&t| t > 1) {
        if let Some(x) = r.against_lammps(t) {
            println!("cgdem {t} threads / LAMMPS {t} processes, this round: {x:.2}x");
        }
    }
    Ok(r)
}

/// Thread (or process) counts above one that the rounds measured.
fn counts_above_one(args: &BenchArgs) -> Vec<usize> {
    let mut t: Vec<usize> = args.threads.iter().copied().filter(|&t| t > 1).collect();
    t.sort_unstable();
    t.dedup();
    t
}

/// Prints the median and range of every figure over the rounds.
fn summarise(rounds: &[Round], args: &BenchArgs) {
    println!("over {} rounds: median (min - max)", rounds.len());
    let show = |label: &str, v: Option<(f64, f64, f64)>, fmt: fn(f64) -> String| {
        if let Some((m, lo, hi)) = v {
            println!("  {label}: {} ({} - {})", fmt(m), fmt(lo), fmt(hi));
        }
    };
    let rate = |x: f64| format!("{x:.3e}");
    let ratio = |x: f64| format!("{x:.2}x");
    show(
        "cgdem 1 thread, particle-steps/s",
        spread(rounds.iter().filter_map(|r| r.cgdem(1))),
        rate,
    );
    for &t in &counts_above_one(args) {
        show(
            &format!("cgdem {t} threads, particle-steps/s"),
            spread(rounds.iter().filter_map(|r| r.cgdem(t))),
            rate,
        );
        show(
            &format!("speed-up at {t} threads"),
            spread(rounds.iter().filter_map(|r| r.speedup(t))),
            ratio,
        );
    }
    show(
        "machine ceiling",
        spread(rounds.iter().filter_map(|r| r.ceiling.map(|c| c.1))),
        ratio,
    );
    for &t in &counts_above_one(args) {
        show(
            &format!("speed-up at {t} threads over the machine ceiling"),
            spread(rounds.iter().filter_map(|r| r.of_ceiling(t))),
            |x| format!("{x:.2}"),
        );
    }
    for &p in &args.lammps_procs {
        let label = if p == 1 {
            "LAMMPS 1 process, particle-steps/s".to_string()
        } else {
            format!("LAMMPS {p} processes, particle-steps/s")
        };
        show(
            &label,
            spread(rounds.iter().filter_map(|r| r.lammps(p))),
            rate,
        );
    }
    show(
        "ratio cgdem/LAMMPS per core",
        spread(rounds.iter().filter_map(|r| r.against_lammps(1))),
        ratio,
    );
    for &t in &counts_above_one(args) {
        show(
            &format!("ratio cgdem {t} threads / LAMMPS {t} processes"),
            spread(rounds.iter().filter_map(|r| r.against_lammps(t))),
            ratio,
        );
    }
}

/// The medians of the headline ratios, one bare line each (what scripts and checks read).
fn medians(rounds: &[Round], args: &BenchArgs) {
    let median = |v: Vec<f64>| (!v.is_empty()).then(|| md_bridge::bench::median(&v));
    let s = if rounds.len() == 1 { "" } else { "s" };
    println!("medians over {} round{s}:", rounds.len());
    for &t in &counts_above_one(args) {
        if let Some(x) = median(rounds.iter().filter_map(|r| r.speedup(t)).collect()) {
            println!("speed-up at {t} threads: {x:.2}x");
        }
    }
    if let Some(x) = median(rounds.iter().filter_map(|r| r.against_lammps(1)).collect()) {
        println!("ratio cgdem/LAMMPS per core: {x:.2}x");
    }
    for &t in &counts_above_one(args) {
        if let Some(x) = median(rounds.iter().filter_map(|r| r.against_lammps(t)).collect()) {
            println!("ratio cgdem {t} threads / LAMMPS {t} processes: {x:.2}x");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spread_is_median_min_max() {
        assert_eq!(spread([3.0, 1.0, 2.0].into_iter()), Some((2.0, 1.0, 3.0)));
        assert_eq!(
            spread([4.0, 1.0, 2.0, 3.0].into_iter()),
            Some((2.5, 1.0, 4.0))
        );
        assert_eq!(spread(std::iter::empty()), None);
    }

    #[test]
    fn rounds_give_speedups_and_ratios_of_matching_counts() {
        let r = Round {
            cgdem: vec![(1, 2.0), (2, 3.6)],
            ceiling: None,
            lammps: vec![(1, 1.0), (2, 2.0)],
        };
        assert_eq!(r.speedup(2), Some(1.8));
        assert_eq!(r.of_ceiling(2), None, "no ceiling measured");
        assert_eq!(r.against_lammps(1), Some(2.0));
        assert_eq!(r.against_lammps(2), Some(1.8));
        assert_eq!(r.against_lammps(4), None);
    }

    #[test]
    fn the_speed_up_over_the_ceiling_needs_the_ceiling_of_as_many_copies() {
        let r = Round {
            cgdem: vec![(1, 2.0), (2, 3.0), (3, 4.0)],
            ceiling: Some((2, 1.875)),
            lammps: vec![],
        };
        assert_eq!(r.of_ceiling(2), Some(0.8));
        assert_eq!(r.of_ceiling(3), None, "the ceiling was of 2 copies");
    }
}
