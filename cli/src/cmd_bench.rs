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
use std::process::Command;
use std::time::Instant;

use anyhow::{bail, Context, Result};
use clap::Args;
use dem::sample::hcp::hcp_lattice;
use dem::state::{sphere_inertia, sphere_mass};
use dem::{Material, PairModel, Parallelism, RunConfig, Simulation};
use md_bridge::venv::Venv;
use rand::{Rng, SeedableRng};

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

/// Sphere diameter (lattice spacing): 0.6 d_c for Table 4, so delta_f = d/3 reaches neither the
/// second shell nor beyond.
const SPACING: f64 = 90.0;
/// Overlap of touching neighbours, as a fraction of the spacing.
const SQUEEZE: f64 = 1e-3;

fn packing(cells: usize) -> Result<(dem::Particles, dem::SimBox)> {
    let nz = (cells * 4 / 5).max(2) & !1;
    let (mut p, bx) = hcp_lattice(cells, cells & !1, nz, SPACING, 1.0, [true; 3])?;
    let r = 0.5 * SPACING * (1.0 + SQUEEZE);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2024);
    for i in 0..p.len() {
        p.radius[i] = r;
        p.mass[i] = sphere_mass(1.0, r);
        p.inertia[i] = sphere_inertia(p.mass[i], r);
        for a in 0..3 {
            p.vel[i][a] = 0.01 * (2.0 * rng.gen::<f64>() - 1.0);
        }
    }
    Ok((p, bx))
}

fn model() -> PairModel {
    PairModel::cohesive(Material::table4(0.15))
}

/// Times `steps` steps after one warm-up step (which builds the neighbour list).
fn time_cgdem(threads: usize, steps: u64, cells: usize) -> Result<(f64, usize, usize, f64)> {
    let (p, bx) = packing(cells)?;
    let par = if threads <= 1 {
        Parallelism::Sequential
    } else {
        Parallelism::Threads(threads)
    };
    let mut sim = Simulation::new(p, bx, model(), vec![], RunConfig::default(), par)?;
    sim.step()?;
    let n = sim.particles.len();
    let pairs = sim.neighbors().len();
    let t = Instant::now();
    sim.run(steps)?;
    let secs = t.elapsed().as_secs_f64();
    Ok((secs, n, pairs, sim.dt()))
}

/// The speed-up the machine itself allows: `copies` independent 1-thread runs side by side share
/// nothing but the hardware (memory bandwidth, caches, clocks), so their aggregate rate over one run's
/// rate bounds what `copies` threads on one system can reach.
fn time_copies(copies: usize, steps: u64, cells: usize) -> Result<(f64, usize)> {
    let runs: Vec<Result<(f64, usize, usize, f64)>> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..copies)
            .map(|_| s.spawn(|| time_cgdem(1, steps, cells)))
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().unwrap_or_else(|_| bail!("a bench copy panicked")))
            .collect()
    });
    let mut slowest = 0.0f64;
    let mut n = 0;
    for r in runs {
        let (secs, np, _, _) = r?;
        slowest = slowest.max(secs);
        n = np;
    }
    Ok((slowest, n))
}

fn write_lammps_inputs(dir: &Path, cells: usize, steps: u64, dt: f64) -> Result<PathBuf> {
    let (p, bx) = packing(cells)?;
    let mdl = model();
    let pp = mdl.params(p.radius[0], p.radius[0], p.mass[0], p.mass[0]);
    std::fs::create_dir_all(dir)?;
    let data = dir.join("hcp.data");
    let mut f = std::io::BufWriter::new(std::fs::File::create(&data)?);
    writeln!(
        f,
        "cgdem bench packing\n\n{} atoms\n1 atom types\n",
        p.len()
    )?;
    for (a, name) in ["x", "y", "z"].iter().enumerate() {
        writeln!(f, "{:.17e} {:.17e} {name}lo {name}hi", bx.lo[a], bx.hi[a])?;
    }
    writeln!(f, "\nAtoms # sphere\n")?;
    for i in 0..p.len() {
        let x = p.pos[i];
        writeln!(
            f,
            "{} 1 {:.17e} 1.0 {:.17e} {:.17e} {:.17e}",
            i + 1,
            2.0 * p.radius[i],
            x.x,
            x.y,
            x.z
        )?;
    }
    writeln!(f, "\nVelocities\n")?;
    for i in 0..p.len() {
        let v = p.vel[i];
        writeln!(f, "{} {:.17e} {:.17e} {:.17e} 0 0 0", i + 1, v.x, v.y, v.z)?;
    }
    f.flush()?;
    let skin = RunConfig::default().skin_fraction * SPACING;
    let input = dir.join("in.bench");
    std::fs::write(
        &input,
        format!(
            "units lj\natom_style sphere\nboundary p p p\ncomm_modify vel yes\nnewton off\n\
             read_data {data}\n\
             pair_style gran/hooke/history {kn:.17e} {kt:.17e} 0.0 0.0 0.5 1\npair_coeff * *\n\
             neighbor {skin:.17e} bin\nneigh_modify delay 0 every 1 check yes\n\
             fix 1 all nve/sphere\ntimestep {dt:.17e}\nthermo 0\nrun 1\nrun {steps}\n",
            data = data.display(),
            kn = pp.k_n,
            kt = pp.k_t,
        ),
    )?;
    Ok(input)
}

/// The project venv, or the reason the comparison cannot run.
fn lammps_venv() -> Result<Venv> {
    let venv = Venv::locate();
    venv.check().context("LAMMPS comparison needs the project venv (run `bash scripts/setup-venv`), or pass --no-lammps")?;
    Ok(venv)
}

/// Runs LAMMPS from `venv` and returns (loop seconds of the timed run, atoms).
fn time_lammps(venv: &Venv, input: &Path, steps: u64) -> Result<(f64, usize)> {
    let exe = venv.lmp_exe()?;
    let log = input.with_file_name("log.lammps");
    let out = Command::new(&exe)
        .args(["-screen", "none", "-nocite", "-log"])
        .arg(&log)
        .arg("-in")
        .arg(input)
        .env("LD_LIBRARY_PATH", venv.root.join("lib"))
        .env("OMP_NUM_THREADS", "1")
        .output()
        .with_context(|| format!("starting {}", exe.display()))?;
    let text = std::fs::read_to_string(&log).unwrap_or_default();
    if !out.status.success() {
        bail!(
            "lmp failed ({}): {}",
            out.status,
            text.lines().rev().take(5).collect::<Vec<_>>().join(" | ")
        );
    }
    // "Loop time of 12.3 on 1 procs for 300 steps with 51200 atoms": the last one is the timed run.
    let line = text
        .lines()
        .rev()
        .find(|l| l.starts_with("Loop time of") && l.contains(&format!("for {steps} steps")))
        .context("no loop time in the LAMMPS log")?;
    let w: Vec<&str> = line.split_whitespace().collect();
    Ok((w[3].parse()?, w[w.len() - 2].parse()?))
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
