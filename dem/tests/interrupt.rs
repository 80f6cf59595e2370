//! Ctrl-C handling: a requested interrupt stops the next step with a typed error and leaves the state of
//! the last completed step, from which the run continues exactly; a patch campaign interrupted in its
//! second case keeps the first, and a rerun continues from it. (Own test binary: the flag is global,
//! so the tests here take turns.)

mod common;

use std::sync::Mutex;
use std::time::{Duration, Instant};

use common::*;
use dem::scenario::patch::{run_suite, PatchReport};
use dem::{DemError, Material, PairModel, Parallelism, RunConfig};

/// The interrupt flag is process-wide: one test at a time may set it.
static FLAG: Mutex<()> = Mutex::new(());

#[test]
fn interrupt_stops_at_a_step_boundary_and_the_run_can_continue() {
    let _turn = FLAG.lock().unwrap_or_else(|e| e.into_inner());
    let model = PairModel::cohesive(Material::table4(0.1));
    let mut a = sim(
        pair_of(45.0, -1.0),
        open_box(1e4),
        model.clone(),
        RunConfig::default(),
    );
    let mut b = sim(
        pair_of(45.0, -1.0),
        open_box(1e4),
        model,
        RunConfig::default(),
    );
    a.run(50).unwrap();
    dem::interrupt::request();
    let err = a.step().unwrap_err();
    assert!(matches!(err, DemError::Interrupted { step: 50 }), "{err}");
    assert_eq!(a.step_count(), 50, "the interrupted step did not happen");
    dem::interrupt::clear();
    a.run(50).unwrap();
    b.run(100).unwrap();
    assert_eq!(a.particles.pos, b.particles.pos);
}

/// Cases finished in `dir`'s report so far (0 while it does not exist or is being replaced).
fn finished(dir: &std::path::Path) -> usize {
    std::fs::read(dir.join("report.json"))
        .ok()
        .and_then(|b| serde_json::from_slice::<PatchReport>(&b).ok())
        .map_or(0, |r| r.cases.len())
}

#[test]
fn an_interrupted_campaign_keeps_its_finished_cases_and_continues() {
    let _turn = FLAG.lock().unwrap_or_else(|e| e.into_inner());
    // Two HCP cases with an elastic and a tensile test each (the tensile test runs ~30 000 steps, a
    // wide window in which to interrupt the second case).
    let suite = hcp_campaign(r#""elastic", "tensile""#, &[0.0, 0.1]);
    let dir = std::env::temp_dir().join(format!("cgdem_interrupt_{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();

    // Ctrl-C as soon as the first case is on disk, i.e. during the second.
    let err = std::thread::scope(|s| {
        let run = s.spawn(|| run_suite(&suite, Some(&dir), Parallelism::Sequential));
        let t0 = Instant::now();
        while finished(&dir) == 0 && !run.is_finished() {
            assert!(
                t0.elapsed() < Duration::from_secs(120),
                "first case too slow"
            );
            std::thread::sleep(Duration::from_millis(1));
        }
        dem::interrupt::request();
        run.join().unwrap()
    })
    .unwrap_err();
    dem::interrupt::clear();
    assert!(matches!(err, DemError::Interrupted { .. }), "{err}");
    let kept =
        serde_json::from_slice::<PatchReport>(&std::fs::read(dir.join("report.json")).unwrap())
            .unwrap();
    assert_eq!(kept.cases.len(), 1, "the finished case is on disk");

    // The rerun continues: the first case is the stored one (same wall-clock figures), the second
    // is computed.
    let done = run_suite(&suite, Some(&dir), Parallelism::Sequential).unwrap();
    assert_eq!(done.cases.len(), 2);
    assert_eq!(done.cases[0].sample_seconds, kept.cases[0].sample_seconds);
    // ... bit for bit as in an uninterrupted run.
    let whole = run_suite(&suite, None, Parallelism::Sequential).unwrap();
    for k in 0..2 {
        let (a, b) = (&done.cases[k], &whole.cases[k]);
        let strength =
            |c: &dem::scenario::patch::suite::PatchCase| c.tensile.as_ref().unwrap().strength;
        let young =
            |c: &dem::scenario::patch::suite::PatchCase| c.elastic.as_ref().unwrap().young_modulus;
        assert_eq!((strength(a), young(a)), (strength(b), young(b)), "case {k}");
    }
    std::fs::remove_dir_all(&dir).ok();
}
