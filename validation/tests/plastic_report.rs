//! The plastic-wear part of the validation report: the quick profile runs (through a job cache), its
//! claims are judged, and its figures are written as PNG, SVG and CSV whose rows are the results'
//! numbers (checked here, not the pixels).

use dem::jobs::{JobCache, RunJobs};
use dem::scenario::plastic::{ImpactConfig, ImpactPoint};
use validation::figures::plastic::{fig12, fig4, impact_figures, scratch_figures, write_all};
use validation::plastic::{claims, quick_profile};

#[test]
fn quick_profile_claims_and_figures() {
    let dir = std::env::temp_dir().join(format!("cgdem_plastic_report_{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    let cache = JobCache::new(dir.join("jobs"));
    let how = RunJobs {
        at_once: 2,
        ..RunJobs::default()
    };
    let t = std::time::Instant::now();
    let res = quick_profile(&cache, &how).unwrap();
    println!("quick profile: {:.1} s", t.elapsed().as_secs_f64());
    let rows = claims(&res);
    for c in &rows {
        println!(
            "Fig. {:<3} {:<72} ref {:<8} measured {:<12.5} {:<8} {}",
            c.figure,
            c.quantity,
            c.reference,
            c.measured,
            c.tolerance_text(),
            if c.pass { "pass" } else { "FAIL" }
        );
    }
    assert_eq!(rows.len(), 15, "every claim is judged");
    // The one the model misses, and by how much: eq 16 at 7 GPa (the Hertzian springs return 21 % of
    // the energy at rebound, docs/plastic-wear.md). Everything else holds.
    for c in &rows {
        if c.figure == "4a" {
            assert!(!c.pass && (0.74..0.80).contains(&c.measured), "{c:?}");
        } else {
            assert!(c.pass, "{c:?}");
        }
    }
    // A rerun reads every job from the cache.
    let t = std::time::Instant::now();
    let again = quick_profile(&cache, &how).unwrap();
    assert_eq!(again, res);
    println!("from the cache: {:.2} s", t.elapsed().as_secs_f64());

    // Figures of the profile, from its numbers.
    let fig_dir = dir.join("figures");
    let by_h: Vec<ImpactPoint> = res
        .normal
        .iter()
        .filter(|r| r.speed == 45.0)
        .map(|r| ImpactPoint::of(std::slice::from_ref(r)))
        .collect();
    let by_v: Vec<ImpactPoint> = res
        .normal
        .iter()
        .filter(|r| r.hardness == 1.7e9)
        .map(|r| ImpactPoint::of(std::slice::from_ref(r)))
        .collect();
    let base: ImpactConfig = toml::from_str(
        "[model]\nhardness = 6.6e9\n[projectile]\nradius = 0.003\ndensity = 2500.0\n\
         [impact]\nspeed = 35.0\nangle_deg = 45.0\n",
    )
    .unwrap();
    let mut figures = vec![fig4(&by_h, &by_v), fig12(&res.oblique_runs)];
    figures.extend(impact_figures(&res.oblique, &base));
    figures.extend(scratch_figures(std::slice::from_ref(&res.scratch)));
    let names: Vec<&str> = figures.iter().map(|f| f.name.as_str()).collect();
    assert_eq!(
        names,
        ["fig4", "fig12", "fig5", "fig6", "fig7", "fig10", "fig3", "fig13", "fig8-9"]
    );
    let files = write_all(&figures, &fig_dir).unwrap();
    for (f, files) in figures.iter().zip(&files) {
        let png = std::fs::read(&files.png).unwrap();
        assert!(
            png.starts_with(b"\x89PNG\r\n\x1a\n") && png.len() > 5000,
            "{}",
            f.name
        );
        let svg = std::fs::read_to_string(&files.svg).unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("</svg>"));
        let csv = std::fs::read_to_string(&files.csv).unwrap();
        assert_eq!(csv, f.csv(), "{}", f.name);
        let points: usize = f
            .panels
            .iter()
            .flat_map(|p| &p.lines)
            .map(|l| l.points.len())
            .sum();
        assert_eq!(csv.lines().count(), points + 1, "{}", f.name);
    }
    // Fig. 4 plots each normal impact's wear volume in mm^3 at its hardness in GPa.
    let csv = std::fs::read_to_string(&files[0].csv).unwrap();
    for r in res.normal.iter().filter(|r| r.speed == 45.0) {
        let row = format!(",{},{}", r.hardness / 1e9, r.wear_volume * 1e9);
        assert!(csv.contains(&row), "{row} not in fig4.csv");
    }
    // Fig. 10 plots the scratch's wear per distance in mm^3/mm against kN.
    let csv = std::fs::read_to_string(&files[5].csv).unwrap();
    for (f, w) in res.scratch.loads.iter().zip(&res.scratch.wear_per_distance) {
        assert!(csv.contains(&format!(",{},{}", f / 1e3, w * 1e6)));
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// The report's `wear-impact` section: the quick profile's claims as summary rows (the one known miss
/// is eq 16 at 7 GPa), its nine figures as report figures with the CSV behind each, and the profile
/// notice on every figure.
#[test]
fn report_section_gives_the_claims_and_figures() {
    use validation::report::{run, Options, Profile, Silent, Verdict};
    let out = std::env::temp_dir().join(format!("cgdem_plastic_section_{}", std::process::id()));
    std::fs::remove_dir_all(&out).ok();
    let opts = Options {
        profile: Profile::Quick,
        out: out.clone(),
        cache: None,
        only: Some(vec!["wear-impact".into()]),
        at_once: 2,
        md: None,
    };
    let w = run(&opts, &Silent).unwrap();
    assert!(w.failed_sections().is_empty(), "{:?}", w.failed_sections());
    let claims: Vec<_> = w.claims().collect();
    assert_eq!(claims.len(), 15);
    for c in &claims {
        assert_eq!(c.paper, "001");
        if c.item == "Fig. 4a" {
            assert_eq!(c.verdict(), Verdict::Fail, "{c:?}");
            assert!((0.74..0.80).contains(&c.measured), "{c:?}");
            assert!(!c.note.is_empty());
        } else {
            assert_eq!(c.verdict(), Verdict::Pass, "{c:?}");
        }
    }
    let summary = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    assert_eq!(summary.lines().count(), 16);
    for name in [
        "fig4", "fig12", "fig5", "fig6", "fig7", "fig10", "fig3", "fig13", "fig8-9",
    ] {
        let stem = out.join("figures").join(format!("plastic-{name}"));
        for ext in ["png", "svg", "csv"] {
            let p = stem.with_extension(ext);
            let len = std::fs::metadata(&p).map(|m| m.len()).unwrap_or(0);
            assert!(len > 1000, "{}", p.display());
        }
    }
    // Fig. 4's CSV holds the eq 16 ratio's simulation point at 1.7 GPa, 45 m/s (W_V in mm^3).
    let csv = std::fs::read_to_string(out.join("figures").join("plastic-fig4.csv")).unwrap();
    let sim = csv.lines().filter(|l| l.contains(",simulation,")).count();
    let refs = csv.lines().filter(|l| l.contains(",reference,")).count();
    assert!(
        sim >= 6 && refs > 0,
        "{sim} simulation rows, {refs} reference rows"
    );
    let html = std::fs::read_to_string(&w.html).unwrap();
    assert!(html.contains("<section id=\"wear-impact\""));
    assert!(!html.contains("Not on main yet: the impact"));
    assert!(html.matches("QUICK PROFILE").count() >= 9);
    std::fs::remove_dir_all(&out).ok();
}
