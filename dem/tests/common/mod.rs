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

/// Two spheres of radius `r` on the x axis, centres 2r + gap apart: the engine's two-particle rig.
#[allow(unused_imports)] // Not every test binary that includes this module builds pairs.
pub use dem::scenario::pair::pair_of;

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

/// A driven run (junction, sliding) given its dump path, progress file and progress callback.
pub type DrivenRun<'a, R> = dyn Fn(
        &std::path::Path,
        Option<&dem::io::progress::ProgressFile>,
        &mut dyn FnMut(u64, u64),
    ) -> Result<R, dem::DemError>
    + 'a;

/// Runs `run` whole, then again until an interrupt arrives just after its first periodic save, then
/// once more from that save; asserts that the interrupt stopped it early, that progress was reported,
/// and that the resumed result (`timeless`: without wall-clock fields) and dump are the whole run's to
/// the bit, each frame once. Alone in its test binary: the interrupt flag is process-wide.
pub fn assert_resumes_bit_identically<R>(
    name: &str,
    run: &DrivenRun<'_, R>,
    timeless: impl Fn(&R) -> String,
) {
    use std::time::Duration;
    let dir = std::env::temp_dir().join(format!("cgdem_{name}_resume_{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    let whole_dump = dir.join("whole.dump");
    let whole = run(&whole_dump, None, &mut |_, _| {}).unwrap();
    let file = dem::io::progress::ProgressFile {
        path: dir.join(format!("{name}.progress.json")),
        every: Duration::ZERO,
    };
    let cut_dump = dir.join("cut.dump");
    // Interrupt once the first periodic save exists: the run stops somewhere inside an interval.
    let watched = file.path.clone();
    let watcher = std::thread::spawn(move || {
        while !watched.exists() {
            std::thread::sleep(Duration::from_millis(1));
        }
        std::thread::sleep(Duration::from_millis(5));
        dem::interrupt::request();
    });
    let mut reported = 0;
    let cut = run(&cut_dump, Some(&file), &mut |_, _| reported += 1);
    watcher.join().unwrap();
    dem::interrupt::clear();
    match cut {
        Err(dem::DemError::Interrupted { step }) => assert!(step > 0, "{name}: stopped at step 0"),
        Err(e) => panic!("{name}: expected an interrupt, got {e}"),
        Ok(r) => panic!(
            "{name}: the run ended before the interrupt: {}",
            timeless(&r)
        ),
    }
    assert!(reported > 0, "{name}: no progress reported");
    let resumed = run(&cut_dump, Some(&file), &mut |_, _| {}).unwrap();
    assert_eq!(
        timeless(&resumed),
        timeless(&whole),
        "{name}: resumed result"
    );
    assert_eq!(
        std::fs::read(&cut_dump).unwrap(),
        std::fs::read(&whole_dump).unwrap(),
        "{name}: the resumed dump holds every frame once, as the uninterrupted one"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// The small sliding box of the sliding tests: L = 10 d0 (d0 = 0.1 L), d* = 0.3 L, p_N = 0.02 E,
/// `distance_over_l` L of sliding in 4 windows of 5 samples, relaxed on one thread.
pub fn small_sliding(
    distance_over_l: f64,
) -> (
    dem::sample::Sample,
    PairModel,
    dem::scenario::sliding::SlidingConfig,
) {
    use dem::scenario::sliding::{SlidingConfig, SlidingMaterial};
    let cfg = SlidingConfig {
        d0_over_l: 0.1,
        material: SlidingMaterial {
            strength: 0.1,
            surface_energy: None,
            d_star: Some(0.3),
        },
        pressure: 0.02,
        distance_over_l,
        bins: 40,
        windows: 4,
        samples_per_window: 5,
        force_samples: 100,
        dump_frames: 0,
        ..SlidingConfig::default()
    };
    let model = cfg.model().unwrap();
    let sample = dem::sample::make_sample(
        &cfg.recipe().unwrap(),
        &model,
        &dem::sample::RelaxConfig::default(),
        Parallelism::Sequential,
    )
    .unwrap();
    (sample, model, cfg)
}
