//! Figures of a sliding run (paper 004 Figs. 3-5):
//! - `profiles.png`: the steady velocity profile (Fig. 4a) and density profile with its
//!   Savitzky-Golay filter and the fitted Gaussian (Fig. 4b), over y / H on the horizontal axis; the
//!   TBL's boundaries as dashed verticals (the paper shades the band);
//! - `h_tbl.png`: h_TBL / H per window and its moving average against the slide (Fig. 5);
//! - `snapshot.png`: side views of the first and last frames, every particle (the system is
//!   quasi-2D, B = 3 d0) coloured by its initial height, as Fig. 3.

use std::path::Path;

use dem::scenario::sliding::{MaterialStrength, MeasuredPeak, SlidingResult};
use plotters::prelude::*;
use wear::tbl::moving_average;

use super::chart::{keyed_figure, panel, Mark, Scale, Series};
use super::style::{draw_err, ensure_font, FAMILY};
use crate::error::Result;

fn bounds_series(r: &SlidingResult, top: f64) -> Vec<Series> {
    r.layer.bounds.map_or_else(Vec::new, |b| {
        vec![
            (
                String::new(),
                vec![(b.lo, 0.0), (b.lo, top)],
                Mark::Target,
                3,
            ),
            (
                String::new(),
                vec![(b.hi, 0.0), (b.hi, top)],
                Mark::Target,
                3,
            ),
        ]
    })
}

/// Draws the steady velocity and density profiles.
pub fn draw_profiles(path: &Path, r: &SlidingResult) -> Result<()> {
    ensure_font()?;
    let labels = [
        "velocity / v0 (left), density / rho_0 (right)",
        "Savitzky-Golay filtered (order 3, 7 samples)",
        "least-squares Gaussian (its minimum is rho_TBL)",
        "TBL boundaries (0.1 v0 and 0.9 v0)",
    ];
    let (root, body) = keyed_figure(path, (1400, 560), &labels, 2, None)?;
    let halves = body.split_evenly((1, 2));
    let y = r.profile.centres();
    let u: Vec<(f64, f64)> = y
        .iter()
        .zip(&r.profile.velocity_over_v0)
        .filter_map(|(&y, v)| v.map(|v| (y, v)))
        .collect();
    let mut left: Vec<Series> = vec![(String::new(), u, Mark::Line, 0)];
    left.extend(bounds_series(r, 1.0));
    panel(
        path,
        &halves[0],
        ("steady velocity profile (Fig. 4a)", "y / H", "v_x / v0"),
        Scale::Linear,
        &left,
    )?;
    let raw: Vec<(f64, f64)> = y
        .iter()
        .zip(&r.profile.density)
        .map(|(&y, d)| (y, d / r.rho0))
        .collect();
    let filt: Vec<(f64, f64)> = y
        .iter()
        .cloned()
        .zip(r.layer.density_filtered.iter().cloned())
        .collect();
    let fit: Vec<(f64, f64)> = y.iter().map(|&y| (y, r.layer.fit.at(y))).collect();
    let top = raw.iter().fold(1.0f64, |a, p| a.max(p.1));
    let mut right: Vec<Series> = vec![
        (String::new(), raw, Mark::Line, 0),
        (String::new(), filt, Mark::Line, 1),
        (String::new(), fit, Mark::Target, 2),
    ];
    right.extend(bounds_series(r, top));
    let title = format!(
        "steady density profile (Fig. 4b): rho_TBL = {:.3} rho_0",
        r.rho_tbl
    );
    panel(
        path,
        &halves[1],
        (&title, "y / H", "density / rho_0"),
        Scale::Linear,
        &right,
    )?;
    root.present().map_err(|e| draw_err(path, e))
}

/// Draws h_TBL / H per window and its moving average over `window` windows against the slide / L.
pub fn draw_h_tbl(path: &Path, r: &SlidingResult, length: f64, window: usize) -> Result<()> {
    ensure_font()?;
    let labels = [
        "h_TBL / H per window",
        "moving average",
        "windows whose TBL lies against a rigid body",
    ];
    let (root, body) = keyed_figure(path, (1100, 520), &labels, 2, None)?;
    let pts: Vec<(f64, f64)> = r
        .windows
        .iter()
        .filter_map(|w| w.h_tbl.map(|h| (w.slide / length, h)))
        .collect();
    let h: Vec<f64> = pts.iter().map(|p| p.1).collect();
    let avg: Vec<(f64, f64)> = pts
        .iter()
        .zip(moving_average(&h, window))
        .map(|(p, m)| (p.0, m))
        .collect();
    let at_body: Vec<(f64, f64)> = r
        .windows
        .iter()
        .zip(&r.windows_at_body)
        .filter(|(_, &b)| b)
        .filter_map(|(w, _)| w.h_tbl.map(|h| (w.slide / length, h)))
        .collect();
    let series: Vec<Series> = vec![
        (String::new(), pts, Mark::Points, 0),
        (String::new(), avg, Mark::Line, 1),
        (String::new(), at_body, Mark::Dots, 2),
    ];
    let title = format!(
        "TBL thickness over time (Fig. 5), regime: {}",
        r.regime.label()
    );
    panel(
        path,
        &body,
        (&title, "slide distance / L", "h_TBL / H"),
        Scale::Linear,
        &series,
    )?;
    root.present().map_err(|e| draw_err(path, e))
}

/// Draws the layer's wear particles against the slide (Fig. 3a and 3c): the largest one's equivalent
/// diameter over L (0 in a window without a loose cluster of `min_members`) and the detached fraction
/// of the layer, per window (`dem::scenario::sliding::WearRecord`).
pub fn draw_wear_particles(
    path: &Path,
    r: &SlidingResult,
    length: f64,
    min_members: usize,
) -> Result<()> {
    ensure_font()?;
    let labels = [
        "largest wear particle: equivalent diameter / L",
        "detached fraction of the layer",
    ];
    let (root, body) = keyed_figure(path, (1100, 520), &labels, 2, None)?;
    let size: Vec<(f64, f64)> = r
        .wear
        .iter()
        .map(|w| {
            let d = w.particles.wear_particle_diameter(min_members);
            (w.slide / length, d / length)
        })
        .collect();
    let detached: Vec<(f64, f64)> = r
        .wear
        .iter()
        .map(|w| (w.slide / length, w.particles.detached))
        .collect();
    let series: Vec<Series> = vec![
        (String::new(), size, Mark::Line, 0),
        (String::new(), detached, Mark::Points, 1),
    ];
    let title = format!(
        "Wear particles over time (Fig. 3), regime: {}",
        r.regime.label()
    );
    panel(
        path,
        &body,
        (&title, "slide distance / L", "diameter / L, fraction"),
        Scale::Linear,
        &series,
    )?;
    root.present().map_err(|e| draw_err(path, e))
}

/// Colour of an initial-height band in [0, 1]: blue at the bottom through green to orange on top.
fn band_colour(f: f64) -> RGBColor {
    let stops = [
        (31.0, 119.0, 180.0),
        (44.0, 160.0, 44.0),
        (255.0, 127.0, 14.0),
    ];
    let t = f.clamp(0.0, 1.0) * 2.0;
    let (a, b, s) = if t < 1.0 {
        (stops[0], stops[1], t)
    } else {
        (stops[1], stops[2], t - 1.0)
    };
    let mix = |x: f64, y: f64| (x + (y - x) * s).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// Draws the first and last frames side by side, particles coloured by their initial height band,
/// the rigid bodies' particles darker.
pub fn draw_snapshot(path: &Path, r: &SlidingResult) -> Result<()> {
    ensure_font()?;
    let bands = dem::scenario::sliding::HEIGHT_BANDS as f64;
    let s0 = &r.first;
    let (lx, ly) = (s0.hi[0] - s0.lo[0], s0.hi[1] - s0.lo[1]);
    let scale = (600.0 / lx).min(600.0 / ly);
    let (w, h) = ((lx * scale) as u32 + 40, (ly * scale) as u32 + 80);
    let root = BitMapBackend::new(path, (2 * w, h)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| draw_err(path, e))?;
    let panels = root.split_evenly((1, 2));
    let views = [
        (
            &r.first,
            "start, coloured by initial height (Fig. 3)".to_string(),
        ),
        (
            &r.last,
            format!(
                "after {:.3} L of sliding: {}",
                r.windows.last().map_or(0.0, |w| w.slide) / lx,
                r.regime.label()
            ),
        ),
    ];
    for (area, (s, title)) in panels.iter().zip(views) {
        let px = |x: f64, y: f64| {
            let xw = (x - s.lo[0]).rem_euclid(lx);
            (
                20 + (xw * scale) as i32,
                50 + ((s.lo[1] + ly - y) * scale) as i32,
            )
        };
        area.draw(&Text::new(title, (20, 12), (FAMILY, 18)))
            .map_err(|e| draw_err(path, e))?;
        let mut order: Vec<usize> = (0..s.pos.len()).collect();
        order.sort_by(|&a, &b| s.pos[b][2].total_cmp(&s.pos[a][2]));
        for i in order {
            let mut c = band_colour((s.body[i] as f64 + 0.5) / bands);
            if s.role[i] == 2 {
                c = RGBColor(c.0 / 2, c.1 / 2, c.2 / 2);
            }
            let rad = ((s.radius[i] * scale).round() as u32).max(1);
            let at = px(s.pos[i][0], s.pos[i][1]);
            area.draw(&Circle::new(at, rad, c.filled()))
                .map_err(|e| draw_err(path, e))?;
            area.draw(&Circle::new(at, rad, BLACK.mix(0.3).stroke_width(1)))
                .map_err(|e| draw_err(path, e))?;
        }
    }
    root.present().map_err(|e| draw_err(path, e))
}

/// Draws the strength tests of a sliding material: the shear curve (sigma_xy, and sigma_yy that the
/// constant wall separation builds up) and the tensile curve, over sigma_m, with the peaks, the flow
/// stress over its window and the paper's tau_m = 0.22 sigma_m.
pub fn draw_strength(path: &Path, m: &MaterialStrength) -> Result<()> {
    ensure_font()?;
    let labels = [
        "stress of the test (sigma_xy in shear, sigma_yy in tension)",
        "sigma_yy in the shear test (tension positive)",
        "paper 004: tau_m = 0.22 sigma_m",
        "peak (tau_m, sigma_t)",
        "flow stress tau_flow (mean of its window)",
    ];
    let (root, body) = keyed_figure(path, (1400, 560), &labels, 2, None)?;
    let halves = body.split_evenly((1, 2));
    let s = m.sigma_m;
    let scaled = |c: &[(f64, f64, f64)], k: usize| -> Vec<(f64, f64)> {
        c.iter()
            .map(|p| (p.0, if k == 1 { p.1 } else { p.2 } / s))
            .collect()
    };
    let peak = |p: &MeasuredPeak| vec![(p.strain_at_peak, p.peak / s)];
    let last = |p: &MeasuredPeak| p.curve.last().map_or(0.0, |c| c.0);
    let shear: Vec<Series> = vec![
        (String::new(), scaled(&m.shear.curve, 1), Mark::Line, 0),
        (String::new(), scaled(&m.shear.curve, 2), Mark::Line, 1),
        (
            String::new(),
            vec![(0.0, 0.22), (last(&m.shear), 0.22)],
            Mark::Target,
            2,
        ),
        (String::new(), peak(&m.shear), Mark::Dots, 3),
    ]
    .into_iter()
    .chain(m.tau_flow.map(|f| {
        (
            String::new(),
            vec![(f.from, f.mean / s), (f.to, f.mean / s)],
            Mark::Line,
            4,
        )
    }))
    .collect();
    let flow = m
        .tau_flow
        .map_or(String::new(), |f| format!(", tau_flow = {:.3}", f.mean / s));
    let title = format!(
        "shear: tau_m = {:.3}{flow} sigma_m ({} particles)",
        m.tau_over_sigma_m(),
        m.particles
    );
    panel(
        path,
        &halves[0],
        (&title, "shear strain", "stress / sigma_m"),
        Scale::Linear,
        &shear,
    )?;
    let tension: Vec<Series> = vec![
        (String::new(), scaled(&m.tensile.curve, 1), Mark::Line, 0),
        (String::new(), peak(&m.tensile), Mark::Dots, 3),
    ];
    let title = format!("tension: sigma_t = {:.3} sigma_m", m.sigma_t / s);
    panel(
        path,
        &halves[1],
        (&title, "normal strain", "stress / sigma_m"),
        Scale::Linear,
        &tension,
    )?;
    root.present().map_err(|e| draw_err(path, e))
}
