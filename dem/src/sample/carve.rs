//! Carving: keep or remove particles by shape, and put the particles inside a shape into a group (the
//! walls of the patch tests, paper 000 Fig. 4; the surfaces and junctions of the wear set-ups).
//! A particle belongs to a shape when its centre does.

use serde::{Deserialize, Serialize};

use crate::error::{DemError, Result};
use crate::state::Particles;
use crate::Vec3;

/// A region of space.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "shape")]
pub enum Shape {
    /// Points x with (x - point) . normal >= 0 (the normal points into the region).
    HalfSpace { point: Vec3, normal: Vec3 },
    /// Points with `lo <= x[axis] < hi`.
    Slab { axis: usize, lo: f64, hi: f64 },
    /// Points within `radius` of the line through `point` along `direction` (infinite cylinder).
    Cylinder {
        point: Vec3,
        direction: Vec3,
        radius: f64,
    },
    /// Points within `radius` of `centre`.
    Sphere { centre: Vec3, radius: f64 },
    /// Points with lo <= x < hi on every axis.
    Cuboid { lo: Vec3, hi: Vec3 },
}

impl Shape {
    /// Checks that the shape is well defined (finite, non-degenerate).
    pub fn validate(&self) -> Result<()> {
        let finite = |v: &Vec3| v.iter().all(|x| x.is_finite());
        let ok = match self {
            Shape::HalfSpace { point, normal } => {
                finite(point) && finite(normal) && normal.norm() > 0.0
            }
            Shape::Slab { axis, lo, hi } => {
                *axis < 3 && lo.is_finite() && hi.is_finite() && lo <= hi
            }
            Shape::Cylinder {
                point,
                direction,
                radius,
            } => {
                finite(point)
                    && finite(direction)
                    && direction.norm() > 0.0
                    && radius.is_finite()
                    && *radius >= 0.0
            }
            Shape::Sphere { centre, radius } => {
                finite(centre) && radius.is_finite() && *radius >= 0.0
            }
            Shape::Cuboid { lo, hi } => finite(lo) && finite(hi),
        };
        if ok {
            Ok(())
        } else {
            Err(DemError::InvalidConfig(format!(
                "degenerate or non-finite shape {self:?}"
            )))
        }
    }

    /// Whether `x` lies inside.
    pub fn contains(&self, x: &Vec3) -> bool {
        match self {
            Shape::HalfSpace { point, normal } => (x - point).dot(normal) >= 0.0,
            Shape::Slab { axis, lo, hi } => x[*axis] >= *lo && x[*axis] < *hi,
            Shape::Cylinder {
                point,
                direction,
                radius,
            } => {
                let u = direction.normalize();
                let r = x - point;
                (r - r.dot(&u) * u).norm_squared() <= radius * radius
            }
            Shape::Sphere { centre, radius } => (x - centre).norm_squared() <= radius * radius,
            Shape::Cuboid { lo, hi } => (0..3).all(|a| x[a] >= lo[a] && x[a] < hi[a]),
        }
    }
}

/// Keeps only the particles inside `shape`; returns how many were removed.
pub fn keep_inside(p: &mut Particles, shape: &Shape) -> Result<usize> {
    shape.validate()?;
    let n = p.len();
    let inside: Vec<bool> = p.pos.iter().map(|x| shape.contains(x)).collect();
    p.retain(|i| inside[i]);
    Ok(n - p.len())
}

/// Removes the particles inside `shape`; returns how many were removed.
pub fn remove_inside(p: &mut Particles, shape: &Shape) -> Result<usize> {
    shape.validate()?;
    let n = p.len();
    let inside: Vec<bool> = p.pos.iter().map(|x| shape.contains(x)).collect();
    p.retain(|i| !inside[i]);
    Ok(n - p.len())
}

/// Puts the particles inside `shape` into group `group`; returns how many.
pub fn assign_group(p: &mut Particles, shape: &Shape, group: u32) -> Result<usize> {
    shape.validate()?;
    let mut count = 0;
    for i in 0..p.len() {
        if shape.contains(&p.pos[i]) {
            p.group[i] = group;
            count += 1;
        }
    }
    Ok(count)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line() -> Particles {
        let mut p = Particles::default();
        for k in 0..10 {
            p.push_sphere(Vec3::new(k as f64, 0.0, 0.0), 0.5, 1.0);
        }
        p
    }

    #[test]
    fn shapes_select_by_centre() {
        let mut p = line();
        let half = Shape::HalfSpace {
            point: Vec3::new(4.5, 0.0, 0.0),
            normal: Vec3::new(-1.0, 0.0, 0.0),
        };
        assert_eq!(remove_inside(&mut p, &half).unwrap(), 5);
        assert_eq!(p.pos[0].x, 5.0);
        let slab = Shape::Slab {
            axis: 0,
            lo: 6.0,
            hi: 8.0,
        };
        assert_eq!(assign_group(&mut p, &slab, 2).unwrap(), 2);
        assert_eq!(p.group, vec![0, 2, 2, 0, 0]);
        let cyl = Shape::Cylinder {
            point: Vec3::zeros(),
            direction: Vec3::new(0.0, 1.0, 0.0),
            radius: 7.5,
        };
        assert_eq!(keep_inside(&mut p, &cyl).unwrap(), 2);
        assert!(Shape::Sphere {
            centre: Vec3::zeros(),
            radius: 1.0
        }
        .contains(&Vec3::new(0.0, 1.0, 0.0)));
        assert!(!Shape::Cuboid {
            lo: Vec3::zeros(),
            hi: Vec3::repeat(1.0)
        }
        .contains(&Vec3::repeat(1.0)));
    }

    #[test]
    fn degenerate_shapes_are_refused() {
        let mut p = line();
        let bad = Shape::HalfSpace {
            point: Vec3::zeros(),
            normal: Vec3::zeros(),
        };
        assert!(keep_inside(&mut p, &bad).is_err());
        assert!(assign_group(
            &mut p,
            &Shape::Slab {
                axis: 3,
                lo: 0.0,
                hi: 1.0
            },
            1
        )
        .is_err());
        assert_eq!(p.len(), 10);
    }
}
