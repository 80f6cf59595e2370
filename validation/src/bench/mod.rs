//! The bench system shared by `cgdem bench` and the report's performance section: a periodic HCP
//! packing of equal spheres compressed by 0.1 % of a diameter, so that every sphere overlaps its 12
//! neighbours and nothing else lies within range (the next shell is at sqrt(2) d), with small seeded
//! random velocities. cgdem runs the full cohesive force with tangential history (paper 000, Table 4
//! material at nu = 0.15, d = 0.6 d_c); LAMMPS runs `pair_style gran/hooke/history` with
//! `fix nve/sphere` on 1 process, from the identical data file, with the same particle count, time step
//! and number of steps. The figures are loop times (set-up excluded on both sides).

use std::path::{Path, PathBuf};
use std::time::Instant;

use dem::sample::hcp::hcp_lattice;
use dem::state::{sphere_inertia, sphere_mass};
use dem::{Material, PairModel, Parallelism, RunConfig, Simulation};
use md_bridge::venv::Venv;
use rand::{Rng, SeedableRng};

use crate::{Result, ValidationError};

pub mod lammps;

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

/// The LAMMPS inputs of the packing: the same data, with LAMMPS's radii equal to cgdem's (the
/// packing's overlapping neighbours are exactly its pairs).
pub fn write_lammps_inputs(dir: &Path, cells: usize, steps: u64, dt: f64) -> Result<PathBuf> {
    let (p, bx) = packing(cells)?;
    let pp = model().params(p.radius[0], p.radius[0], p.mass[0], p.mass[0]);
    let sys = lammps::System {
        radius: p.radius.clone(),
        density: 1.0,
        k_n: pp.k_n,
        k_t: pp.k_t,
        skin: RunConfig::default().skin_fraction * SPACING,
    };
    lammps::write_inputs(dir, &p, &bx, &sys, steps, dt)
}

/// Runs LAMMPS from `venv` on 1 process and returns (loop seconds of the timed run, atoms).
pub fn time_lammps(venv: &Venv, input: &Path, steps: u64) -> Result<(f64, usize)> {
    let run = lammps::time(venv, input, steps, 1)?;
    Ok((run.secs, run.atoms))
}
