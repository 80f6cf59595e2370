//! Figures of the plastic-wear model (paper 001, `cgdem impact` and `cgdem scratch`), each written as
//! PNG (shipped font), SVG (for the HTML report) and the CSV of the numbers it plots:
//!
//! - `fig4`: wear volume of normal impacts against the hardness and against the speed, beside eq 16;
//! - `fig5`: wear volume against the impact angle for several speeds, and its normal and scratch
//!   parts; `fig6`: the same for several mu_a; `fig7`: COR (eq 17) and deviation angle (eq 18);
//! - `fig12`: energy terms of impacts against time; `fig13`: of a scratch, against the external work;
//! - `fig3`: wear per distance near the scratching threshold and F_x against A_z (shear hardness);
//! - `fig10`: wear per distance against the load, with the linear fit at small loads;
//! - `fig8-9`: the indentation (force and indented area against depth) and the slide (depth and
//!   load-bearing areas against distance).
//!
//! Each figure is first a [`Figure`] of plain series, which tests check against the results, then
//! drawn. Units on the axes: mm^3, mm^2, GPa, kN, m/s, degrees, microseconds, joules.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use dem::scenario::plastic::{ImpactConfig, ImpactPoint, ImpactResult, ScratchResult, ScratchRun};
use plotters::prelude::*;

use super::chart::{key_height, keyed_body, panel, Mark, Scale, Series};
use super::style::{draw_err, ensure_font};
use crate::error::{Result, ValidationError};

/// How a line is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    /// Measured points joined by a thin line.
    Points,
    /// A measured curve.
    Line,
    /// A reference (dashed): an equation, a fit, a threshold.
    Reference,
}

/// One series of a panel: colour `key` (the figure's key entry of that index).
#[derive(Debug, Clone, PartialEq)]
pub struct Line {
    pub key: usize,
    pub points: Vec<(f64, f64)>,
    pub style: Style,
}

/// One panel: title, axis names, series.
#[derive(Debug, Clone, PartialEq)]
pub struct Panel {
    pub title: String,
    pub x: String,
    pub y: String,
    pub lines: Vec<Line>,
}

/// A figure: file stem, the colour key above the panels, panels in rows of `columns`.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    pub name: String,
    pub key: Vec<String>,
    pub note: Option<String>,
    pub columns: usize,
    pub panels: Vec<Panel>,
}

/// The files a figure was written to.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FigureFiles {
    pub png: PathBuf,
    pub svg: PathBuf,
    pub csv: PathBuf,
}

const MM3: f64 = 1e9;
const MM2: f64 = 1e6;

impl Figure {
    /// Writes `<dir>/<name>.png`, `.svg` and `.csv`.
    pub fn write(&self, dir: &Path) -> Result<FigureFiles> {
        ensure_font()?;
        std::fs::create_dir_all(dir).map_err(|e| draw_err(dir, e))?;
        let files = FigureFiles {
            png: dir.join(format!("{}.png", self.name)),
            svg: dir.join(format!("{}.svg", self.name)),
            csv: dir.join(format!("{}.csv", self.name)),
        };
        let cols = self.columns.max(1);
        let rows = self.panels.len().div_ceil(cols).max(1);
        let per_row = self.key.len().clamp(1, 4);
        let size = (
            640 * cols as u32,
            430 * rows as u32 + key_height(self.key.len(), per_row, self.note.is_some()),
        );
        {
            let root = BitMapBackend::new(&files.png, size).into_drawing_area();
            self.draw(&files.png, &root, per_row)?;
            root.present().map_err(|e| draw_err(&files.png, e))?;
        }
        {
            let root = SVGBackend::new(&files.svg, size).into_drawing_area();
            self.draw(&files.svg, &root, per_row)?;
            root.present().map_err(|e| draw_err(&files.svg, e))?;
        }
        std::fs::write(&files.csv, self.csv()).map_err(|e| draw_err(&files.csv, e))?;
        Ok(files)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        path: &Path,
        root: &DrawingArea<DB, plotters::coord::Shift>,
        per_row: usize,
    ) -> Result<()>
    where
        DB::ErrorType: 'static,
    {
        let labels: Vec<&str> = self.key.iter().map(String::as_str).collect();
        let body = keyed_body(path, root, &labels, per_row, self.note.as_deref())?;
        let cols = self.columns.max(1);
        let rows = self.panels.len().div_ceil(cols).max(1);
        let areas = body.split_evenly((rows, cols));
        for (area, p) in areas.iter().zip(&self.panels) {
            let series: Vec<Series> = p
                .lines
                .iter()
                .map(|l| {
                    let mark = match l.style {
                        Style::Points => Mark::Points,
                        Style::Line => Mark::Line,
                        Style::Reference => Mark::Target,
                    };
                    (String::new(), l.points.clone(), mark, l.key)
                })
                .collect();
            panel(path, area, (&p.title, &p.x, &p.y), Scale::Linear, &series)?;
        }
        Ok(())
    }

    /// The plotted numbers, one row per point: panel, axes, series (its key entry), x, y.
    pub fn csv(&self) -> String {
        let mut s = String::from("panel,x_label,y_label,series,x,y\n");
        let q = |t: &str| format!("\"{}\"", t.replace('"', "'"));
        for p in &self.panels {
            for l in &p.lines {
                let name = self.key.get(l.key).cloned().unwrap_or_default();
                for (x, y) in &l.points {
                    let _ = writeln!(
                        s,
                        "{},{},{},{},{x},{y}",
                        q(&p.title),
                        q(&p.x),
                        q(&p.y),
                        q(&name)
                    );
                }
            }
        }
        s
    }
}

fn line(key: usize, points: Vec<(f64, f64)>, style: Style) -> Line {
    Line { key, points, style }
}

fn sorted(mut pts: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    pts
}

/// Distinct values of `f` over `items`, in increasing order.
fn distinct<T>(items: &[T], f: impl Fn(&T) -> f64) -> Vec<f64> {
    let mut v: Vec<f64> = items.iter().map(f).collect();
    v.sort_by(f64::total_cmp);
    v.dedup();
    v
}

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
        a.push(line(
            k,
            sorted(
                t.loads
                    .iter()
                    .zip(&t.wear_per_distance)
                    .map(|(f, w)| (f / 1e3, w * MM2))
                    .collect(),
            ),
            Style::Points,
        ));
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
        lines: vec![line(
            0,
            sorted(
                test.loads
                    .iter()
                    .zip(&test.wear_per_distance)
                    .map(|(f, w)| (f / 1e3, w * MM2))
                    .collect(),
            ),
            Style::Points,
        )],
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

/// Writes every figure into `dir`.
pub fn write_all(figures: &[Figure], dir: &Path) -> Result<Vec<FigureFiles>> {
    figures.iter().map(|f| f.write(dir)).collect()
}

/// A figure asked of results that cannot give it.
pub fn missing(what: &str) -> ValidationError {
    ValidationError::Draw {
        path: what.into(),
        reason: "the results hold no data for this figure".into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
