//! The figure of a calibration (`cgdem calibrate`, `cgdem pipeline`): `calibration.png`.
//!
//! - left: the relative error of each target property, |measured - target| / target in percent on a
//!   log scale, for the first guess (the closed form unless the config sets `[start]`), the calibrated
//!   card and, when the card was verified on fresh samples of its recipe, their mean; a property the
//!   calibration did not fit but the verification measured against a target (the shear strength of a
//!   card fitted to E, nu and sigma_N, the surface energy) gets its verified bar too, so that what the
//!   fit left out is in the figure as it is in `summary.txt`;
//! - right: the least-squares cost 1/2 |r|^2 after each solver iteration (log scale),
//!   starting from the first guess at iteration 0.

use std::path::Path;

use calibrate::{Properties, Record, Target};
use plotters::prelude::*;

use super::chart::{builder, log_axis, log_ticks, Axis};
use super::style::{colour, draw_err, ensure_font, FAMILY};
use crate::error::Result;

/// The relative errors of one target property, in percent.
#[derive(Debug, Clone, PartialEq)]
pub struct ErrorRow {
    pub name: &'static str,
    pub uncalibrated: Option<f64>,
    pub calibrated: Option<f64>,
    pub verified: Option<f64>,
}

/// One row per property that has a target, in the order of the calibration's table: the fitted
/// `targets`, then (verified bar only) those of `verified_targets` that were not fitted.
pub fn error_rows(
    targets: &Properties,
    uncalibrated: &Properties,
    calibrated: &Properties,
    verified: Option<&Properties>,
    verified_targets: Option<&Properties>,
) -> Vec<ErrorRow> {
    Target::ALL
        .into_iter()
        .filter_map(|t| {
            let fitted = targets.get(t);
            let target = fitted.or_else(|| verified.and(verified_targets)?.get(t))?;
            let err = |p: &Properties| p.get(t).map(|v| 100.0 * (v - target) / target);
            let fit = |p: &Properties| fitted.and_then(|_| err(p));
            Some(ErrorRow {
                name: t.name(),
                uncalibrated: fit(uncalibrated),
                calibrated: fit(calibrated),
                verified: verified.and_then(err),
            })
        })
        .collect()
}

/// (iteration, cost after it) from a calibration's history: iteration 0 is the first guess; a
/// rejected or failed step keeps the cost.
pub fn cost_series(history: &[Record]) -> Vec<(usize, f64)> {
    let mut out = Vec::new();
    for rec in history {
        if out.is_empty() {
            out.push((rec.iteration.saturating_sub(1), rec.cost));
        }
        let after = match (rec.accepted, rec.cost_trial) {
            (true, Some(c)) => c,
            _ => rec.cost,
        };
        out.push((rec.iteration, after));
    }
    out
}

/// The index a tick at `v` stands for, when it sits on a non-negative integer (the bars and the
/// iterations are at integers; plotters also asks for labels between them).
fn integer_tick(v: f64) -> Option<usize> {
    let k = v.round();
    ((v - k).abs() < 1e-6 && k >= 0.0).then_some(k as usize)
}

/// Which error of a row a bar shows.
type Pick = fn(&ErrorRow) -> Option<f64>;

/// Draws `calibration.png`.
pub fn draw(path: &Path, rows: &[ErrorRow], costs: &[(usize, f64)]) -> Result<()> {
    ensure_font()?;
    let err = |e: &dyn std::fmt::Display| draw_err(path, e);
    let root = BitMapBackend::new(path, (1400, 600)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let (left, right) = root.split_horizontally(800);

    // Left: grouped bars of |error| per property.
    let kinds: [(&str, Pick); 3] = [
        ("first guess (closed form unless [start])", |r| {
            r.uncalibrated
        }),
        ("calibrated", |r| r.calibrated),
        ("verified (mean on fresh samples)", |r| r.verified),
    ];
    let values = || {
        rows.iter()
            .flat_map(|r| kinds.iter().filter_map(|(_, f)| f(r)))
            .map(f64::abs)
    };
    let floor = values()
        .filter(|v| *v > 0.0)
        .fold(f64::INFINITY, f64::min)
        .min(0.1)
        / 3.0;
    // Log10 coordinates throughout (see `chart::log_axis`); room above the tallest bar for the
    // legend.
    let floor = if floor.is_finite() { floor } else { 1e-3 }.log10();
    let top = (values().fold(1.0, f64::max) * 12.0).log10();
    let n = rows.len().max(1) as f64;
    let names: Vec<&str> = rows.iter().map(|r| r.name).collect();
    let mut chart = builder(&left, "error against target")
        .build_cartesian_2d(-0.5..n - 0.5, floor..top)
        .map_err(|e| err(&e))?;
    let x_name = |v: &f64| {
        integer_tick(*v)
            .and_then(|k| names.get(k))
            .map_or(String::new(), |s| s.to_string())
    };
    chart
        .configure_mesh()
        .disable_x_mesh()
        .x_labels(2 * rows.len() + 1)
        .x_label_formatter(&x_name)
        .y_labels(0)
        .disable_y_mesh()
        .y_desc("|measured - target| / target (%)")
        .label_style((FAMILY, 15))
        .axis_desc_style((FAMILY, 17))
        .draw()
        .map_err(|e| err(&e))?;
    log_axis(path, &left, &mut chart, Axis::Y, &log_ticks(floor, top))?;
    for (s, (label, f)) in kinds.iter().enumerate() {
        let c = colour(s);
        let bars = rows.iter().enumerate().filter_map(|(k, r)| {
            let v = f(r)?.abs().log10().max(floor);
            let x0 = k as f64 - 0.36 + 0.24 * s as f64;
            Some(Rectangle::new([(x0, floor), (x0 + 0.22, v)], c.filled()))
        });
        let any = rows.iter().any(|r| f(r).is_some());
        let drawn = chart.draw_series(bars).map_err(|e| err(&e))?;
        if any {
            drawn
                .label(*label)
                .legend(move |(x, y)| Rectangle::new([(x, y - 6), (x + 16, y + 6)], c.filled()));
        }
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .label_font((FAMILY, 15))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(|e| err(&e))?;

    // Right: cost per iteration.
    let last = costs.last().map_or(1, |c| c.0.max(1)) as f64;
    let (lo, hi) = costs
        .iter()
        .map(|c| c.1)
        .filter(|c| *c > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(a, b), c| (a.min(c), b.max(c)));
    let (lo, hi) = if lo <= hi {
        (lo.log10() - 0.5, hi.log10() + 0.5)
    } else {
        (-6.0, 0.0)
    };
    let mut chart = builder(&right, "least-squares cost")
        .build_cartesian_2d(-0.2..last + 0.2, lo..hi)
        .map_err(|e| err(&e))?;
    chart
        .configure_mesh()
        .x_labels(costs.len().max(2))
        // Iterations are integers: no light lines between them.
        .x_max_light_lines(0)
        .x_label_formatter(&|v| integer_tick(*v).map_or(String::new(), |k| k.to_string()))
        .y_labels(0)
        .disable_y_mesh()
        .x_desc("solver iteration (Levenberg-Marquardt or trust region)")
        .y_desc("1/2 |r|^2")
        .label_style((FAMILY, 15))
        .axis_desc_style((FAMILY, 17))
        .draw()
        .map_err(|e| err(&e))?;
    log_axis(path, &right, &mut chart, Axis::Y, &log_ticks(lo, hi))?;
    let pts: Vec<(f64, f64)> = costs
        .iter()
        .filter(|c| c.1 > 0.0)
        .map(|&(k, c)| (k as f64, c.log10()))
        .collect();
    let c = colour(0);
    chart
        .draw_series(LineSeries::new(pts.iter().copied(), c.stroke_width(2)))
        .map_err(|e| err(&e))?;
    chart
        .draw_series(pts.iter().map(|&p| Circle::new(p, 5, c.filled())))
        .map_err(|e| err(&e))?;
    root.present().map_err(|e| err(&e))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(iteration: usize, cost: f64, trial: Option<f64>, accepted: bool) -> Record {
        Record {
            iteration,
            x_trial: vec![],
            r_trial: None,
            noise_trial: vec![],
            failure: None,
            cost,
            cost_trial: trial,
            predicted: 0.0,
            accepted,
            lambda: 1.0,
            r: vec![],
            evaluations: 0,
            seconds: 0.0,
        }
    }

    #[test]
    fn costs_start_at_the_closed_form_and_keep_rejected_steps_out() {
        let h = [
            record(1, 0.05, Some(1e-3), true),
            record(2, 1e-3, Some(2e-3), false),
            record(3, 1e-3, None, false),
            record(4, 1e-3, Some(1e-6), true),
        ];
        assert_eq!(
            cost_series(&h),
            [(0, 0.05), (1, 1e-3), (2, 1e-3), (3, 1e-3), (4, 1e-6)]
        );
        assert!(cost_series(&[]).is_empty());
    }

    #[test]
    fn errors_are_relative_to_the_targets_in_percent() {
        let p = |e: f64, s: Option<f64>| Properties {
            young_modulus: Some(e),
            shear_strength: s,
            ..Properties::default()
        };
        let rows = error_rows(
            &p(2.0, Some(0.1)),
            &p(2.5, Some(0.05)),
            &p(2.0, None),
            None,
            None,
        );
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[0].name, "young_modulus");
        assert_eq!(rows[0].uncalibrated, Some(25.0));
        assert_eq!(rows[0].calibrated, Some(0.0));
        assert_eq!(rows[1].uncalibrated, Some(-50.0));
        assert_eq!((rows[1].calibrated, rows[1].verified), (None, None));
    }

    #[test]
    fn a_verified_property_that_was_not_fitted_gets_its_verified_bar_only() {
        let fitted = Properties {
            young_modulus: Some(2.0),
            ..Properties::default()
        };
        let all = Properties {
            young_modulus: Some(2.0),
            shear_strength: Some(0.1),
            ..Properties::default()
        };
        let measured = Properties {
            young_modulus: Some(2.2),
            shear_strength: Some(0.133),
            ..Properties::default()
        };
        let rows = error_rows(&fitted, &measured, &measured, Some(&measured), Some(&all));
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[1].name, "shear_strength");
        assert_eq!((rows[1].uncalibrated, rows[1].calibrated), (None, None));
        assert!((rows[1].verified.unwrap() - 33.0).abs() < 1e-9);
        // Without a verification the unfitted property has no row.
        assert_eq!(
            error_rows(&fitted, &measured, &measured, None, Some(&all)).len(),
            1
        );
    }
}
