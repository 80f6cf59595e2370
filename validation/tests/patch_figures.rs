//! The campaign figures plot the campaign's numbers: the series are checked against the report and
//! its CSV curves, then drawn to PNG files whose headers are checked (not their pixels).

use dem::scenario::patch::{run_suite, PatchSuite};
use dem::Parallelism;
use validation::figures::patch::{curve_series, draw, trends, TrendAxis};
use validation::ValidationError;

fn campaign() -> PatchSuite {
    toml::from_str(
        r#"
tests = ["elastic", "tensile"]
[material]
young_modulus = 1.0
poisson_ratio = 0.0
tensile_strength = 0.2
shear_strength = 0.1
surface_energy = 1.5
restitution = 0.95
density = 1.0
[sample]
kind = "hcp"
d0_over_dc = 0.6
l_over_d0 = 8.0
w_over_d0 = 3.0
[tensile]
mode = "tensile"
post_peak_strain = 0.01
[sweep]
poisson_ratio = [0.0, 0.2]
"#,
    )
    .unwrap()
}

/// Width and height from a PNG's IHDR chunk, after checking the signature.
fn png_size(path: &std::path::Path) -> (u32, u32) {
    let b = std::fs::read(path).unwrap();
    assert_eq!(
        &b[..8],
        b"\x89PNG\r\n\x1a\n",
        "{} is not a PNG",
        path.display()
    );
    assert_eq!(&b[12..16], b"IHDR");
    let be = |i: usize| u32::from_be_bytes(b[i..i + 4].try_into().unwrap());
    (be(16), be(20))
}

#[test]
fn figures_plot_the_campaigns_numbers() {
    let dir = std::env::temp_dir().join(format!("cgdem_figures_{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    let report = run_suite(&campaign(), Some(&dir), Parallelism::Sequential).unwrap();

    let t = trends(&report).expect("nu takes two values");
    assert_eq!(t.axis, TrendAxis::Nu);
    assert_eq!(t.groups.len(), 1, "one scaling exponent");
    let points = &t.groups[0].1;
    for (p, c) in points.iter().zip(&report.cases) {
        let (e, s) = (c.elastic.as_ref().unwrap(), c.tensile.as_ref().unwrap());
        assert_eq!(p.x, c.poisson_ratio);
        assert_eq!(p.e_ratio, Some(e.young_modulus / e.target_young_modulus));
        assert_eq!(p.nu, Some(e.poisson_ratio));
        assert_eq!(p.tensile, Some((s.strength, s.target_strength)));
        assert_eq!(p.shear, None, "no shear test in this campaign");
        assert_eq!(p.volume_fraction, c.volume_fraction);
        assert_eq!(p.coordination, c.coordination.interacting);
    }

    // The curves come back from the CSV files (9 significant digits) as stress over target.
    let [tensile, shear] = curve_series(&report, &dir).unwrap();
    assert!(shear.is_empty());
    assert_eq!(tensile.len(), 2);
    for (series, c) in tensile.iter().zip(&report.cases) {
        let r = c.tensile.as_ref().unwrap();
        assert_eq!(series.points.len(), r.curve.points.len());
        for (&(e, s), q) in series.points.iter().zip(&r.curve.points) {
            assert!((e - q.strain_yy).abs() <= 1e-8 * q.strain_yy.abs().max(1e-3));
            let want = q.stress[1] / r.target_strength;
            assert!(
                (s - want).abs() <= 1e-8 * want.abs().max(1e-3),
                "{s} vs {want}"
            );
        }
    }
    let peak = tensile[0]
        .points
        .iter()
        .map(|p| p.1)
        .fold(f64::MIN, f64::max);
    let ratio = report.cases[0].tensile.as_ref().unwrap().ratio.unwrap();
    assert!(
        (peak - ratio).abs() < 1e-8,
        "the curve peaks at the reported ratio"
    );

    let written = draw(&report, &dir).unwrap();
    let names: Vec<_> = written.iter().map(|p| p.file_name().unwrap()).collect();
    assert_eq!(names, ["curves.png", "trends.png"]);
    let (w, h) = png_size(&written[1]);
    assert!(w == 1400 && h > 1500, "{w} x {h}");
    let (w, h) = png_size(&written[0]);
    assert!(w == 1400 && h > 560, "{w} x {h}");

    // The same cases as a d0 sweep from 0.6 to 19.2 d_c: a log axis over the range on which
    // plotters' own log scale looped forever (the figure must come back).
    let mut v = serde_json::to_value(&report).unwrap();
    v["cases"][0]["d0_over_dc"] = serde_json::json!(0.6);
    v["cases"][1]["d0_over_dc"] = serde_json::json!(19.2);
    let swept: dem::scenario::patch::PatchReport = serde_json::from_value(v).unwrap();
    assert_eq!(trends(&swept).unwrap().axis, TrendAxis::D0);
    assert_eq!(draw(&swept, &dir).unwrap().len(), 2);

    // A damaged curve file is a clear error naming the line.
    std::fs::write(
        dir.join("case1_tensile.csv"),
        "header\n1,2,3,4,5\n1,2,x,4,5\n",
    )
    .unwrap();
    match curve_series(&report, &dir) {
        Err(ValidationError::Curve { reason, .. }) => {
            assert!(reason.contains("line 3"), "{reason}")
        }
        other => panic!("expected a curve error, got {other:?}"),
    }
    std::fs::remove_dir_all(&dir).ok();
}
