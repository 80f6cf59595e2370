//! A report figure as plain data: panels of named series, each either a simulation result (solid) or
//! a reference (dashed: a formula or a paper's value). The same data is drawn as SVG (inlined in the
//! HTML) and PNG, and written as the CSV behind the figure, so tests read the numbers a figure plots
//! rather than its pixels.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::error::Result;
use crate::figures::chart::{row_panel, swatch, Mark, Scale};
use crate::figures::style::{colour, draw_err, ensure_font, FAMILY};
use crate::ValidationError;

/// How a series was obtained, which decides how it is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Measured by the workbench, drawn as a solid line.
    Simulation,
    /// Measured by the workbench at discrete points: dots joined by a solid line.
    SimulationPoints,
    /// Outcomes of separate runs: dots that no line joins.
    SimulationMarks,
    /// A formula or a paper's value: dashed.
    Reference,
    /// A paper's outcomes at discrete points: hollow circles (a run's dot sits inside its ring).
    ReferenceMarks,
}

impl Kind {
    fn mark(self) -> Mark {
        match self {
            Kind::Simulation => Mark::Line,
            Kind::SimulationPoints => Mark::Points,
            Kind::SimulationMarks => Mark::Dots,
            Kind::Reference => Mark::Target,
            Kind::ReferenceMarks => Mark::Rings,
        }
    }
}

impl Kind {
    /// The name in the CSV.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Simulation | Kind::SimulationPoints | Kind::SimulationMarks => "simulation",
            Kind::Reference | Kind::ReferenceMarks => "reference",
        }
    }
}

/// One curve.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    pub label: String,
    pub kind: Kind,
    pub points: Vec<(f64, f64)>,
}

impl Series {
    pub fn new(label: impl Into<String>, kind: Kind, points: Vec<(f64, f64)>) -> Self {
        Series {
            label: label.into(),
            kind,
            points,
        }
    }
}

/// One panel: its title, axis labels with units, and series.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Panel {
    pub title: String,
    /// Axis label with its unit, e.g. "delta_N / delta_e (-)".
    pub x: String,
    pub y: String,
    pub log_x: bool,
    /// Names of the rows 0, 1, ... of a row chart (outcomes per run), written on the y axis in place
    /// of numbers; empty for a numeric y axis.
    pub y_rows: Vec<String>,
    /// Where the x axis has its ticks when they are chosen (a count such as threads, which has no
    /// 1.2); empty for the automatic ticks.
    pub x_ticks: Vec<f64>,
    pub series: Vec<Series>,
}

impl Panel {
    pub fn new(title: &str, x: &str, y: &str) -> Self {
        Panel {
            title: title.into(),
            x: x.into(),
            y: y.into(),
            log_x: false,
            y_rows: Vec::new(),
            x_ticks: Vec::new(),
            series: Vec::new(),
        }
    }

    /// Adds a series (builder style).
    pub fn with(mut self, label: impl Into<String>, kind: Kind, points: Vec<(f64, f64)>) -> Self {
        self.series.push(Series::new(label, kind, points));
        self
    }

    pub fn log_x(mut self) -> Self {
        self.log_x = true;
        self
    }

    /// Ticks of the x axis at `at` only (builder style; a linear x axis).
    pub fn x_ticks(mut self, at: Vec<f64>) -> Self {
        self.x_ticks = at;
        self
    }

    /// A row chart: the y values 0, 1, ... are the rows `names` (builder style).
    pub fn rows(mut self, names: Vec<String>) -> Self {
        self.y_rows = names;
        self
    }
}

/// A figure of the report.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// File stem (`figures/<name>.svg`, `.png`, `.csv`).
    pub name: String,
    /// One sentence under the figure.
    pub caption: String,
    /// The paper figure it mirrors, e.g. "paper 000 Fig. 2".
    pub mirrors: String,
    pub panels: Vec<Panel>,
    /// Panels per row.
    pub columns: usize,
    /// A line drawn in the figure itself (e.g. the quick profile's notice); empty for none.
    pub banner: String,
}

impl Figure {
    pub fn new(name: &str, mirrors: &str, caption: &str) -> Self {
        Figure {
            name: name.into(),
            caption: caption.into(),
            mirrors: mirrors.into(),
            panels: Vec::new(),
            columns: 2,
            banner: String::new(),
        }
    }

    pub fn panel(mut self, p: Panel) -> Self {
        self.panels.push(p);
        self
    }

    /// The data behind the figure: one row per point, `panel,series,kind,x,y` (numbers in their
    /// shortest round-trip form, so a reader gets the plotted values to the bit).
    pub fn csv(&self) -> String {
        let mut s = String::from("panel,series,kind,x,y\n");
        for p in &self.panels {
            for ser in &p.series {
                for (x, y) in &ser.points {
                    s += &format!(
                        "{},{},{},{x:?},{y:?}\n",
                        csv_field(&p.title),
                        csv_field(&ser.label),
                        ser.kind.name()
                    );
                }
            }
        }
        s
    }

    /// Distinct series labels in order of appearance, each with the marks it is drawn with (a
    /// simulated and a reference series of one label share its colour and differ by the mark): one
    /// colour per label across panels.
    fn key(&self) -> Vec<(&str, Vec<Mark>)> {
        let mut key: Vec<(&str, Vec<Mark>)> = Vec::new();
        for p in &self.panels {
            for s in &p.series {
                let mark = s.kind.mark();
                match key.iter_mut().find(|(l, _)| *l == s.label) {
                    Some((_, marks)) if !marks.contains(&mark) => marks.push(mark),
                    Some(_) => {}
                    None => key.push((&s.label, vec![mark])),
                }
            }
        }
        for (_, marks) in &mut key {
            // Simulation first, then the reference, as the note under the key reads.
            marks.sort_by_key(|m| matches!(m, Mark::Target | Mark::Rings));
        }
        key
    }

    /// Key entries per row.
    fn per_row(&self) -> usize {
        (self.size_width() / KEY_ENTRY_WIDTH).max(1) as usize
    }

    fn size_width(&self) -> u32 {
        if self.columns.clamp(1, self.panels.len().max(1)) == 1 {
            960
        } else {
            1300
        }
    }

    fn size(&self) -> (u32, u32, u32) {
        let cols = self.columns.clamp(1, self.panels.len().max(1));
        let rows = self.panels.len().div_ceil(cols).max(1) as u32;
        let key_rows = self.key().len().div_ceil(self.per_row()) as u32 + 3;
        let strip = 12 + 26 * key_rows;
        let width = if cols == 1 { 960 } else { 1300 };
        (width, strip, strip + 430 * rows)
    }

    /// Draws the figure onto `root` (either backend); `path` names it in errors.
    fn draw_on<DB: DrawingBackend>(&self, path: &Path, root: DrawingArea<DB, Shift>) -> Result<()>
    where
        DB::ErrorType: 'static,
    {
        ensure_font()?;
        root.fill(&WHITE).map_err(|e| draw_err(path, e))?;
        let (_, strip_h, _) = self.size();
        let (strip, body) = root.split_vertically(strip_h);
        let key = self.key();
        self.draw_key(path, &strip, &key)?;
        let cols = self.columns.clamp(1, self.panels.len().max(1));
        let rows = self.panels.len().div_ceil(cols).max(1);
        let areas = body.split_evenly((rows, cols));
        for (area, p) in areas.iter().zip(&self.panels) {
            let scale = if p.log_x { Scale::Log } else { Scale::Linear };
            let series: Vec<_> = p
                .series
                .iter()
                .map(|s| {
                    let c = key.iter().position(|(l, _)| *l == s.label).unwrap_or(0);
                    (s.label.clone(), scale.map(&s.points), s.kind.mark(), c)
                })
                .collect();
            row_panel(
                path,
                area,
                (&p.title, &p.x, &p.y),
                scale,
                (&p.x_ticks, &p.y_rows),
                &series,
            )?;
        }
        root.present().map_err(|e| draw_err(path, e))
    }

    /// The key above the panels: a line sample (solid or dashed) in each series' colour and its
    /// label, then what the figure mirrors and the banner.
    fn draw_key<DB: DrawingBackend>(
        &self,
        path: &Path,
        strip: &DrawingArea<DB, Shift>,
        key: &[(&str, Vec<Mark>)],
    ) -> Result<()>
    where
        DB::ErrorType: 'static,
    {
        let err = |e: &dyn std::fmt::Display| draw_err(path, e);
        let width = strip.dim_in_pixel().0 as i32 - 40;
        let per_row = self.per_row();
        let col = width / per_row as i32;
        let left = TextStyle::from((FAMILY, 16)).pos(Pos::new(HPos::Left, VPos::Center));
        for (k, (label, marks)) in key.iter().enumerate() {
            let x = 20 + col * (k % per_row) as i32;
            let y = 20 + 26 * (k / per_row) as i32;
            let c = colour(k);
            for (n, mark) in marks.iter().take(2).enumerate() {
                swatch(strip, *mark, (x + 28 * n as i32, y), c).map_err(|e| err(&e))?;
            }
            strip
                .draw(&Text::new(label.to_string(), (x + 56, y), left.clone()))
                .map_err(|e| err(&e))?;
        }
        let y = 20 + 26 * key.len().div_ceil(per_row) as i32;
        let notes = [
            "solid lines and dots: simulation (the workbench); dashed lines and rings: reference (formula or paper, named in the panel title)".to_string(),
            format!("mirrors {}", self.mirrors),
        ];
        for (k, note) in notes.into_iter().enumerate() {
            strip
                .draw(&Text::new(note, (20, y + 26 * k as i32), left.clone()))
                .map_err(|e| err(&e))?;
        }
        let y = y + 26;
        if !self.banner.is_empty() {
            let style = TextStyle::from((FAMILY, 16))
                .pos(Pos::new(HPos::Left, VPos::Center))
                .color(&RED);
            strip
                .draw(&Text::new(self.banner.clone(), (20, y + 26), style))
                .map_err(|e| err(&e))?;
        }
        Ok(())
    }

    /// The figure as an SVG document.
    pub fn svg(&self) -> Result<String> {
        let (w, _, h) = self.size();
        let mut buf = String::new();
        let path = PathBuf::from(format!("{}.svg", self.name));
        {
            let root = SVGBackend::with_string(&mut buf, (w, h)).into_drawing_area();
            self.draw_on(&path, root)?;
        }
        Ok(buf)
    }

    /// Writes `<name>.svg`, `<name>.png` and `<name>.csv` into `dir`; returns the SVG text.
    pub fn write(&self, dir: &Path) -> Result<String> {
        std::fs::create_dir_all(dir).map_err(|e| ValidationError::io(dir, e))?;
        let svg = self.svg()?;
        let p = dir.join(format!("{}.svg", self.name));
        std::fs::write(&p, &svg).map_err(|e| ValidationError::io(&p, e))?;
        let p = dir.join(format!("{}.csv", self.name));
        std::fs::write(&p, self.csv()).map_err(|e| ValidationError::io(&p, e))?;
        let p = dir.join(format!("{}.png", self.name));
        let (w, _, h) = self.size();
        let root = BitMapBackend::new(&p, (w, h)).into_drawing_area();
        self.draw_on(&p, root)?;
        Ok(svg)
    }
}

/// Width of one key entry (line samples and label), pixels.
const KEY_ENTRY_WIDTH: u32 = 420;

/// A CSV field: quoted when it holds a comma or a quote.
pub fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// Splits one CSV line into fields (the quoting of [`csv_field`]).
pub fn csv_split(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                cur.push('"');
                chars.next();
            }
            ('"', _) => quoted = !quoted,
            (',', false) => out.push(std::mem::take(&mut cur)),
            _ => cur.push(c),
        }
    }
    out.push(cur);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fig() -> Figure {
        Figure::new("t", "paper 000 Fig. 2", "test").panel(
            Panel::new("a, b", "x (-)", "y (-)")
                .with("sim", Kind::Simulation, vec![(0.0, 1.0), (1.0, 0.1 + 0.2)])
                .with("eq \"3\"", Kind::Reference, vec![(0.0, 1.0)]),
        )
    }

    #[test]
    fn csv_round_trips_labels_and_numbers_to_the_bit() {
        let csv = fig().csv();
        let rows: Vec<Vec<String>> = csv.lines().skip(1).map(csv_split).collect();
        assert_eq!(rows.len(), 3);
        assert_eq!(rows[0][0], "a, b");
        assert_eq!(rows[2][1], "eq \"3\"");
        assert_eq!(rows[2][2], "reference");
        assert_eq!(rows[1][4].parse::<f64>().unwrap(), 0.1 + 0.2);
    }

    #[test]
    fn svg_has_the_key_and_the_mirrored_figure() {
        let svg = fig().svg().unwrap();
        assert!(svg.starts_with("<svg"));
        assert!(svg.contains("mirrors paper 000 Fig. 2"));
        assert!(svg.contains("stroke-dasharray") || svg.matches("<polyline").count() >= 2);
    }

    #[test]
    fn a_row_chart_names_its_rows_instead_of_numbering_them() {
        let rows = |names: Vec<String>| {
            Figure::new("r", "issue 17", "test")
                .panel(
                    Panel::new("outcomes", "D (nm)", "run")
                        .with(
                            "wear",
                            Kind::SimulationMarks,
                            vec![(10.0, 0.0), (20.0, 1.0)],
                        )
                        .rows(names),
                )
                .svg()
                .unwrap()
        };
        let named = rows(vec!["MD seed 7".into(), "DEM d0 0.5 seed 3".into()]);
        assert!(named.contains("MD seed 7") && named.contains("DEM d0 0.5 seed 3"));
        // The numeric ticks of the y axis give way to the names: 0.5 labels a numbered axis only.
        let numbered = rows(vec![]);
        let half = ">\n0.5\n<";
        assert!(numbered.contains(half) && !named.contains(half));
        assert!(!numbered.contains("MD seed 7"));
    }

    #[test]
    fn chosen_x_ticks_replace_the_automatic_ones() {
        let threads = |at: Vec<f64>| {
            Figure::new("p", "DESIGN.md 8", "test")
                .panel(
                    Panel::new("rate", "threads (-)", "rate")
                        .with(
                            "cgdem",
                            Kind::SimulationPoints,
                            vec![(1.0, 5.0), (2.0, 9.0)],
                        )
                        .x_ticks(at),
                )
                .svg()
                .unwrap()
        };
        let (chosen, automatic) = (threads(vec![1.0, 2.0]), threads(vec![]));
        let label = |v: &str| format!(">\n{v}\n<");
        assert!(automatic.contains(&label("1.2")) && !chosen.contains(&label("1.2")));
        assert!(chosen.contains(&label("1")) && chosen.contains(&label("2")));
    }
}
