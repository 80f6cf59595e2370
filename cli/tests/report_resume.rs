//! `cgdem report` stopped by Ctrl-C (SIGINT) in the middle of its patch cases keeps every finished
//! case in its cache, says how to continue, and the same command then runs only what was missing;
//! a third run finds everything cached and runs nothing.

mod common;

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Finished cases in the report's cache (`<key>/result.json`).
fn finished(cache: &Path) -> usize {
    std::fs::read_dir(cache)
        .map(|d| {
            d.filter_map(|e| e.ok())
                .filter(|e| e.path().join("result.json").is_file())
                .count()
        })
        .unwrap_or(0)
}

/// (cases run, cases reused) from the report's closing line.
fn counts(stdout: &str) -> (usize, usize) {
    let line = stdout
        .lines()
        .find(|l| l.contains("cases run"))
        .unwrap_or_else(|| panic!("no summary line in:\n{stdout}"));
    let num = |word: &str| -> usize {
        let before = line.split(word).next().unwrap();
        before
            .rsplit(|c: char| !c.is_ascii_digit())
            .find(|s| !s.is_empty())
            .unwrap()
            .parse()
            .unwrap()
    };
    (num(" cases run"), num(" reused"))
}

#[test]
fn an_interrupted_report_resumes_from_its_cache() {
    let dir = common::scratch("report-resume");
    let out = dir.join("report");
    let cache = out.join("cache");
    let args = ["report", "--only", "two-particle,patch-hcp", "--out"];
    let mut child = Command::new(env!("CARGO_BIN_EXE_cgdem"))
        .args(args)
        .arg(&out)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The two-particle cases finish in a fraction of a second; wait for two patch cases more.
    let t0 = Instant::now();
    let two_particle = 20;
    while finished(&cache) < two_particle + 2 {
        assert!(
            t0.elapsed() < Duration::from_secs(600),
            "no progress in 10 minutes"
        );
        assert!(
            child.try_wait().unwrap().is_none(),
            "the report ended before the interrupt"
        );
        std::thread::sleep(Duration::from_millis(100));
    }
    let status = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let stopped = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&stopped.stderr);
    assert!(
        !stopped.status.success(),
        "an interrupted report must not exit 0"
    );
    assert!(
        stderr.contains("rerun the same command"),
        "the message does not say how to continue:\n{stderr}"
    );
    let kept = finished(&cache);
    assert!(kept >= two_particle + 2, "{kept} cases kept");
    assert!(
        !out.join("report.html").exists(),
        "no page for an unfinished report"
    );

    let rerun = || {
        let o = Command::new(env!("CARGO_BIN_EXE_cgdem"))
            .args(args)
            .arg(&out)
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&o.stdout).to_string();
        assert!(
            o.status.success(),
            "{stdout}\n{}",
            String::from_utf8_lossy(&o.stderr)
        );
        (stdout, counts(&String::from_utf8_lossy(&o.stdout)))
    };
    let (_, (ran, reused)) = rerun();
    let total = finished(&cache);
    assert_eq!(reused, kept, "every kept case reused");
    assert_eq!(ran + reused, total);
    assert!(ran >= 1, "the interrupted cases ran again");
    assert!(out.join("report.html").is_file());
    let first = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    let (stdout, (ran, reused)) = rerun();
    assert_eq!((ran, reused), (0, total), "{stdout}");
    assert_eq!(
        first,
        std::fs::read_to_string(out.join("summary.csv")).unwrap()
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A mistyped `--only` is refused before anything runs, with the sections to choose from, and not
/// reported as a stopped report to rerun.
#[test]
fn an_unknown_section_is_an_input_error_that_names_the_sections() {
    let out = common::scratch("report-bad-only");
    let o = Command::new(env!("CARGO_BIN_EXE_cgdem"))
        .args(["report", "--only", "sliding", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("no section 'sliding'") && err.contains("wear-sliding"),
        "{err}"
    );
    assert!(!err.contains("rerun the same command"), "{err}");
    assert!(!out.join("cache").exists(), "nothing runs");
}
