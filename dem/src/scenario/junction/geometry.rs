//! The junction's geometry: carve a relaxed box into two solids and one cylindrical junction.

use crate::error::{DemError, Result};
use crate::sample::carve::Shape;
use crate::sample::Sample;
use crate::Vec3;

use super::JunctionConfig;

/// Body label of the particles initially below the mid-height (the lower solid and the junction's
/// lower half).
pub const BODY_LOWER: u32 = 0;
/// Body label of the particles initially above it.
pub const BODY_UPPER: u32 = 1;

/// A carved sample and what the run needs to know of it.
#[derive(Debug, Clone, PartialEq)]
pub struct Geometry {
    /// The two solids and the junction (still in the relaxed sample's periodic box).
    pub sample: Sample,
    /// Indices of the junction members: particles whose centres lie in the junction.
    pub members: Vec<usize>,
    /// Initial body of each particle ([`BODY_LOWER`] or [`BODY_UPPER`]), the colour of the dumps.
    pub body: Vec<u32>,
    /// The gap between the solids along y, [lo, hi).
    pub gap: (f64, f64),
    /// A point on the junction's axis: the box centre.
    pub centre: Vec3,
    /// Particles removed to open the gap.
    pub removed: usize,
}

/// Carves `relaxed` (a periodic relaxed box) as `cfg` says: the slab of height H around mid-height is
/// removed except the cylinder of diameter D through the box centre, along the width (ridge) or the
/// normal (column).
pub fn build(relaxed: &Sample, cfg: &JunctionConfig) -> Result<Geometry> {
    cfg.validate()?;
    let bx = relaxed.sim_box;
    if bx.periodic != [true; 3] {
        return Err(DemError::InvalidBox(
            "the junction is carved from a sample periodic on every axis (a relaxed sample)".into(),
        ));
    }
    let c = bx.centre();
    let h = cfg.height();
    let gap = (c.y - 0.5 * h, c.y + 0.5 * h);
    let l = bx.lengths();
    if cfg.diameter >= cfg.room_across(l.x, l.z) {
        return Err(DemError::InvalidConfig(format!(
            "junction: diameter {} does not fit the relaxed box {:.4} x {:.4}",
            cfg.diameter, l.x, l.z
        )));
    }
    let slab = Shape::Slab {
        axis: 1,
        lo: gap.0,
        hi: gap.1,
    };
    let junction = Shape::Cylinder {
        point: c,
        direction: cfg.shape.axis(),
        radius: 0.5 * cfg.diameter,
    };
    slab.validate()?;
    junction.validate()?;
    let mut sample = relaxed.clone();
    let p = &sample.particles;
    let keep: Vec<bool> = (0..p.len())
        .map(|i| !slab.contains(&p.pos[i]) || junction.contains(&p.pos[i]))
        .collect();
    let n0 = p.len();
    sample.particles.retain(|i| keep[i]);
    let removed = n0 - sample.particles.len();
    let p = &sample.particles;
    let members: Vec<usize> = (0..p.len()).filter(|&i| slab.contains(&p.pos[i])).collect();
    if members.is_empty() {
        return Err(DemError::InvalidConfig(format!(
            "junction: no particle centre lies in the junction of diameter {} and height {h:.4} \
             (d0 = {}); use a larger D or a smaller d0",
            cfg.diameter, cfg.d0
        )));
    }
    let body = p
        .pos
        .iter()
        .map(|x| if x.y < c.y { BODY_LOWER } else { BODY_UPPER })
        .collect();
    sample.kind = format!("{} carved into a junction", relaxed.kind);
    Ok(Geometry {
        sample,
        members,
        body,
        gap,
        centre: c,
        removed,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::junction::JunctionShape;

    /// A simple cubic set of points (30 x 20 x 20, spacing 1) stands in for a relaxed sample: the
    /// carving is geometry only.
    fn grid() -> Sample {
        let mut p = crate::state::Particles::default();
        for i in 0..30 {
            for j in 0..20 {
                for k in 0..20 {
                    p.push_sphere(
                        Vec3::new(i as f64 + 0.5, j as f64 + 0.5, k as f64 + 0.5),
                        0.5,
                        1.0,
                    );
                }
            }
        }
        let bx = crate::domain::SimBox::new(Vec3::zeros(), Vec3::new(30.0, 20.0, 20.0), [true; 3])
            .unwrap();
        Sample::new(p, bx, 1.0, "grid")
    }

    fn small(shape: JunctionShape) -> JunctionConfig {
        JunctionConfig {
            lengths: [30.0, 20.0, 20.0],
            diameter: 10.0,
            shape,
            d0: 1.0,
            dl: 1.25,
            ..JunctionConfig::default()
        }
    }

    #[test]
    fn carving_keeps_the_column_and_opens_the_gap() {
        let g = build(&grid(), &small(JunctionShape::Column)).unwrap();
        // Gap: y in [7.5, 12.5): rows 7.5 .. 11.5 (5 rows); cylinder radius 5 about (15, 10).
        assert_eq!(g.gap, (7.5, 12.5));
        let in_disc = (0..30)
            .flat_map(|i| (0..20).map(move |k| (i as f64 + 0.5 - 15.0, k as f64 + 0.5 - 10.0)))
            .filter(|(x, z)| x * x + z * z <= 25.0)
            .count();
        assert_eq!(g.members.len(), 5 * in_disc);
        assert_eq!(g.removed, 5 * (600 - in_disc));
        assert_eq!(g.sample.particles.len(), 12_000 - g.removed);
        // Below mid-height (y = 10): 7 full rows and the junction's lower 3 rows.
        let lower = g.body.iter().filter(|&&b| b == BODY_LOWER).count();
        assert_eq!(lower, 7 * 600 + 3 * in_disc);
        assert!(g.members.iter().all(|&i| {
            let x = g.sample.particles.pos[i];
            (x.x - 15.0).powi(2) + (x.z - 10.0).powi(2) <= 25.0 && (7.5..12.5).contains(&x.y)
        }));
    }

    #[test]
    fn carving_keeps_the_ridge_across_the_width() {
        let g = build(&grid(), &small(JunctionShape::Ridge)).unwrap();
        assert_eq!(g.gap, (7.5, 12.5));
        // The ridge's cross-section in the x-y plane: the gap's 5 rows inside the circle of radius 5
        // about (15, 10); every one of the 20 layers along z keeps it.
        let in_section = (0..30)
            .flat_map(|i| (7..12).map(move |j| (i as f64 + 0.5 - 15.0, j as f64 + 0.5 - 10.0)))
            .filter(|(x, y)| x * x + y * y <= 25.0)
            .count();
        assert_eq!(g.members.len(), 20 * in_section);
        assert_eq!(g.removed, 5 * 600 - 20 * in_section);
        assert!(g.members.iter().all(|&i| {
            let x = g.sample.particles.pos[i];
            (x.x - 15.0).powi(2) + (x.y - 10.0).powi(2) <= 25.0 && (7.5..12.5).contains(&x.y)
        }));
        // A ridge only has to fit the sliding length: as wide as the box's width (20) it is accepted,
        // a column of that diameter is not (it would touch its image across z).
        let wide = |shape| JunctionConfig {
            diameter: 20.0,
            lengths: [30.0, 60.0, 20.0],
            ..small(shape)
        };
        assert!(wide(JunctionShape::Ridge).validate().is_ok());
        let err = wide(JunctionShape::Column)
            .validate()
            .unwrap_err()
            .to_string();
        assert!(err.contains("and the width"), "{err}");
    }
}
