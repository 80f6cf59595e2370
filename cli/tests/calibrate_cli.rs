//! `cgdem calibrate` as a process: a calibration killed (SIGKILL) midway and rerun reaches the same
//! card as an uninterrupted one; unreachable targets are refused with a non-zero exit before any file
//! is written. A tiny elastic-only case (HCP 8 d0, E and nu by k_N, k_T) keeps it to seconds.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

const TINY: &str = "targets = [\"young_modulus\", \"poisson_ratio\"]\nunknowns = [\"k_n\", \"k_t\"]\n\
    [material]\nyoung_modulus = 1.0\npoisson_ratio = NU\ntensile_strength = 0.2\nshear_strength = 0.1\n\
    surface_energy = 1.5\nrestitution = 0.95\ndensity = 1.0\n\
    [sample]\nkind = \"hcp\"\nd0_over_dc = 0.6\nl_over_d0 = 8.0\nw_over_d0 = 3.0\n\
    [start]\nk_n = 1.4\nk_t = 0.5\ndelta_e = 1.0\ndelta_f = 1.0\nf_mt = 1.0\n";

fn dir(name: &str) -> PathBuf {
    common::scratch(&format!("cal-{name}"))
}

fn cgdem(config: &Path, out: &Path) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_cgdem"));
    c.args(["--threads", "1", "calibrate"])
        .arg(config)
        .arg("--out")
        .arg(out);
    c.env("RUST_LOG", "warn");
    c
}

fn evaluations_done(out: &Path) -> usize {
    std::fs::read_dir(out.join("evals")).map_or(0, |d| d.count())
}

fn card_without_provenance(out: &Path) -> toml::Value {
    let mut v: toml::Value = std::fs::read_to_string(out.join("card.toml"))
        .unwrap()
        .parse()
        .unwrap();
    v.as_table_mut().unwrap().remove("provenance");
    v
}

#[test]
fn killed_process_resumes_to_the_same_card() {
    let d = dir("kill");
    let cfg = d.join("tiny.toml");
    std::fs::write(&cfg, TINY.replace("NU", "0.15")).unwrap();
    let (whole, killed) = (d.join("whole"), d.join("killed"));
    assert!(cgdem(&cfg, &whole).status().unwrap().success());

    let mut child = cgdem(&cfg, &killed).spawn().unwrap();
    let t = Instant::now();
    // Kill once a few evaluations (the start and part of the first Jacobian) are on disk.
    while evaluations_done(&killed) < 3 && t.elapsed() < Duration::from_secs(120) {
        if child.try_wait().unwrap().is_some() {
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let finished_early = child.try_wait().unwrap().is_some();
    child.kill().ok();
    child.wait().unwrap();
    assert!(
        !finished_early,
        "the calibration ended before it could be killed"
    );
    assert!(!killed.join("card.toml").exists(), "killed before the end");
    assert!(cgdem(&cfg, &killed).status().unwrap().success());
    assert_eq!(
        card_without_provenance(&killed),
        card_without_provenance(&whole)
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn unreachable_poisson_ratio_is_refused_before_any_simulation() {
    let d = dir("refuse");
    let cfg = d.join("bad.toml");
    std::fs::write(&cfg, TINY.replace("NU", "0.3")).unwrap();
    let out = d.join("out");
    let o = cgdem(&cfg, &out).output().unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("unreachable") && err.contains("1/4"), "{err}");
    assert!(!out.exists());
    let _ = std::fs::remove_dir_all(&d);
}
