//! The bench system shared by `cgdem bench` and the report's performance section: a periodic HCP
//! packing of equal spheres compressed by 0.1 % of a diameter, so that every sphere overlaps its 12
//! neighbours and nothing else lies within range (the next shell is at sqrt(2) d), with small seeded
//! random velocities. cgdem runs the full cohesive force with tangential history (paper 000, Table 4
//! material at nu = 0.15, d = 0.6 d_c); LAMMPS runs `pair_style gran/hooke/history` with
//! `fix nve/sphere` on 1 process, from the identical data file, with the same particle count, time step
//! and number of steps. The figures are loop times (set-up excluded on both sides).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use dem::sample::hcp::hcp_lattice;
use dem::state::{sphere_inertia, sphere_mass};
use dem::{Material, PairModel, Parallelism, RunConfig, Simulation};
use md_bridge::venv::Venv;
use rand::{Rng, SeedableRng};

use crate::{Result, ValidationError};

/// Sphere diameter (lattice spacing): 0.6 d_c for Table 4, so delta_f = d/3 reaches neither the
/// second shell nor beyond.
pub const SPACING: f64 = 90.0;
/// Overlap of touching neighbours, as a fraction of the spacing.
pub const SQUEEZE: f64 = 1e-3;

pub fn packing(cells: usize) -> Result<(dem::Particles, dem::SimBox)> {
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

pub fn model() -> PairModel {
    PairModel::cohesive(Material::table4(0.15))
}

/// Times `steps` steps after one warm-up step (which builds the neighbour list).
pub fn time_cgdem(threads: usize, steps: u64, cells: usize) -> Result<(f64, usize, usize, f64)> {
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
pub fn time_copies(copies: usize, steps: u64, cells: usize) -> Result<(f64, usize)> {
    let runs: Vec<Result<(f64, usize, usize, f64)>> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..copies)
            .map(|_| s.spawn(|| time_cgdem(1, steps, cells)))
            .collect();
        handles
            .into_iter()
            .map(|h| {
                h.join().unwrap_or_else(|_| {
                    Err(ValidationError::Report("a bench copy panicked".into()))
                })
            })
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

pub fn write_lammps_inputs(dir: &Path, cells: usize, steps: u64, dt: f64) -> Result<PathBuf> {
    let (p, bx) = packing(cells)?;
    let mdl = model();
    let pp = mdl.params(p.radius[0], p.radius[0], p.mass[0], p.mass[0]);
    std::fs::create_dir_all(dir).map_err(|e| ValidationError::io(dir, e))?;
    let data = dir.join("hcp.data");
    let mut f = String::new();
    // Writing into a String cannot fail.
    let _ = writeln!(
        f,
        "cgdem bench packing\n\n{} atoms\n1 atom types\n",
        p.len()
    );
    for (a, name) in ["x", "y", "z"].iter().enumerate() {
        let _ = writeln!(f, "{:.17e} {:.17e} {name}lo {name}hi", bx.lo[a], bx.hi[a]);
    }
    let _ = writeln!(f, "\nAtoms # sphere\n");
    for i in 0..p.len() {
        let x = p.pos[i];
        let _ = writeln!(
            f,
            "{} 1 {:.17e} 1.0 {:.17e} {:.17e} {:.17e}",
            i + 1,
            2.0 * p.radius[i],
            x.x,
            x.y,
            x.z
        );
    }
    let _ = writeln!(f, "\nVelocities\n");
    for i in 0..p.len() {
        let v = p.vel[i];
        let _ = writeln!(f, "{} {:.17e} {:.17e} {:.17e} 0 0 0", i + 1, v.x, v.y, v.z);
    }
    std::fs::write(&data, f).map_err(|e| ValidationError::io(&data, e))?;
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
    )
    .map_err(|e| ValidationError::io(&input, e))?;
    Ok(input)
}

/// Runs LAMMPS from `venv` and returns (loop seconds of the timed run, atoms).
pub fn time_lammps(venv: &Venv, input: &Path, steps: u64) -> Result<(f64, usize)> {
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
        .map_err(|e| ValidationError::io(&exe, e))?;
    let text = std::fs::read_to_string(&log).unwrap_or_default();
    if !out.status.success() {
        return Err(ValidationError::Report(format!(
            "lmp failed ({}): {}",
            out.status,
            text.lines().rev().take(5).collect::<Vec<_>>().join(" | ")
        )));
    }
    // "Loop time of 12.3 on 1 procs for 300 steps with 51200 atoms": the last one is the timed run.
    let line = text
        .lines()
        .rev()
        .find(|l| l.starts_with("Loop time of") && l.contains(&format!("for {steps} steps")))
        .ok_or_else(|| ValidationError::Report(format!("no loop time in {}", log.display())))?;
    let w: Vec<&str> = line.split_whitespace().collect();
    let bad = || {
        ValidationError::Report(format!(
            "unreadable loop time line in {}: {line}",
            log.display()
        ))
    };
    let secs = w.get(3).and_then(|v| v.parse().ok()).ok_or_else(bad)?;
    let atoms = w
        .iter()
        .rev()
        .nth(1)
        .and_then(|v| v.parse().ok())
        .ok_or_else(bad)?;
    Ok((secs, atoms))
}
