//! `cgdem compare` as a process on a tiny comparison (real LAMMPS for the MD card and junctions, the
//! DEM d* search on a small box of the paper's silica recipe, which is only there to exercise the
//! DEM half: the nm lengths go through the card's sigma_nm): the outputs that checks read are
//! written, a rerun reads every run from the caches and writes the same bytes, a comparison that
//! lost a run (as an interrupted one has) runs only that run again and gives the same result, and a
//! bad config exits 1 with the reason.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::{scratch, text, venv_or_fail};

fn cgdem(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_cgdem"))
        .args(args)
        .env("CGDEM_VENV", md_bridge::Venv::locate().root)
        .output()
        .unwrap()
}

/// The small DEM search: 36 x 36 x 24 nm at d0 = 6 nm, D = 12 and 14 nm, one round.
const DEM: &str = r#"
units = "nano"
[material]
preset = "table5"
[junction]
lengths = [36.0, 36.0, 24.0]
d0 = 6.0
duration = 1.0
frames = 20
force_samples = 100
dump_frames = 5
[search]
range = [12.0, 14.0]
seeds = [1, 2]
relative_width = 0.5
max_rounds = 1
measure = false
"#;

/// The model card and two MD sizes (8 and 10 sigma, half a D of sliding), one round; a scan of one
/// more seed at the bracket's ends.
const COMPARE: &str = r#"
[model]
cutoff = 1.3
[md]
range = [8.0, 10.0]
seeds = [1, 2]
max_rounds = 1
[md.junction]
cutoff = 1.3
length_factor = 2.0
slab_factor = 0.35
slide_factor = 0.5
frames = 4
dump_file = "junction.dump"
[[dem]]
config = "dem.toml"
[scan]
seeds = [3]
outside = false
"#;

struct Case {
    cfg: String,
    out: PathBuf,
    cache: PathBuf,
}

fn case(name: &str) -> Case {
    let d = scratch(name);
    std::fs::write(d.join("dem.toml"), DEM).unwrap();
    std::fs::write(d.join("compare.toml"), COMPARE).unwrap();
    Case {
        cfg: d.join("compare.toml").to_str().unwrap().into(),
        out: d.join("out"),
        cache: d.join("md-cache"),
    }
}

fn run(c: &Case) -> Output {
    run_with(c, 1)
}

fn run_with(c: &Case, jobs: usize) -> Output {
    let o = cgdem(&[
        "compare",
        &c.cfg,
        "--out",
        c.out.to_str().unwrap(),
        "--md-cache",
        c.cache.to_str().unwrap(),
        "--jobs",
        &jobs.to_string(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    o
}

/// `v` without the keys whose name holds `seconds` (wall times and the costs summed from them), at
/// any depth.
fn without_times(v: &serde_json::Value) -> serde_json::Value {
    match v {
        serde_json::Value::Object(m) => m
            .iter()
            .filter(|(k, _)| !k.contains("seconds"))
            .map(|(k, x)| (k.clone(), without_times(x)))
            .collect(),
        serde_json::Value::Array(a) => a.iter().map(without_times).collect(),
        x => x.clone(),
    }
}

#[test]
fn md_runs_side_by_side_give_the_runs_of_one_at_a_time() {
    venv_or_fail();
    let (one, two) = (case("compare-jobs-1"), case("compare-jobs-2"));
    run_with(&one, 1);
    let o = run_with(&two, 2);
    // Every run ran (none came from a cache), each as its own worker.
    assert_eq!(md_lines(&o).1, 0, "{}", text(&o.stderr));
    let (a, b) = (
        json(&one.out.join("compare.json")),
        json(&two.out.join("compare.json")),
    );
    for k in ["md", "md_bracket", "md_detachment"] {
        assert_eq!(without_times(&a[k]), without_times(&b[k]), "{k}");
    }
    assert_eq!(a["md"]["runs"].as_array().unwrap().len(), 4);
    // The same requests: the same MD job hashes in both caches.
    let hashes = |c: &Case| {
        let mut h: Vec<String> = std::fs::read_dir(&c.cache)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        h.sort();
        h
    };
    assert_eq!(hashes(&one), hashes(&two));
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap()
}

/// MD lines of stderr that ran a job, and that read one from the cache.
fn md_lines(o: &Output) -> (usize, usize) {
    let e = text(&o.stderr);
    let md: Vec<&str> = e.lines().filter(|l| l.starts_with("MD D = ")).collect();
    (
        md.iter().filter(|l| l.contains("(ran,")).count(),
        md.iter().filter(|l| l.contains("(cached,")).count(),
    )
}

#[test]
fn a_comparison_writes_its_outputs_and_reruns_from_its_caches() {
    venv_or_fail();
    let c = case("compare-cache");
    let first = run(&c);
    let v = json(&c.out.join("compare.json"));
    // The scan ran seed 3 at each end the bisection found (no split sizes: one round), on both
    // sides, and fitted every run of the side.
    let ends = |b: &serde_json::Value| -> Vec<f64> {
        b.as_array()
            .unwrap()
            .iter()
            .filter_map(|x| x.as_f64())
            .collect()
    };
    let md_scan = &v["md_detachment"];
    let md_ends = ends(&v["md_bracket"]);
    assert!(!md_ends.is_empty(), "{}", v["md_bracket"]);
    assert_eq!(ends(&md_scan["sizes"]), md_ends);
    let n_scan = md_scan["scan_runs"].as_u64().unwrap() as usize;
    assert_eq!(n_scan, md_ends.len());
    assert_eq!(md_scan["fit"]["runs"].as_u64(), Some(4 + n_scan as u64));
    assert!(md_scan["trials"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|t| t["scan"].as_bool() == Some(true))
        .all(|t| t["seed"].as_u64() == Some(3)));
    assert_eq!(md_lines(&first), (4 + n_scan, 0), "{}", text(&first.stderr));
    // A fit or a status, never a NaN (a NaN would not even be valid JSON).
    assert!(md_scan["fit"]["status"].is_string());
    let dem_scan = &v["dem"][0]["detachment"];
    let dem_ends = ends(&v["dem"][0]["bracket"]);
    assert_eq!(ends(&dem_scan["sizes"]), dem_ends);
    assert_eq!(dem_scan["scan_runs"].as_u64(), Some(dem_ends.len() as u64));
    assert_eq!(
        dem_scan["fit"]["runs"].as_u64(),
        Some(4 + dem_ends.len() as u64)
    );
    // The fields checks read: md_bracket, dem[].bracket (sigma), dstar_theory (eq 22, sigma).
    assert_eq!(v["md_bracket"].as_array().unwrap().len(), 2);
    let dem = v["dem"].as_array().unwrap();
    assert_eq!(dem.len(), 1);
    assert_eq!(dem[0]["bracket"].as_array().unwrap().len(), 2);
    // d0 = 6 nm in sigma (0.34 nm).
    assert!((dem[0]["d0"].as_f64().unwrap() - 6.0 / 0.34).abs() < 1e-9);
    // The card's d* of eq 22 at cut-off 1.3: 25.0 sigma (docs/md-bridge.md).
    let t = v["dstar_theory"].as_f64().unwrap();
    assert!((t - 25.0).abs() < 0.5, "{t}");
    // Every run of the bisection with its cost: 4 MD runs, 4 DEM runs.
    let runs = v["md"]["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 4);
    assert!(runs
        .iter()
        .all(|r| r["wall_seconds"].as_f64().unwrap() > 0.0));
    assert_eq!(dem[0]["runs"].as_array().unwrap().len(), 4);
    assert_eq!(v["properties"].as_array().unwrap().len(), 6);
    let svg = std::fs::read_to_string(c.out.join("compare.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("P(wear particle)"));
    assert!(svg.contains("MD (LAMMPS): ") && svg.contains("DEM d0 = "));
    let map = std::fs::read_to_string(c.out.join("outcomes.svg")).unwrap();
    assert!(map.starts_with("<svg") && map.contains("MD (LAMMPS), seed 3"));
    for f in ["compare.png", "outcomes.png"] {
        assert_eq!(&std::fs::read(c.out.join(f)).unwrap()[1..4], b"PNG", "{f}");
    }
    assert!(std::fs::read_to_string(c.out.join("compare.md"))
        .unwrap()
        .contains("| property | MD card | unit |"));

    // Rerun: nothing runs, the same bytes come out.
    let before: Vec<Vec<u8>> = ["compare.json", "compare.md", "compare.svg"]
        .iter()
        .map(|f| std::fs::read(c.out.join(f)).unwrap())
        .collect();
    let second = run(&c);
    assert_eq!(
        md_lines(&second),
        (0, 4 + n_scan),
        "{}",
        text(&second.stderr)
    );
    for (f, b) in ["compare.json", "compare.md", "compare.svg"]
        .iter()
        .zip(&before)
    {
        assert_eq!(&std::fs::read(c.out.join(f)).unwrap(), b, "{f} changed");
    }

    // A comparison that lost a finished MD run (an interruption before its record was written)
    // runs that one again, reads the rest, and gives the same verdicts.
    let lost = runs[1]["job"].as_str().unwrap();
    std::fs::remove_file(c.cache.join(lost).join("record.json")).unwrap();
    std::fs::remove_file(c.out.join("compare.json")).unwrap();
    let third = run(&c);
    assert_eq!(md_lines(&third), (1, 3 + n_scan), "{}", text(&third.stderr));
    let w = json(&c.out.join("compare.json"));
    let verdicts = |v: &serde_json::Value| -> Vec<(String, String)> {
        v["md"]["runs"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| (r["diameter"].to_string(), r["outcome"].to_string()))
            .collect()
    };
    assert_eq!(verdicts(&v), verdicts(&w));
    assert_eq!(v["md_bracket"], w["md_bracket"]);
    assert_eq!(v["dem"][0]["bracket"], w["dem"][0]["bracket"]);
    // The same fit (the rerun's wall time is its own).
    for k in ["fit", "fractions", "sizes"] {
        assert_eq!(v["md_detachment"][k], w["md_detachment"][k], "{k}");
    }
}

#[test]
fn bad_compare_configs_exit_1_with_the_reason() {
    let c = case("compare-bad");
    let cases = [
        (
            COMPARE.replace("cutoff = 1.3\n[md]", "cutoff = 1.6\n[md]"),
            "differs from the model card",
        ),
        (
            COMPARE.replace("range = [8.0, 10.0]", "range = [10.0, 8.0]"),
            "range",
        ),
        (
            COMPARE.replace("max_rounds = 1", "max_round = 1"),
            "max_round",
        ),
        (COMPARE.replace("dem.toml", "missing.toml"), "missing.toml"),
        (
            COMPARE.replace("seeds = [3]", "seeds = [2, 3]"),
            "search seeds",
        ),
        (
            COMPARE.replace("seeds = [3]", "seeds = []"),
            "at least one seed",
        ),
        (
            COMPARE.replace("seeds = [3]", "seeds = [3, 3]"),
            "listed twice",
        ),
        (
            COMPARE
                .replace("[scan]\nseeds = [3]\noutside = false\n", "")
                .replace("\"dem.toml\"", "\"dem.toml\"\nscan_seeds = [3]"),
            "need a [scan] section",
        ),
    ];
    for (toml, reason) in cases {
        std::fs::write(&c.cfg, toml).unwrap();
        let o = cgdem(&[
            "compare",
            &c.cfg,
            "--out",
            c.out.to_str().unwrap(),
            "--md-cache",
            c.cache.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(1), "{reason}: {}", text(&o.stderr));
        let e = text(&o.stderr);
        assert!(e.contains(reason), "{reason}: {e}");
        assert!(!e.contains("panicked"), "{e}");
    }
}
