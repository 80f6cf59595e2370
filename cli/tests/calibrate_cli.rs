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
    [start]\nk_n = 1.4\nk_t = 0.5\ndelta_e = 1.0\ndelta_f = 1.0\nf_mt = 1.0\n\
    [verification]\nsamples = [{ seed = 101 }]\n";

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

/// A tiny amorphous recipe (issue 16: every evaluation relaxes its two samples with the trial
/// parameters): E and nu by k_N and k_T, the trust-region solver, verified on one fresh sample.
const RECIPE: &str = "targets = [\"young_modulus\", \"poisson_ratio\"]\nunknowns = [\"k_n\", \"k_t\"]\n\
    [material]\nyoung_modulus = 1.0\npoisson_ratio = 0.15\ntensile_strength = 0.2\nshear_strength = 0.1\n\
    surface_energy = 1.5\nrestitution = 0.95\ndensity = 1.0\n\
    [sample]\nkind = \"amorphous\"\nd0_over_dc = 0.6\nl_over_d0 = 6.0\nw_over_d0 = 3.0\nseed = 1\n\
    [recipe]\nseeds = [1, 2]\n[verification]\nsamples = [{ seed = 11 }]\n\
    [solver]\nmethod = \"trust_region\"\ntolerance = 0.01\nmax_iterations = 20\n";

/// Ctrl-C (SIGINT) in the middle of a recipe-level calibration: the process stops after the round
/// in flight with the interrupt's message and a non-zero status, and the same command then finishes
/// with the uninterrupted run's card (provenance aside), bit for bit; `summary.txt` says Converged.
#[test]
fn an_interrupted_recipe_level_calibration_resumes_to_the_same_card() {
    let d = dir("sigint");
    let cfg = d.join("recipe.toml");
    std::fs::write(&cfg, RECIPE).unwrap();
    let (whole, cut) = (d.join("whole"), d.join("cut"));
    assert!(cgdem(&cfg, &whole).status().unwrap().success());
    let summary = std::fs::read_to_string(whole.join("summary.txt")).unwrap();
    assert!(summary.contains("Converged"), "{summary}");

    let mut child = cgdem(&cfg, &cut)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let t = Instant::now();
    while evaluations_done(&cut) < 4 && t.elapsed() < Duration::from_secs(300) {
        if child.try_wait().unwrap().is_some() {
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    assert!(
        child.try_wait().unwrap().is_none(),
        "ended before the interrupt"
    );
    let sent = Command::new("kill")
        .args(["-s", "INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success());
    let out = child.wait_with_output().unwrap();
    assert!(
        !out.status.success(),
        "an interrupted run is not a finished one"
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("interrupted"), "{err}");
    assert!(!cut.join("card.toml").exists());
    assert!(cgdem(&cfg, &cut).status().unwrap().success());
    assert_eq!(
        card_without_provenance(&cut),
        card_without_provenance(&whole)
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// `cgdem patch` re-measures a card on a sample of one's choosing: `--card FILE` or `[model] card`
/// (relative to the campaign file), with `--seed` replacing the recipe's seed. The report records the
/// card's model.
#[test]
fn cgdem_patch_measures_a_card_on_any_seed() {
    let d = dir("patch-card");
    let cfg = d.join("tiny.toml");
    std::fs::write(&cfg, TINY.replace("NU", "0.15")).unwrap();
    let cal = d.join("cal");
    assert!(cgdem(&cfg, &cal).status().unwrap().success());
    let card: toml::Value = std::fs::read_to_string(cal.join("card.toml"))
        .unwrap()
        .parse()
        .unwrap();
    let campaign = "tests = [\"elastic\"]\n[model]\ncard = \"cal/card.toml\"\n\
        [sample]\nkind = \"amorphous\"\nd0_over_dc = 0.6\nl_over_d0 = 6.0\nw_over_d0 = 3.0\nseed = 1\n";
    std::fs::write(d.join("campaign.toml"), campaign).unwrap();
    let patch = |args: &[&str], out: &Path| {
        let o = Command::new(env!("CARGO_BIN_EXE_cgdem"))
            .args(["--threads", "1", "patch"])
            .arg(d.join("campaign.toml"))
            .arg("--out")
            .arg(out)
            .args(args)
            .env("RUST_LOG", "warn")
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let r: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.join("report.json")).unwrap()).unwrap();
        r
    };
    let by_file = patch(&["--seed", "7"], &d.join("p1"));
    let by_flag = patch(
        &[
            "--seed",
            "7",
            "--card",
            cal.join("card.toml").to_str().unwrap(),
        ],
        &d.join("p2"),
    );
    let model = |r: &serde_json::Value| r["config"]["model"]["pair_model"]["scale"].clone();
    let k_n = card["model"]["scale"]["k_n"].as_float().unwrap();
    assert_eq!(model(&by_file)["k_n"].as_f64().unwrap(), k_n);
    assert_eq!(model(&by_file), model(&by_flag));
    assert_eq!(by_file["config"]["sample"]["seed"], 7);
    // The same results to the bit, wall times aside.
    assert_eq!(timeless(&by_file["cases"]), timeless(&by_flag["cases"]));
    let other_seed = patch(&["--seed", "8"], &d.join("p3"));
    assert_ne!(
        timeless(&other_seed["cases"][0]["elastic"]),
        timeless(&by_file["cases"][0]["elastic"])
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// `v` without the wall-time fields (`*seconds`), which differ from run to run.
fn timeless(v: &serde_json::Value) -> serde_json::Value {
    match v {
        serde_json::Value::Object(m) => serde_json::Value::Object(
            m.iter()
                .filter(|(k, _)| !k.ends_with("seconds"))
                .map(|(k, v)| (k.clone(), timeless(v)))
                .collect(),
        ),
        serde_json::Value::Array(a) => serde_json::Value::Array(a.iter().map(timeless).collect()),
        other => other.clone(),
    }
}
