//! The detachment-probability figure of the comparison: for each side (MD, each DEM d0) the
//! fraction of its runs that detached a wear particle at each junction size (marks, the number of
//! runs beside each), the fitted logistic P(wear | D) (line), D50 (a diamond at P = 1/2 with its
//! interval as a bar), and the bisection's bracket (a bar of the side's colour under the axis of
//! probabilities); reference sizes (eq 22) dashed. x on a log axis, in any unit the caller scales to.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::chart::{log_axis, log_ticks, Axis};
use super::style::{colour, draw_err, ensure_font, FAMILY};
use crate::error::Result;

/// One side.
#[derive(Debug, Clone, PartialEq)]
pub struct ProbabilitySeries {
    pub label: String,
    /// (x, runs, wear) per size.
    pub fractions: Vec<(f64, usize, usize)>,
    /// (x50, slope per unit of ln x) of the fitted logistic, if any.
    pub curve: Option<(f64, f64)>,
    /// Its interval on x50 (open ends None).
    pub interval: [Option<f64>; 2],
    /// The bisection's bracket (lower, upper].
    pub bracket: [Option<f64>; 2],
}

/// Where the bracket bar of series `k` sits (below P = 0).
fn bar_y(k: usize) -> f64 {
    -0.08 - 0.06 * k as f64
}

/// Draws the figure (SVG for a path ending in `.svg`, PNG otherwise).
pub fn draw_detachment(
    path: &Path,
    x_label: &str,
    series: &[ProbabilitySeries],
    refs: &[(String, f64)],
) -> Result<()> {
    ensure_font()?;
    let key_rows = series.len() + refs.len() + 1;
    let size = (1200, 560 + 26 * key_rows as u32 + 24 * series.len() as u32);
    if path.extension().is_some_and(|e| e == "svg") {
        draw_on(
            SVGBackend::new(path, size).into_drawing_area(),
            path,
            x_label,
            series,
            refs,
        )
    } else {
        draw_on(
            BitMapBackend::new(path, size).into_drawing_area(),
            path,
            x_label,
            series,
            refs,
        )
    }
}

/// The x extent (log10) that shows every mark, bracket end, interval end and reference.
fn extent(series: &[ProbabilitySeries], refs: &[(String, f64)]) -> (f64, f64) {
    let xs = series
        .iter()
        .flat_map(|s| {
            s.fractions
                .iter()
                .map(|f| f.0)
                .chain(s.bracket.iter().flatten().copied())
                .chain(s.interval.iter().flatten().copied())
        })
        .chain(refs.iter().map(|r| r.1))
        .filter(|x| x.is_finite() && *x > 0.0)
        .map(f64::log10);
    let (lo, hi) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
        (a.min(x), b.max(x))
    });
    if lo.is_finite() && lo < hi {
        (lo - 0.04, hi + 0.04)
    } else if lo.is_finite() {
        (lo - 0.3, lo + 0.3)
    } else {
        (-1.0, 1.0)
    }
}

fn draw_on<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    path: &Path,
    x_label: &str,
    series: &[ProbabilitySeries],
    refs: &[(String, f64)],
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    let err = |e: &dyn std::fmt::Display| draw_err(path, e);
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let key_rows = series.len() + refs.len() + 1;
    let (key, body) = root.split_vertically(16 + 26 * key_rows as u32);
    let mut y = 8;
    key.draw(&Text::new(
        "marks: fraction of runs that detach a wear particle (runs beside); line: fitted P; \
         diamond and bar at P = 1/2: D50 and its interval; bar below: bisection bracket",
        (20, y),
        (FAMILY, 16),
    ))
    .map_err(|e| err(&e))?;
    for (k, s) in series.iter().enumerate() {
        y += 26;
        let c = colour(k);
        key.draw(&Circle::new((30, y + 9), 6, c.filled()))
            .map_err(|e| err(&e))?;
        key.draw(&Text::new(
            s.label.clone(),
            (44, y),
            (FAMILY, 18).into_font().color(&c),
        ))
        .map_err(|e| err(&e))?;
    }
    for (label, v) in refs {
        y += 26;
        let c = RGBColor(90, 90, 90);
        key.draw(&PathElement::new(
            [(16, y + 9), (42, y + 9)],
            c.stroke_width(2),
        ))
        .map_err(|e| err(&e))?;
        key.draw(&Text::new(
            format!("{label} at {v}"),
            (50, y),
            (FAMILY, 18).into_font().color(&c),
        ))
        .map_err(|e| err(&e))?;
    }
    let (lo, hi) = extent(series, refs);
    let y_lo = bar_y(series.len().saturating_sub(1)) - 0.05;
    let mut chart = ChartBuilder::on(&body)
        .margin(16)
        .x_label_area_size(52)
        .y_label_area_size(70)
        .build_cartesian_2d(lo..hi, y_lo..1.06)
        .map_err(|e| err(&e))?;
    chart
        .configure_mesh()
        .x_desc(format!("{x_label} (log scale)"))
        .y_desc("P(wear particle)")
        .x_labels(0)
        .disable_x_mesh()
        .y_labels(6)
        .y_label_formatter(&|v| {
            if *v >= -1e-9 {
                format!("{:.1}", v.max(0.0))
            } else {
                String::new()
            }
        })
        .label_style((FAMILY, 15))
        .axis_desc_style((FAMILY, 17))
        .draw()
        .map_err(|e| err(&e))?;
    log_axis(path, &body, &mut chart, Axis::X, &log_ticks(lo, hi))?;
    let grey = RGBColor(90, 90, 90);
    for (_, v) in refs {
        let x = v.log10();
        chart
            .draw_series(DashedLineSeries::new(
                [(x, y_lo), (x, 1.06)],
                8,
                5,
                grey.stroke_width(2),
            ))
            .map_err(|e| err(&e))?;
    }
    // P = 0, 1/2 and 1 as thin guides.
    for p in [0.0, 0.5, 1.0] {
        chart
            .draw_series(LineSeries::new(
                [(lo, p), (hi, p)],
                RGBColor(215, 215, 215).stroke_width(1),
            ))
            .map_err(|e| err(&e))?;
    }
    for (k, s) in series.iter().enumerate() {
        let c = colour(k);
        if let Some((x50, slope)) = s.curve {
            let n = 300;
            let pts = (0..=n).map(|i| {
                let lx = lo + (hi - lo) * i as f64 / n as f64;
                let z = slope * (lx - x50.log10()) * std::f64::consts::LN_10;
                (lx, 1.0 / (1.0 + (-z).exp()))
            });
            chart
                .draw_series(LineSeries::new(pts, c.stroke_width(3)))
                .map_err(|e| err(&e))?;
            // The interval at P = 1/2 (each side a little apart), open ends to the axis.
            let py = 0.5 + 0.025 * (k as f64 - 0.5 * (series.len() as f64 - 1.0));
            let a = s.interval[0].map_or(lo, f64::log10);
            let b = s.interval[1].map_or(hi, f64::log10);
            chart
                .draw_series(LineSeries::new([(a, py), (b, py)], c.stroke_width(4)))
                .map_err(|e| err(&e))?;
            let x = x50.log10();
            let d = 0.022;
            chart
                .draw_series(std::iter::once(Polygon::new(
                    vec![(x - 0.012, py), (x, py + d), (x + 0.012, py), (x, py - d)],
                    c.filled(),
                )))
                .map_err(|e| err(&e))?;
        }
        for &(x, runs, wear) in &s.fractions {
            if x <= 0.0 || runs == 0 {
                continue;
            }
            let at = (x.log10(), wear as f64 / runs as f64);
            let mark = EmptyElement::at(at)
                + Circle::new((0, 0), 7, c.filled())
                + Circle::new((0, 0), 7, WHITE.stroke_width(1))
                + Text::new(
                    format!("{runs}"),
                    (8, -20),
                    (FAMILY, 13).into_font().color(&c),
                );
            chart
                .draw_series(std::iter::once(mark))
                .map_err(|e| err(&e))?;
        }
        let by = bar_y(k);
        let a = s.bracket[0].map_or(lo, f64::log10);
        let b = s.bracket[1].map_or(hi, f64::log10);
        chart
            .draw_series(std::iter::once(Rectangle::new(
                [(a, by - 0.018), (b, by + 0.018)],
                c.mix(0.6).filled(),
            )))
            .map_err(|e| err(&e))?;
    }
    root.present().map_err(|e| err(&e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_extent_holds_marks_brackets_intervals_and_references() {
        let s = ProbabilitySeries {
            label: "a".into(),
            fractions: vec![(1.0, 8, 2)],
            curve: Some((1.2, 10.0)),
            interval: [Some(0.9), Some(3.0)],
            bracket: [Some(0.5), Some(1.5)],
        };
        let (lo, hi) = extent(&[s], &[("eq 22".into(), 4.0)]);
        assert!(lo < 0.5f64.log10() && hi > 4f64.log10(), "{lo} {hi}");
        assert!(bar_y(0) < 0.0 && bar_y(3) < bar_y(2));
    }
}
