//! Measures the 2D properties of hex monolayers matched in closed form to the MD model material
//! (cut-off 1.3 sigma: E_2D 66, nu 1/3, sigma_N 2.36, sigma_T 3.11, gamma 0.306; docs/junction.md):
//! `cargo run --release -p dem --example monolayer_measure -- D0 POLYDISPERSITY SIZE CORRECTION SEED...`
//! (SIZE: the layer's side in sigma; CORRECTION: `tensile_correction`, 1 for the closed form). Prints
//! one line per seed and the mean.

use dem::material::PairModel;
use dem::sample::monolayer::{hex_monolayer, relax_planar};
use dem::scenario::monolayer::{measure, MeasureConfig, MonolayerMaterial, Properties2d};
use dem::Parallelism;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let a: Vec<String> = std::env::args().skip(1).collect();
    if a.len() < 5 {
        return Err("usage: monolayer_measure D0 POLYDISPERSITY SIZE CORRECTION SEED...".into());
    }
    let d0: f64 = a[0].parse()?;
    let p: f64 = a[1].parse()?;
    let size: f64 = a[2].parse()?;
    let src = MonolayerMaterial {
        properties: Properties2d {
            young_modulus: 66.0,
            poisson_ratio: 1.0 / 3.0,
            tensile_strength: 2.36,
            shear_strength: 3.11,
            surface_energy: 0.306,
        },
        d0,
        areal_density: 0.9165,
        restitution: 0.95,
        tensile_correction: a[3].parse()?,
    };
    let (mat, _) = src.resolve()?;
    println!("pair material: {mat:?}");
    let model = PairModel::cohesive(mat.clone());
    let mut all = Vec::new();
    for s in &a[4..] {
        let seed: u64 = s.parse()?;
        let t = std::time::Instant::now();
        let raw = hex_monolayer(size, size, d0, 2.5 * d0, mat.density, p, seed)?;
        let relaxed = relax_planar(&raw, &model, Parallelism::Sequential)?;
        let m = measure(
            &relaxed,
            &model,
            &MeasureConfig::default(),
            Parallelism::Sequential,
        )?;
        let q = m.properties;
        println!(
            "d0 {d0} p {p} seed {seed}: N {} E2 {:.3} nu2 {:.4} sN {:.4} (strain {:.4}) sT {:.4} (strain {:.4}) pure shear {:.4} (strain {:.4}) gamma {:.4} d*(eq22) {:.1}  c11 {:.2} c22 {:.2} c12 {:.2} c21 {:.2}  [{:.1} s]",
            m.particles, q.young_modulus, q.poisson_ratio, q.tensile_strength, m.tensile_peak_strain,
            q.shear_strength, m.shear_peak_strain, m.pure_shear_strength, m.pure_shear_peak_strain, q.surface_energy, q.dstar(), m.c11, m.c22, m.c12, m.c21,
            t.elapsed().as_secs_f64()
        );
        all.push(q);
    }
    let n = all.len() as f64;
    let mean = |f: &dyn Fn(&Properties2d) -> f64| all.iter().map(f).sum::<f64>() / n;
    println!(
        "mean over {} seeds: E2 {:.3} nu2 {:.4} sN {:.4} sT {:.4} gamma {:.4}",
        all.len(),
        mean(&|q| q.young_modulus),
        mean(&|q| q.poisson_ratio),
        mean(&|q| q.tensile_strength),
        mean(&|q| q.shear_strength),
        mean(&|q| q.surface_energy)
    );
    Ok(())
}
