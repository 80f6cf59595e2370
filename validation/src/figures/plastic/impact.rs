//! The impact figures: Figs. 4-7 of paper 001 from a sweep's points, Fig. 12 from single runs.

use dem::scenario::plastic::{ImpactConfig, ImpactPoint, ImpactResult};

use super::{distinct, line, sorted, Figure, Panel, Style, MM3};

/// Fig. 4: wear volume of normal impacts against H (at one speed) and against V_z (at one H), with
/// eq 16 drawn as a dashed curve. Either list may be empty (its panel is left out).
pub fn fig4(by_hardness: &[ImpactPoint], by_speed: &[ImpactPoint]) -> Figure {
    let mut panels = Vec::new();
    let eq16 = |p: &ImpactPoint, h: f64, v: f64| {
        // m V^2 / (2 H) scales from the point's own reference.
        p.reference_wear_volume * (v / p.speed).powi(2) * (p.hardness / h) * MM3
    };
    if let Some(p0) = by_hardness.first() {
        let (lo, hi) = by_hardness.iter().fold((f64::MAX, 0.0f64), |(a, b), p| {
            (a.min(p.hardness), b.max(p.hardness))
        });
        let curve = (0..=60)
            .map(|k| lo + (hi - lo) * k as f64 / 60.0)
            .map(|h| (h / 1e9, eq16(p0, h, p0.speed)))
            .collect();
        panels.push(Panel {
            title: format!("(a) V_z = {} m/s", p0.speed),
            x: "hardness H (GPa)".into(),
            y: "wear volume W_V (mm^3)".into(),
            lines: vec![
                line(
                    0,
                    sorted(
                        by_hardness
                            .iter()
                            .map(|p| (p.hardness / 1e9, p.wear_volume * MM3))
                            .collect(),
                    ),
                    Style::Points,
                ),
                line(1, curve, Style::Reference),
            ],
        });
    }
    if let Some(p0) = by_speed.first() {
        let (lo, hi) = by_speed.iter().fold((f64::MAX, 0.0f64), |(a, b), p| {
            (a.min(p.speed), b.max(p.speed))
        });
        let curve = (0..=60)
            .map(|k| lo + (hi - lo) * k as f64 / 60.0)
            .map(|v| (v, eq16(p0, p0.hardness, v)))
            .collect();
        panels.push(Panel {
            title: format!("(b) H = {} GPa", p0.hardness / 1e9),
            x: "normal speed V_z (m/s)".into(),
            y: "wear volume W_V (mm^3)".into(),
            lines: vec![
                line(
                    0,
                    sorted(
                        by_speed
                            .iter()
                            .map(|p| (p.speed, p.wear_volume * MM3))
                            .collect(),
                    ),
                    Style::Points,
                ),
                line(1, curve, Style::Reference),
            ],
        });
    }
    Figure {
        name: "fig4".into(),
        key: vec![
            "this model (normal impact)".into(),
            "eq 16: W_V = m V_z^2 / (2 H)".into(),
        ],
        note: None,
        columns: panels.len().max(1),
        panels,
    }
}

fn by_angle(points: &[ImpactPoint], f: impl Fn(&ImpactPoint) -> f64) -> Vec<(f64, f64)> {
    sorted(points.iter().map(|p| (p.angle_deg, f(p))).collect())
}

fn near(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs())
}

/// Fig. 5: (a) wear volume against the impact angle, one line per speed, at `mu_a`; (b) its normal
/// and scratch parts at `speed`.
pub fn fig5(points: &[ImpactPoint], mu_a: f64, speed: f64) -> Figure {
    let at_mu: Vec<&ImpactPoint> = points.iter().filter(|p| near(p.mu_a, mu_a)).collect();
    let speeds = distinct(&at_mu, |p| p.speed);
    let mut key: Vec<String> = speeds.iter().map(|v| format!("V = {v} m/s")).collect();
    let mut a = Vec::new();
    for (k, &v) in speeds.iter().enumerate() {
        let pts: Vec<ImpactPoint> = at_mu
            .iter()
            .filter(|p| near(p.speed, v))
            .map(|p| (*p).clone())
            .collect();
        a.push(line(
            k,
            by_angle(&pts, |p| p.wear_volume * MM3),
            Style::Points,
        ));
    }
    let at_v: Vec<ImpactPoint> = at_mu
        .iter()
        .filter(|p| near(p.speed, speed))
        .map(|p| (*p).clone())
        .collect();
    let n = key.len();
    key.push(format!("normal part (V = {speed} m/s)"));
    key.push(format!("scratch part (V = {speed} m/s)"));
    let b = vec![
        line(
            n,
            by_angle(&at_v, |p| p.wear_volume_normal * MM3),
            Style::Points,
        ),
        line(
            n + 1,
            by_angle(&at_v, |p| p.wear_volume_scratch * MM3),
            Style::Points,
        ),
    ];
    Figure {
        name: "fig5".into(),
        key,
        note: Some(format!(
            "mu_a = {mu_a}; each point the mean over landing points in the grid's cell"
        )),
        columns: 2,
        panels: vec![
            Panel {
                title: "(a) wear volume".into(),
                x: "impact angle (deg)".into(),
                y: "W_V (mm^3)".into(),
                lines: a,
            },
            Panel {
                title: "(b) normal and scratch parts".into(),
                x: "impact angle (deg)".into(),
                y: "W_V (mm^3)".into(),
                lines: b,
            },
        ],
    }
}

fn per_mu_a(points: &[ImpactPoint], speed: f64) -> Vec<(f64, Vec<ImpactPoint>)> {
    let at_v: Vec<ImpactPoint> = points
        .iter()
        .filter(|p| near(p.speed, speed))
        .cloned()
        .collect();
    distinct(&at_v, |p| p.mu_a)
        .into_iter()
        .map(|m| {
            (
                m,
                at_v.iter().filter(|p| near(p.mu_a, m)).cloned().collect(),
            )
        })
        .collect()
}

/// Fig. 6: wear volume against the impact angle, one line per mu_a, at `speed`.
pub fn fig6(points: &[ImpactPoint], speed: f64) -> Figure {
    let groups = per_mu_a(points, speed);
    Figure {
        name: "fig6".into(),
        key: groups.iter().map(|(m, _)| format!("mu_a = {m}")).collect(),
        note: Some(format!("V = {speed} m/s")),
        columns: 1,
        panels: vec![Panel {
            title: "wear volume".into(),
            x: "impact angle (deg)".into(),
            y: "W_V (mm^3)".into(),
            lines: groups
                .iter()
                .enumerate()
                .map(|(k, (_, g))| line(k, by_angle(g, |p| p.wear_volume * MM3), Style::Points))
                .collect(),
        }],
    }
}

/// Fig. 7: (a) COR and (b) deviation angle against the impact angle, one line per mu_a, at `speed`.
pub fn fig7(points: &[ImpactPoint], speed: f64) -> Figure {
    let groups = per_mu_a(points, speed);
    let lines = |f: fn(&ImpactPoint) -> f64| {
        groups
            .iter()
            .enumerate()
            .map(|(k, (_, g))| line(k, by_angle(g, f), Style::Points))
            .collect()
    };
    Figure {
        name: "fig7".into(),
        key: groups.iter().map(|(m, _)| format!("mu_a = {m}")).collect(),
        note: Some(format!("V = {speed} m/s")),
        columns: 2,
        panels: vec![
            Panel {
                title: "(a) restitution, eq 17".into(),
                x: "impact angle (deg)".into(),
                y: "COR = V_r / V".into(),
                lines: lines(|p| p.cor),
            },
            Panel {
                title: "(b) deviation, eq 18".into(),
                x: "impact angle (deg)".into(),
                y: "theta_r - theta (deg)".into(),
                lines: lines(|p| p.deviation_deg),
            },
        ],
    }
}

/// Fig. 12: kinetic, strain, friction and wear energy and their sum against time, one panel per
/// impact.
pub fn fig12(runs: &[ImpactResult]) -> Figure {
    let panels = runs
        .iter()
        .map(|r| {
            let s = &r.series;
            let t: Vec<f64> = s.time.iter().map(|t| t * 1e6).collect();
            let col = |v: &[f64]| t.iter().copied().zip(v.iter().copied()).collect::<Vec<_>>();
            let sum: Vec<f64> = (0..s.len()).map(|k| s.balance(k)).collect();
            let top = sum.iter().fold(0.0f64, |m, v| m.max(*v));
            let t0 = r.first_contact * 1e6;
            Panel {
                title: format!("theta = {} deg, V = {} m/s", r.angle_deg, r.speed),
                x: "time (us)".into(),
                y: "energy (J)".into(),
                lines: vec![
                    line(0, col(&s.kinetic), Style::Line),
                    line(1, col(&s.strain), Style::Line),
                    line(2, col(&s.friction), Style::Line),
                    line(3, col(&s.wear), Style::Line),
                    line(4, col(&sum), Style::Reference),
                    line(5, vec![(t0, 0.0), (t0, top)], Style::Reference),
                ],
            }
        })
        .collect::<Vec<_>>();
    Figure {
        name: "fig12".into(),
        key: vec![
            "kinetic".into(),
            "strain (Hertz)".into(),
            "friction".into(),
            "wear (eq 22)".into(),
            "sum".into(),
            "first contact".into(),
        ],
        note: None,
        columns: panels.len().clamp(1, 3),
        panels,
    }
}

/// The figures an impact sweep calls for: Fig. 4 when normal impacts sweep H or V; Figs. 5-7 when the
/// angle is swept (at the base mu_a and speed of `base`).
pub fn impact_figures(points: &[ImpactPoint], base: &ImpactConfig) -> Vec<Figure> {
    let mut out = Vec::new();
    let angles = distinct(points, |p| p.angle_deg);
    let (v0, h0, m0) = (base.impact.speed, base.model.hardness, base.model.mu_a);
    if angles.len() > 1 {
        out.push(fig5(points, m0, v0));
        if distinct(points, |p| p.mu_a).len() > 1 {
            out.push(fig6(points, v0));
        }
        out.push(fig7(points, v0));
    } else {
        let pick = |f: &dyn Fn(&ImpactPoint) -> bool| -> Vec<ImpactPoint> {
            points.iter().filter(|p| f(p)).cloned().collect()
        };
        let by_h = pick(&|p| near(p.speed, v0) && near(p.mu_a, m0));
        let by_v = pick(&|p| near(p.hardness, h0) && near(p.mu_a, m0));
        let (by_h, by_v) = (
            if distinct(&by_h, |p| p.hardness).len() > 1 {
                by_h
            } else {
                vec![]
            },
            if distinct(&by_v, |p| p.speed).len() > 1 {
                by_v
            } else {
                vec![]
            },
        );
        if !(by_h.is_empty() && by_v.is_empty()) {
            out.push(fig4(&by_h, &by_v));
        }
    }
    out
}
