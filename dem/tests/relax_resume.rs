//! A relaxation interrupted (Ctrl-C) in phase 1, resumed, interrupted again in phase 2 and resumed
//! again gives the same relaxed sample, to the last bit, as an uninterrupted one.
//!
//! One test in this binary: the interrupt flag is process-wide.

use std::path::PathBuf;
use std::time::Duration;

use dem::io::progress::ProgressFile;
use dem::sample::insert::{random_insertion, InsertionConfig};
use dem::sample::relax::relax_resumable;
use dem::sample::{relax, RelaxConfig, Sample, SizeDistribution};
use dem::{DemError, Material, PairModel, Parallelism, Vec3};

/// The sample as saved, without the wall-clock time of its relaxation.
fn measured(s: &Sample) -> serde_json::Value {
    let mut v = serde_json::to_value(s).unwrap();
    v["relaxation"]["wall_seconds"] = serde_json::Value::Null;
    v
}

/// The step of the simulation held by a progress file (None while it does not exist).
fn saved_step(path: &PathBuf) -> Option<u64> {
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(path).ok()?).ok()?;
    v["state"]["sim"]["step"].as_u64()
}

/// Runs the relaxation with a watcher that interrupts it once the progress file holds a step past
/// `after`; returns the step it stopped at.
fn interrupted_at(
    raw: &Sample,
    model: &PairModel,
    cfg: &RelaxConfig,
    file: &ProgressFile,
    after: u64,
) -> u64 {
    let path = file.path.clone();
    let watcher = std::thread::spawn(move || {
        while saved_step(&path).is_none_or(|s| s <= after) {
            std::thread::sleep(Duration::from_millis(1));
        }
        dem::interrupt::request();
    });
    let r = relax_resumable(raw, model, cfg, Parallelism::Sequential, Some(file));
    watcher.join().unwrap();
    dem::interrupt::clear();
    match r {
        Err(DemError::Interrupted { step }) => step,
        other => panic!(
            "expected an interrupt, got {:?}",
            other.map(|s| s.particles.len())
        ),
    }
}

#[test]
fn an_interrupted_relaxation_resumes_bit_identically() {
    let m = Material::table4(0.15);
    let d0 = 0.6 * m.critical_diameter();
    let raw = random_insertion(&InsertionConfig {
        lengths: Vec3::new(6.0 * d0, 6.0 * d0, 3.0 * d0),
        sizes: SizeDistribution::paper000_default(d0),
        volume_fraction: 0.75,
        density: m.density,
        seed: 7,
    })
    .unwrap();
    let model = PairModel::cohesive(m);
    let cfg = RelaxConfig {
        stress_tolerance: 1e-12,
        ..RelaxConfig::default()
    };
    let whole = relax(&raw, &model, &cfg, Parallelism::Sequential).unwrap();
    let report = whole.relaxation.as_ref().unwrap();
    assert!(report.converged && report.phase2_steps > 1000, "{report:?}");

    let dir = std::env::temp_dir().join(format!("cgdem_relax_resume_{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    let file = ProgressFile {
        path: dir.join("relax.progress.json"),
        every: Duration::ZERO,
    };
    let p1 = cfg.phase1_steps;
    let first = interrupted_at(&raw, &model, &cfg, &file, 0);
    assert!(first < p1, "first stop in phase 1, at step {first}");
    let second = interrupted_at(&raw, &model, &cfg, &file, p1 + 300);
    assert!(
        second > p1 + 300,
        "second stop in phase 2, at step {second}"
    );
    let resumed =
        relax_resumable(&raw, &model, &cfg, Parallelism::Sequential, Some(&file)).unwrap();
    assert_eq!(measured(&resumed), measured(&whole));
    std::fs::remove_dir_all(&dir).ok();
}
