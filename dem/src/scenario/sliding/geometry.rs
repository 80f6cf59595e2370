//! The sliding system's geometry: one relaxed periodic box cut at mid-height into two halves whose
//! interface does not match.
//!
//! Decision (the non-matching interface): paper 004 says only that the two halves are disjoined at
//! the start (Fig. 2). Cutting one relaxed box leaves two faces that fit each other perfectly, a
//! healed solid rather than two bodies in contact; relaxing two boxes separately leaves faces that
//! overlap anywhere. So the top half is shifted by L / 2 along x (any shift breaks the amorphous
//! match; half the period is the farthest from the original) and then lifted by the least height at
//! which no pair across the interface overlaps (every surface gap >= 0, found by brute force over the
//! particles within one largest diameter of the cut). The interface then starts in contact without
//! overlap, and the pressure closes it at the first steps.

use crate::error::{DemError, Result};
use crate::sample::Sample;
use crate::Vec3;

use super::SlidingConfig;

/// Body label of the particles of the bottom half.
pub const BODY_BOTTOM_HALF: u32 = 0;
/// Body label of the particles of the top half.
pub const BODY_TOP_HALF: u32 = 1;

/// The stacked halves and what the run needs to know of them.
#[derive(Debug, Clone, PartialEq)]
pub struct Geometry {
    /// The two halves, in a box periodic along x and z and lengthened along y by `lift`.
    pub sample: Sample,
    /// Half of each particle ([`BODY_BOTTOM_HALF`] or [`BODY_TOP_HALF`]).
    pub body: Vec<u32>,
    /// Initial height of each particle over the box height, in [0, 1): the colour of Fig. 3.
    pub height0: Vec<f64>,
    /// Shift of the top half along x and lift along y.
    pub shift: f64,
    pub lift: f64,
}

/// Cuts `relaxed` (periodic on every axis) at mid-height, shifts the top half by half the period
/// along x and lifts it clear of the bottom half.
pub fn build(relaxed: &Sample, cfg: &SlidingConfig) -> Result<Geometry> {
    cfg.validate()?;
    let bx = relaxed.sim_box;
    if bx.periodic != [true; 3] {
        return Err(DemError::InvalidBox(
            "sliding halves are cut from a sample periodic on every axis (a relaxed sample)".into(),
        ));
    }
    let l = bx.lengths();
    let mid = bx.centre().y;
    let p = &relaxed.particles;
    let body: Vec<u32> = p
        .pos
        .iter()
        .map(|x| {
            if x.y < mid {
                BODY_BOTTOM_HALF
            } else {
                BODY_TOP_HALF
            }
        })
        .collect();
    let shift = 0.5 * l.x;
    let mut pos = p.pos.clone();
    for (x, &b) in pos.iter_mut().zip(&body) {
        if b == BODY_TOP_HALF {
            x.x += shift;
            bx.wrap(x);
        }
    }
    let dmax = 2.0 * p.radius.iter().cloned().fold(0.0, f64::max);
    let near = |b: u32| -> Vec<usize> {
        (0..p.len())
            .filter(|&i| body[i] == b && (pos[i].y - mid).abs() < dmax)
            .collect()
    };
    let (lower, upper) = (near(BODY_BOTTOM_HALF), near(BODY_TOP_HALF));
    let mut lift = 0.0f64;
    for &i in &lower {
        for &j in &upper {
            let d = bx.min_image(&pos[i], &pos[j]);
            let reach = p.radius[i] + p.radius[j];
            let h2 = d.x * d.x + d.z * d.z;
            if h2 < reach * reach {
                // The top particle must sit at least sqrt(reach^2 - h^2) above the bottom one.
                lift = lift.max((reach * reach - h2).sqrt() - (pos[j].y - pos[i].y));
            }
        }
    }
    let mut sample = relaxed.clone();
    let height0: Vec<f64> = p.pos.iter().map(|x| (x.y - bx.lo.y) / l.y).collect();
    for (i, x) in pos.iter_mut().enumerate() {
        if body[i] == BODY_TOP_HALF {
            x.y += lift;
        }
    }
    sample.particles.pos = pos;
    sample.sim_box = crate::domain::SimBox::new(
        bx.lo,
        Vec3::new(bx.hi.x, bx.hi.y + lift, bx.hi.z),
        [true; 3],
    )?;
    sample.kind = format!("{} cut into two sliding halves", relaxed.kind);
    Ok(Geometry {
        sample,
        body,
        height0,
        shift,
        lift,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halves_are_shifted_and_lifted_clear_of_each_other() {
        // Random spheres stand in for a relaxed sample: the cut is geometry only.
        let cfg = SlidingConfig {
            d0_over_l: 0.1,
            material: super::super::SlidingMaterial {
                d_star: Some(0.3),
                ..Default::default()
            },
            ..SlidingConfig::default()
        };
        let mut p = crate::state::Particles::default();
        let mut s = 12345u64;
        let mut rnd = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..400 {
            let x = Vec3::new(rnd(), rnd(), 0.3 * rnd());
            p.push_sphere(x, 0.04 + 0.02 * rnd(), 1.0);
        }
        let bx =
            crate::domain::SimBox::new(Vec3::zeros(), Vec3::new(1.0, 1.0, 0.3), [true; 3]).unwrap();
        let g = build(&Sample::new(p, bx, 0.1, "random"), &cfg).unwrap();
        assert_eq!(g.shift, 0.5);
        assert!(g.lift > 0.0, "random spheres overlap across the cut");
        let q = &g.sample.particles;
        let gb = g.sample.sim_box;
        let mut closest = f64::INFINITY;
        for i in 0..q.len() {
            for j in 0..q.len() {
                if g.body[i] == BODY_BOTTOM_HALF && g.body[j] == BODY_TOP_HALF {
                    let d = gb.min_image(&q.pos[i], &q.pos[j]);
                    // Pairs across the cut (not across the periodic y boundary).
                    if (q.pos[i].y - 0.5).abs() < 0.2 && (q.pos[j].y - 0.5 - g.lift).abs() < 0.2 {
                        closest = closest.min(d.norm() - q.radius[i] - q.radius[j]);
                    }
                }
            }
        }
        // No overlap, and the lift is the least: some pair touches.
        assert!((-1e-12..1e-9).contains(&closest), "closest gap {closest}");
        assert!((gb.hi.y - 1.0 - g.lift).abs() < 1e-15);
        assert!(g.height0.iter().all(|&h| (0.0..1.0).contains(&h)));
    }
}
