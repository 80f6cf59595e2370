//! A strength test interrupted (Ctrl-C) continues from its progress file to the same numbers, to the
//! last bit, as an uninterrupted run; a finished test's file returns its result at once; a file made
//! for other inputs is not resumed; a campaign removes its progress files once a case is reported.
//!
//! One test in this binary: the interrupt flag is process-wide.

mod common;

use std::time::Duration;

use common::hcp_campaign;
use dem::sample::Sample;
use dem::scenario::patch::{
    run_suite, strength, strength_resumable, ProgressFile, StrengthConfig, StrengthMode,
    StrengthResult,
};
use dem::{DemError, Material, PairModel, Parallelism, Vec3};

/// Everything a strength test measured except its wall-clock time.
fn measured(r: &StrengthResult) -> String {
    let mut r = r.clone();
    r.wall_seconds = 0.0;
    format!("{:?} {:?}", r, r.curve)
}

#[test]
fn an_interrupted_strength_test_resumes_bit_identically() {
    let m = Material::table4(0.0);
    let d0 = 0.6 * m.critical_diameter();
    let sample = Sample::hcp(Vec3::new(8.0 * d0, 8.0 * d0, 3.0 * d0), d0, m.density).unwrap();
    let model = PairModel::cohesive(m);
    let cfg = StrengthConfig::paper(StrengthMode::Tensile);
    let par = Parallelism::Sequential;
    let whole = strength(&sample, &model, &cfg, par).unwrap();
    assert!(whole.fracture.unwrap().separated && whole.curve.points.len() > 100);

    let dir = std::env::temp_dir().join(format!("cgdem_strength_resume_{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    let file = ProgressFile {
        path: dir.join("tensile.progress.json"),
        every: Duration::ZERO,
    };
    // Interrupt as soon as the first periodic save exists (after the first record): the run then
    // stops at whatever step it has reached, usually inside a record.
    let watched = file.path.clone();
    let watcher = std::thread::spawn(move || {
        while !watched.exists() {
            std::thread::sleep(Duration::from_millis(1));
        }
        dem::interrupt::request();
    });
    let cut = strength_resumable(&sample, &model, &cfg, par, Some(&file));
    watcher.join().unwrap();
    dem::interrupt::clear();
    let step = match cut {
        Err(DemError::Interrupted { step }) => step,
        other => panic!("expected an interrupt, got {other:?}"),
    };
    assert!(
        step < whole.steps,
        "stopped at step {step} of {}",
        whole.steps
    );
    assert!(file.path.exists(), "the interrupt saved the progress");

    let resumed = strength_resumable(&sample, &model, &cfg, par, Some(&file)).unwrap();
    assert_eq!(measured(&resumed), measured(&whole));

    // Finished: the file holds the result, returned without running again.
    let t = std::time::Instant::now();
    let again = strength_resumable(&sample, &model, &cfg, par, Some(&file)).unwrap();
    assert_eq!(measured(&again), measured(&whole));
    assert!(t.elapsed() < Duration::from_secs_f64(0.5 * whole.wall_seconds.max(0.2)));

    // Other inputs (here a shorter run) do not take the stored result.
    let short = StrengthConfig {
        max_strain: 0.01,
        ..cfg
    };
    let other = strength_resumable(&sample, &model, &short, par, Some(&file)).unwrap();
    assert!(other.steps < whole.steps / 2, "{} steps", other.steps);

    // A campaign leaves no progress file behind once its cases are reported.
    let campaign = dir.join("campaign");
    let report = run_suite(
        &hcp_campaign("\"tensile\", \"shear\"", &[0.0]),
        Some(&campaign),
        par,
    )
    .unwrap();
    assert!(report.cases[0].tensile.is_some() && report.cases[0].shear.is_some());
    let left: Vec<_> = std::fs::read_dir(&campaign)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains("progress"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
    std::fs::remove_dir_all(&dir).ok();
}
