//! Engine-only throughput on the `cgdem bench` packing (no LAMMPS, no CLI):
//! `cargo run --release -p dem --example hcp_throughput -- [cells] [steps] [threads]`.

use dem::sample::hcp::hcp_lattice;
use dem::state::{sphere_inertia, sphere_mass};
use dem::{Material, PairModel, Parallelism, RunConfig, Simulation};
use rand::seq::SliceRandom;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let arg = |k: usize, d: usize| {
        std::env::args()
            .nth(k)
            .and_then(|s| s.parse().ok())
            .unwrap_or(d)
    };
    let (cells, steps, threads) = (arg(1, 24), arg(2, 100) as u64, arg(3, 1));
    // Optional 4th argument "shuffle": the same packing stored in random order (as random insertion
    // leaves an amorphous sample), to see what memory order costs.
    let shuffle = std::env::args().nth(4).is_some_and(|s| s == "shuffle");
    let d = 90.0;
    let (mut p, bx) = hcp_lattice(
        cells,
        cells & !1,
        (cells * 4 / 5).max(2) & !1,
        d,
        1.0,
        [true; 3],
    )?;
    let r = 0.5 * d * 1.001;
    for i in 0..p.len() {
        p.radius[i] = r;
        p.mass[i] = sphere_mass(1.0, r);
        p.inertia[i] = sphere_inertia(p.mass[i], r);
        p.vel[i].x = 0.01 * ((i * 7919 % 200) as f64 / 100.0 - 1.0);
    }
    if shuffle {
        let mut order: Vec<usize> = (0..p.len()).collect();
        order.shuffle(&mut ChaCha8Rng::seed_from_u64(7));
        p.permute(&order)?;
    }
    let par = if threads > 1 {
        Parallelism::Threads(threads)
    } else {
        Parallelism::Sequential
    };
    let mut sim = Simulation::new(
        p,
        bx,
        PairModel::cohesive(Material::table4(0.15)),
        vec![],
        RunConfig::default(),
        par,
    )?;
    sim.step()?;
    let t = std::time::Instant::now();
    sim.run(steps)?;
    let s = t.elapsed().as_secs_f64();
    let n = sim.particles.len();
    println!(
        "{n} particles, {} pairs, {steps} steps, {threads} thread(s): {:.3e} particle-steps/s",
        sim.neighbors().len(),
        n as f64 * steps as f64 / s
    );
    Ok(())
}
