//! The report end to end on its cheap sections (force laws, two-particle checks, the wear
//! placeholders): the files it writes, the summary's columns, every claim's measured value found in
//! the CSV of the figure that plots it, and a rerun that reuses every case from the cache.

use std::path::{Path, PathBuf};

use validation::report::figure::csv_split;
use validation::report::{run, Options, Profile, Silent, Verdict};

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("cgdem-report-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn options(out: &Path, only: &[&str]) -> Options {
    Options {
        profile: Profile::Quick,
        out: out.to_path_buf(),
        cache: None,
        only: Some(only.iter().map(|s| s.to_string()).collect()),
        at_once: 2,
        md: None,
    }
}

/// Rows of a CSV file as fields (header first).
fn rows(path: &Path) -> Vec<Vec<String>> {
    std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .lines()
        .map(csv_split)
        .collect()
}

#[test]
fn cheap_sections_write_a_consistent_report_and_rerun_from_the_cache() {
    let out = scratch("cheap");
    let only = ["force-laws", "two-particle", "wear-junction"];
    let w = run(&options(&out, &only), &Silent).unwrap();
    assert!(w.failed_sections().is_empty(), "{:?}", w.failed_sections());
    assert!(w.cases_run > 10, "{} cases ran", w.cases_run);

    // summary.csv: the agreed columns, one row per claim, verdicts as computed.
    let summary = rows(&out.join("summary.csv"));
    assert_eq!(
        summary[0],
        [
            "paper",
            "item",
            "quantity",
            "reference",
            "measured",
            "tolerance",
            "pass"
        ]
    );
    let claims: Vec<_> = w.claims().collect();
    assert_eq!(summary.len() - 1, claims.len());
    for (row, c) in summary[1..].iter().zip(&claims) {
        assert_eq!(row.len(), 7, "{row:?}");
        assert_eq!(row[2], c.quantity);
        assert_eq!(
            row[4].parse::<f64>().unwrap().to_bits(),
            c.measured.to_bits()
        );
        assert_eq!(row[6], c.verdict().name());
        // Every physics claim of these two sections holds (info rows are the paper's own numbers).
        assert_ne!(c.verdict(), Verdict::Fail, "{row:?}");
    }

    // Figures through their data: each plotted claim's value is in its figure's CSV.
    let mut checked = 0;
    for c in &claims {
        let Some(p) = &c.plotted else { continue };
        let csv = rows(&out.join("figures").join(format!("{}.csv", p.figure)));
        assert_eq!(csv[0], ["panel", "series", "kind", "x", "y"]);
        let hit = csv[1..]
            .iter()
            .find(|r| r[0] == p.panel && r[1] == p.series && r[3].parse::<f64>().unwrap() == p.x);
        let hit = hit.unwrap_or_else(|| panic!("no point for {c:?} in {}", p.figure));
        assert_eq!(hit[2], "simulation");
        assert_eq!(
            hit[4].parse::<f64>().unwrap().to_bits(),
            c.measured.to_bits(),
            "{c:?}"
        );
        checked += 1;
    }
    assert!(checked >= 10, "only {checked} claims are plotted");
    for f in ["force-laws", "two-particle"] {
        for ext in ["svg", "png", "csv"] {
            let p = out.join("figures").join(format!("{f}.{ext}"));
            assert!(
                std::fs::metadata(&p)
                    .map(|m| m.len() > 1000)
                    .unwrap_or(false),
                "{}",
                p.display()
            );
        }
    }

    // The page: self-contained, summary before provenance before the sections, the quick notice.
    let html = std::fs::read_to_string(&w.html).unwrap();
    let at = |s: &str| html.find(s).unwrap_or_else(|| panic!("no {s} in the page"));
    assert!(at("id=\"summary-table\"") < at("id=\"provenance\""));
    assert!(at("id=\"provenance\"") < at("<section id=\"force-laws\""));
    assert_eq!(html.matches("<svg").count(), 2);
    assert!(
        !html.contains("http://")
            || html.matches("http://").count()
                == html.matches("xmlns=\"http://www.w3.org/2000/svg\"").count()
    );
    assert!(!html.contains("<script") && !html.contains("src="));
    assert!(html.matches("QUICK PROFILE").count() > only.len());
    assert!(html.contains("Not on main yet"));
    for key in [
        "git revision",
        "LAMMPS version",
        "potential checksum",
        "host",
        "date (UTC)",
        "wall time (s)",
    ] {
        assert!(html.contains(key), "provenance lacks {key}");
    }

    // A warm rerun runs nothing and gives the same summary.
    let again = run(&options(&out, &only), &Silent).unwrap();
    assert_eq!(again.cases_run, 0);
    assert_eq!(again.cases_reused, w.cases_run);
    let summary2 = rows(&out.join("summary.csv"));
    assert_eq!(summary, summary2);
    std::fs::remove_dir_all(&out).unwrap();
}

#[test]
fn an_unknown_section_is_refused_with_the_list() {
    let out = scratch("unknown");
    let err = run(&options(&out, &["no-such"]), &Silent)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("no-such") && err.contains("force-laws"),
        "{err}"
    );
}
