//! The steady state of a sliding run and its regime (paper 004 section 3, Figs. 3 and 5):
//! - [`steady_mean`]: the mean of a time series over its steady part, the samples at or after a start
//!   time (p_T, h_TBL);
//! - [`shear_traction`]: p_T = (|F_x,top| + |F_x,bottom|) / (2 A), the mean of the horizontal forces on
//!   the two bodies over the interface area (the paper takes either body; in steady state the two
//!   agree, and their mean halves the inertial noise of the layer between them);
//! - [`classify_regime`]: mixed (wear particles, a gap), shear band (full contact), growing large
//!   particles (rolling bodies that lubricate), or a TBL that has reached a rigid body;
//! - [`touches_body`]: whether a TBL's boundaries lie against a rigid body's face.
//!
//! Decision (the label, which the paper gives by eye): the paper ties the regimes to measures that
//! this crate has. Large growing particles show as "erratic changes of TBL thickness" (Fig. 5) and a
//! lubricated p_T "as low as 0.001 E", far below tau_m rho_TBL / rho_0; a shear band is full contact,
//! "maximum TBL density" with p_T ~ tau_m; the mixed regime keeps a gap, rho_TBL below rho_0. So, in
//! this order: p_T below `lubricated` x tau_m rho_TBL / rho_0, or a relative spread of h_TBL about
//! its moving average above `erratic`, is growing particles; rho_TBL / rho_0 at or above
//! `full_contact` is a shear band; anything else is mixed. The thresholds are settings with defaults.
//!
//! Decision (the fourth case, checked first): paper 004 (Fig. 5 caption and section 3) names a case
//! it drops from its analysis as unphysical: "the TBL reaches a boundary of the system", after which
//! the sliding happens at a rigid body's face. A steady TBL one of whose velocity boundaries lies
//! within `boundary_reach` particle diameters of a body's inner face (the scenario passes the faces
//! of its bodies' particle layers plus one diameter, where the density fit starts) has reached it:
//! no intact particle layer is left between the sheared band and the rigid body, so p_T there is
//! the strength of the body's interface, not of the layer. It is checked before the other labels
//! because its measures are not those of any of the paper's three regimes.
//!
//! Decision (the wear particles, checked before everything): where the run measured its wear
//! particles ([`crate::tbl::wear_particles()`]), a steady mean size of the largest one at or above
//! `growing_size` L is growing particles whatever the other measures say. That is Fig. 3c's own
//! definition ("large wear particles, that grow in size until reaching the size of the system"); a
//! particle that size lies against both bodies, so the boundary test would otherwise hide the very
//! regime it grows into. Mixed-regime wear particles stay a few d0 across, hundredths of L.

use serde::{Deserialize, Serialize};

use crate::error::{Result, WearError};
use crate::tbl::filter::moving_average;
use crate::tbl::TblBounds;

/// The regimes of Fig. 3.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Regime {
    /// (a) wear particles formed, agglomerated and reattached; a gap of stationary size.
    Mixed,
    /// (b) the bodies fully connected, vertical mixing; a finite sheared layer.
    ShearBand,
    /// (c) large wear particles growing to the size of the system, lubricated sliding.
    GrowingParticles,
    /// The TBL against a rigid body: the sliding happens at the body's face (paper 004 drops this
    /// phase as unphysical).
    BoundaryReached,
}

impl Regime {
    /// The label written in summaries and tables.
    pub fn label(&self) -> &'static str {
        match self {
            Regime::Mixed => "mixed",
            Regime::ShearBand => "shear_band",
            Regime::GrowingParticles => "growing_particles",
            Regime::BoundaryReached => "boundary_reached",
        }
    }
}

/// Thresholds of the label (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RegimeParams {
    /// rho_TBL / rho_0 at or above which the layer is full contact (a shear band): within the
    /// few-percent noise of the fitted minimum of a homogeneous solid's profile.
    pub full_contact: f64,
    /// p_T below this fraction of tau_m rho_TBL / rho_0 is lubricated (rolling particles): the paper's
    /// mixed runs sit near 1, its lubricated ones two orders below.
    pub lubricated: f64,
    /// Relative rms of h_TBL about its moving average above which the thickness is erratic: steady
    /// runs of Fig. 5 wander by a few tenths of their mean at most.
    pub erratic: f64,
    /// Samples of the moving average of h_TBL (odd).
    pub window: usize,
    /// Distance, in particle diameters, from a body's inner face within which a TBL boundary has
    /// reached the body: half a particle, less than one intact layer between band and body.
    pub boundary_reach: f64,
    /// Steady mean equivalent diameter of the largest wear particle, over L, at or above which the
    /// run is growing particles (module docs): a fifth of the system, ten times the few d0 of the
    /// mixed regime's particles at the paper's d0 = 0.01 L.
    pub growing_size: f64,
}

impl Default for RegimeParams {
    fn default() -> Self {
        RegimeParams {
            full_contact: 0.93,
            lubricated: 0.2,
            erratic: 0.5,
            window: 9,
            boundary_reach: 0.5,
            growing_size: 0.2,
        }
    }
}

/// What the label is decided from, all in steady state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RegimeData {
    /// rho_TBL / rho_0.
    pub rho_tbl: f64,
    /// Mean p_T and the shear strength tau_m (same units).
    pub p_t: f64,
    pub tau_m: f64,
    /// The h_TBL / H series of the steady part.
    pub h_tbl: Vec<f64>,
    /// The steady TBL's boundaries over H (`None`: nothing slid inside the system).
    pub bounds: Option<TblBounds>,
    /// The bodies' inner faces over H (bottom, top) and the particle diameter d0 / H.
    pub faces: (f64, f64),
    pub d0: f64,
    /// The steady mean equivalent diameter of the largest wear particle over L (`None`: not
    /// measured).
    pub wear_particle_size: Option<f64>,
}

/// Whether `bounds` (over H) lies within `reach` (over H) of the bodies' inner `faces` (bottom, top).
pub fn touches_body(bounds: &TblBounds, faces: (f64, f64), reach: f64) -> bool {
    bounds.lo <= faces.0 + reach || bounds.hi >= faces.1 - reach
}

/// Mean of the samples of `x` at times `t >= from`; an error when none is.
pub fn steady_mean(t: &[f64], x: &[f64], from: f64) -> Result<f64> {
    if t.len() != x.len() {
        return Err(WearError::Frames(format!(
            "a series needs one value per time ({} times, {} values)",
            t.len(),
            x.len()
        )));
    }
    let (sum, n) = t
        .iter()
        .zip(x)
        .filter(|(&ti, _)| ti >= from)
        .fold((0.0, 0usize), |(s, n), (_, &v)| (s + v, n + 1));
    if n == 0 {
        return Err(WearError::Frames(format!(
            "no sample at or after t = {from}"
        )));
    }
    Ok(sum / n as f64)
}

/// p_T from the horizontal forces on the top and bottom bodies over the interface `area`.
pub fn shear_traction(fx_top: f64, fx_bottom: f64, area: f64) -> f64 {
    0.5 * (fx_top.abs() + fx_bottom.abs()) / area
}

/// Relative rms of `h` about its centred moving average over `window` samples, over the mean of `h`.
pub fn erratic_spread(h: &[f64], window: usize) -> f64 {
    if h.is_empty() {
        return 0.0;
    }
    let m = moving_average(h, window);
    let mean = h.iter().sum::<f64>() / h.len() as f64;
    let rms = (h.iter().zip(&m).map(|(a, b)| (a - b).powi(2)).sum::<f64>() / h.len() as f64).sqrt();
    if mean > 0.0 {
        rms / mean
    } else {
        0.0
    }
}

/// The regime of a run from its steady-state measures.
pub fn classify_regime(data: &RegimeData, params: &RegimeParams) -> Result<Regime> {
    if !(data.rho_tbl.is_finite() && data.p_t.is_finite() && data.tau_m > 0.0) {
        return Err(WearError::Setting(format!(
            "a regime needs finite rho_TBL and p_T and a positive tau_m (rho_TBL {}, p_T {}, tau_m {})",
            data.rho_tbl, data.p_t, data.tau_m
        )));
    }
    if !(data.faces.0 < data.faces.1 && data.d0 > 0.0 && params.boundary_reach >= 0.0) {
        return Err(WearError::Setting(format!(
            "a regime needs body faces in order, a positive d0 and a reach >= 0 (faces {:?}, d0 {}, \
             reach {})",
            data.faces, data.d0, params.boundary_reach
        )));
    }
    if data
        .wear_particle_size
        .is_some_and(|d| d >= params.growing_size)
    {
        return Ok(Regime::GrowingParticles);
    }
    if let Some(b) = &data.bounds {
        if touches_body(b, data.faces, params.boundary_reach * data.d0) {
            return Ok(Regime::BoundaryReached);
        }
    }
    let contact = data.tau_m * data.rho_tbl.max(0.0);
    if data.p_t < params.lubricated * contact
        || erratic_spread(&data.h_tbl, params.window) > params.erratic
    {
        return Ok(Regime::GrowingParticles);
    }
    Ok(if data.rho_tbl >= params.full_contact {
        Regime::ShearBand
    } else {
        Regime::Mixed
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A layer in the middle of a box whose bodies' faces are at 0.1 and 0.9 H, d0 = 0.05 H.
    fn data(rho: f64, p_t: f64, h: Vec<f64>) -> RegimeData {
        RegimeData {
            rho_tbl: rho,
            p_t,
            tau_m: 0.022,
            h_tbl: h,
            bounds: Some(TblBounds { lo: 0.4, hi: 0.6 }),
            faces: (0.1, 0.9),
            d0: 0.05,
            wear_particle_size: None,
        }
    }

    #[test]
    fn steady_means_and_traction() {
        let t = [0.0, 1.0, 2.0, 3.0];
        let x = [10.0, 1.0, 2.0, 3.0];
        assert_eq!(steady_mean(&t, &x, 1.0).unwrap(), 2.0);
        assert!(steady_mean(&t, &x, 4.0).is_err());
        assert!(steady_mean(&t, &x[..3], 0.0).is_err());
        // Equal and opposite forces on the bodies: p_T is their magnitude over the area.
        assert_eq!(shear_traction(-3.0, 3.0, 2.0), 1.5);
    }

    #[test]
    fn the_three_regimes_of_fig_3() {
        let p = RegimeParams::default();
        let steady: Vec<f64> = (0..40).map(|i| 0.2 + 0.01 * (i as f64).sin()).collect();
        // Full contact, p_T at tau_m: shear band.
        let r = classify_regime(&data(0.99, 0.022, steady.clone()), &p).unwrap();
        assert_eq!(r, Regime::ShearBand);
        // A porous layer carrying tau_m rho_TBL: mixed.
        let r = classify_regime(&data(0.7, 0.7 * 0.022, steady.clone()), &p).unwrap();
        assert_eq!(r, Regime::Mixed);
        // Lubricated (0.001 E against 0.015): growing particles.
        let r = classify_regime(&data(0.7, 0.001, steady.clone()), &p).unwrap();
        assert_eq!(r, Regime::GrowingParticles);
        // An erratic thickness (jumps between 0.05 and 0.6): growing particles.
        let jumpy: Vec<f64> = (0..40)
            .map(|i| if (i / 2) % 2 == 0 { 0.05 } else { 0.6 })
            .collect();
        assert!(erratic_spread(&jumpy, 9) > 0.5);
        assert!(erratic_spread(&steady, 9) < 0.1);
        let r = classify_regime(&data(0.7, 0.7 * 0.022, jumpy), &p).unwrap();
        assert_eq!(r, Regime::GrowingParticles);
        // A wear particle a quarter of the system across: growing particles, even against a body
        // and at full contact; a few d0 across (0.03 L) changes nothing.
        let mut d = data(0.99, 0.022, steady.clone());
        d.bounds = Some(TblBounds { lo: 0.8, hi: 0.89 });
        d.wear_particle_size = Some(0.03);
        assert_eq!(classify_regime(&d, &p).unwrap(), Regime::BoundaryReached);
        d.wear_particle_size = Some(0.25);
        assert_eq!(classify_regime(&d, &p).unwrap(), Regime::GrowingParticles);
        assert!(classify_regime(&data(f64::NAN, 0.0, steady), &p).is_err());
        assert_eq!(Regime::ShearBand.label(), "shear_band");
    }

    #[test]
    fn a_layer_against_a_body_has_reached_the_boundary() {
        let p = RegimeParams::default();
        let steady: Vec<f64> = (0..40).map(|i| 0.1 + 0.01 * (i as f64).sin()).collect();
        // Half a diameter (0.025 H) from either face is the reach.
        for (lo, hi, reached) in [
            (0.80, 0.89, true),  // against the top body (the quick runs' layers)
            (0.80, 0.876, true), // just past the reach (0.875)
            (0.80, 0.87, false), // just inside
            (0.12, 0.30, true),  // against the bottom body
            (0.13, 0.30, false),
            (0.05, 0.95, true), // the whole box: both faces
        ] {
            let mut d = data(0.99, 0.022, steady.clone());
            d.bounds = Some(TblBounds { lo, hi });
            let r = classify_regime(&d, &p).unwrap();
            assert_eq!(r == Regime::BoundaryReached, reached, "{lo} {hi}: {r:?}");
            assert_eq!(
                touches_body(&TblBounds { lo, hi }, (0.1, 0.9), 0.025),
                reached
            );
        }
        // Nothing slid inside the system: no boundaries, the density decides.
        let mut d = data(0.99, 0.022, steady.clone());
        d.bounds = None;
        assert_eq!(classify_regime(&d, &p).unwrap(), Regime::ShearBand);
        // Faces out of order, or no particle size: an error, not a label.
        let mut d = data(0.99, 0.022, steady);
        d.faces = (0.9, 0.1);
        assert!(classify_regime(&d, &p).is_err());
        d.faces = (0.1, 0.9);
        d.d0 = 0.0;
        assert!(classify_regime(&d, &p).is_err());
        assert_eq!(Regime::BoundaryReached.label(), "boundary_reached");
    }
}
