//! Figures of a junction run (paper 000 Figs. 9-10 and A.10):
//! - `snapshot.png`: side views of the first and last frames, particles drawn as discs coloured by the
//!   body they initially belonged to (lower blue, upper orange, as the paper's figures), junction
//!   members in a lighter tint of their body's colour, wall particles darker. A side view of a 3D
//!   sample would show the front of the solids and hide the junction, so each view is a slice about
//!   the box's mid-plane along z (through a column's axis; across a ridge, which spans the width): the
//!   particles whose centres lie within D/2 of it along z, drawn back to front;
//! - `force.png`: the tangential (x) and normal (y) pair force on the top wall against the slide
//!   distance.

use std::path::Path;

use dem::observe::ForceSample;
use dem::scenario::junction::Snapshot;
use plotters::prelude::*;

use super::chart::{keyed_figure, panel, Mark, Scale, Series};
use super::style::{draw_err, ensure_font, FAMILY};
use crate::error::Result;

/// One disc of a side view, in box coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Disc {
    pub x: f64,
    pub y: f64,
    pub r: f64,
    /// Depth along z (larger is farther from the viewer, drawn first).
    pub z: f64,
    pub rgb: (u8, u8, u8),
}

const LOWER: (u8, u8, u8) = (31, 119, 180);
const UPPER: (u8, u8, u8) = (255, 127, 14);

fn tint((r, g, b): (u8, u8, u8), towards: u8, f: f64) -> (u8, u8, u8) {
    let mix = |c: u8| (c as f64 + (towards as f64 - c as f64) * f).round() as u8;
    (mix(r), mix(g), mix(b))
}

/// The discs of a slice of `s` around `axis_z` of half-width `half`, back to front.
pub fn slice(s: &Snapshot, axis_z: f64, half: f64) -> Vec<Disc> {
    let lz = s.hi[2] - s.lo[2];
    let mut discs: Vec<Disc> = (0..s.pos.len())
        .filter_map(|i| {
            let p = s.pos[i];
            // Minimum-image distance to the axis along the periodic z.
            let dz = p[2] - axis_z - lz * ((p[2] - axis_z) / lz).round();
            (dz.abs() <= half).then(|| {
                let base = if s.body[i] == 0 { LOWER } else { UPPER };
                let rgb = match s.role[i] {
                    1 => tint(base, 255, 0.45),
                    2 => tint(base, 0, 0.45),
                    _ => base,
                };
                Disc {
                    x: p[0],
                    y: p[1],
                    r: s.radius[i],
                    z: dz,
                    rgb,
                }
            })
        })
        .collect();
    discs.sort_by(|a, b| b.z.total_cmp(&a.z));
    discs
}

/// Draws the first and last frames side by side (`titles` under each); `length_unit` follows a
/// length as written (" nm", or "" for reduced units).
pub fn draw_snapshots(
    path: &Path,
    views: [(&Snapshot, String); 2],
    axis_z: f64,
    half: f64,
    length_unit: &str,
) -> Result<()> {
    ensure_font()?;
    let s0 = views[0].0;
    let (lx, ly) = (s0.hi[0] - s0.lo[0], s0.hi[1] - s0.lo[1]);
    let scale = (700.0 / lx).min(600.0 / ly);
    let slices: Vec<Vec<Disc>> = views.iter().map(|(s, _)| slice(s, axis_z, half)).collect();
    // Discs reach beyond the box by up to their radius (walls, and the periodic direction):
    // a margin that wide keeps them off the title and the scale bar.
    let reach = slices
        .iter()
        .flatten()
        .map(|d| d.r * scale)
        .fold(0.0, f64::max)
        .ceil() as i32;
    // The top wall rises as the junction dilates, past the box of the first frame: each view is
    // drawn from its highest disc down, and the figure is as tall as the taller view.
    let tops: Vec<f64> = views
        .iter()
        .zip(&slices)
        .map(|((s, _), discs)| discs.iter().map(|d| d.y).fold(s.hi[1], f64::max))
        .collect();
    let bottoms: Vec<f64> = views
        .iter()
        .zip(&slices)
        .map(|((s, _), discs)| discs.iter().map(|d| d.y).fold(s.lo[1], f64::min))
        .collect();
    let tall = tops
        .iter()
        .zip(&bottoms)
        .map(|(t, b)| t - b)
        .fold(ly, f64::max);
    let (left, top) = (20 + reach, 40 + reach);
    let w = (lx * scale) as u32 + 2 * left as u32;
    let h = (tall * scale) as u32 + (top + reach + 34) as u32;
    let root = BitMapBackend::new(path, (2 * w, h)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| draw_err(path, e))?;
    let panels = root.split_evenly((1, 2));
    for (((area, (s, title)), discs), y_top) in panels.iter().zip(views).zip(slices).zip(tops) {
        let px = |x: f64, y: f64| {
            (
                left + ((x - s.lo[0]) * scale) as i32,
                top + ((y_top - y) * scale) as i32,
            )
        };
        area.draw(&Text::new(title, (20, 12), (FAMILY, 20)))
            .map_err(|e| draw_err(path, e))?;
        let frame = [px(s.lo[0], s.hi[1]), px(s.hi[0], s.lo[1])];
        area.draw(&Rectangle::new(frame, BLACK.stroke_width(1)))
            .map_err(|e| draw_err(path, e))?;
        for d in discs {
            let c = RGBColor(d.rgb.0, d.rgb.1, d.rgb.2);
            let r = ((d.r * scale).round() as u32).max(1);
            area.draw(&Circle::new(px(d.x, d.y), r, c.filled()))
                .map_err(|e| draw_err(path, e))?;
            area.draw(&Circle::new(
                px(d.x, d.y),
                r,
                BLACK.mix(0.35).stroke_width(1),
            ))
            .map_err(|e| draw_err(path, e))?;
        }
        let bar = format!("box {:.0}{length_unit} wide", lx);
        let (x0, y0) = px(s.lo[0], s.lo[1]);
        area.draw(&Text::new(bar, (x0, y0 + reach + 8), (FAMILY, 16)))
            .map_err(|e| draw_err(path, e))?;
    }
    root.present().map_err(|e| draw_err(path, e))
}

/// Points of a curve.
pub type Points = Vec<(f64, f64)>;

/// The force curves: (slide, F_x) and (slide, F_y) of the top wall.
pub fn force_series(samples: &[ForceSample]) -> (Points, Points) {
    let fx = samples
        .iter()
        .map(|s| (s.displacement[0], s.force[0]))
        .collect();
    let fy = samples
        .iter()
        .map(|s| (s.displacement[0], s.force[1]))
        .collect();
    (fx, fy)
}

/// Draws the top wall's tangential and normal pair force against the slide distance.
pub fn draw_force(path: &Path, samples: &[ForceSample], units: (&str, &str)) -> Result<()> {
    ensure_font()?;
    let (fx, fy) = force_series(samples);
    let labels = [
        "tangential F_x on the top wall",
        "normal F_y on the top wall",
    ];
    let (root, body) = keyed_figure(path, (1100, 520), &labels, 2, None)?;
    let series: Vec<Series> = vec![
        (String::new(), fx, Mark::Line, 0),
        (String::new(), fy, Mark::Line, 1),
    ];
    let x = format!("slide distance ({})", units.0);
    let y = format!("pair force on the top wall ({})", units.1);
    panel(
        path,
        &body,
        ("junction shear (paper 000 section 4)", &x, &y),
        Scale::Linear,
        &series,
    )?;
    root.present().map_err(|e| draw_err(path, e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_slice_keeps_the_axis_neighbourhood_across_the_period_back_to_front() {
        let s = Snapshot {
            step: 0,
            lo: [0.0; 3],
            hi: [10.0, 10.0, 10.0],
            pos: vec![
                [1.0, 1.0, 5.0],
                [2.0, 2.0, 9.5],
                [3.0, 3.0, 0.2],
                [4.0, 4.0, 5.9],
            ],
            radius: vec![0.5; 4],
            body: vec![0, 1, 0, 1],
            role: vec![0, 1, 2, 0],
        };
        // Axis at z = 9.8, half-width 1: particles 1 (dz -0.3) and 2 (dz +0.4 across the period).
        let d = slice(&s, 9.8, 1.0);
        assert_eq!(d.len(), 2);
        assert_eq!((d[0].x, d[1].x), (3.0, 2.0));
        assert!((d[0].z - 0.4).abs() < 1e-12);
        // Colours: a junction member is lighter than its body, a wall particle darker.
        assert_eq!(d[1].rgb, tint(UPPER, 255, 0.45));
        assert_eq!(d[0].rgb, tint(LOWER, 0, 0.45));
    }

    #[test]
    fn force_series_follow_the_samples() {
        let s = ForceSample {
            step: 10,
            time: 1.0,
            force: [2.0, -3.0, 0.0],
            displacement: [0.5, 0.0, 0.0],
        };
        assert_eq!(force_series(&[s]), (vec![(0.5, 2.0)], vec![(0.5, -3.0)]));
    }
}
