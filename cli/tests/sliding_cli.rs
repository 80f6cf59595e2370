//! `cgdem sliding` on a grid, as a process: the grid's relaxed boxes are jobs of their own, one per
//! material, which the material's strength job and every run of it read (each box relaxed once), and a
//! rerun finds everything cached.

mod common;

use common::{cgdem, scratch, text};
use std::path::Path;

/// Two runs of one material (p_N 0.01 and 0.02 E) and one of a stronger material: two boxes. L = 10 d0
/// (a few hundred particles), 0.3 L of sliding, a short shear test: the plumbing, not the physics.
const GRID: &str = r#"
[sliding]
d0_over_l = 0.1
distance_over_l = 0.3
bins = 20
windows = 3
samples_per_window = 4
force_samples = 30
dump_frames = 0

# The shear test stopped 0.1 strain past its peak (no flow stress): the strengths, not the flow.
[sliding.strength_tests.shear]
mode = "shear"
post_peak_strain = 0.1
max_strain = 0.5

[[grid]]
pressure = 0.01
strength = 0.1
d_star = 0.4

[[grid]]
pressure = 0.02
strength = 0.1
d_star = 0.4

[[grid]]
pressure = 0.01
strength = 0.2
d_star = 0.4
"#;

/// The job folders under `dir` that hold a result.
fn done_jobs(dir: &Path) -> Vec<std::path::PathBuf> {
    let mut v: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.join("result.json").exists())
        .collect();
    v.sort();
    v
}

/// Every file under `dir` whose name is `name`.
fn find(dir: &Path, name: &str, found: &mut Vec<std::path::PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            find(&p, name, found);
        } else if p.file_name().is_some_and(|n| n == name) {
            found.push(p);
        }
    }
}

#[test]
fn a_grid_relaxes_each_box_once_for_its_strength_job_and_its_runs() {
    let dir = scratch("sliding-grid");
    let cfg = dir.join("grid.toml");
    std::fs::write(&cfg, GRID).unwrap();
    let out = dir.join("out");
    let args = [
        "sliding",
        cfg.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--jobs",
        "2",
    ];
    let o = cgdem(&args);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(
        text(&o.stdout).contains("3 of 3 runs done"),
        "{}",
        text(&o.stdout)
    );
    // One box per material, each a finished job with its sample; no relaxation anywhere else.
    let boxes = done_jobs(&out.join("samples"));
    assert_eq!(boxes.len(), 2, "{boxes:?}");
    for b in &boxes {
        assert!(b.join("sample.json").exists(), "{b:?}");
    }
    let mut samples = Vec::new();
    find(&out, "sample.json", &mut samples);
    assert_eq!(samples.len(), 2, "{samples:?}");
    let mut progress = Vec::new();
    find(&out, "relax.progress.json", &mut progress);
    assert!(progress.is_empty(), "{progress:?}");
    assert_eq!(done_jobs(&out.join("strength")).len(), 2);
    let runs = done_jobs(&out.join("runs"));
    assert_eq!(runs.len(), 3);
    // The two runs of the weaker material read one box: the same relaxation record, to the bit, and
    // the same particle count as the strength job measured on.
    let summary = |p: &Path| -> serde_json::Value {
        serde_json::from_slice(&std::fs::read(p.join("summary.json")).unwrap()).unwrap()
    };
    let s: Vec<serde_json::Value> = runs.iter().map(|r| summary(r)).collect();
    let weak: Vec<&serde_json::Value> = s.iter().filter(|v| v["strength"] == 0.1).collect();
    assert_eq!(weak.len(), 2);
    assert_eq!(weak[0]["relax_seconds"], weak[1]["relax_seconds"]);
    assert_eq!(weak[0]["tau_m"], weak[1]["tau_m"]);
    assert_ne!(weak[0]["p_n"], weak[1]["p_n"]);
    let csv = std::fs::read_to_string(out.join("grid.csv")).unwrap();
    assert_eq!(csv.lines().count(), 4, "{csv}");
    assert!(!csv.contains("pending"), "{csv}");
    // A rerun computes nothing: the same grid, no new box.
    let again = cgdem(&args);
    assert!(again.status.success(), "{}", text(&again.stderr));
    assert_eq!(std::fs::read_to_string(out.join("grid.csv")).unwrap(), csv);
    assert_eq!(done_jobs(&out.join("samples")), boxes);
}

/// Paper 004 section 3 at the paper's size: its shear-band example (Fig. 3b) is a shear band inside
/// the material, at full contact, and carries p_T near the shear strength tau_m that the shear patch
/// test measures on the same box (the report's 30 %: one seed, 4 L). About 45 minutes on 2 cores.
#[test]
#[ignore = "paper-size sliding, ~45 min on 2 cores: cargo test --release -p cgdem --test sliding_cli -- --ignored"]
fn paper_size_shear_band_carries_tau_m() {
    let cfg =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../configs/sliding-paper-shear-band.toml");
    let out = scratch("sliding-paper-shear-band").join("out");
    let args = [
        "--threads",
        "2",
        "sliding",
        cfg.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    let o = cgdem(&args);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let s: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["regime"], "shear_band", "{s}");
    // The band never reached a rigid body and the layer is at full contact (no gap: rho_TBL at or
    // above the relaxed density, which p_N compacts).
    assert_eq!(s["steady_windows_at_body"], 0, "{s}");
    assert!(s["rho_tbl"].as_f64().unwrap() >= 1.0, "{s}");
    // tau_m measured on this box (a measured strength comes with its tensile one).
    assert!(s["sigma_t"].is_number(), "{s}");
    let ratio = s["p_t_over_tau_m"].as_f64().unwrap();
    assert!((ratio - 1.0).abs() <= 0.3, "p_T / tau_m = {ratio}");
}

/// A single run's long stages show their progress without `-v` (off a terminal as plain lines): the
/// relaxation, the strength tests before the run (a paper-size box spends half an hour there) and
/// the run's own tenths; the normal-only law's shear test has no target, so no ratio to one.
#[test]
fn a_single_run_logs_the_progress_of_every_stage_by_default() {
    let dir = scratch("sliding-progress");
    let cfg = dir.join("one.toml");
    let single = GRID
        .split("[[grid]]")
        .next()
        .unwrap()
        .replace("dump_frames = 0", "dump_frames = 0\npressure = 0.01")
        + "[sliding.material]\nstrength = 0.1\nd_star = 0.4\n";
    std::fs::write(&cfg, single).unwrap();
    let out = dir.join("out");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_cgdem"))
        .args([
            "sliding",
            cfg.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .env_remove("RUST_LOG")
        .output()
        .unwrap();
    let err = text(&o.stderr);
    assert!(o.status.success(), "{err}");
    for line in [
        "stage: relaxation phase 1",
        "stage: relaxed",
        "stage: strength test mode=Shear",
        "stage: strength test mode=Tensile",
        "progress: sliding: 100 %",
    ] {
        assert!(err.contains(line), "no '{line}' in:\n{err}");
    }
    assert!(!err.contains("inf"), "{err}");
    assert!(out.join("summary.json").exists());
}

/// `grid.csv` without its wall-clock column: every figure the physics gives, row by row.
fn grid_rows(out: &Path) -> Vec<String> {
    let csv = std::fs::read_to_string(out.join("grid.csv")).unwrap();
    let mut lines = csv.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let clock = head.iter().position(|&h| h == "run_seconds").unwrap();
    lines
        .map(|l| {
            let mut f: Vec<&str> = l.split(',').collect();
            f.remove(clock);
            f.join(",")
        })
        .collect()
}

/// The grid run in one process, two jobs side by side: the reference of the sharded runs.
fn one_process_grid(dir: &Path, cfg: &Path) -> Vec<String> {
    let out = dir.join("one");
    let o = cgdem(&[
        "sliding",
        cfg.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--jobs",
        "2",
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    grid_rows(&out)
}

/// A Slurm array task runs its share of the pending stage and exits; the arrays of scripts/slurm-grid
/// are chained `afterok`, so a task whose runs wait on another task's box or strength job must leave
/// them pending and exit 0, never fail (it did: "this shard's run needs a strength job that another
/// shard has not finished"). Three rounds of two tasks, in turn, as three chained arrays would run
/// them when each task's stage ends before the other's starts; then the same bits as one process.
#[test]
fn a_sharded_grid_exits_cleanly_at_every_stage_and_gives_the_one_process_grid() {
    let dir = scratch("sliding-shards");
    let cfg = dir.join("grid.toml");
    std::fs::write(&cfg, GRID).unwrap();
    let out = dir.join("out");
    let mut done = Vec::new();
    for round in 1..=3 {
        for shard in ["0/2", "1/2"] {
            let o = cgdem(&[
                "sliding",
                cfg.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
                "--jobs",
                "1",
                "--threads",
                "2",
                "--shard",
                shard,
            ]);
            let err = text(&o.stderr);
            assert!(o.status.success(), "round {round}, shard {shard}: {err}");
            let said = text(&o.stdout);
            let line = said.lines().last().unwrap_or_default().to_string();
            done.push(line.split(" of ").next().unwrap_or_default().to_string());
        }
    }
    // The first round relaxes the boxes and leaves every run pending; the last finds all done.
    assert_eq!(done[0], "0", "{done:?}");
    assert_eq!(done[5], "3", "{done:?}");
    let rows = grid_rows(&out);
    assert!(!rows.iter().any(|r| r.contains("pending")), "{rows:?}");
    // Two threads per job in the tasks, one per job side by side: the same bits.
    assert_eq!(rows, one_process_grid(&dir, &cfg));
}

/// The cluster path under the real scheduler: scripts/slurm-grid submits the grid as three chained
/// arrays of two tasks and a final task, on the one-node cluster of scripts/setup-slurm (which the
/// test command runs first). Every run is done by one of the two array tasks, and the grid is the
/// one process's to the bit.
#[test]
fn a_grid_run_as_chained_slurm_arrays_gives_the_one_process_grid() {
    let sinfo = std::process::Command::new("sinfo")
        .args(["-h", "-o", "%T"])
        .output();
    let up = sinfo.is_ok_and(|o| o.status.success() && !text(&o.stdout).trim().is_empty());
    assert!(
        up,
        "no Slurm cluster answers `sinfo`: run `bash scripts/setup-slurm` (the test command does)"
    );
    let dir = scratch("sliding-slurm");
    let cfg = dir.join("grid.toml");
    std::fs::write(&cfg, GRID).unwrap();
    let out = dir.join("out");
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scripts/slurm-grid");
    let o = std::process::Command::new("bash")
        .arg(&script)
        .args(["2", "3", "--wait", "--", "sliding"])
        .arg(&cfg)
        .arg("--out")
        .arg(&out)
        .env("CGDEM", env!("CARGO_BIN_EXE_cgdem"))
        .env("SBATCH_OPTS", "--cpus-per-task=1")
        .current_dir(&dir)
        .output()
        .unwrap();
    let logs = out.join("slurm-logs");
    let final_log = std::fs::read_to_string(logs.join("final.log")).unwrap_or_default();
    assert!(
        o.status.success(),
        "{}\n{}\nfinal task:\n{final_log}",
        text(&o.stdout),
        text(&o.stderr)
    );
    assert!(final_log.contains("3 of 3 runs done"), "{final_log}");
    for stage in 1..=3 {
        for task in 0..2 {
            assert!(logs.join(format!("stage{stage}-{task}.log")).exists());
        }
    }
    // The array tasks ran every run (the final task only collected): shards 0 and 1 of 2.
    let mut by: Vec<String> = done_jobs(&out.join("runs"))
        .iter()
        .map(|r| {
            std::fs::read_to_string(r.join("ran_by"))
                .unwrap()
                .trim()
                .to_string()
        })
        .collect();
    by.sort();
    assert_eq!(by, ["0 2", "0 2", "1 2"], "{by:?}");
    assert_eq!(grid_rows(&out), one_process_grid(&dir, &cfg));
}
