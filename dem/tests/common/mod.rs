//! Shared set-ups for the engine's physics tests.
#![allow(dead_code)]

use dem::{
    Group, Material, PairModel, Parallelism, Particles, RunConfig, SimBox, Simulation, TimeStep,
    Vec3,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Table 4 material without damping (eta = 1), for conservative tests.
pub fn undamped(nu: f64) -> Material {
    let mut m = Material::table4(nu);
    m.restitution = 1.0;
    m
}

/// A big non-periodic box around the origin.
pub fn open_box(half: f64) -> SimBox {
    SimBox::new(Vec3::repeat(-half), Vec3::repeat(half), [false; 3]).unwrap()
}

/// Two spheres of radius `r` on the x axis, centres 2r + gap apart.
pub fn pair_of(r: f64, gap: f64) -> Particles {
    let mut p = Particles::default();
    p.push_sphere(Vec3::new(-(r + 0.5 * gap), 0.0, 0.0), r, 1.0);
    p.push_sphere(Vec3::new(r + 0.5 * gap, 0.0, 0.0), r, 1.0);
    p
}

/// Run settings at a fraction of dt_c.
pub fn config(frac: f64) -> RunConfig {
    RunConfig {
        time_step: TimeStep::FractionOfCritical(frac),
        track_energy: true,
        ..Default::default()
    }
}

/// A simulation with default groups.
pub fn sim(p: Particles, bx: SimBox, model: PairModel, cfg: RunConfig) -> Simulation {
    Simulation::new(
        p,
        bx,
        model,
        vec![Group::free("all")],
        cfg,
        Parallelism::Sequential,
    )
    .unwrap()
}

/// Seeded random velocities and spins of magnitude up to `v` / `w`.
pub fn thermalise(p: &mut Particles, v: f64, w: f64, seed: u64) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut draw = |scale: f64| Vec3::from_fn(|_, _| scale * (2.0 * rng.gen::<f64>() - 1.0));
    for i in 0..p.len() {
        p.vel[i] = draw(v);
        p.omega[i] = draw(w);
    }
}

/// A small HCP patch-test campaign (8 d0 box, Table 4 material at nu = 0) running `tests` (TOML
/// array body, e.g. `"elastic"`) over the target Poisson's ratios `nus`: quick cases for the tests
/// of campaign bookkeeping.
pub fn hcp_campaign(tests: &str, nus: &[f64]) -> dem::scenario::patch::PatchSuite {
    let nus: Vec<String> = nus.iter().map(|v| format!("{v:?}")).collect();
    toml::from_str(&format!(
        r#"
tests = [{tests}]
[material]
young_modulus = 1.0
poisson_ratio = 0.0
tensile_strength = 0.2
shear_strength = 0.1
surface_energy = 1.5
restitution = 0.95
density = 1.0
[sample]
kind = "hcp"
d0_over_dc = 0.6
l_over_d0 = 8.0
w_over_d0 = 3.0
[sweep]
poisson_ratio = [{}]
"#,
        nus.join(", ")
    ))
    .expect("valid campaign")
}
