//! A junction run interrupted (Ctrl-C) continues from its progress file to the same result, to the last
//! bit, as an uninterrupted one, and its dump holds each frame once. One test in this binary: the
//! interrupt flag is process-wide.

use std::time::Duration;

use dem::material::{Material, PairModel};
use dem::sample::{make_sample, RelaxConfig, SampleSpec};
use dem::scenario::junction::{run, run_resumable, JunctionConfig, JunctionResult};
use dem::scenario::patch::ProgressFile;
use dem::{DemError, Parallelism, UnitSystem};

fn timeless(r: &JunctionResult) -> String {
    let mut r = r.clone();
    r.wall_seconds = 0.0;
    format!("{r:?}")
}

#[test]
fn an_interrupted_junction_resumes_bit_identically() {
    let u = UnitSystem::NANO;
    let model = PairModel::cohesive(Material {
        young_modulus: u.stress_from_pa(73e9),
        poisson_ratio: 0.17,
        tensile_strength: u.stress_from_pa(16e9),
        shear_strength: u.stress_from_pa(9e9),
        surface_energy: u.surface_energy_from_si(1.5),
        restitution: 0.9,
        density: u.density_from_si(2200.0),
        scaling: 0.5,
    });
    let cfg = JunctionConfig {
        lengths: [36.0, 30.0, 24.0],
        diameter: 10.0,
        d0: 6.0,
        duration: 1.0,
        frames: 20,
        force_samples: 100,
        dump_frames: 10,
        ..JunctionConfig::default()
    };
    let spec = SampleSpec::Amorphous {
        d0_over_dc: cfg.d0 / model.material.critical_diameter(),
        l_over_d0: 6.0,
        w_over_d0: 4.0,
        h_over_d0: Some(5.0),
        ds_over_d0: 0.75,
        dl_over_d0: 1.25,
        dl_over_l: None,
        seed: 5,
        insert_fraction: 0.75,
    };
    let sample = make_sample(
        &spec,
        &model,
        &RelaxConfig::default(),
        Parallelism::Sequential,
    )
    .unwrap();
    let dir = std::env::temp_dir().join(format!("cgdem_junction_resume_{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    let whole_dump = dir.join("whole.dump");
    let whole = run(
        &sample,
        &model,
        &cfg,
        Parallelism::Sequential,
        Some(&whole_dump),
    )
    .unwrap();

    let file = ProgressFile {
        path: dir.join("junction.progress.json"),
        every: Duration::ZERO,
    };
    let cut_dump = dir.join("cut.dump");
    // Interrupt once the first periodic save exists: the run stops somewhere inside a frame interval.
    let watched = file.path.clone();
    let watcher = std::thread::spawn(move || {
        while !watched.exists() {
            std::thread::sleep(Duration::from_millis(1));
        }
        std::thread::sleep(Duration::from_millis(20));
        dem::interrupt::request();
    });
    let mut reported = 0;
    let cut = run_resumable(
        &sample,
        &model,
        &cfg,
        Parallelism::Sequential,
        Some(&cut_dump),
        Some(&file),
        &mut |_, _| reported += 1,
    );
    watcher.join().unwrap();
    dem::interrupt::clear();
    let step = match cut {
        Err(DemError::Interrupted { step }) => step,
        other => panic!("expected an interrupt, got {:?}", other.map(|r| r.steps)),
    };
    assert!(
        step < whole.steps,
        "stopped at step {step} of {}",
        whole.steps
    );
    assert!(reported > 0);
    let resumed = run_resumable(
        &sample,
        &model,
        &cfg,
        Parallelism::Sequential,
        Some(&cut_dump),
        Some(&file),
        &mut |_, _| {},
    )
    .unwrap();
    assert_eq!(timeless(&resumed), timeless(&whole));
    assert_eq!(
        std::fs::read(&cut_dump).unwrap(),
        std::fs::read(&whole_dump).unwrap(),
        "the resumed dump holds every frame once, as the uninterrupted one"
    );
    std::fs::remove_dir_all(&dir).ok();
}
