//! Particle state as structure-of-arrays: each attribute is one contiguous vector, so the force and
//! integration loops stream through exactly the data they need.

use serde::{Deserialize, Serialize};

use crate::error::{DemError, Result};
use crate::Vec3;

/// Largest particle count the sample generators make: a configuration that asks for more (a box
/// lengths typed in the wrong unit, say) is refused before it exhausts memory. At ~1 KB of state,
/// neighbour list and scratch per particle, 5e7 particles already take ~50 GB.
pub const MAX_PARTICLES: usize = 50_000_000;

/// Moment of inertia of a solid sphere, 2/5 m r^2.
#[inline]
pub fn sphere_inertia(mass: f64, radius: f64) -> f64 {
    0.4 * mass * radius * radius
}

/// Volume of a sphere.
#[inline]
pub fn sphere_volume(radius: f64) -> f64 {
    4.0 / 3.0 * std::f64::consts::PI * radius.powi(3)
}

/// Mass of a sphere of density `rho`. Written out rather than as `rho * sphere_volume(radius)`: the
/// products in this order are what every sample and cached result was made with (another order
/// changes masses in the last bit for rho != 1).
#[inline]
pub fn sphere_mass(rho: f64, radius: f64) -> f64 {
    rho * 4.0 / 3.0 * std::f64::consts::PI * radius.powi(3)
}

/// All particles of a simulation. Index `i` in every vector is the same particle.
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
pub struct Particles {
    /// Centre positions (not wrapped between neighbour-list rebuilds).
    pub pos: Vec<Vec3>,
    /// Translational velocities.
    pub vel: Vec<Vec3>,
    /// Angular velocities.
    pub omega: Vec<Vec3>,
    /// Radii.
    pub radius: Vec<f64>,
    /// Masses.
    pub mass: Vec<f64>,
    /// Moments of inertia (solid spheres unless set otherwise).
    pub inertia: Vec<f64>,
    /// Group index of each particle (0 is the default group of free particles).
    pub group: Vec<u32>,
}

impl Particles {
    /// Empty set with room for `n` particles.
    pub fn with_capacity(n: usize) -> Self {
        Particles {
            pos: Vec::with_capacity(n),
            vel: Vec::with_capacity(n),
            omega: Vec::with_capacity(n),
            radius: Vec::with_capacity(n),
            mass: Vec::with_capacity(n),
            inertia: Vec::with_capacity(n),
            group: Vec::with_capacity(n),
        }
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.pos.len()
    }

    /// Whether there are no particles.
    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }

    /// Adds a solid sphere at rest of density `rho`, in group 0; returns its index.
    pub fn push_sphere(&mut self, pos: Vec3, radius: f64, rho: f64) -> usize {
        let m = sphere_mass(rho, radius);
        self.pos.push(pos);
        self.vel.push(Vec3::zeros());
        self.omega.push(Vec3::zeros());
        self.radius.push(radius);
        self.mass.push(m);
        self.inertia.push(sphere_inertia(m, radius));
        self.group.push(0);
        self.len() - 1
    }

    /// Rescales all masses and inertias by `factor` (used to hit a target bulk density).
    pub fn scale_masses(&mut self, factor: f64) {
        self.mass.iter_mut().for_each(|m| *m *= factor);
        self.inertia.iter_mut().for_each(|m| *m *= factor);
    }

    /// Reorders the particles so that neighbours in space are neighbours in memory: by cells of edge
    /// `cell` (at least one diameter is a good choice) over the box from `lo` with edges `lengths`,
    /// the axis with the most cells first and the one with the fewest last (ties in z, y, x order, so
    /// a cube is sorted by z, then y, then x), ties kept in their current order. Randomly inserted
    /// samples otherwise scatter every particle's partners over the whole array, which halves the
    /// force loop's speed on 50 000 particles (cache misses, and most pairs reaching outside their
    /// force block).
    ///
    /// Why the longest axis leads: the force blocks are runs of this order, and a pair whose
    /// partner lies two blocks or more ahead is parked (`force::compute`). With the thin axis of a
    /// quasi-2D box (3 d0, the sliding and junction boxes) leading, the order is three slabs of a
    /// third of the system each, a pair between slabs reaches a third or two thirds of the system
    /// ahead, and with four blocks most of those are parked; with the thin axis last a pair reaches
    /// one row of cells ahead. Deterministic; returns the permutation applied (`new index k` holds
    /// the particle that was at `order[k]`).
    pub fn sort_by_cells(&mut self, lo: Vec3, lengths: Vec3, cell: f64) -> Vec<usize> {
        let cells = |a: usize| (lengths[a] / cell).ceil();
        let mut axes = [2usize, 1, 0];
        // Stable: equal counts keep z, y, x.
        axes.sort_by(|&a, &b| cells(b).total_cmp(&cells(a)));
        let key = |x: &Vec3| {
            let c = |a: usize| ((x[a] - lo[a]) / cell).floor().max(0.0) as u64;
            (c(axes[0]), c(axes[1]), c(axes[2]))
        };
        let mut order: Vec<usize> = (0..self.len()).collect();
        order.sort_by_key(|&i| key(&self.pos[i]));
        self.reorder(&order);
        order
    }

    /// Stores the particles in another order: new index `k` holds the particle that was at `order[k]`.
    /// `order` must be a permutation of `0..len()`; anything else is refused.
    pub fn permute(&mut self, order: &[usize]) -> Result<()> {
        let mut seen = vec![false; self.len()];
        let valid = order.len() == self.len()
            && order
                .iter()
                .all(|&i| i < seen.len() && !std::mem::replace(&mut seen[i], true));
        if !valid {
            return Err(DemError::InvalidConfig(format!(
                "a reordering of {} particles must list each index once",
                self.len()
            )));
        }
        self.reorder(order);
        Ok(())
    }

    /// [`Particles::permute`] for an order known to be a permutation.
    fn reorder(&mut self, order: &[usize]) {
        fn apply<T: Clone>(v: &mut Vec<T>, order: &[usize]) {
            *v = order.iter().map(|&i| v[i].clone()).collect();
        }
        apply(&mut self.pos, order);
        apply(&mut self.vel, order);
        apply(&mut self.omega, order);
        apply(&mut self.radius, order);
        apply(&mut self.mass, order);
        apply(&mut self.inertia, order);
        apply(&mut self.group, order);
    }

    /// Keeps only the particles for which `keep(i)` is true, preserving order.
    pub fn retain(&mut self, mut keep: impl FnMut(usize) -> bool) {
        let mask: Vec<bool> = (0..self.len()).map(&mut keep).collect();
        fn filter<T: Clone>(v: &mut Vec<T>, mask: &[bool]) {
            let mut k = 0;
            v.retain(|_| {
                k += 1;
                mask[k - 1]
            });
        }
        filter(&mut self.pos, &mask);
        filter(&mut self.vel, &mask);
        filter(&mut self.omega, &mask);
        filter(&mut self.radius, &mask);
        filter(&mut self.mass, &mask);
        filter(&mut self.inertia, &mask);
        filter(&mut self.group, &mask);
    }

    /// Total volume of the spheres.
    pub fn solid_volume(&self) -> f64 {
        self.radius.iter().map(|&r| sphere_volume(r)).sum()
    }

    /// Checks lengths and that every attribute is finite and physical.
    pub fn validate(&self) -> Result<()> {
        let n = self.len();
        let lens = [
            self.vel.len(),
            self.omega.len(),
            self.radius.len(),
            self.mass.len(),
            self.inertia.len(),
            self.group.len(),
        ];
        if lens.iter().any(|&l| l != n) {
            return Err(DemError::InvalidConfig(format!(
                "particle arrays have different lengths: pos {n}, others {lens:?}"
            )));
        }
        for i in 0..n {
            let bad = |reason: String| Err(DemError::InvalidParticle { index: i, reason });
            if !(self.radius[i].is_finite() && self.radius[i] > 0.0) {
                return bad(format!("radius {} must be positive", self.radius[i]));
            }
            if !(self.mass[i].is_finite() && self.mass[i] > 0.0) {
                return bad(format!("mass {} must be positive", self.mass[i]));
            }
            if !(self.inertia[i].is_finite() && self.inertia[i] > 0.0) {
                return bad(format!(
                    "moment of inertia {} must be positive",
                    self.inertia[i]
                ));
            }
            let vecs = [
                ("position", self.pos[i]),
                ("velocity", self.vel[i]),
                ("angular velocity", self.omega[i]),
            ];
            for (what, v) in vecs {
                if !v.iter().all(|x| x.is_finite()) {
                    return bad(format!("{what} {v:?} is not finite"));
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sorting_by_cells_orders_space_and_keeps_each_particle_whole() {
        let mut p = Particles::default();
        let xs = [
            (2.5, 0.1, 0.2),
            (0.5, 0.1, 1.5),
            (0.2, 0.3, 0.1),
            (1.5, 0.0, 0.0),
        ];
        for (k, &(x, y, z)) in xs.iter().enumerate() {
            let i = p.push_sphere(Vec3::new(x, y, z), 0.1 + k as f64, 1.0);
            p.group[i] = k as u32;
        }
        let order = p.sort_by_cells(Vec3::zeros(), Vec3::new(3.0, 3.0, 3.0), 1.0);
        // z cell first (particle 1 is in the second z layer), then x along the first row.
        assert_eq!(order, vec![2, 3, 0, 1]);
        for (k, &from) in order.iter().enumerate() {
            assert_eq!(p.group[k], from as u32);
            assert_eq!(p.radius[k], 0.1 + from as f64);
            assert_eq!(p.pos[k].x, xs[from].0);
        }
    }

    #[test]
    fn a_thin_axis_varies_fastest_in_the_cell_order() {
        // A quasi-2D box 4 x 4 x 1 cells: y leads, then x, and the thin z comes last, so a pair
        // across the thin axis stays one row of cells apart in memory.
        let mut p = Particles::default();
        let xs = [
            (1.5, 0.2, 0.9),
            (0.5, 0.2, 0.1),
            (0.5, 1.5, 0.5),
            (0.2, 0.3, 0.8),
        ];
        for &(x, y, z) in &xs {
            p.push_sphere(Vec3::new(x, y, z), 0.1, 1.0);
        }
        let order = p.sort_by_cells(Vec3::zeros(), Vec3::new(4.0, 4.0, 1.0), 1.0);
        // Row y = 0: cell x = 0 holds 1 and 3 (kept in their order), then x = 1 holds 0; row y = 1: 2.
        assert_eq!(order, vec![1, 3, 0, 2]);
        // The z-major cube order of a box whose thin axis is x: z, then y, then x as for a cube.
        let mut q = Particles::default();
        for &(x, y, z) in &xs {
            q.push_sphere(Vec3::new(0.1 * x, y, z), 0.1, 1.0);
        }
        let order = q.sort_by_cells(Vec3::zeros(), Vec3::new(1.0, 4.0, 4.0), 1.0);
        // (All in z cell 0 and x cell 0: by y, ties in their order.)
        assert_eq!(order, vec![0, 1, 3, 2]);
    }

    #[test]
    fn permute_moves_whole_particles_and_refuses_non_permutations() {
        let mut p = Particles::default();
        for k in 0..3 {
            p.push_sphere(Vec3::new(k as f64, 0.0, 0.0), 1.0 + k as f64, 1.0);
        }
        p.permute(&[2, 0, 1]).unwrap();
        assert_eq!(p.pos[0].x, 2.0);
        assert_eq!(p.radius[0], 3.0);
        assert_eq!(p.radius[1], 1.0);
        for bad in [&[0, 1][..], &[0, 1, 1], &[0, 1, 3]] {
            assert!(matches!(p.permute(bad), Err(DemError::InvalidConfig(_))));
        }
        assert_eq!(
            p.radius,
            vec![3.0, 1.0, 2.0],
            "a refused order changes nothing"
        );
    }

    #[test]
    fn retain_keeps_columns_aligned() {
        let mut p = Particles::default();
        for k in 0..5 {
            p.push_sphere(Vec3::new(k as f64, 0.0, 0.0), 1.0 + k as f64, 1.0);
        }
        p.retain(|i| i % 2 == 0);
        assert_eq!(p.len(), 3);
        assert_eq!(p.radius, vec![1.0, 3.0, 5.0]);
        assert_eq!(p.pos[2].x, 4.0);
        assert!((p.mass[1] - sphere_mass(1.0, 3.0)).abs() < 1e-12);
    }

    #[test]
    fn validate_rejects_bad_particles() {
        let mut p = Particles::default();
        p.push_sphere(Vec3::zeros(), 1.0, 1.0);
        assert!(p.validate().is_ok());
        p.radius[0] = -1.0;
        assert!(matches!(
            p.validate(),
            Err(DemError::InvalidParticle { index: 0, .. })
        ));
        p.radius[0] = 1.0;
        p.vel[0].y = f64::NAN;
        assert!(p.validate().unwrap_err().to_string().contains("velocity"));
    }
}
