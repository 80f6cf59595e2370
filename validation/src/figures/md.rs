//! The figure of an MD material card (`cgdem md silica`): `silica.png`, the tension and shear
//! loading curves of the glass (stress in GPa against engineering strain) with their peaks, the
//! card's strengths, beside paper 000 Table 5's strengths as dashed lines.

use std::path::Path;

use md_bridge::loading::Strength;

use super::chart::{keyed_figure, panel, Mark, Scale, Series};
use super::style::{draw_err, ensure_font};
use crate::error::Result;

/// A loading curve in GPa: (strain, stress / 1e9), and its peak.
pub fn gpa_curve(s: &Strength) -> (Vec<(f64, f64)>, (f64, f64)) {
    let pts = s.curve.iter().map(|p| (p[0], p[1] / 1e9)).collect();
    (pts, (s.peak_strain, s.peak_stress / 1e9))
}

/// Draws the loading curves (either may be missing) with reference strengths `reference` (Pa,
/// tensile and shear) as dashed lines.
pub fn draw(
    path: &Path,
    tension: Option<&Strength>,
    shear: Option<&Strength>,
    reference: (f64, f64),
) -> Result<()> {
    ensure_font()?;
    let labels = ["MD, this card (dot: the peak)", "paper 000 Table 5"];
    let (root, body) = keyed_figure(path, (1400, 560), &labels, 2, None)?;
    let panels = body.split_evenly((1, 2));
    let tests = [
        (
            "uniaxial tension",
            "strain eps_xx",
            "sigma_xx (GPa)",
            tension,
            reference.0,
        ),
        (
            "simple shear",
            "strain gamma_xy",
            "tau_xy (GPa)",
            shear,
            reference.1,
        ),
    ];
    for (area, (title, xd, yd, s, r)) in panels.iter().zip(tests) {
        let mut series: Vec<Series> = Vec::new();
        if let Some(s) = s {
            let (pts, peak) = gpa_curve(s);
            let end = pts.last().map_or(peak.0, |p| p.0);
            series.push((String::new(), pts, Mark::Line, 0));
            series.push((String::new(), vec![peak], Mark::Points, 0));
            series.push((
                String::new(),
                vec![(0.0, r / 1e9), (end, r / 1e9)],
                Mark::Target,
                1,
            ));
        }
        panel(path, area, (title, xd, yd), Scale::Linear, &series)?;
    }
    root.present().map_err(|e| draw_err(path, e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn curves_are_plotted_in_gpa_with_their_peak() {
        let s = Strength {
            peak_stress: 16e9,
            peak_strain: 0.2,
            peak_reached: true,
            curve: vec![[0.1, 8e9], [0.2, 16e9], [0.3, 2e9]],
        };
        let (pts, peak) = gpa_curve(&s);
        assert_eq!(pts, [(0.1, 8.0), (0.2, 16.0), (0.3, 2.0)]);
        assert_eq!(peak, (0.2, 16.0));
    }
}
