//! Engine-only throughput on the amorphous workload of `cgdem bench --workload amorphous` (no LAMMPS,
//! no CLI), from a saved sample of paper 000's silica recipe:
//! `cargo run --release -p dem --example amorphous_throughput -- SAMPLE.json [steps] [threads]`.
//! The sample is made by `cgdem sample` or found in the bench's cache
//! (`runs/bench-cache/<key>/result.json`); particles get the bench's motion (10 m/s along x plus a
//! seeded random part up to 1 m/s per component). Prints the rate, the pairs and the list builds.

use dem::sample::Sample;
use dem::{Material, PairModel, Parallelism, RunConfig, Simulation, Vec3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let path = args
        .get(1)
        .ok_or("usage: amorphous_throughput SAMPLE.json [steps] [threads]")?;
    let arg = |k: usize, d: u64| args.get(k).and_then(|s| s.parse().ok()).unwrap_or(d);
    let (steps, threads) = (arg(2, 500), arg(3, 1) as usize);
    let sample = Sample::load(std::path::Path::new(path))?;
    // Paper 000 Table 5 in nm, ag, ns (UnitSystem::NANO).
    let silica = Material::from_si(&dem::SiMaterial::table5(), dem::UnitSystem::NANO);
    let mut p = sample.particles;
    let mut rng = ChaCha8Rng::seed_from_u64(2024);
    for v in p.vel.iter_mut() {
        *v = Vec3::new(10.0, 0.0, 0.0) + Vec3::from_fn(|_, _| 2.0 * rng.gen::<f64>() - 1.0);
    }
    let par = if threads > 1 {
        Parallelism::Threads(threads)
    } else {
        Parallelism::Sequential
    };
    let model = PairModel::cohesive(silica);
    let mut sim = Simulation::new(p, sample.sim_box, model, vec![], RunConfig::default(), par)?;
    sim.step()?;
    let b0 = sim.neighbor_builds();
    let t = std::time::Instant::now();
    sim.run(steps)?;
    let s = t.elapsed().as_secs_f64();
    let n = sim.particles.len();
    println!(
        "{n} particles, {} pairs, {steps} steps, {} list builds, {threads} thread(s): {:.3e} particle-steps/s",
        sim.neighbors().len(),
        sim.neighbor_builds() - b0,
        n as f64 * steps as f64 / s
    );
    Ok(())
}
