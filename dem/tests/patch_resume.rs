//! A patch-test campaign continues where it stopped: `report.json` is rewritten after every case, and a
//! rerun into the same directory reuses its finished cases and computes only the rest; a report of a
//! different campaign is refused, never overwritten.

mod common;

use common::hcp_campaign;
use dem::scenario::patch::suite::PatchCase;
use dem::scenario::patch::{run_suite, PatchReport};
use dem::{DemError, Parallelism};

fn dir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("cgdem_resume_{}_{name}", std::process::id()));
    std::fs::remove_dir_all(&d).ok();
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn read_report(path: &std::path::Path) -> PatchReport {
    serde_json::from_slice(&std::fs::read(path.join("report.json")).unwrap()).unwrap()
}

/// A report as written to disk (the stress-strain curves go to their own CSV files).
fn on_disk(r: &PatchReport) -> serde_json::Value {
    serde_json::to_value(r).unwrap()
}

/// What a case measured, without its wall-clock times.
fn measured(c: &PatchCase) -> [f64; 6] {
    let e = c.elastic.as_ref().unwrap();
    let steps = e.steps as f64;
    [
        c.volume_fraction,
        e.c11,
        e.c12,
        e.young_modulus,
        e.poisson_ratio,
        steps,
    ]
}

#[test]
fn an_interrupted_campaign_reuses_its_finished_cases() {
    // Two quick cases differing in the target nu.
    let suite = hcp_campaign("\"elastic\"", &[0.0, 0.2]);
    let full_dir = dir("full");
    let full = run_suite(&suite, Some(&full_dir), Parallelism::Sequential).unwrap();
    assert_eq!(full.cases.len(), 2);
    assert_eq!(
        on_disk(&read_report(&full_dir)),
        on_disk(&full),
        "the report on disk is the result"
    );

    // What an interruption during the second case leaves: a report with the first case only. Its
    // E is marked (doubled) so that reuse, not recomputation, is visible.
    let cut_dir = dir("cut");
    let mut partial = full.clone();
    partial.cases.truncate(1);
    let marked = 2.0 * full.cases[0].elastic.as_ref().unwrap().young_modulus;
    partial.cases[0].elastic.as_mut().unwrap().young_modulus = marked;
    std::fs::write(
        cut_dir.join("report.json"),
        serde_json::to_vec(&partial).unwrap(),
    )
    .unwrap();
    let resumed = run_suite(&suite, Some(&cut_dir), Parallelism::Sequential).unwrap();
    assert_eq!(
        resumed.cases[0].elastic.as_ref().unwrap().young_modulus,
        marked,
        "the finished case was reused"
    );
    assert_eq!(
        measured(&resumed.cases[1]),
        measured(&full.cases[1]),
        "the missing case was computed, bit for bit as in the uninterrupted run"
    );
    assert_eq!(on_disk(&read_report(&cut_dir)), on_disk(&resumed));

    // Another campaign into the same directory: refused, and the report left as it was.
    let before = std::fs::read(cut_dir.join("report.json")).unwrap();
    let err = run_suite(
        &hcp_campaign("\"elastic\"", &[0.0, 0.1]),
        Some(&cut_dir),
        Parallelism::Sequential,
    )
    .unwrap_err();
    assert!(
        matches!(&err, DemError::InvalidConfig(m) if m.contains("another campaign")),
        "{err}"
    );
    assert_eq!(std::fs::read(cut_dir.join("report.json")).unwrap(), before);

    // A damaged report is a clear error, not a panic and not a silent restart.
    std::fs::write(cut_dir.join("report.json"), b"{\"config\": 3").unwrap();
    let err = run_suite(&suite, Some(&cut_dir), Parallelism::Sequential).unwrap_err();
    assert!(matches!(err, DemError::Format { .. }), "{err}");

    for d in [full_dir, cut_dir] {
        std::fs::remove_dir_all(d).ok();
    }
}
