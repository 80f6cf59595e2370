//! One averaged profile to the TBL's measures (paper 004 Fig. 4): the boundaries from the velocity
//! thresholds (0.1 v0 and 0.9 v0), the Savitzky-Golay filtered density (order 3, 7 samples) that the
//! figures draw, and rho_TBL / rho_0 from the Gaussian fitted to the unfiltered density.
//!
//! The layer's agitation is the root mean square of the bins' agitation (`profile` module docs)
//! over the bins whose centres lie within the TBL boundaries, each bin weighted alike as the density
//! fit weights them.
//!
//! Decision (the fitted range): the density falls to zero above the top body and is a solid's at the
//! rigid bodies; the fit covers only the bins of the free particles, the range [lo, hi] over H that
//! the caller gives (the scenario passes the inner faces of its bodies), so that the ends of the
//! system do not read as a dip.

use serde::{Deserialize, Serialize};

use crate::error::{Result, WearError};
use crate::tbl::{fit_gaussian_dip, savitzky_golay, tbl_bounds, GaussFit, Profile, TblBounds};

/// The filter and fit settings of paper 004.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct LayerParams {
    /// Velocity thresholds over v0 (paper: 0.1 and 0.9).
    pub v_lower: f64,
    pub v_upper: f64,
    /// Savitzky-Golay window and order (paper: 7 samples, order 3).
    pub sg_window: usize,
    pub sg_order: usize,
    /// Smallest Gaussian width over H: one particle diameter over the height, so that a single thin
    /// bin is not a layer (the scenario passes d0 / H).
    pub min_width: f64,
}

impl Default for LayerParams {
    fn default() -> Self {
        LayerParams {
            v_lower: 0.1,
            v_upper: 0.9,
            sg_window: 7,
            sg_order: 3,
            min_width: 0.01,
        }
    }
}

/// The measures of one profile.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LayerMeasures {
    /// TBL boundaries over H (`None` when nothing slides: the velocity never reaches the thresholds).
    pub bounds: Option<TblBounds>,
    /// The density over rho_0 per bin, Savitzky-Golay filtered.
    pub density_filtered: Vec<f64>,
    /// The Gaussian fitted to the unfiltered density over rho_0, in the fitted range.
    pub fit: GaussFit,
    /// rho_TBL / rho_0: the fitted curve's minimum.
    pub rho_tbl: f64,
    /// The TBL's agitation over v0 ([`layer_agitation`]; `None` without boundaries or squares).
    #[serde(default)]
    pub agitation: Option<f64>,
}

/// Root mean square of the bins' agitation over v0 for the bins with centres in the TBL `bounds`
/// (`None` when no such bin has one).
pub fn layer_agitation(profile: &Profile, bounds: &TblBounds) -> Option<f64> {
    let (sum, n) = profile
        .centres()
        .iter()
        .zip(&profile.agitation_over_v0)
        .filter(|(&c, _)| c >= bounds.lo && c <= bounds.hi)
        .filter_map(|(_, a)| *a)
        .fold((0.0, 0usize), |(s, n), a| (s + a * a, n + 1));
    (n > 0).then(|| (sum / n as f64).sqrt())
}

/// Measures `profile` with `rho0` the bulk density and the fit over the bins with centres in
/// [fit_lo, fit_hi] (over H).
pub fn measure_layer(
    profile: &Profile,
    rho0: f64,
    (fit_lo, fit_hi): (f64, f64),
    params: &LayerParams,
) -> Result<LayerMeasures> {
    if !(rho0.is_finite() && rho0 > 0.0) {
        return Err(WearError::Setting(format!(
            "bulk density {rho0} must be positive"
        )));
    }
    let centres = profile.centres();
    let bounds = tbl_bounds(
        &centres,
        &profile.velocity_over_v0,
        params.v_lower,
        params.v_upper,
    );
    let rho: Vec<f64> = profile.density.iter().map(|d| d / rho0).collect();
    let density_filtered = savitzky_golay(&rho, params.sg_window, params.sg_order)?;
    let (x, y): (Vec<f64>, Vec<f64>) = centres
        .iter()
        .zip(&rho)
        .filter(|(&c, _)| c >= fit_lo && c <= fit_hi)
        .map(|(&c, &r)| (c, r))
        .unzip();
    let fit = fit_gaussian_dip(&x, &y, params.min_width)?;
    let agitation = bounds.as_ref().and_then(|b| layer_agitation(profile, b));
    Ok(LayerMeasures {
        agitation,
        bounds,
        density_filtered,
        rho_tbl: fit.minimum,
        fit,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_synthetic_layer_is_measured() {
        // 400 bins: bodies at rest below 0.4 and at v0 above 0.6, a porous layer of density
        // 1 - 0.3 exp(-(y - 0.5)^2 / (2 0.04^2)) around the shear, and no mass above 0.95.
        let n = 400;
        let c: Vec<f64> = (0..n).map(|k| (k as f64 + 0.5) / n as f64).collect();
        let rho0 = 2.0;
        let profile = Profile {
            velocity_over_v0: c
                .iter()
                .map(|&y| Some(((y - 0.4) / 0.2).clamp(0.0, 1.0)))
                .collect(),
            density: c
                .iter()
                .map(|&y| {
                    if y > 0.95 {
                        0.0
                    } else {
                        rho0 * (1.0 - 0.3 * (-0.5 * ((y - 0.5) / 0.04f64).powi(2)).exp())
                    }
                })
                .collect(),
            // Agitation 0.2 v0 inside the layer (0.42-0.58), 0.01 v0 outside.
            agitation_over_v0: c
                .iter()
                .map(|&y| {
                    Some(if (0.42..=0.58).contains(&y) {
                        0.2
                    } else {
                        0.01
                    })
                })
                .collect(),
            height: 1.0,
            v0: 0.1,
        };
        let m = measure_layer(&profile, rho0, (0.05, 0.9), &LayerParams::default()).unwrap();
        let b = m.bounds.unwrap();
        assert!(
            (b.lo - 0.42).abs() < 1e-9 && (b.hi - 0.58).abs() < 1e-9,
            "{b:?}"
        );
        assert!((m.rho_tbl - 0.7).abs() < 1e-6, "{:?}", m.fit);
        assert!(
            (m.agitation.unwrap() - 0.2).abs() < 1e-12,
            "{:?}",
            m.agitation
        );
        // Unknown squares, or no layer: no agitation.
        let unknown = Profile {
            agitation_over_v0: vec![None; n],
            ..profile.clone()
        };
        assert_eq!(layer_agitation(&unknown, &b), None);
        // The filter keeps a smooth profile (error of a cubic fit to a Gaussian of 16 bins' width).
        assert!((m.density_filtered[200] - profile.density[200] / rho0).abs() < 1e-3);
        assert!(measure_layer(&profile, 0.0, (0.05, 0.9), &LayerParams::default()).is_err());
        assert!(measure_layer(&profile, rho0, (0.5, 0.505), &LayerParams::default()).is_err());
    }
}
