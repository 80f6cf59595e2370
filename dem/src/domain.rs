//! The simulation box: orthogonal, each axis periodic or not, optionally deforming.
//!
//! Deformation is affine about the box centre: a strain increment `de` along axis a maps
//! x -> c + (x - c)(1 + de) for every particle when `remap` is on (periodic images move with the box).
//! The stress-controlled mode moves the box until the mean virial stress reaches a target, as in the
//! second relaxation phase of paper 000 section 3.2.

use serde::{Deserialize, Serialize};

use crate::error::{DemError, Result};
use crate::Vec3;

/// Orthogonal box [lo, hi) with per-axis periodicity.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SimBox {
    pub lo: Vec3,
    pub hi: Vec3,
    pub periodic: [bool; 3],
}

impl SimBox {
    /// A box from its corners; fails unless hi > lo on every axis and all values are finite.
    pub fn new(lo: Vec3, hi: Vec3, periodic: [bool; 3]) -> Result<Self> {
        for a in 0..3 {
            if !(lo[a].is_finite() && hi[a].is_finite() && hi[a] > lo[a]) {
                return Err(DemError::InvalidBox(format!(
                    "axis {a}: lo {} must be below hi {}",
                    lo[a], hi[a]
                )));
            }
        }
        Ok(SimBox { lo, hi, periodic })
    }

    /// Edge lengths.
    #[inline]
    pub fn lengths(&self) -> Vec3 {
        self.hi - self.lo
    }

    /// Volume.
    pub fn volume(&self) -> f64 {
        let l = self.lengths();
        l.x * l.y * l.z
    }

    /// Centre.
    pub fn centre(&self) -> Vec3 {
        0.5 * (self.lo + self.hi)
    }

    /// Periodic shift vector for an integer image `s`.
    #[inline]
    pub fn shift(&self, s: [i8; 3]) -> Vec3 {
        let l = self.lengths();
        Vec3::new(s[0] as f64 * l.x, s[1] as f64 * l.y, s[2] as f64 * l.z)
    }

    /// Wraps `x` into [lo, hi) along periodic axes. A coordinate already inside is left as it is, bit
    /// for bit: (x - lo) / l * l + lo can differ from x in the last place, which would move a planar
    /// layer's particles off their plane at every neighbour-list rebuild.
    pub fn wrap(&self, x: &mut Vec3) {
        let l = self.lengths();
        for a in 0..3 {
            if self.periodic[a] && !(x[a] >= self.lo[a] && x[a] < self.hi[a]) {
                let mut u = (x[a] - self.lo[a]) / l[a];
                u -= u.floor();
                // Rounding can give exactly 1.0 for tiny negative inputs; keep the half-open interval.
                if u >= 1.0 {
                    u = 0.0;
                }
                x[a] = self.lo[a] + u * l[a];
            }
        }
    }

    /// Minimum-image separation vector from `a` to `b` (for analysis, not for the force loop, which uses
    /// explicit images from the neighbour list).
    pub fn min_image(&self, a: &Vec3, b: &Vec3) -> Vec3 {
        let l = self.lengths();
        let mut d = b - a;
        for k in 0..3 {
            if self.periodic[k] {
                d[k] -= l[k] * (d[k] / l[k]).round();
            }
        }
        d
    }

    /// Scales axis `a` about the centre by `1 + de`, returning the affine map's factor.
    pub fn strain_axis(&mut self, a: usize, de: f64) -> f64 {
        let c = 0.5 * (self.lo[a] + self.hi[a]);
        let f = 1.0 + de;
        self.lo[a] = c + (self.lo[a] - c) * f;
        self.hi[a] = c + (self.hi[a] - c) * f;
        f
    }
}

/// How the box evolves during a run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case", tag = "mode")]
pub enum BoxControl {
    /// The box does not move.
    #[default]
    Fixed,
    /// Engineering strain rate per axis (1/time); particles are remapped affinely when `remap`.
    StrainRate { rate: Vec3, remap: bool },
    /// Moves the selected axes until the diagonal virial stress equals `target` (tension positive):
    /// each step the strain increment along a is `gain (sigma_aa - target_a) / modulus`, capped at
    /// `max_strain_step`, and particles are remapped affinely.
    Stress {
        target: Vec3,
        axes: [bool; 3],
        modulus: f64,
        gain: f64,
        max_strain_step: f64,
    },
}

impl BoxControl {
    pub(crate) fn validate(&self, bx: &SimBox) -> Result<()> {
        match *self {
            BoxControl::Fixed => Ok(()),
            BoxControl::StrainRate { rate, .. } => {
                if rate.iter().all(|r| r.is_finite()) {
                    Ok(())
                } else {
                    Err(DemError::InvalidConfig(
                        "box strain rate must be finite".into(),
                    ))
                }
            }
            BoxControl::Stress {
                target,
                axes,
                modulus,
                gain,
                max_strain_step,
            } => {
                if !(modulus > 0.0
                    && gain > 0.0
                    && max_strain_step > 0.0
                    && target.iter().all(|t| t.is_finite()))
                {
                    return Err(DemError::InvalidConfig(
                        "stress control needs finite target and positive modulus, gain and max_strain_step".into(),
                    ));
                }
                for a in 0..3 {
                    if axes[a] && !bx.periodic[a] {
                        return Err(DemError::InvalidConfig(format!(
                            "stress control on axis {a} needs that axis periodic"
                        )));
                    }
                }
                Ok(())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_and_min_image() {
        let b = SimBox::new(
            Vec3::zeros(),
            Vec3::new(10.0, 10.0, 10.0),
            [true, true, false],
        )
        .unwrap();
        let mut x = Vec3::new(-0.5, 23.0, -4.0);
        b.wrap(&mut x);
        assert!((x - Vec3::new(9.5, 3.0, -4.0)).norm() < 1e-12);
        let d = b.min_image(&Vec3::new(0.5, 0.5, 0.5), &Vec3::new(9.5, 0.5, 9.5));
        assert!((d - Vec3::new(-1.0, 0.0, 9.0)).norm() < 1e-12);
        let mut tiny = Vec3::new(-1e-300, 0.0, 0.0);
        b.wrap(&mut tiny);
        assert!(tiny.x >= 0.0 && tiny.x < 10.0);
    }

    #[test]
    fn bad_boxes_are_refused() {
        assert!(SimBox::new(Vec3::zeros(), Vec3::new(1.0, 0.0, 1.0), [false; 3]).is_err());
        assert!(SimBox::new(Vec3::zeros(), Vec3::new(1.0, f64::NAN, 1.0), [false; 3]).is_err());
    }

    #[test]
    fn strain_about_centre() {
        let mut b = SimBox::new(Vec3::zeros(), Vec3::new(10.0, 10.0, 10.0), [true; 3]).unwrap();
        b.strain_axis(0, 0.1);
        assert!((b.lo.x + 0.5).abs() < 1e-12 && (b.hi.x - 10.5).abs() < 1e-12);
    }
}
