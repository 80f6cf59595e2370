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

use plotters::prelude::*;

use super::chart::{key_height, keyed_body, panel, Mark, Scale, Series};
use super::style::{draw_err, ensure_font};
use crate::error::{Result, ValidationError};

mod impact;
mod scratch;
#[cfg(test)]
mod tests;

pub use impact::{fig12, fig4, fig5, fig6, fig7, impact_figures};
pub use scratch::{fig10, fig13, fig3, fig8_9, scratch_figures};

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
