//! The README's main job, `cgdem pipeline` on its default (small) settings, as a process: it must
//! exit cleanly, write the card, and the verification (the patch tests re-run with the card's
//! model) must meet every target within 1 % where the closed-form parameters miss by more than
//! 5 %; the calibration figure is a PNG of the expected size.

mod common;

use std::process::Command;

#[test]
fn the_main_job_calibrates_and_verifies_its_card() {
    let out = common::scratch("pipeline");
    let run = Command::new(env!("CARGO_BIN_EXE_cgdem"))
        .args(["pipeline", "--out"])
        .arg(&out)
        .env("RUST_LOG", "warn")
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(out.join("card.toml").exists());
    let v: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("verification.json")).unwrap()).unwrap();
    let mut worst_before: f64 = 0.0;
    let mut checked = 0;
    for (name, target) in v["targets"].as_object().unwrap() {
        let Some(target) = target.as_f64() else {
            continue;
        };
        let err = |set: &str| (v[set][name].as_f64().unwrap() - target).abs() / target;
        assert!(
            err("verified") < 0.01,
            "{name}: {:.3} %",
            100.0 * err("verified")
        );
        worst_before = worst_before.max(err("uncalibrated"));
        checked += 1;
    }
    assert_eq!(
        checked, 4,
        "E, nu and both strengths are calibrated by default"
    );
    assert!(
        worst_before > 0.05,
        "the closed form misses by {worst_before}"
    );

    let png = std::fs::read(out.join("calibration.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let be = |i: usize| u32::from_be_bytes(png[i..i + 4].try_into().unwrap());
    assert_eq!((be(16), be(20)), (1400, 600));
    let _ = std::fs::remove_dir_all(&out);
}
