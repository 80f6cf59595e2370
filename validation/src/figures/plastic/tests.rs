use super::*;
use dem::scenario::plastic::ImpactPoint;

fn point(angle: f64, speed: f64, mu_a: f64, w: f64) -> ImpactPoint {
    ImpactPoint {
        speed,
        angle_deg: angle,
        hardness: 6.6e9,
        mu_a,
        aims: 4,
        wear_volume: w,
        wear_volume_sd: 0.0,
        wear_volume_normal: 0.25 * w,
        wear_volume_scratch: 0.75 * w,
        reference_wear_volume: 2.0 * w,
        cor: 0.7,
        cor_sd: 0.0,
        deviation_deg: 5.0,
        deviation_sd: 0.0,
        crater_depth: 1e-5,
        max_balance_error: 0.0,
    }
}

#[test]
fn fig4_plots_mm3_against_gpa_beside_eq16() {
    let mk = |h: f64, v: f64| {
        let mut p = point(90.0, v, 0.25, 1e-8 * 1.7e9 / h);
        p.hardness = h;
        p.reference_wear_volume = 2e-8 * (v / 45.0).powi(2) * 1.7e9 / h;
        p
    };
    let f = fig4(&[mk(3e9, 45.0), mk(1e9, 45.0)], &[mk(1.7e9, 20.0)]);
    assert_eq!(f.panels.len(), 1 + 1);
    let a = &f.panels[0];
    // Sorted by H, in GPa and mm^3.
    assert_eq!(a.lines[0].points[0].0, 1.0);
    assert!((a.lines[0].points[0].1 - 17.0).abs() < 1e-9);
    // Eq 16 at H = 1 GPa: 2e-8 m^3 * 1.7 = 34 mm^3.
    assert!((a.lines[1].points[0].1 - 34.0).abs() < 1e-9);
    assert_eq!(a.lines[1].style, Style::Reference);
    // The CSV carries every plotted point.
    let rows = f.csv().lines().count() - 1;
    let n: usize = f
        .panels
        .iter()
        .flat_map(|p| &p.lines)
        .map(|l| l.points.len())
        .sum();
    assert_eq!(rows, n);
}

#[test]
fn angle_figures_group_by_speed_and_mu_a() {
    let mut pts = Vec::new();
    for (v, m) in [(30.0, 0.25), (35.0, 0.25), (35.0, 0.1)] {
        for a in [60.0, 30.0, 90.0] {
            pts.push(point(a, v, m, v * a * 1e-12));
        }
    }
    let f5 = fig5(&pts, 0.25, 35.0);
    assert_eq!(
        f5.key[..2],
        ["V = 30 m/s".to_string(), "V = 35 m/s".to_string()]
    );
    assert_eq!(f5.panels[0].lines.len(), 2);
    let got = &f5.panels[0].lines[1].points;
    for (g, a) in got.iter().zip([30.0, 60.0, 90.0]) {
        assert_eq!(g.0, a);
        assert!((g.1 - 35.0 * a * 1e-3).abs() < 1e-12, "{g:?}");
    }
    let parts = &f5.panels[1].lines;
    assert!((parts[0].points[0].1 + parts[1].points[0].1 - 35.0 * 30.0e-3).abs() < 1e-12);
    let f6 = fig6(&pts, 35.0);
    assert_eq!(f6.key, ["mu_a = 0.1", "mu_a = 0.25"]);
    let f7 = fig7(&pts, 35.0);
    assert_eq!(f7.panels[0].lines[0].points[0], (30.0, 0.7));
    assert_eq!(f7.panels[1].lines[1].points[2], (90.0, 5.0));
}
