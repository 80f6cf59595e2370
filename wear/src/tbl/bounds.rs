//! The boundaries of the third-body layer from the horizontal velocity profile (paper 004 Fig. 4a):
//! the bottom body is at rest and the top one moves at v0; the TBL is where the velocity goes from
//! v_th = 0.1 v0 to v'_th = 0.9 v0.
//!
//! Decision (an oscillating profile): the lower boundary is where the profile first reaches v_th
//! coming up from the bottom, the upper one where it first drops to v'_th coming down from the top,
//! each placed by linear interpolation between the two bin centres around the crossing. So the TBL
//! holds every bin between the last one that moves with the bottom body and the first that moves
//! with the top one, the widest band the thresholds allow; a profile that crosses back and forth
//! inside it does not split it. Bins without a particle centre are skipped.

use serde::{Deserialize, Serialize};

/// The TBL's boundaries over the height H.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TblBounds {
    pub lo: f64,
    pub hi: f64,
}

impl TblBounds {
    /// h_TBL / H (zero when the boundaries cross, a jump narrower than a bin).
    pub fn thickness(&self) -> f64 {
        (self.hi - self.lo).max(0.0)
    }
}

/// Where `u` (velocity over v0 at `centres`, `None` for empty bins) crosses `lower` from below and
/// `upper` from above; `None` when it never reaches `lower` or never drops to `upper`.
pub fn tbl_bounds(centres: &[f64], u: &[Option<f64>], lower: f64, upper: f64) -> Option<TblBounds> {
    let pts: Vec<(f64, f64)> = centres
        .iter()
        .zip(u)
        .filter_map(|(&y, v)| v.filter(|v| v.is_finite()).map(|v| (y, v)))
        .collect();
    let cross = |a: (f64, f64), b: (f64, f64), level: f64| {
        if b.1 == a.1 {
            0.5 * (a.0 + b.0)
        } else {
            a.0 + (level - a.1) / (b.1 - a.1) * (b.0 - a.0)
        }
    };
    let k = pts.iter().position(|p| p.1 >= lower)?;
    let lo = if k == 0 {
        pts[0].0
    } else {
        cross(pts[k - 1], pts[k], lower)
    };
    let j = pts.iter().rposition(|p| p.1 <= upper)?;
    let hi = if j + 1 == pts.len() {
        pts[j].0
    } else {
        cross(pts[j], pts[j + 1], upper)
    };
    Some(TblBounds { lo, hi })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn centres(n: usize) -> Vec<f64> {
        (0..n).map(|k| (k as f64 + 0.5) / n as f64).collect()
    }

    #[test]
    fn uniform_shear_spans_eight_tenths() {
        let y = centres(400);
        let u: Vec<Option<f64>> = y.iter().map(|&v| Some(v)).collect();
        let b = tbl_bounds(&y, &u, 0.1, 0.9).unwrap();
        assert!(
            (b.lo - 0.1).abs() < 1e-12 && (b.hi - 0.9).abs() < 1e-12,
            "{b:?}"
        );
        assert!((b.thickness() - 0.8).abs() < 1e-12);
    }

    #[test]
    fn a_band_with_oscillations_and_holes() {
        // At rest below 0.4, v0 above 0.6, linear between, with wiggles inside the band and empty
        // bins: the boundaries are the outermost crossings.
        let y = centres(100);
        let u: Vec<Option<f64>> = y
            .iter()
            .enumerate()
            .map(|(k, &v)| {
                if k % 9 == 4 {
                    return None;
                }
                let base = ((v - 0.4) / 0.2).clamp(0.0, 1.0);
                let wiggle = if (0.45..0.55).contains(&v) {
                    0.3 * (k as f64).sin()
                } else {
                    0.0
                };
                Some(base + wiggle)
            })
            .collect();
        let b = tbl_bounds(&y, &u, 0.1, 0.9).unwrap();
        assert!((b.lo - 0.42).abs() < 0.011, "{b:?}");
        assert!((b.hi - 0.58).abs() < 0.011, "{b:?}");
    }

    #[test]
    fn a_sharp_slip_plane_is_thinner_than_a_bin() {
        let y = centres(10);
        let u: Vec<Option<f64>> = (0..10)
            .map(|k| Some(if k < 5 { 0.0 } else { 1.0 }))
            .collect();
        let b = tbl_bounds(&y, &u, 0.1, 0.9).unwrap();
        assert!((b.thickness() - 0.08).abs() < 1e-12, "{b:?}");
        // Never reaching the lower threshold (nothing moves): no TBL.
        let still = vec![Some(0.0); 10];
        assert!(tbl_bounds(&y, &still, 0.1, 0.9).is_none());
    }
}
