//! An MD job interrupted by Ctrl-C keeps its finished stages and resumes after them, the
//! resumed result is bit-identical to an uninterrupted run of the same request, and `--no-cache`
//! recomputes every stage. Real LAMMPS, a tiny fast silica workflow, the real `cgdem` binary and
//! a real SIGINT to its process group, as a terminal sends it.

mod common;

use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

// Every stage short: a 96-atom glass, short averages, a fast strain rate. The elastic stage on
// the 0 K minimisation path (15.6 s -> 3.9 s per run); md_silica.rs covers the thermal path.
const TINY: &str = "formula_units = 32
elastic_temperature = 0.0
melt_ps = 1.0
anneal_ps = 0.5
elastic_md_ps = 0.3
strain_rate = 0.5
surface_anneal_ps = 0.3
";

/// `cgdem md silica` on the tiny config in `dir`, on `np` MPI ranks.
fn cgdem(dir: &Path, np: u32, out: &str, cache: &str) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_cgdem"));
    c.args(["md", "silica", "--np", &np.to_string(), "--config"])
        .arg(dir.join("tiny.toml"))
        .arg("--out")
        .arg(dir.join(out))
        .arg("--cache")
        .arg(dir.join(cache));
    c
}

fn check(out: &Output) -> String {
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(
        out.status.success(),
        "stdout {}\nstderr {stderr}",
        String::from_utf8_lossy(&out.stdout)
    );
    stderr
}

/// The one cache entry's directory under `cache` (None while the job has not started).
fn job_dir(cache: &Path) -> Option<PathBuf> {
    std::fs::read_dir(cache).ok()?.find_map(|e| {
        let p = e.ok()?.path();
        p.is_dir().then_some(p)
    })
}

/// The job's output with its wall-clock timings removed (they differ from run to run).
fn output_without_timings(out_dir: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(out_dir.join("silica.json")).unwrap();
    let mut rec: serde_json::Value = serde_json::from_str(&text).unwrap();
    let silica = &mut rec["output"]["silica"];
    assert!(silica["timings"].is_array(), "{silica}");
    silica["timings"] = serde_json::Value::Null;
    rec["output"].take()
}

#[test]
fn ctrl_c_keeps_finished_stages_and_the_resumed_run_matches_an_uninterrupted_one() {
    interrupt_resume_and_compare(1);
}

/// Under `mpirun`: rank 0 writes the stages, every rank reads them back, and the interrupt
/// reaches the ranks through mpirun.
#[test]
fn the_same_holds_on_two_mpi_ranks() {
    interrupt_resume_and_compare(2);
}

fn interrupt_resume_and_compare(np: u32) {
    common::venv_or_fail();
    let d = common::scratch(&format!("md-resume-test-np{np}"));
    std::fs::write(d.join("tiny.toml"), TINY).unwrap();

    // 1. Interrupted: Ctrl-C once the elastic stage is saved (the tension stage is running).
    let mut child = cgdem(&d, np, "out-a", "cache-a")
        .process_group(0)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let started = Instant::now();
    let stages = loop {
        if let Some(stages) = job_dir(&d.join("cache-a")).map(|j| j.join("stages")) {
            if stages.join("elastic.json").exists() {
                break stages;
            }
        }
        assert!(
            child.try_wait().unwrap().is_none(),
            "the job ended before its elastic stage was saved"
        );
        assert!(
            started.elapsed() < Duration::from_secs(600),
            "no elastic stage after 10 min"
        );
        std::thread::sleep(Duration::from_millis(10));
    };
    let sigint = Command::new("kill")
        .args(["-INT", "--", &format!("-{}", child.id())])
        .status()
        .unwrap();
    assert!(sigint.success());
    let interrupted = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&interrupted.stderr);
    assert!(!interrupted.status.success(), "{stderr}");
    assert!(
        stderr.contains("finished stages kept") && stderr.contains("elastic, glass"),
        "the error names the kept stages:\n{stderr}"
    );
    assert!(
        !stages.join("tension.json").exists(),
        "tension finished before Ctrl-C"
    );
    assert!(!d.join("out-a/silica.json").exists());

    // 2. The same command again: resumes after glass and elastic, and completes.
    check(&cgdem(&d, np, "out-a", "cache-a").output().unwrap());
    let log = std::fs::read_to_string(stages.parent().unwrap().join("worker.log")).unwrap();
    for stage in ["glass", "elastic"] {
        assert!(
            log.contains(&format!("stage {stage}: resumed")),
            "{stage} not resumed:\n{log}"
        );
    }
    for stage in ["tension", "shear", "surface"] {
        assert!(
            log.contains(&format!("stage {stage}: done")),
            "{stage} not run:\n{log}"
        );
    }

    // 3. Uninterrupted, in another cache: the same numbers to the last bit (JSON floats are the
    // shortest round-trip representation, so equal text means equal bits).
    check(&cgdem(&d, np, "out-b", "cache-b").output().unwrap());
    let (a, b) = (
        output_without_timings(&d.join("out-a")),
        output_without_timings(&d.join("out-b")),
    );
    assert_eq!(a, b, "resumed and uninterrupted results differ");
    assert_eq!(
        std::fs::read_to_string(d.join("out-a/card.toml"))
            .unwrap()
            .lines()
            .filter(|l| !l.contains("wall") && !l.contains("finished"))
            .collect::<Vec<_>>(),
        std::fs::read_to_string(d.join("out-b/card.toml"))
            .unwrap()
            .lines()
            .filter(|l| !l.contains("wall") && !l.contains("finished"))
            .collect::<Vec<_>>(),
    );

    // 4. `--no-cache` recomputes every stage (none is resumed) and, deterministic, gives the same
    // numbers once more.
    check(
        &cgdem(&d, np, "out-c", "cache-a")
            .arg("--no-cache")
            .output()
            .unwrap(),
    );
    let log = std::fs::read_to_string(stages.parent().unwrap().join("worker.log")).unwrap();
    assert!(
        !log.contains("resumed"),
        "--no-cache resumed a stage:\n{log}"
    );
    assert_eq!(output_without_timings(&d.join("out-c")), a);
    let _ = std::fs::remove_dir_all(&d);
}
