//! The outcome map of a d* search (and of the DEM-vs-MD comparison): one row per series (a seed, a
//! discretisation, a side), each run a mark at its junction size (filled red: a wear particle detached;
//! open blue: plastic smoothing), the brackets shaded, and reference sizes (eq 22) as dashed lines.

use std::path::Path;

use plotters::prelude::*;
use wear::Outcome;

use super::chart::range;
use super::style::{colour, draw_err, ensure_font, tick, FAMILY};
use crate::error::Result;

/// One row of the map.
#[derive(Debug, Clone, PartialEq)]
pub struct OutcomeRow {
    pub label: String,
    /// (size, outcome) of each run.
    pub points: Vec<(f64, Outcome)>,
}

/// The x range that shows every mark, bracket end and reference.
pub fn x_extent(
    rows: &[OutcomeRow],
    brackets: &[(String, [Option<f64>; 2])],
    refs: &[(String, f64)],
) -> std::ops::Range<f64> {
    let xs = rows
        .iter()
        .flat_map(|r| r.points.iter().map(|p| p.0))
        .chain(brackets.iter().flat_map(|b| b.1.iter().flatten().copied()))
        .chain(refs.iter().map(|r| r.1));
    range(xs)
}

/// Draws the map: `rows` bottom to top, each bracket (lower, upper) shaded in its own colour (an open
/// end reaches the axis), each reference a dashed vertical line; a key above names them. A path
/// ending in `.svg` gets an SVG, any other a PNG.
pub fn draw_outcomes(
    path: &Path,
    x_label: &str,
    rows: &[OutcomeRow],
    brackets: &[(String, [Option<f64>; 2])],
    refs: &[(String, f64)],
) -> Result<()> {
    ensure_font()?;
    let key_rows = 1 + brackets.len() + refs.len();
    let size = (
        1200,
        140 + 48 * rows.len().max(2) as u32 + 26 * key_rows as u32,
    );
    if path.extension().is_some_and(|e| e == "svg") {
        let root = SVGBackend::new(path, size).into_drawing_area();
        draw_on(root, path, x_label, rows, brackets, refs)
    } else {
        let root = BitMapBackend::new(path, size).into_drawing_area();
        draw_on(root, path, x_label, rows, brackets, refs)
    }
}

fn draw_on<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    path: &Path,
    x_label: &str,
    rows: &[OutcomeRow],
    brackets: &[(String, [Option<f64>; 2])],
    refs: &[(String, f64)],
) -> Result<()> {
    let err = |e: &dyn std::fmt::Display| draw_err(path, e);
    let key_rows = 1 + brackets.len() + refs.len();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let (key, body) = root.split_vertically(16 + 26 * key_rows as u32);
    // The key: marks, then brackets and references in their colours.
    let mut y = 8;
    key.draw(&Circle::new((30, y + 9), 7, colour(3).filled()))
        .map_err(|e| err(&e))?;
    key.draw(&Text::new("wear particle", (44, y), (FAMILY, 18)))
        .map_err(|e| err(&e))?;
    key.draw(&Circle::new((230, y + 9), 7, colour(0).stroke_width(2)))
        .map_err(|e| err(&e))?;
    key.draw(&Text::new("plastic smoothing", (244, y), (FAMILY, 18)))
        .map_err(|e| err(&e))?;
    for (k, (label, _)) in brackets.iter().enumerate() {
        y += 26;
        let c = colour(k + 4).mix(0.25);
        key.draw(&Rectangle::new([(20, y + 2), (40, y + 16)], c.filled()))
            .map_err(|e| err(&e))?;
        key.draw(&Text::new(
            format!("{label} (shaded)"),
            (50, y),
            (FAMILY, 18),
        ))
        .map_err(|e| err(&e))?;
    }
    for (k, (label, v)) in refs.iter().enumerate() {
        y += 26;
        let c = colour(k + 1);
        key.draw(&PathElement::new(
            [(16, y + 9), (42, y + 9)],
            c.stroke_width(2),
        ))
        .map_err(|e| err(&e))?;
        key.draw(&Text::new(
            format!("{label}: {}", tick(v)),
            (50, y),
            (FAMILY, 18).into_font().color(&c),
        ))
        .map_err(|e| err(&e))?;
    }
    let xr = x_extent(rows, brackets, refs);
    let n = rows.len().max(1) as f64;
    let labels: Vec<String> = rows.iter().map(|r| r.label.clone()).collect();
    let mut chart = ChartBuilder::on(&body)
        .margin(14)
        .x_label_area_size(48)
        .y_label_area_size(300)
        .build_cartesian_2d(xr.clone(), -0.6..(n - 0.4))
        .map_err(|e| err(&e))?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .x_label_formatter(&|v| tick(v))
        .y_labels(rows.len().max(1))
        .y_label_formatter(&|v| {
            let k = v.round();
            if (v - k).abs() < 1e-6 && k >= 0.0 {
                labels.get(k as usize).cloned().unwrap_or_default()
            } else {
                String::new()
            }
        })
        .disable_y_mesh()
        .label_style((FAMILY, 15))
        .axis_desc_style((FAMILY, 17))
        .draw()
        .map_err(|e| err(&e))?;
    for (k, (_, [lo, hi])) in brackets.iter().enumerate() {
        let (a, b) = (lo.unwrap_or(xr.start), hi.unwrap_or(xr.end));
        chart
            .draw_series(std::iter::once(Rectangle::new(
                [(a, -0.6), (b, n - 0.4)],
                colour(k + 4).mix(0.25).filled(),
            )))
            .map_err(|e| err(&e))?;
    }
    for (k, (_, v)) in refs.iter().enumerate() {
        chart
            .draw_series(DashedLineSeries::new(
                [(*v, -0.6), (*v, n - 0.4)],
                8,
                5,
                colour(k + 1).stroke_width(2),
            ))
            .map_err(|e| err(&e))?;
    }
    for (row, r) in rows.iter().enumerate() {
        for &(x, o) in &r.points {
            let at = (x, row as f64);
            let mark = match o {
                Outcome::WearParticle => Circle::new(at, 7, colour(3).filled()),
                Outcome::PlasticSmoothing => Circle::new(at, 7, colour(0).stroke_width(2)),
            };
            chart
                .draw_series(std::iter::once(mark))
                .map_err(|e| err(&e))?;
        }
    }
    root.present().map_err(|e| err(&e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_extent_holds_marks_brackets_and_references() {
        let rows = [OutcomeRow {
            label: "a".into(),
            points: vec![
                (10.0, Outcome::PlasticSmoothing),
                (20.0, Outcome::WearParticle),
            ],
        }];
        let r = x_extent(
            &rows,
            &[("b".into(), [Some(10.0), None])],
            &[("eq 22".into(), 30.0)],
        );
        assert!(r.start < 10.0 && r.end > 30.0, "{r:?}");
    }
}
