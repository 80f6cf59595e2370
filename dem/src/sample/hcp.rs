//! Hexagonal close-packed lattice of equal spheres.
//!
//! Layers are triangular lattices in the x-y plane (spacing d along x, rows d sqrt(3)/2 apart along y),
//! stacked ABAB along z with spacing d sqrt(2/3). Each sphere touches its 12 neighbours; the next shell
//! is at sqrt(2) d. With `nx` cells along x, `ny` rows (even) and `nz` layers (even) the lattice tiles a
//! periodic box of nx d x ny d sqrt(3)/2 x nz d sqrt(2/3).

use crate::domain::SimBox;
use crate::error::{DemError, Result};
use crate::state::{Particles, MAX_PARTICLES};
use crate::Vec3;

/// An HCP block of `nx * ny * nz` spheres of diameter `d` and density `rho`, with its periodic box.
pub fn hcp_lattice(
    nx: usize,
    ny: usize,
    nz: usize,
    d: f64,
    rho: f64,
    periodic: [bool; 3],
) -> Result<(Particles, SimBox)> {
    if nx == 0 || ny == 0 || nz == 0 || ny % 2 == 1 || nz % 2 == 1 {
        return Err(DemError::InvalidConfig(format!(
            "HCP lattice needs nx >= 1 and even ny, nz >= 2 (got {nx} x {ny} x {nz})"
        )));
    }
    if !(d.is_finite() && d > 0.0 && rho.is_finite() && rho > 0.0) {
        return Err(DemError::InvalidConfig(format!(
            "HCP diameter {d} and density {rho} must be positive"
        )));
    }
    let count = nx
        .checked_mul(ny)
        .and_then(|c| c.checked_mul(nz))
        .filter(|&c| c <= MAX_PARTICLES);
    let Some(count) = count else {
        return Err(DemError::InvalidConfig(format!(
            "HCP lattice of {nx} x {ny} x {nz} spheres is above the limit of {MAX_PARTICLES} particles"
        )));
    };
    let dy = d * 3f64.sqrt() / 2.0;
    let dz = d * (2.0f64 / 3.0).sqrt();
    let mut p = Particles::with_capacity(count);
    for k in 0..nz {
        // B layers sit over the centroids of A triangles.
        let (ox, oy) = if k % 2 == 0 {
            (0.0, 0.0)
        } else {
            (0.5 * d, d / (2.0 * 3f64.sqrt()))
        };
        for j in 0..ny {
            let row_x = if j % 2 == 0 { 0.0 } else { 0.5 * d };
            for i in 0..nx {
                let x = Vec3::new(
                    (i as f64 + 0.25) * d + row_x + ox,
                    (j as f64 + 0.25) * dy + oy,
                    (k as f64 + 0.5) * dz,
                );
                p.push_sphere(x, 0.5 * d, rho);
            }
        }
    }
    let hi = Vec3::new(nx as f64 * d, ny as f64 * dy, nz as f64 * dz);
    let mut bx = SimBox::new(Vec3::zeros(), hi, periodic)?;
    // Non-periodic axes: leave room for the outermost spheres.
    for a in 0..3 {
        if !periodic[a] {
            bx.lo[a] -= d;
            bx.hi[a] += d;
        }
    }
    for x in p.pos.iter_mut() {
        bx.wrap(x);
    }
    Ok((p, bx))
}

/// Lattice counts (nx, ny, nz) whose periodic HCP box is closest to `lengths` for diameter `d`: rows
/// and layers rounded to even numbers (at least 2), cells to at least 1.
pub fn counts_for(lengths: Vec3, d: f64) -> Result<(usize, usize, usize)> {
    if !(d.is_finite() && d > 0.0 && lengths.iter().all(|l| l.is_finite() && *l > 0.0)) {
        return Err(DemError::InvalidConfig(format!(
            "HCP block {lengths:?} of diameter {d} must be positive"
        )));
    }
    // Saturating float-to-int casts: an absurd ratio becomes a huge count that hcp_lattice refuses.
    let even = |x: f64| (2.0 * (0.5 * x).round()).max(2.0) as usize;
    let nx = (lengths.x / d).round().max(1.0) as usize;
    Ok((
        nx,
        even(lengths.y / (d * 3f64.sqrt() / 2.0)),
        even(lengths.z / (d * (2.0f64 / 3.0).sqrt())),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_sphere_has_twelve_touching_neighbours() {
        let (p, bx) = hcp_lattice(4, 4, 4, 1.0, 1.0, [true; 3]).unwrap();
        for i in 0..p.len() {
            let mut touching = 0;
            let mut next = f64::INFINITY;
            for j in 0..p.len() {
                if i == j {
                    continue;
                }
                let r = bx.min_image(&p.pos[i], &p.pos[j]).norm();
                if (r - 1.0).abs() < 1e-9 {
                    touching += 1;
                } else {
                    next = next.min(r);
                }
                assert!(r > 1.0 - 1e-9, "overlap {r}");
            }
            assert_eq!(touching, 12, "particle {i}");
            assert!(
                (next - 2f64.sqrt()).abs() < 1e-9,
                "second shell at sqrt 2: {next}"
            );
        }
    }

    #[test]
    fn counts_for_the_papers_slab() {
        // L = 25 d0, W = 3 d0 (paper 000 section 3.1): 25 cells, 28 rows, 4 layers.
        assert_eq!(
            counts_for(Vec3::new(25.0, 25.0, 3.0), 1.0).unwrap(),
            (25, 28, 4)
        );
        assert!(counts_for(Vec3::new(1.0, -1.0, 1.0), 1.0).is_err());
    }

    #[test]
    fn a_lattice_beyond_the_particle_limit_is_refused_before_allocating() {
        let (nx, ny, nz) = counts_for(Vec3::new(25.0, 25.0, 3e9), 1.0).unwrap();
        let e = hcp_lattice(nx, ny, nz, 1.0, 1.0, [true; 3]).unwrap_err();
        assert!(e.to_string().contains("limit"), "{e}");
        assert!(hcp_lattice(usize::MAX, 2, 2, 1.0, 1.0, [true; 3]).is_err());
    }
}
