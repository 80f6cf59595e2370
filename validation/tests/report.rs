//! The report end to end on its cheap sections (force laws, two-particle checks): the files it writes, the summary's columns, every claim's measured value found in
//! the CSV of the figure that plots it, and a rerun that reuses every case from the cache; then the
//! junction section (quick profile: two runs and a d* search at d0 = 6 nm, about 80 s) and the
//! sliding section (five quick runs of paper 004 Fig. 6, about a minute).

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
    let only = ["force-laws", "two-particle"];
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

    let checked = plotted_claims_are_in_their_figures(&out, &claims);
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
    assert!(!html.contains("<script"));
    // Images only inline (data: URIs), never a file or the network.
    assert_eq!(
        html.matches("src=").count(),
        html.matches("src=\"data:").count()
    );
    assert!(html.matches("QUICK PROFILE").count() > only.len());
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

/// Figures through their data: each plotted claim's value is in its figure's CSV, as a simulated
/// point at the claim's x. Returns how many claims were checked.
fn plotted_claims_are_in_their_figures(out: &Path, claims: &[&validation::report::Claim]) -> usize {
    let mut checked = 0;
    for c in claims {
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
    checked
}

#[test]
fn the_junction_section_reports_its_runs_and_search_consistently() {
    let out = scratch("junction");
    let only = ["wear-junction"];
    let w = run(&options(&out, &only), &Silent).unwrap();
    assert!(w.failed_sections().is_empty(), "{:?}", w.failed_sections());
    let claims: Vec<_> = w.claims().collect();
    assert!(plotted_claims_are_in_their_figures(&out, &claims) >= 2);
    // The paper's small junction smooths plastically in the DEM too (Fig. 10 a-b, d0 = 6 nm).
    let small = claims
        .iter()
        .find(|c| c.item == "Fig. 10 (a-b)")
        .expect("the D = 10 nm claim");
    assert_eq!(small.verdict(), Verdict::Pass, "{small:?}");
    // The solids held: the top wall descended by less than a junction height in every run.
    let descent = claims
        .iter()
        .find(|c| c.quantity.starts_with("largest top-wall descent"))
        .expect("the descent claim");
    assert!(
        descent.measured > 0.0 && descent.measured < 1.0,
        "{descent:?}"
    );
    assert_eq!(descent.verdict(), Verdict::Pass, "{descent:?}");
    // The search's claim is a number (a bracket centre, or the smallest detaching D), never NaN.
    let search = claims
        .iter()
        .find(|c| {
            c.item == "section 4"
                && (c.quantity.starts_with("d* from the DEM search")
                    || c.quantity.starts_with("smallest D"))
        })
        .expect("the search claim");
    assert!(
        search.measured.is_finite() && search.measured >= 12.0,
        "{search:?}"
    );
    // eq 22 of Table 5 is the reference of both eq 22 rows: 18.5 nm (paper 000 section 4).
    for c in claims.iter().filter(|c| c.item == "eq 22") {
        assert!((c.reference - 18.49).abs() < 0.01, "{c:?}");
    }
    // Both runs' snapshots are inside the page, and the figure has its data.
    let html = std::fs::read_to_string(&w.html).unwrap();
    assert_eq!(html.matches("src=\"data:image/png;base64,").count(), 2);
    let csv = rows(&out.join("figures").join("junction-outcomes.csv"));
    assert!(csv.iter().any(|r| r[1] == "plastic smoothing"));
    let again = run(&options(&out, &only), &Silent).unwrap();
    assert_eq!(again.cases_run, 0);
    std::fs::remove_dir_all(&out).unwrap();
}

#[test]
fn the_sliding_section_reports_the_trends_of_fig_6_from_its_runs() {
    let out = scratch("sliding");
    let only = ["wear-sliding"];
    let w = run(&options(&out, &only), &Silent).unwrap();
    assert!(w.failed_sections().is_empty(), "{:?}", w.failed_sections());
    let claims: Vec<_> = w.claims().collect();
    // Each trend claim is the ratio of two points of its figure's data.
    let csv = rows(&out.join("figures").join("sliding-rho.csv"));
    let y = |panel: &str, series: &str, x: f64| -> f64 {
        let r = csv[1..]
            .iter()
            .find(|r| r[0] == panel && r[1] == series && r[3].parse::<f64>().unwrap() == x)
            .unwrap_or_else(|| panic!("no point {series} at {x} in {panel}"));
        r[4].parse().unwrap()
    };
    for (item, panel, series, lo, hi) in [
        (
            "Fig. 6a",
            "rho_TBL against p_N (Fig. 6a)",
            "sigma_m = 0.1 E",
            0.01,
            0.04,
        ),
        (
            "Fig. 6b",
            "rho_TBL against sigma_m at fixed d* (Fig. 6b)",
            "p_N = 0.01 E",
            0.1,
            0.2,
        ),
    ] {
        let c = claims
            .iter()
            .find(|c| c.item == item)
            .unwrap_or_else(|| panic!("no {item} claim"));
        let ratio = y(panel, series, hi) / y(panel, series, lo);
        assert_eq!(ratio.to_bits(), c.measured.to_bits(), "{c:?}");
    }
    // Two p_T rows per run (the grid's five and the resolution study's 40 d0 run), each a finite
    // ratio: one against the measured peak tau_m, one against the flow stress after it; one measured
    // tau_m and one tau_flow per material and box (sigma_m = 0.1, 0.14, 0.2 E on 20 d0, 0.2 E on
    // 40 d0), each a positive fraction of sigma_m, the flow below the peak.
    let section3 = claims.iter().filter(|c| c.item == "section 3");
    for (what, n) in [("tau_m measured", 6), ("flow stress", 6)] {
        let pt: Vec<_> = section3
            .clone()
            .filter(|c| c.quantity.starts_with("p_T") && c.quantity.contains(what))
            .collect();
        assert_eq!(pt.len(), n, "{what}");
        assert!(
            pt.iter()
                .all(|c| c.measured.is_finite() && c.measured > 0.0),
            "{pt:?}"
        );
        // Each names the layer's measured agitation, the cause docs/sliding.md measured.
        for c in &pt {
            let a: f64 = c
                .note
                .split("agitated (")
                .nth(1)
                .and_then(|t| t.split(' ').next())
                .and_then(|v| v.parse().ok())
                .unwrap_or_else(|| panic!("no agitation in {:?}", c.note));
            assert!(a > 0.0 && a < 10.0, "{}", c.note);
            // A run whose steady TBL lies against a body says so, with where it got there.
            assert_eq!(
                c.quantity.contains("boundary_reached"),
                c.note.contains("lay against a rigid body from"),
                "{c:?}"
            );
        }
    }
    // The interior-phase rows (paper 004's first stationary phase, TBL off both bodies) stand on at
    // least three windows each, and come in pairs (tau_m and tau_flow) per run that has them.
    let interior: Vec<_> = section3
        .clone()
        .filter(|c| c.quantity.contains("over the interior phase"))
        .collect();
    assert_eq!(interior.len() % 2, 0, "{interior:?}");
    for c in &interior {
        let windows: usize = c.note.split(' ').next().unwrap().parse().unwrap();
        assert!(windows >= 3, "{c:?}");
        assert!(c.measured.is_finite() && c.measured > 0.0, "{c:?}");
    }
    let tau = |name: &str| -> Vec<f64> {
        section3
            .clone()
            .filter(|c| c.quantity.starts_with(name))
            .map(|c| c.measured)
            .collect()
    };
    let (peak, flow) = (tau("tau_m"), tau("tau_flow"));
    assert_eq!((peak.len(), flow.len()), (4, 4));
    for (p, f) in peak.iter().zip(&flow) {
        assert!(
            *p > 0.0 && *p < 1.0 && *f > 0.0 && f < p,
            "{peak:?} {flow:?}"
        );
    }
    // The resolution study: the shear band's p_T / tau_m over the interior phase on the 20 d0 and
    // 40 d0 boxes is the figure's two points and the two runs' own interior rows, and the claim reads
    // the line through them at 0.01 L.
    let panel = "shear band p_T / tau_m against d0 / L (sec. 3)";
    let at = |x: f64| y(panel, "p_N = 0.01 E, sigma_m = 0.2 E, interior phase", x);
    let (coarse, fine) = (at(0.05), at(0.025));
    let row = |tag: &str| -> f64 {
        let q = format!(
            "p_T / tau_m over the interior phase (TBL inside the material) at p_N = 0.01 E, \
             sigma_m = 0.2 E{tag}"
        );
        claims
            .iter()
            .find(|c| c.quantity == q)
            .unwrap_or_else(|| panic!("no row {q}"))
            .measured
    };
    assert_eq!((coarse, fine), (row(""), row(" on the 40 d0 box")));
    let read = claims
        .iter()
        .find(|c| {
            c.quantity
                .contains("read off the line through the 20 d0 and 40 d0 boxes")
        })
        .expect("the resolution claim");
    let line = coarse + (fine - coarse) * (0.01 - 0.05) / (0.025 - 0.05);
    assert!((read.measured - line).abs() <= 1e-12, "{read:?} {line}");
    let html = std::fs::read_to_string(&w.html).unwrap();
    assert_eq!(html.matches("src=\"data:image/png;base64,").count(), 3);
    assert!(html.contains("TBL at a body from (L)") && html.contains("interior windows"));
    let again = run(&options(&out, &only), &Silent).unwrap();
    assert_eq!(again.cases_run, 0);
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

/// The MD chain (MD card -> calibration -> junction) costs about an hour, so the quick profile runs
/// none of it and says how to; the paper profile's run is documented in docs/calibration.md.
#[test]
fn the_quick_profile_names_the_md_chain_without_running_it() {
    let out = scratch("md-chain");
    let w = run(&options(&out, &["md-chain"]), &Silent).unwrap();
    assert!(w.failed_sections().is_empty(), "{:?}", w.failed_sections());
    assert_eq!((w.cases_run, w.cases_reused), (0, 0));
    assert_eq!(w.claims().count(), 0);
    let html = std::fs::read_to_string(&w.html).unwrap();
    assert!(html.contains("--profile paper --only md-chain"));
    std::fs::remove_dir_all(out).unwrap();
}
