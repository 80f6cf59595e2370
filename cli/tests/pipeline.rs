//! The README's main job, `cgdem pipeline` on its default (small) settings, as a process: it must
//! exit cleanly, write the card, and the verification (the patch tests re-run with the card's
//! model) must meet every target within 1 % where the closed-form parameters miss by more than
//! 5 %; the calibration figure is a PNG of the expected size. The MD card's calibration (issue 16)
//! is the ignored test below.

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

/// Issue 16's MD line as a user runs it: the card `cgdem md silica` measures with LAMMPS, calibrated
/// by `cgdem pipeline --material CARD` on its defaults (five 12 d0 samples per evaluation), must
/// converge, verify within 5 % in the mean and 10 % per fresh sample on E, nu and both strengths, and
/// hold under shear. Output under `runs/issue16-md-pipeline` so that a rerun resumes (docs/
/// calibration.md, "The MD card on five 12 d0 samples": 4 323 s under load; alone ~4 min of MD and
/// ~45 min of pipeline).
#[test]
#[ignore = "issue 16 acceptance, ~50 min on 2 cores: cargo test --release -p cgdem --test pipeline -- --ignored"]
fn the_md_silica_card_converges_verifies_on_fresh_samples_and_holds_under_shear() {
    common::venv_or_fail();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../runs/issue16-md-pipeline");
    let (md, out) = (root.join("md"), root.join("pipeline"));
    let step = |args: &[&str]| {
        let run = common::cgdem(args);
        assert!(
            run.status.success(),
            "{args:?}: {}",
            common::text(&run.stderr)
        );
    };
    step(&["md", "silica", "--np", "2", "--out", md.to_str().unwrap()]);
    let card = md.join("card.toml");
    step(&[
        "--threads",
        "2",
        "pipeline",
        "--material",
        card.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let summary = std::fs::read_to_string(out.join("summary.txt")).unwrap();
    eprintln!("{summary}");
    assert!(summary.contains("status Converged"), "{summary}");
    assert!(summary.contains("holds under shear"), "{summary}");
    let v: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("verification.json")).unwrap()).unwrap();
    for name in [
        "young_modulus",
        "poisson_ratio",
        "tensile_strength",
        "shear_strength",
    ] {
        let c = &v["verification"][name];
        let (mean, target) = (c["mean"].as_f64().unwrap(), c["target"].as_f64().unwrap());
        let spread = c["spread"].as_f64().unwrap();
        assert!((mean / target - 1.0).abs() <= 0.05, "{name}: {summary}");
        assert!(spread <= 0.10, "{name}: {summary}");
    }
}
