//! `cgdem junction` and `cgdem dstar` as processes: a small junction writes every output it promises,
//! bad configs exit 1 with the reason (never a panic), and the d* search under `mpirun -np 2` (the
//! project venv's MPICH) shares its rounds between the two ranks and gives the one-process result.

mod common;

use std::path::Path;
use std::process::Command;

use common::{cgdem, scratch, text, venv_or_fail};

/// A small box of the paper's silica recipe at d0 = 6 nm (36 x 30 x 24 nm), 1 ns of sliding.
const SMALL: &str = r#"
units = "nano"
[material]
preset = "table5"
[junction]
lengths = [36.0, 30.0, 24.0]
d0 = 6.0
duration = 1.0
frames = 20
force_samples = 100
dump_frames = 5
"#;

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

#[test]
fn a_junction_run_writes_its_verdict_curves_frames_dump_and_snapshot() {
    let d = scratch("junction-run");
    // `--seed` replaces the config's seed: the run is seed 2's.
    let cfg = write(&d, "j.toml", &format!("{SMALL}diameter = 10.0\nseed = 1\n"));
    let out = d.join("run");
    let o = cgdem(&[
        "junction",
        &cfg,
        "--seed",
        "2",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let v: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("verdict.json")).unwrap()).unwrap();
    assert_eq!(v["junction"]["seed"], 2);
    assert_eq!(v["summary"]["seed"], 2);
    // The top wall settles and the junction flattens, by less than a junction height (the collapse
    // guard's limit).
    let descent = v["summary"]["wall_descent_over_height"].as_f64().unwrap();
    assert!(descent > 0.0 && descent < 1.0, "{descent}");
    let outcome = v["outcome"].as_str().unwrap();
    assert!(
        outcome == "plastic_smoothing" || outcome == "wear_particle",
        "{outcome}"
    );
    assert_eq!(v["evidence"]["outcome"], v["outcome"]);
    assert!(v["evidence"]["turn"].is_f64() && v["evidence"]["rigidity"].is_f64());
    assert!(v["evidence"]["detachment"]["debris_fraction"].is_f64());
    assert!(v["material"].as_str().unwrap().contains("Table 5"));
    let dstar = v["dstar_eq22_target"].as_f64().unwrap();
    assert!((dstar - 18.48).abs() < 0.01, "{dstar}");
    // About one force row per requested sample, the last at the last step: a slide of v t = 10 nm.
    let force = std::fs::read_to_string(out.join("force.csv")).unwrap();
    assert!(
        (101..=103).contains(&force.lines().count()),
        "{}",
        force.lines().count()
    );
    let last: Vec<f64> = force
        .lines()
        .last()
        .unwrap()
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect();
    assert!((last[2] - 10.0).abs() < 0.02, "slide {}", last[2]);
    let frames: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("frames.json")).unwrap()).unwrap();
    assert_eq!(frames["frames"].as_array().unwrap().len(), 21);
    let dump = std::fs::read_to_string(out.join("junction.dump")).unwrap();
    assert_eq!(dump.matches("ITEM: TIMESTEP").count(), 6);
    assert!(dump.contains("omegaz ix iy iz body junction"));
    for png in ["snapshot.png", "force.png"] {
        let bytes = std::fs::read(out.join(png)).unwrap();
        assert_eq!(&bytes[1..4], b"PNG", "{png}");
    }
    assert!(!out.join("junction.progress.json").exists());
    assert!(text(&o.stdout).contains("wrote"));
}

#[test]
fn bad_junction_configs_exit_1_with_the_reason() {
    let d = scratch("junction-bad");
    let cases = [
        (
            "wide",
            format!("{SMALL}diameter = 40.0\n"),
            "does not fit the box",
        ),
        (
            "wide-column",
            format!("{SMALL}diameter = 30.0\nshape = \"column\"\n"),
            "does not fit the box",
        ),
        (
            "shape",
            format!("{SMALL}diameter = 10.0\nshape = \"cone\"\n"),
            "unknown variant",
        ),
        (
            "walls",
            format!("{SMALL}diameter = 10.0\nwall_thickness_over_d0 = 2.0\n"),
            "walls would cut the junction",
        ),
        ("small", format!("{SMALL}diameter = 8.0\n"), "below 1.5 d0"),
        (
            "units",
            SMALL.replace("units = \"nano\"", "units = \"reduced\"") + "diameter = 10.0\n",
            "units = \\\"nano\\\"",
        ),
        (
            "key",
            format!("{SMALL}diameter = 10.0\ndiametre = 3.0\n"),
            "diametre",
        ),
        (
            "two",
            SMALL.replace(
                "preset = \"table5\"",
                "preset = \"table5\"\ncard = \"x.toml\"",
            ),
            "exactly one",
        ),
    ];
    for (name, body, needle) in cases {
        let cfg = write(&d, &format!("{name}.toml"), &body);
        let o = cgdem(&["junction", &cfg, "--out", d.join(name).to_str().unwrap()]);
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{name}: {err}");
        assert!(
            err.contains(needle.trim_matches('\\')) || err.contains(&needle.replace("\\\"", "\"")),
            "{name}: {err}"
        );
    }
    let o = cgdem(&["junction", d.join("missing.toml").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
}

fn ranks(runs: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(runs)
        .unwrap()
        .filter_map(|e| std::fs::read_to_string(e.unwrap().path().join("ran_by")).ok())
        .map(|s| s.trim().to_string())
        .collect();
    v.sort();
    v
}

#[test]
fn the_dstar_search_shares_its_rounds_between_mpirun_ranks_and_matches_one_process() {
    venv_or_fail();
    let d = scratch("dstar-mpi");
    let taller = SMALL.replace("[36.0, 30.0, 24.0]", "[36.0, 36.0, 24.0]");
    let cfg = write(
        &d,
        "s.toml",
        &format!("{taller}\n[search]\nrange = [12.0, 14.0]\nseeds = [1, 2]\nrelative_width = 0.5\nmax_rounds = 1\nmeasure = false\n"),
    );
    let mpirun = md_bridge::Venv::locate().mpirun();
    let two = d.join("two");
    let o = Command::new(&mpirun)
        .args([
            "-np",
            "2",
            env!("CARGO_BIN_EXE_cgdem"),
            "dstar",
            &cfg,
            "--out",
            two.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o.stderr));
    // Four runs (two sizes, two seeds): two by each rank.
    let by = ranks(&two.join("runs"));
    assert_eq!(by, ["0 2", "0 2", "1 2", "1 2"], "{by:?}");
    let one = d.join("one");
    let o = cgdem(&["dstar", &cfg, "--out", one.to_str().unwrap(), "--jobs", "1"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert_eq!(ranks(&one.join("runs")), ["0 1"; 4]);
    let read = |p: &Path| -> serde_json::Value {
        let mut v: serde_json::Value =
            serde_json::from_slice(&std::fs::read(p.join("dstar.json")).unwrap()).unwrap();
        // Wall-clock figures differ; every number the physics gives must not.
        v["cost_seconds"] = 0.into();
        for r in v["runs"].as_array_mut().unwrap() {
            r["run_seconds"] = 0.into();
            r["relax_seconds"] = 0.into();
        }
        v
    };
    assert_eq!(read(&two), read(&one));
    assert!(two.join("outcomes.png").exists());
    // A rerun finds every run in the cache.
    let t = std::time::Instant::now();
    let o = cgdem(&["dstar", &cfg, "--out", one.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(t.elapsed().as_secs_f64() < 10.0);
    assert_eq!(read(&one), read(&two));
}
