//! The panel every figure is made of: axes sized to the data, a linear or logarithmic x axis, and
//! series drawn as lines, dots or dashed targets (colours keyed outside the panels, by each figure).

use std::path::Path;

use plotters::prelude::*;

use super::style::{colour, draw_err, tick, FAMILY};
use crate::error::Result;

/// How a series is drawn.
#[derive(Clone, Copy, PartialEq)]
pub(crate) enum Mark {
    /// Solid line (measured curves).
    Line,
    /// Line with circles (measured points).
    Points,
    /// Dashed line (targets).
    Target,
}

/// A series ready to draw: label, points in plot coordinates, how, colour index.
pub(crate) type Series = (String, Vec<(f64, f64)>, Mark, usize);

/// Linear or logarithmic x axis.
#[derive(Clone, Copy, PartialEq)]
pub(crate) enum Scale {
    Linear,
    Log,
}

impl Scale {
    /// The points a log axis can show (x > 0).
    pub(crate) fn map(self, pts: &[(f64, f64)]) -> Vec<(f64, f64)> {
        match self {
            Scale::Linear => pts.to_vec(),
            Scale::Log => pts.iter().copied().filter(|(x, _)| *x > 0.0).collect(),
        }
    }
}

/// The padded range of `v` (a unit-wide one around a single value).
pub(crate) fn range(v: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (lo, hi) = v
        .filter(|x| x.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        });
    // No finite value: the fold leaves lo = +inf > hi = -inf.
    if lo > hi {
        return 0.0..1.0;
    }
    let pad = if hi > lo {
        0.06 * (hi - lo)
    } else {
        0.5 * lo.abs().max(1e-12)
    };
    (lo - pad)..(hi + pad)
}

pub(crate) fn panel<DB: DrawingBackend>(
    path: &Path,
    area: &DrawingArea<DB, plotters::coord::Shift>,
    (title, x_desc, y_desc): (&str, &str, &str),
    x_scale: Scale,
    series: &[Series],
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    let all = || series.iter().flat_map(|s| s.1.iter());
    let yr = range(all().map(|p| p.1));
    match x_scale {
        Scale::Linear => {
            let xr = range(all().map(|p| p.0));
            let chart = ChartBuilder::on(area)
                .caption(title, (FAMILY, 24))
                .margin(14)
                .x_label_area_size(48)
                .y_label_area_size(72)
                .build_cartesian_2d(xr, yr)
                .map_err(|e| draw_err(path, e))?;
            fill(path, chart, (x_desc, y_desc), series)
        }
        Scale::Log => {
            // Positive x only (`Scale::Log` filtered them); a decade around a single value.
            let (lo, hi) = all().fold((f64::INFINITY, 0.0f64), |(a, b), p| {
                (a.min(p.0), b.max(p.0))
            });
            let (lo, hi) = if lo < hi {
                (lo / 1.25, hi * 1.25)
            } else {
                (lo / 3.0, lo * 3.0)
            };
            let lo = if lo.is_finite() && lo > 0.0 { lo } else { 0.1 };
            let chart = ChartBuilder::on(area)
                .caption(title, (FAMILY, 24))
                .margin(14)
                .x_label_area_size(48)
                .y_label_area_size(72)
                .build_cartesian_2d((lo..hi.max(2.0 * lo)).log_scale(), yr)
                .map_err(|e| draw_err(path, e))?;
            fill(
                path,
                chart,
                (&format!("{x_desc} (log scale)"), y_desc),
                series,
            )
        }
    }
}

/// Mesh, series and legend of one panel.
fn fill<'a, DB: DrawingBackend + 'a, X>(
    path: &Path,
    mut chart: ChartContext<'a, DB, Cartesian2d<X, plotters::coord::types::RangedCoordf64>>,
    (x_desc, y_desc): (&str, &str),
    series: &[Series],
) -> Result<()>
where
    DB::ErrorType: 'static,
    X: Ranged<ValueType = f64> + plotters::coord::ranged1d::ValueFormatter<f64>,
{
    let err = |e: &dyn std::fmt::Display| draw_err(path, e);
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .x_labels(8)
        .x_label_formatter(&|v| tick(v))
        .y_label_formatter(&|v| tick(v))
        .label_style((FAMILY, 15))
        .axis_desc_style((FAMILY, 17))
        .draw()
        .map_err(|e| err(&e))?;
    for (_, pts, mark, c) in series {
        let colour = colour(*c);
        match mark {
            Mark::Line => {
                chart
                    .draw_series(LineSeries::new(pts.iter().copied(), colour.stroke_width(2)))
                    .map_err(|e| err(&e))?;
            }
            Mark::Points => {
                chart
                    .draw_series(PointSeries::of_element(
                        pts.iter().copied(),
                        5,
                        colour.filled(),
                        &|p, s, st| Circle::new(p, s, st),
                    ))
                    .map_err(|e| err(&e))?;
                chart
                    .draw_series(LineSeries::new(pts.iter().copied(), colour.stroke_width(1)))
                    .map_err(|e| err(&e))?;
            }
            Mark::Target => {
                chart
                    .draw_series(DashedLineSeries::new(
                        pts.iter().copied(),
                        8,
                        5,
                        colour.stroke_width(2),
                    ))
                    .map_err(|e| err(&e))?;
            }
        }
    }
    Ok(())
}

/// A colour key above the panels (a legend inside a panel hides data): entry `k` of `labels` in
/// colour `k`, `per_row` to a row, then an optional line of black text. Returns the strip's height.
pub(crate) fn key_height(labels: usize, per_row: usize, note: bool) -> u32 {
    16 + 28 * (labels.div_ceil(per_row.max(1)) + usize::from(note)) as u32
}

/// Draws the key of [`key_height`] into `strip` (as wide as the figure).
pub(crate) fn draw_key<DB: DrawingBackend>(
    path: &Path,
    strip: &DrawingArea<DB, plotters::coord::Shift>,
    labels: &[&str],
    per_row: usize,
    note: Option<&str>,
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    let width = strip.dim_in_pixel().0 as i32 - 48;
    let per_row = per_row.max(1);
    let col = width / per_row as i32;
    for (k, label) in labels.iter().enumerate() {
        let at = (
            24 + col * (k % per_row) as i32,
            10 + 28 * (k / per_row) as i32,
        );
        let c = colour(k);
        let style = TextStyle::from((FAMILY, 18)).color(&c);
        strip
            .draw(&Text::new(label.to_string(), at, style))
            .map_err(|e| draw_err(path, e))?;
    }
    if let Some(note) = note {
        let y = 10 + 28 * labels.len().div_ceil(per_row) as i32;
        strip
            .draw(&Text::new(note.to_string(), (24, y), (FAMILY, 18)))
            .map_err(|e| draw_err(path, e))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_pad_and_survive_degenerate_data() {
        let r = range([1.0, 3.0].into_iter());
        assert!(r.start < 1.0 && r.end > 3.0);
        let r = range([2.0].into_iter());
        assert!(r.start < 2.0 && r.end > 2.0);
        assert_eq!(range([f64::NAN].into_iter()), 0.0..1.0);
        assert_eq!(range(std::iter::empty()), 0.0..1.0);
    }
}
