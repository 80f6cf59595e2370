//! The panel every figure is made of: axes sized to the data, a linear or logarithmic x axis, and
//! series drawn as lines, dots or dashed targets (colours keyed outside the panels, by each figure).

use std::path::Path;

use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::style::{colour, draw_err, tick, FAMILY};
use crate::error::Result;

/// How a series is drawn.
#[derive(Clone, Copy, PartialEq)]
pub(crate) enum Mark {
    /// Solid line (measured curves).
    Line,
    /// Line with circles (measured points).
    Points,
    /// Circles alone (outcomes of separate runs, which no line should join).
    Dots,
    /// Dashed line (targets).
    Target,
    /// Hollow circles (a paper's outcomes at discrete points).
    Rings,
}

/// The key's sample of `mark` in colour `c`, starting at `(x, y)` and 22 pixels wide.
pub(crate) fn swatch<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    mark: Mark,
    (x, y): (i32, i32),
    c: RGBColor,
) -> std::result::Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let line = |a: i32, b: i32| PathElement::new(vec![(a, y), (b, y)], c.stroke_width(2));
    match mark {
        Mark::Line => area.draw(&line(x, x + 22)),
        Mark::Points => {
            area.draw(&line(x, x + 22))?;
            area.draw(&Circle::new((x + 11, y), 4, c.filled()))
        }
        Mark::Dots => area.draw(&Circle::new((x + 11, y), 6, c.filled())),
        Mark::Target => {
            area.draw(&line(x, x + 8))?;
            area.draw(&line(x + 13, x + 21))
        }
        Mark::Rings => area.draw(&Circle::new((x + 11, y), 8, c.stroke_width(2))),
    }
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
    /// The points in plot coordinates: a log axis plots log10 x (of the points with x > 0).
    ///
    /// Decision: log axes are drawn as linear axes of log10 values with ticks at 1, 2, 5 x 10^k
    /// (see [`log_ticks`]) rather than with plotters' `log_scale()`, whose tick search looped
    /// forever on a range of 0.48..24 (a d0 sweep to 19.2 d_c) in plotters 0.3.7.
    pub(crate) fn map(self, pts: &[(f64, f64)]) -> Vec<(f64, f64)> {
        match self {
            Scale::Linear => pts.to_vec(),
            Scale::Log => pts
                .iter()
                .filter(|(x, _)| *x > 0.0)
                .map(|&(x, y)| (x.log10(), y))
                .collect(),
        }
    }
}

/// Ticks of a log10 axis spanning `lo..hi` (log10 values): the log10 of 1, 2 and 5 x 10^k inside
/// it, thinned to whole decades when there are more than 12; the ends when none falls inside.
pub(crate) fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    if !(lo.is_finite() && hi.is_finite() && lo < hi) {
        return vec![];
    }
    let inside = |mantissas: &[f64]| -> Vec<f64> {
        let (k0, k1) = (lo.floor() as i32, hi.ceil() as i32);
        (k0..=k1)
            .flat_map(|k| mantissas.iter().map(move |m| m.log10() + k as f64))
            .filter(|v| (lo..=hi).contains(v))
            .collect()
    };
    let mut t = inside(&[1.0, 2.0, 5.0]);
    if t.len() > 12 {
        t = inside(&[1.0]);
    }
    if t.is_empty() {
        t = vec![lo, hi];
    }
    t
}

/// A tick label for log10 value `v`: 10^v with three significant digits.
pub(crate) fn log_label(v: &f64) -> String {
    let x = 10f64.powf(*v);
    if (1e-3..1e5).contains(&x) {
        let digits = (2 - x.log10().floor() as i32).max(0) as usize;
        let s = format!("{x:.digits$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{x:.0e}")
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

/// One panel: its title, axis descriptions, x scale and series.
pub(crate) fn panel<DB: DrawingBackend>(
    path: &Path,
    area: &DrawingArea<DB, plotters::coord::Shift>,
    descs: (&str, &str, &str),
    x_scale: Scale,
    series: &[Series],
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    row_panel(path, area, descs, x_scale, (&[], &[]), series)
}

/// [`panel`] with chosen ticks: x ticks at `x_ticks` only (a count such as threads), and y values
/// 0, 1, ... named by `y_rows` (outcomes per run) in place of numbers; with neither it is [`panel`].
pub(crate) fn row_panel<DB: DrawingBackend>(
    path: &Path,
    area: &DrawingArea<DB, plotters::coord::Shift>,
    (title, x_desc, y_desc): (&str, &str, &str),
    x_scale: Scale,
    (x_ticks, y_rows): (&[f64], &[String]),
    series: &[Series],
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    if series.iter().all(|s| s.1.is_empty()) {
        // Nothing measured (the campaign did not run this test): say so instead of empty axes.
        let inner = area
            .titled(title, (FAMILY, 24))
            .map_err(|e| draw_err(path, e))?;
        let (w, h) = inner.dim_in_pixel();
        let style = TextStyle::from((FAMILY, 18)).pos(Pos::new(HPos::Center, VPos::Center));
        return inner
            .draw(&Text::new(
                "not measured in this campaign",
                (w as i32 / 2, h as i32 / 2),
                style,
            ))
            .map_err(|e| draw_err(path, e));
    }
    let all = || series.iter().flat_map(|s| s.1.iter());
    let yr = range(all().map(|p| p.1));
    match x_scale {
        Scale::Linear => {
            let xr = range(all().map(|p| p.0));
            let chart = rows_builder(area, title, y_rows)
                .build_cartesian_2d(xr, yr)
                .map_err(|e| draw_err(path, e))?;
            let ticks = (!x_ticks.is_empty()).then(|| Ticks::Chosen(x_ticks.to_vec()));
            fill(path, area, chart, (x_desc, y_desc), ticks, y_rows, series)
        }
        Scale::Log => {
            // The series are in log10 x already (`Scale::map`); a third of a decade of margin.
            let (lo, hi) = all().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                (a.min(p.0), b.max(p.0))
            });
            let (lo, hi) = if lo < hi {
                (lo - 0.1, hi + 0.1)
            } else {
                (lo - 0.5, lo + 0.5)
            };
            let (lo, hi) = if lo.is_finite() {
                (lo, hi)
            } else {
                (-1.0, 1.0)
            };
            let chart = rows_builder(area, title, y_rows)
                .build_cartesian_2d(lo..hi, yr)
                .map_err(|e| draw_err(path, e))?;
            let desc = format!("{x_desc} (log scale)");
            fill(
                path,
                area,
                chart,
                (&desc, y_desc),
                Some(Ticks::Log(log_ticks(lo, hi))),
                y_rows,
                series,
            )
        }
    }
}

/// Which axis of a chart.
#[derive(Clone, Copy, PartialEq)]
pub(crate) enum Axis {
    X,
    Y,
}

/// Grid lines and 10^v labels of a log10 axis at `ticks` (log10 values), drawn by hand: the mesh
/// of such an axis is configured without labels (`x_labels(0)` or `y_labels(0)`).
pub(crate) fn log_axis<'a, DB: DrawingBackend + 'a>(
    path: &Path,
    area: &DrawingArea<DB, plotters::coord::Shift>,
    chart: &mut ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    axis: Axis,
    ticks: &[f64],
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    let labelled: Vec<(f64, String)> = ticks.iter().map(|t| (*t, log_label(t))).collect();
    labelled_axis(path, area, chart, axis, &labelled)
}

/// Grid lines and text labels at chosen positions of an axis, drawn by hand (a log10 axis, or the
/// named rows of an outcome chart); the mesh of that axis is configured without labels.
pub(crate) fn labelled_axis<'a, DB: DrawingBackend + 'a>(
    path: &Path,
    area: &DrawingArea<DB, plotters::coord::Shift>,
    chart: &mut ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    axis: Axis,
    ticks: &[(f64, String)],
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    let err = |e: &dyn std::fmt::Display| draw_err(path, e);
    let (x0, x1) = (chart.x_range().start, chart.x_range().end);
    let (y0, y1) = (chart.y_range().start, chart.y_range().end);
    let grid = RGBColor(200, 200, 200);
    let (bx, by) = area.get_base_pixel();
    for (t, label) in ticks {
        let t = *t;
        let (line, anchor, label_at) = match axis {
            Axis::X => (
                [(t, y0), (t, y1)],
                Pos::new(HPos::Center, VPos::Top),
                (t, y0),
            ),
            Axis::Y => (
                [(x0, t), (x1, t)],
                Pos::new(HPos::Right, VPos::Center),
                (x0, t),
            ),
        };
        chart
            .draw_series(LineSeries::new(line, grid.stroke_width(1)))
            .map_err(|e| err(&e))?;
        // Labels sit outside the plotting area, in the panel's own pixel frame.
        let (px, py) = chart.backend_coord(&label_at);
        let (dx, dy) = if axis == Axis::X { (0, 6) } else { (-6, 0) };
        let style = TextStyle::from((FAMILY, 15)).pos(anchor);
        area.draw(&Text::new(
            label.as_str(),
            (px - bx + dx, py - by + dy),
            style,
        ))
        .map_err(|e| err(&e))?;
    }
    Ok(())
}

/// Hand-drawn ticks of an x axis: a log10 axis's (log10 values), or chosen linear ones.
enum Ticks {
    Log(Vec<f64>),
    Chosen(Vec<f64>),
}

/// Mesh and series of one panel; `x_ticks` holds the hand-drawn ticks of the x axis (a log10
/// axis's grid lines and 10^v labels at 1, 2, 5 x 10^k, or chosen linear ones), `None` for
/// plotters' own; `y_rows` names the rows of a row chart.
fn fill<'a, DB: DrawingBackend + 'a>(
    path: &Path,
    area: &DrawingArea<DB, plotters::coord::Shift>,
    mut chart: ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    (x_desc, y_desc): (&str, &str),
    x_ticks: Option<Ticks>,
    y_rows: &[String],
    series: &[Series],
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    let err = |e: &dyn std::fmt::Display| draw_err(path, e);
    let mut mesh = chart.configure_mesh();
    mesh.x_desc(x_desc)
        .y_desc(y_desc)
        .y_label_formatter(&|v| tick(v))
        .label_style((FAMILY, 15))
        .axis_desc_style((FAMILY, 17));
    match &x_ticks {
        None => mesh.x_labels(8).x_label_formatter(&|v| tick(v)),
        Some(_) => mesh.x_labels(0).disable_x_mesh(),
    };
    if !y_rows.is_empty() {
        mesh.y_labels(0).disable_y_mesh();
    }
    mesh.draw().map_err(|e| err(&e))?;
    match &x_ticks {
        Some(Ticks::Log(at)) => log_axis(path, area, &mut chart, Axis::X, at)?,
        Some(Ticks::Chosen(at)) => {
            let labelled: Vec<(f64, String)> = at.iter().map(|v| (*v, tick(v))).collect();
            labelled_axis(path, area, &mut chart, Axis::X, &labelled)?
        }
        None => {}
    }
    if !y_rows.is_empty() {
        let rows: Vec<(f64, String)> = y_rows
            .iter()
            .enumerate()
            .map(|(k, name)| (k as f64, name.clone()))
            .collect();
        labelled_axis(path, area, &mut chart, Axis::Y, &rows)?;
    }
    for (_, pts, mark, c) in series {
        let colour = colour(*c);
        match mark {
            Mark::Line => {
                chart
                    .draw_series(LineSeries::new(pts.iter().copied(), colour.stroke_width(2)))
                    .map_err(|e| err(&e))?;
            }
            Mark::Points | Mark::Dots => {
                chart
                    .draw_series(PointSeries::of_element(
                        pts.iter().copied(),
                        if *mark == Mark::Dots { 7 } else { 5 },
                        colour.filled(),
                        &|p, s, st| Circle::new(p, s, st),
                    ))
                    .map_err(|e| err(&e))?;
                if *mark == Mark::Points {
                    chart
                        .draw_series(LineSeries::new(pts.iter().copied(), colour.stroke_width(1)))
                        .map_err(|e| err(&e))?;
                }
            }
            Mark::Rings => {
                chart
                    .draw_series(PointSeries::of_element(
                        pts.iter().copied(),
                        11,
                        colour.stroke_width(2),
                        &|p, s, st| Circle::new(p, s, st),
                    ))
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

/// The frame every panel shares: its title, margins and label areas.
pub(crate) fn builder<'a, 'b, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, plotters::coord::Shift>,
    title: &'b str,
) -> ChartBuilder<'a, 'b, DB> {
    let mut b = ChartBuilder::on(area);
    b.caption(title, (FAMILY, 24))
        .margin(14)
        .x_label_area_size(48)
        .y_label_area_size(72);
    b
}

/// [`builder`], with a label area wide enough for the names of `y_rows` (a row chart) when there
/// are any: about 8 pixels per character of the 15-pixel label font.
fn rows_builder<'a, 'b, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, plotters::coord::Shift>,
    title: &'b str,
    y_rows: &[String],
) -> ChartBuilder<'a, 'b, DB> {
    let mut b = builder(area, title);
    let longest = y_rows.iter().map(|r| r.chars().count()).max().unwrap_or(0);
    if longest > 0 {
        b.y_label_area_size((16 + 8 * longest as u32).max(72));
    }
    b
}

/// A figure file of `width` x `body_height` pixels below a colour key (a legend inside a panel
/// hides data): entry `k` of `labels` in colour `k`, `per_row` to a row, then an optional line of
/// black text. Returns the whole figure (to `present`) and the area below the key.
pub(crate) fn keyed_figure<'a>(
    path: &'a Path,
    (width, body_height): (u32, u32),
    labels: &[&str],
    per_row: usize,
    note: Option<&str>,
) -> Result<(Area<'a>, Area<'a>)> {
    let strip_h = key_height(labels.len(), per_row, note.is_some());
    let root = BitMapBackend::new(path, (width, body_height + strip_h)).into_drawing_area();
    let body = keyed_body(path, &root, labels, per_row, note)?;
    Ok((root, body))
}

/// Height in pixels of the colour key of [`keyed_figure`].
pub(crate) fn key_height(labels: usize, per_row: usize, note: bool) -> u32 {
    let rows = labels.div_ceil(per_row.max(1)) + usize::from(note);
    16 + 28 * rows as u32
}

/// Fills `root` (of any backend: PNG or SVG) white, draws the colour key of [`keyed_figure`] at its
/// top and returns the area below it.
pub(crate) fn keyed_body<DB: DrawingBackend>(
    path: &Path,
    root: &DrawingArea<DB, plotters::coord::Shift>,
    labels: &[&str],
    per_row: usize,
    note: Option<&str>,
) -> Result<DrawingArea<DB, plotters::coord::Shift>>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(|e| draw_err(path, e))?;
    let (strip, body) = root.split_vertically(key_height(labels.len(), per_row, note.is_some()));
    draw_key(path, &strip, labels, per_row, note)?;
    Ok(body)
}

/// A drawing area of a PNG figure.
pub(crate) type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;

/// Draws the key of [`keyed_figure`] into `strip` (as wide as the figure).
fn draw_key<DB: DrawingBackend>(
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
    fn log_ticks_are_one_two_five_and_terminate_where_plotters_looped() {
        // The d0 sweep 0.6..19.2 d_c with its margins, which hung plotters' log_scale().
        let (lo, hi) = (0.48f64.log10(), 24f64.log10());
        let labels: Vec<String> = log_ticks(lo, hi).iter().map(log_label).collect();
        assert_eq!(labels, ["0.5", "1", "2", "5", "10", "20"]);
        // Many decades: whole decades only; a sliver of a decade: its ends.
        let wide = log_ticks(-8.0, 2.0);
        assert_eq!(wide.len(), 11);
        assert_eq!(log_label(&wide[0]), "1e-8");
        assert_eq!(log_ticks(0.31, 0.32), [0.31, 0.32]);
        assert!(log_ticks(1.0, 1.0).is_empty() && log_ticks(f64::NAN, 1.0).is_empty());
    }

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
