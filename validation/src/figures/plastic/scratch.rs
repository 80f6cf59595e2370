//! The scratch figures: Figs. 3, 8-10 and 13 of paper 001 from scratch tests and their runs.

use dem::scenario::plastic::{ScratchResult, ScratchRun};

use super::{line, sorted, Figure, Panel, Style, MM2};

/// Fig. 13: the energy terms of a scratch since the slide began, their sum and the external work.
pub fn fig13(run: &ScratchRun) -> Figure {
    let e = &run.series.energy;
    let col = |v: &[f64], base: f64| {
        e.time
            .iter()
            .copied()
            .zip(v.iter().map(|x| x - base))
            .collect::<Vec<_>>()
    };
    let (k0, s0) = (
        e.kinetic.first().copied().unwrap_or(0.0),
        e.strain.first().copied().unwrap_or(0.0),
    );
    let sum: Vec<f64> = (0..e.len())
        .map(|k| e.kinetic[k] - k0 + e.strain[k] - s0 + e.friction[k] + e.wear[k])
        .collect();
    Figure {
        name: "fig13".into(),
        key: vec![
            "kinetic (change)".into(),
            "strain (change)".into(),
            "friction".into(),
            "wear (eq 22)".into(),
            "sum".into(),
            "external work (eq 23)".into(),
        ],
        note: Some(format!(
            "F_z = {:.0} N, V_x = {} m/s, mu_a = {}",
            run.load, run.speed, run.mu_a
        )),
        columns: 1,
        panels: vec![Panel {
            title: "energy since the slide began".into(),
            x: "time (s)".into(),
            y: "energy (J)".into(),
            lines: vec![
                line(0, col(&e.kinetic, k0), Style::Line),
                line(1, col(&e.strain, s0), Style::Line),
                line(2, col(&e.friction, 0.0), Style::Line),
                line(3, col(&e.wear, 0.0), Style::Line),
                line(4, e.time.iter().copied().zip(sum).collect(), Style::Line),
                line(5, col(&e.external_work, 0.0), Style::Reference),
            ],
        }],
    }
}

/// Fig. 10: wear per distance against the load, one line per test (mu_a, H), with the first test's
/// Archard line (fitted at small loads) extended over the whole range; (b) the small loads and the
/// line, the paper's inset.
pub fn fig10(tests: &[ScratchResult]) -> Figure {
    let mut key = Vec::new();
    let mut a = Vec::new();
    for (k, t) in tests.iter().enumerate() {
        let r0 = &t.runs[0];
        key.push(format!("mu_a = {}, H = {} GPa", r0.mu_a, r0.hardness / 1e9));
        a.push(line(k, wear_points(t), Style::Points));
    }
    let mut panels = vec![Panel {
        title: "(a) wear per distance".into(),
        x: "load F_z (kN)".into(),
        y: "W_V per distance (mm^3/mm)".into(),
        lines: a,
    }];
    if let Some((t, fit)) = tests
        .first()
        .and_then(|t| t.archard.as_ref().map(|f| (t, f)))
    {
        let small: Vec<(f64, f64)> = sorted(
            t.loads
                .iter()
                .zip(&t.wear_per_distance)
                .filter(|(f, _)| **f >= fit.threshold_load && **f <= fit.last_load)
                .map(|(f, w)| (f / 1e3, w * MM2))
                .collect(),
        );
        key.push(format!("Archard fit, R^2 = {:.3}", fit.r2));
        let n = key.len() - 1;
        let top = t.loads.iter().fold(0.0f64, |m, f| m.max(*f));
        let line_at = |f: f64| (f / 1e3, fit.slope * (f - fit.onset_load) * MM2);
        panels[0].lines.push(line(
            n,
            vec![line_at(fit.onset_load), line_at(top)],
            Style::Reference,
        ));
        panels.push(Panel {
            title: "(b) small loads".into(),
            x: "load F_z (kN)".into(),
            y: "W_V per distance (mm^3/mm)".into(),
            lines: vec![
                line(0, small, Style::Points),
                line(
                    n,
                    vec![line_at(fit.onset_load), line_at(fit.last_load)],
                    Style::Reference,
                ),
            ],
        });
    }
    Figure {
        name: "fig10".into(),
        key,
        note: None,
        columns: panels.len(),
        panels,
    }
}

/// Fig. 3: (a) wear per distance against the load around the threshold, (b) F_x against A_z at the
/// threshold and above with the fitted slope H_l and the slope mu_a H.
pub fn fig3(test: &ScratchResult) -> Figure {
    let mut panels = vec![Panel {
        title: "(a) wear per distance".into(),
        x: "load F_z (kN)".into(),
        y: "W_V per distance (mm^3/mm)".into(),
        lines: vec![line(0, wear_points(test), Style::Points)],
    }];
    let mut key = vec!["this model".into()];
    if let Some(h) = &test.shear_hardness {
        let top = test.wear_per_distance.iter().fold(0.0f64, |m, w| m.max(*w)) * MM2;
        panels[0].lines.push(line(
            3,
            vec![(h.threshold_load / 1e3, 0.0), (h.threshold_load / 1e3, top)],
            Style::Reference,
        ));
        let (lo, hi) = h
            .points
            .iter()
            .fold((f64::MAX, 0.0f64), |(a, b), p| (a.min(p[0]), b.max(p[0])));
        let at = |slope: f64, icpt: f64| {
            [lo, hi]
                .iter()
                .map(|&a| (a * MM2, slope * a + icpt))
                .collect::<Vec<_>>()
        };
        // The reference slope through the fit's mean point.
        let n = h.points.len() as f64;
        let (ma, mf) = (
            h.points.iter().map(|p| p[0]).sum::<f64>() / n,
            h.points.iter().map(|p| p[1]).sum::<f64>() / n,
        );
        panels.push(Panel {
            title: format!("(b) H_l = dF_x/dA_z = {:.3} GPa", h.slope / 1e9),
            x: "contact area A_z (mm^2)".into(),
            y: "lateral force F_x (N)".into(),
            lines: vec![
                line(
                    0,
                    h.points.iter().map(|p| (p[0] * MM2, p[1])).collect(),
                    Style::Points,
                ),
                line(1, at(h.slope, h.intercept), Style::Reference),
                line(2, at(h.reference, mf - h.reference * ma), Style::Reference),
            ],
        });
        key.push("least-squares slope".into());
        key.push(format!("slope mu_a H = {:.3} GPa", h.reference / 1e9));
        key.push("threshold".into());
    }
    Figure {
        name: "fig3".into(),
        key,
        note: None,
        columns: panels.len(),
        panels,
    }
}

/// Figs. 8-9: indentation force and indented area against depth; then the slide's depth and
/// load-bearing areas (eqs 19-20) against the distance.
pub fn fig8_9(run: &ScratchRun) -> Figure {
    let ind = &run.indentation;
    let s = &run.series;
    let zip = |x: &[f64], y: &[f64], fx: f64, fy: f64| {
        x.iter()
            .zip(y)
            .map(|(a, b)| (a * fx, b * fy))
            .collect::<Vec<_>>()
    };
    Figure {
        name: "fig8-9".into(),
        key: vec![
            "this model".into(),
            "A_LB^V (eq 19)".into(),
            "A_LB^L (eq 20)".into(),
        ],
        note: Some(format!(
            "load F_z = {:.0} N, mu_a = {}, V_x = {} m/s",
            run.load, run.mu_a, run.speed
        )),
        columns: 2,
        panels: vec![
            Panel {
                title: "(8a) indentation".into(),
                x: "depth (mm)".into(),
                y: "F_z (kN)".into(),
                lines: vec![line(0, zip(&ind.depth, &ind.force, 1e3, 1e-3), Style::Line)],
            },
            Panel {
                title: "(8b) indented area".into(),
                x: "depth (mm)".into(),
                y: "A_ind (mm^2)".into(),
                lines: vec![line(
                    0,
                    zip(&ind.depth, &ind.area_indented, 1e3, MM2),
                    Style::Line,
                )],
            },
            Panel {
                title: "(9a) depth while sliding".into(),
                x: "distance x (mm)".into(),
                y: "depth (mm)".into(),
                lines: vec![line(0, zip(&s.distance, &s.depth, 1e3, 1e3), Style::Line)],
            },
            Panel {
                title: "(9b) load-bearing areas".into(),
                x: "distance x (mm)".into(),
                y: "area (mm^2)".into(),
                lines: vec![
                    line(1, zip(&s.distance, &s.area_vertical, 1e3, MM2), Style::Line),
                    line(2, zip(&s.distance, &s.area_lateral, 1e3, MM2), Style::Line),
                ],
            },
        ],
    }
}

/// The figures of scratch tests: Figs. 10, 3 (of the first test with a shear hardness), 13 and 8-9 (of
/// the first test's run nearest 21 kN, the load of the paper's Fig. 9).
pub fn scratch_figures(tests: &[ScratchResult]) -> Vec<Figure> {
    let mut out = vec![fig10(tests)];
    if let Some(t) = tests.iter().find(|t| t.shear_hardness.is_some()) {
        out.push(fig3(t));
    }
    if let Some(run) = tests.first().and_then(|t| {
        t.runs
            .iter()
            .min_by(|a, b| (a.load - 21e3).abs().total_cmp(&(b.load - 21e3).abs()))
    }) {
        out.push(fig13(run));
        out.push(fig8_9(run));
    }
    out
}

/// A test's wear per distance against its load: (F_z in kN, W_V per distance in mm^3/mm), by load.
fn wear_points(t: &ScratchResult) -> Vec<(f64, f64)> {
    sorted(
        t.loads
            .iter()
            .zip(&t.wear_per_distance)
            .map(|(f, w)| (f / 1e3, w * MM2))
            .collect(),
    )
}
