//! Figures of a patch-test campaign (`cgdem patch`): the stress-strain curves of every case, and how
//! the measured E, nu and strengths move with the swept variable (paper 000 Figs. 5-8 and A.4-A.8).
//!
//! - `curves.png`: stress over the case's target strength (eq 20) against strain, tensile and shear
//!   side by side, one line per case;
//! - `compaction.png` (campaigns with the shear-under-load test): compaction (decrease of the wall
//!   separation since the load was applied, % of L0) against shear strain, one line per case, the
//!   limit dashed;
//! - `trends.png` (campaigns of two or more cases): E / E_target, nu, tensile and shear strength
//!   against d0 / d_c (log scale, when d0 is swept) or against the target nu, one series per scaling
//!   exponent s, with the targets (nu, eq 20) drawn as dashed lines.

use std::path::{Path, PathBuf};

use dem::io::Sig;
use dem::scenario::patch::PatchReport;

use super::chart::{keyed_figure, panel, Mark, Scale, Series};
use super::style::{draw_err, ensure_font};
use crate::error::{Result, ValidationError};

/// One line of `curves.png`: (strain, stress / target strength).
#[derive(Debug, Clone, PartialEq)]
pub struct CurveSeries {
    pub label: String,
    pub points: Vec<(f64, f64)>,
}

/// The curves of the tensile and of the shear tests, read from the campaign's CSV files. A case whose
/// curves repeat an earlier case's (scale-free cases: s = 0 above d_c, or any s below it) hides that
/// case's lines under its own, so its label says so.
pub fn curve_series(report: &PatchReport, dir: &Path) -> Result<[Vec<CurveSeries>; 2]> {
    let mut per_case: Vec<CaseCurves> = Vec::new();
    for (k, case) in report.cases.iter().enumerate() {
        let tests = [
            ("tensile", &case.tensile, 2, 4),
            ("shear", &case.shear, 1, 6),
        ];
        let mut curves = [None, None];
        for (slot, (name, result, strain_col, stress_col)) in tests.into_iter().enumerate() {
            let Some(r) = result else { continue };
            let path = dir.join(format!("case{k}_{name}.csv"));
            curves[slot] = Some(
                read_columns(&path, strain_col, stress_col)?
                    .into_iter()
                    .map(|(e, s)| (e, s / r.target_strength))
                    .collect(),
            );
        }
        per_case.push(curves);
    }
    let mut out = [Vec::new(), Vec::new()];
    for (k, curves) in per_case.iter().enumerate() {
        let mut label = case_label(report, k);
        if let Some(j) = (0..k).find(|&j| same_curves(&per_case[j], curves)) {
            label += &format!(" {SAME} {j})");
        }
        for (slot, points) in curves.iter().enumerate() {
            if let Some(points) = points {
                out[slot].push(CurveSeries {
                    label: label.clone(),
                    points: points.clone(),
                });
            }
        }
    }
    Ok(out)
}

/// A case's tensile and shear curves (None: test not run).
type CaseCurves = [Option<Vec<(f64, f64)>>; 2];

/// Label suffix "(= case j)" of a case whose curves are case j's, and the key's note on it.
const SAME: &str = "(= case";
const SAME_NOTE: &str = "(= case j): the same curves as case j, drawn over them";

/// Whether two cases drew the same lines: the same tests, each curve with the same strains and
/// stresses within 1e-9 of the largest stress (the reduced units of scale-free cases differ in the
/// last bits).
fn same_curves(a: &CaseCurves, b: &CaseCurves) -> bool {
    let close = |p: &[(f64, f64)], q: &[(f64, f64)]| {
        let scale = p.iter().fold(0.0f64, |m, v| m.max(v.1.abs())).max(1e-300);
        p.len() == q.len()
            && p.iter().zip(q).all(|(u, v)| {
                (u.0 - v.0).abs() <= 1e-9 * u.0.abs().max(1e-12)
                    && (u.1 - v.1).abs() <= 1e-9 * scale
            })
    };
    a.iter().any(Option::is_some)
        && a.iter().zip(b).all(|(x, y)| match (x, y) {
            (None, None) => true,
            (Some(p), Some(q)) => close(p, q),
            _ => false,
        })
}

/// What `trends.png` is drawn against.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TrendAxis {
    /// d0 / d_c, on a log scale.
    D0,
    /// The target Poisson's ratio.
    Nu,
}

/// One case in `trends.png`; `None` where the campaign did not run that test.
#[derive(Debug, Clone, PartialEq)]
pub struct TrendPoint {
    pub x: f64,
    pub e_ratio: Option<f64>,
    pub nu: Option<f64>,
    pub nu_target: f64,
    /// (measured, target of eq 20).
    pub tensile: Option<(f64, f64)>,
    pub shear: Option<(f64, f64)>,
    /// The sample's volume fraction and mean number of interacting partners.
    pub volume_fraction: f64,
    pub coordination: f64,
}

/// Volume fraction of the HCP lattice, pi / (3 sqrt 2): the reference of paper 000 Fig. 7.
pub const HCP_VOLUME_FRACTION: f64 = std::f64::consts::PI / (3.0 * std::f64::consts::SQRT_2);

/// The cases grouped by scaling exponent s, against the swept variable.
#[derive(Debug, Clone, PartialEq)]
pub struct Trends {
    pub axis: TrendAxis,
    pub groups: Vec<(String, Vec<TrendPoint>)>,
}

/// The trend series, or `None` when neither d0 nor nu takes two values.
pub fn trends(report: &PatchReport) -> Option<Trends> {
    let distinct = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v.dedup();
        v.len()
    };
    let cases = &report.cases;
    let axis = if distinct(cases.iter().filter_map(|c| c.d0_over_dc).collect()) >= 2 {
        TrendAxis::D0
    } else if distinct(cases.iter().map(|c| c.poisson_ratio).collect()) >= 2 {
        TrendAxis::Nu
    } else {
        return None;
    };
    let mut groups: Vec<(f64, Vec<TrendPoint>)> = Vec::new();
    for c in cases {
        let x = match axis {
            TrendAxis::D0 => match c.d0_over_dc {
                Some(d) => d,
                None => continue,
            },
            TrendAxis::Nu => c.poisson_ratio,
        };
        let e = c.elastic.as_ref();
        let point = TrendPoint {
            x,
            e_ratio: e.map(|e| e.young_modulus / e.target_young_modulus),
            nu: e.map(|e| e.poisson_ratio),
            nu_target: c.poisson_ratio,
            tensile: c.tensile.as_ref().map(|t| (t.strength, t.target_strength)),
            shear: c.shear.as_ref().map(|t| (t.strength, t.target_strength)),
            volume_fraction: c.volume_fraction,
            coordination: c.coordination.interacting,
        };
        match groups.iter_mut().find(|(s, _)| *s == c.scaling) {
            Some((_, points)) => points.push(point),
            None => groups.push((c.scaling, vec![point])),
        }
    }
    for (_, points) in &mut groups {
        points.sort_by(|a, b| a.x.total_cmp(&b.x));
    }
    Some(Trends {
        axis,
        groups: groups
            .into_iter()
            .map(|(s, p)| (format!("s = {s}"), p))
            .collect(),
    })
}

/// Draws the campaign's figures into `dir` and returns their paths.
pub fn draw(report: &PatchReport, dir: &Path) -> Result<Vec<PathBuf>> {
    ensure_font()?;
    let mut written = Vec::new();
    let [tensile, shear] = curve_series(report, dir)?;
    if !(tensile.is_empty() && shear.is_empty()) {
        let path = dir.join("curves.png");
        draw_curves(&path, &tensile, &shear)?;
        written.push(path);
    }
    let compaction = compaction_series(report, dir)?;
    if !compaction.is_empty() {
        let path = dir.join("compaction.png");
        draw_compaction(&path, &compaction, report.config.compaction.max_compaction)?;
        written.push(path);
    }
    if let Some(t) = trends(report) {
        let path = dir.join("trends.png");
        draw_trends(&path, &t)?;
        written.push(path);
    }
    Ok(written)
}

fn draw_curves(path: &Path, tensile: &[CurveSeries], shear: &[CurveSeries]) -> Result<()> {
    // Cases are keyed by colour in a strip above the panels (a legend inside would hide the steep
    // early parts of the curves); a case has the same colour in both panels.
    let mut labels: Vec<&str> = Vec::new();
    for c in tensile.iter().chain(shear) {
        if !labels.contains(&c.label.as_str()) {
            labels.push(&c.label);
        }
    }
    let note = labels.iter().any(|l| l.contains(SAME)).then_some(SAME_NOTE);
    let (root, body) = keyed_figure(path, (1400, 560), &labels, 3, note)?;
    let panels = body.split_evenly((1, 2));
    let as_series = |v: &[CurveSeries]| -> Vec<Series> {
        v.iter()
            .map(|c| {
                let k = labels.iter().position(|l| *l == c.label).unwrap_or(0);
                (c.label.clone(), c.points.clone(), Mark::Line, k)
            })
            .collect()
    };
    let axes = [
        ("tensile test", "strain eps_yy", "sigma_yy / target sigma_N"),
        ("shear test", "strain eps_xy", "sigma_xy / target sigma_T"),
    ];
    for ((area, series), (title, xd, yd)) in panels.iter().zip([tensile, shear]).zip(axes) {
        panel(
            path,
            area,
            (title, xd, yd),
            Scale::Linear,
            &as_series(series),
        )?;
    }
    root.present().map_err(|e| draw_err(path, e))
}

/// The shear phase of every case's shear-under-load test: (shear strain, compaction in % of L0), the
/// compaction counted from the normal strain under the load alone (`loaded_strain`).
pub fn compaction_series(report: &PatchReport, dir: &Path) -> Result<Vec<CurveSeries>> {
    let mut out = Vec::new();
    for (k, case) in report.cases.iter().enumerate() {
        let Some(r) = &case.compaction else { continue };
        let path = dir.join(format!("case{k}_compaction.csv"));
        let points = read_columns(&path, 1, 2)?
            .into_iter()
            .filter(|(exy, _)| *exy > 0.0)
            .map(|(exy, eyy)| (exy, 100.0 * (r.loaded_strain - eyy)))
            .collect();
        out.push(CurveSeries {
            label: case_label(report, k),
            points,
        });
    }
    Ok(out)
}

fn draw_compaction(path: &Path, cases: &[CurveSeries], limit: f64) -> Result<()> {
    let mut labels: Vec<&str> = cases.iter().map(|c| c.label.as_str()).collect();
    let limit_label = "limit (collapsing above)";
    labels.push(limit_label);
    let (root, body) = keyed_figure(path, (1000, 560), &labels, 2, None)?;
    let x_max = cases
        .iter()
        .flat_map(|c| c.points.iter().map(|p| p.0))
        .fold(0.0, f64::max);
    let mut series: Vec<Series> = cases
        .iter()
        .enumerate()
        .map(|(k, c)| (c.label.clone(), c.points.clone(), Mark::Line, k))
        .collect();
    series.push((
        limit_label.to_string(),
        vec![(0.0, 100.0 * limit), (x_max, 100.0 * limit)],
        Mark::Target,
        cases.len(),
    ));
    panel(
        path,
        &body,
        (
            "shear under normal load",
            "shear strain eps_xy",
            "compaction since loading (% of L0)",
        ),
        Scale::Linear,
        &series,
    )?;
    root.present().map_err(|e| draw_err(path, e))
}

fn draw_trends(path: &Path, t: &Trends) -> Result<()> {
    // One key for the four panels: a colour per s, then what dots and dashes mean.
    let labels: Vec<&str> = t.groups.iter().map(|(l, _)| l.as_str()).collect();
    let note = "dots: measured    dashes: target (the target nu; eq 20 for the strengths; HCP for the volume fraction)";
    let (root, body) = keyed_figure(path, (1400, 1500), &labels, 6, Some(note))?;
    let panels = body.split_evenly((3, 2));
    let (x_scale, x_desc) = match t.axis {
        TrendAxis::D0 => (Scale::Log, "d0 / d_c"),
        TrendAxis::Nu => (Scale::Linear, "target nu"),
    };
    type Pick = fn(&TrendPoint) -> Option<(f64, Option<f64>)>;
    let picks: [(&str, &str, Pick); 6] = [
        ("Young's modulus", "E / E_target", |p| {
            p.e_ratio.map(|e| (e, Some(1.0)))
        }),
        ("Poisson's ratio", "nu", |p| {
            p.nu.map(|n| (n, Some(p.nu_target)))
        }),
        ("tensile strength", "sigma_N", |p| {
            p.tensile.map(|(m, t)| (m, Some(t)))
        }),
        ("shear strength", "sigma_T", |p| {
            p.shear.map(|(m, t)| (m, Some(t)))
        }),
        ("relaxed volume fraction (Fig. 7)", "volume fraction", |p| {
            Some((p.volume_fraction, Some(HCP_VOLUME_FRACTION)))
        }),
        ("coordination", "interacting partners per particle", |p| {
            Some((p.coordination, None))
        }),
    ];
    for (area, (title, y_desc, pick)) in panels.iter().zip(picks) {
        let mut series: Vec<Series> = Vec::new();
        for (g, (label, points)) in t.groups.iter().enumerate() {
            let measured: Vec<(f64, f64)> = points
                .iter()
                .filter_map(|p| pick(p).map(|(m, _)| (p.x, m)))
                .collect();
            let target: Vec<(f64, f64)> = points
                .iter()
                .filter_map(|p| pick(p).and_then(|(_, t)| t).map(|t| (p.x, t)))
                .collect();
            if !measured.is_empty() {
                series.push((label.clone(), measured, Mark::Points, g));
                series.push((String::new(), target, Mark::Target, g));
            }
        }
        let series: Vec<Series> = series
            .into_iter()
            .map(|(l, pts, m, c)| (l, x_scale.map(&pts), m, c))
            .collect();
        panel(path, area, (title, x_desc, y_desc), x_scale, &series)?;
    }
    root.present().map_err(|e| draw_err(path, e))
}

/// "case k: nu = .., d0 = .. d_c, s = .." from what the case varies, to four significant digits (a
/// d0 derived from nanometres, 1.7534246575342467 d_c, reads 1.753 d_c; the report keeps every digit).
fn case_label(report: &PatchReport, k: usize) -> String {
    let c = &report.cases[k];
    let mut s = format!("case {k}: nu = {}", Sig(c.poisson_ratio, 4));
    if let Some(d) = c.d0_over_dc {
        s += &format!(", d0 = {} d_c", Sig(d, 4));
    }
    s + &format!(", s = {}", Sig(c.scaling, 4))
}

/// Reads two columns of a curve CSV (header line first).
fn read_columns(path: &Path, a: usize, b: usize) -> Result<Vec<(f64, f64)>> {
    let bad = |reason: String| ValidationError::Curve {
        path: path.display().to_string(),
        reason,
    };
    let text = std::fs::read_to_string(path).map_err(|e| bad(e.to_string()))?;
    text.lines()
        .skip(1)
        .enumerate()
        .map(|(n, line)| {
            let cols: Vec<&str> = line.split(',').collect();
            let get = |i: usize| -> Result<f64> {
                cols.get(i)
                    .and_then(|v| v.trim().parse().ok())
                    .ok_or_else(|| bad(format!("line {}: no number in column {}", n + 2, i + 1)))
            };
            Ok((get(a)?, get(b)?))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::same_curves;

    fn curve(scale: f64) -> Option<Vec<(f64, f64)>> {
        Some(
            (0..50)
                .map(|k| (1e-3 * k as f64, scale * (0.1 * k as f64).sin()))
                .collect(),
        )
    }

    #[test]
    fn curves_are_the_same_to_round_off_only_and_test_by_test() {
        assert!(same_curves(
            &[curve(1.0), None],
            &[curve(1.0 + 1e-13), None]
        ));
        assert!(same_curves(
            &[curve(1.0), curve(2.0)],
            &[curve(1.0), curve(2.0)]
        ));
        assert!(!same_curves(
            &[curve(1.0), None],
            &[curve(1.0 + 1e-6), None]
        ));
        assert!(!same_curves(&[curve(1.0), None], &[curve(1.0), curve(1.0)]));
        assert!(
            !same_curves(&[None, None], &[None, None]),
            "no curves: nothing drawn to hide"
        );
        let mut short = curve(1.0);
        short.as_mut().unwrap().pop();
        assert!(!same_curves(&[curve(1.0), None], &[short, None]));
    }
}
