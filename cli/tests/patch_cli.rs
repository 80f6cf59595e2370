//! `cgdem sample` and `cgdem patch` as processes: a saved sample read back by a patch campaign on two
//! threads gives the library's one-thread results to the last bit, with its figures; bad input exits
//! with status 1 and names the problem (never a panic, whose status is 101).

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use dem::scenario::patch::{run_suite, PatchReport, PatchSuite};
use dem::Parallelism;

const MATERIAL: &str = "[material]\nyoung_modulus = 1.0\npoisson_ratio = 0.15\n\
    tensile_strength = 0.2\nshear_strength = 0.1\nsurface_energy = 1.5\nrestitution = 0.95\n\
    density = 1.0\n";

fn dir(name: &str) -> PathBuf {
    common::scratch(&format!("patch-{name}"))
}

fn cgdem(args: &[&str], config: &Path, out: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_cgdem"))
        .args(args)
        .arg(config)
        .arg("--out")
        .arg(out)
        .env("RUST_BACKTRACE", "0")
        .output()
        .expect("cannot start cgdem")
}

fn is_png(p: &Path) -> bool {
    std::fs::read(p).is_ok_and(|b| b.starts_with(b"\x89PNG\r\n\x1a\n") && b.len() > 1000)
}

#[test]
fn saved_sample_and_campaign_on_two_threads_equal_the_library_on_one() {
    let d = dir("file");
    let sample_cfg = d.join("sample.toml");
    std::fs::write(
        &sample_cfg,
        format!("{MATERIAL}[sample]\nkind = \"hcp\"\nd0_over_dc = 0.6\nl_over_d0 = 8.0\nw_over_d0 = 3.0\n"),
    )
    .unwrap();
    let sample = d.join("hcp.json");
    let out = cgdem(&["--threads", "2", "sample"], &sample_cfg, &sample);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        !d.join("hcp.json.progress.json").exists(),
        "a finished sample keeps no progress file"
    );

    let patch_cfg = d.join("patch.toml");
    let text = format!(
        "tests = [\"elastic\", \"tensile\"]\n{MATERIAL}[sample]\nkind = \"file\"\npath = {:?}\n",
        sample.to_str().unwrap()
    );
    std::fs::write(&patch_cfg, &text).unwrap();
    let campaign = d.join("campaign");
    let out = cgdem(&["--threads", "2", "patch"], &patch_cfg, &campaign);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: PatchReport =
        serde_json::from_slice(&std::fs::read(campaign.join("report.json")).unwrap()).unwrap();
    // One case: its loading curves, and no trends figure (drawn for campaigns of two or more cases).
    assert!(is_png(&campaign.join("curves.png")) && !campaign.join("trends.png").exists());

    let suite: PatchSuite = toml::from_str(&text).unwrap();
    let library = run_suite(&suite, None, Parallelism::Sequential).unwrap();
    assert_eq!(report.cases.len(), 1);
    let (cli, lib) = (&report.cases[0], &library.cases[0]);
    assert_eq!(cli.particles, lib.particles);
    let (ce, le) = (cli.elastic.as_ref().unwrap(), lib.elastic.as_ref().unwrap());
    assert_eq!(ce.young_modulus.to_bits(), le.young_modulus.to_bits());
    assert_eq!(ce.poisson_ratio.to_bits(), le.poisson_ratio.to_bits());
    let (ct, lt) = (cli.tensile.as_ref().unwrap(), lib.tensile.as_ref().unwrap());
    assert_eq!(ct.strength.to_bits(), lt.strength.to_bits());
    // And the numbers are physics, not zeros: an HCP lattice at d0 = 0.6 d_c is stiff and strong.
    assert!(ce.young_modulus > 0.5 && ce.poisson_ratio > 0.0 && ct.strength > 0.1);
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn bad_input_exits_with_status_1_and_the_reason() {
    let d = dir("bad");
    let good = format!(
        "tests = [\"elastic\"]\n{MATERIAL}[sample]\nkind = \"hcp\"\nd0_over_dc = 0.6\nl_over_d0 = 8.0\nw_over_d0 = 3.0\n"
    );
    let cases = [
        (
            "typo",
            good.replace("young_modulus", "youngs_modulus"),
            "unknown field `youngs_modulus`",
        ),
        (
            "negative",
            good.replace("tensile_strength = 0.2", "tensile_strength = -0.2"),
            "tensile_strength = -0.2 must be positive",
        ),
        (
            "nu",
            good.replace("poisson_ratio = 0.15", "poisson_ratio = 0.3"),
            "above 1/4",
        ),
        (
            "syntax",
            good.replace("[\"elastic\"]", "[\"elastic\""),
            "invalid array",
        ),
        ("test", good.replace("elastic", "bending"), "bending"),
        (
            "file",
            good.replace("kind = \"hcp\"", "kind = \"file\"\npath = \"nowhere.json\"")
                .replace("d0_over_dc = 0.6\nl_over_d0 = 8.0\nw_over_d0 = 3.0\n", ""),
            "nowhere.json",
        ),
    ];
    for (name, text, reason) in cases {
        let cfg = d.join(format!("{name}.toml"));
        std::fs::write(&cfg, text).unwrap();
        let out = cgdem(&["patch"], &cfg, &d.join(name));
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{name}: {err}");
        assert!(
            err.contains(reason) && !err.contains("panicked"),
            "{name}: {err}"
        );
    }
    let out = cgdem(&["patch"], &d.join("missing.toml"), &d.join("missing"));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("missing.toml") && err.contains("No such file"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&d);
}
