//! Wear particles of a sliding layer (paper 004 section 3, Fig. 3): the clusters of layer material
//! that hold together and have lost every chain of bonds to both bodies.
//!
//! Fig. 3a shows wear particles that form, aggregate and reattach (the mixed regime), Fig. 3c large
//! wear particles "that grow in size until reaching the size of the system". The paper tells them by
//! eye. This is the measure behind that eye, the junction's cluster rule
//! ([`crate::outcome::cluster`]) applied between two frames of the run a window apart: a bond is a
//! pair within reach in the earlier frame that is still within reach, in the same periodic image, in
//! the later one; clusters of such bonds that hold no body particle are loose.
//!
//! Decision (bonds that persist over an interval, not bonds of one frame): a wear particle rolling
//! between the bodies touches both at every instant, so by the bonds of one frame it would hang on
//! them. Its contacts move as it rolls: over an interval in which the bodies slide several particle
//! diameters past each other, none of them persists, while the bonds inside it do. So the interval
//! must span a slide of a few d0 (the sliding runs use one profile window, 5 d0 or more of slide in
//! every shipped config). Material flowing in a shear band loses its bonds too, but falls apart into
//! small clusters; a *wear particle* is a loose cluster of at least `min_members` particles.
//!
//! Size: a loose cluster of N particles of total volume V_s fills V_s / phi_0 of the box (phi_0 the
//! relaxed volume fraction); in the quasi-2D box of thickness B it is a cylinder along z of
//! cross-section V_s / (phi_0 B), whose equivalent diameter d = sqrt(4 V_s / (pi phi_0 B)) is
//! compared with the system size L.

use serde::{Deserialize, Serialize};

use crate::error::{Result, WearError};
use crate::outcome::cluster::{loose_clusters, Bonding};

/// What the layer holds between two frames.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WearParticles {
    /// Fraction of the layer particles with no chain of persisting bonds to either body.
    pub detached: f64,
    /// Loose clusters of at least `min_members` particles: the wear particles.
    pub count: usize,
    /// Particles in the largest loose cluster, and its fraction of the layer.
    pub largest: usize,
    pub largest_fraction: f64,
    /// Equivalent diameter of the largest loose cluster (module docs), in length units.
    pub largest_diameter: f64,
}

impl WearParticles {
    /// The largest loose cluster's equivalent diameter if it is a wear particle (at least
    /// `min_members` particles), else 0: the size a run's summary and figures read.
    pub fn wear_particle_diameter(&self, min_members: usize) -> f64 {
        if self.largest >= min_members {
            self.largest_diameter
        } else {
            0.0
        }
    }
}

/// Where the layer is and how its clusters are sized.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LayerGeometry<'a> {
    /// Every particle's volume (indices as in the frames).
    pub volume: &'a [f64],
    /// Relaxed volume fraction phi_0 and the box's thickness B along z.
    pub volume_fraction: f64,
    pub thickness: f64,
}

/// The wear particles of `layer` between frames `earlier` and `later` (unwrapped positions of every
/// particle), anchored at the `bodies`' particles.
pub fn wear_particles(
    earlier: &[[f64; 3]],
    later: &[[f64; 3]],
    bonding: &Bonding,
    layer: &[usize],
    bodies: &[usize],
    geometry: &LayerGeometry,
    min_members: usize,
) -> Result<WearParticles> {
    let g = geometry;
    if g.volume.len() != earlier.len() {
        return Err(WearError::Frames(format!(
            "{} particle volumes for {} particles",
            g.volume.len(),
            earlier.len()
        )));
    }
    if !(g.volume_fraction > 0.0 && g.volume_fraction <= 1.0 && g.thickness > 0.0) {
        return Err(WearError::Setting(format!(
            "a wear-particle size needs a volume fraction in (0, 1] and a positive thickness \
             (phi_0 {}, B {})",
            g.volume_fraction, g.thickness
        )));
    }
    if min_members == 0 {
        return Err(WearError::Setting(
            "a wear particle needs at least one member".into(),
        ));
    }
    let loose = loose_clusters(earlier, later, bonding, layer, bodies)?;
    let count = loose
        .clusters
        .iter()
        .filter(|c| c.members >= min_members)
        .count();
    let (largest, largest_diameter) = match loose.clusters.first() {
        Some(c) => {
            let v: f64 = (0..later.len())
                .filter(|&i| loose.labels[i] == c.label)
                .map(|i| g.volume[i])
                .sum();
            let area = v / (g.volume_fraction * g.thickness);
            (c.members, (4.0 * area / std::f64::consts::PI).sqrt())
        }
        None => (0, 0.0),
    };
    Ok(WearParticles {
        detached: loose.detached_members as f64 / layer.len() as f64,
        count,
        largest,
        largest_fraction: largest as f64 / layer.len() as f64,
        largest_diameter,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::outcome::cluster::Periodicity;

    /// Unit spheres on a square grid in x-y (spacing 1, one layer in z): rows 0 and `rows - 1` are
    /// the bodies.
    fn grid(cols: usize, rows: usize) -> Vec<[f64; 3]> {
        (0..rows)
            .flat_map(|r| (0..cols).map(move |c| [c as f64, r as f64, 0.0]))
            .collect()
    }

    fn bonding(n: usize) -> Bonding {
        Bonding {
            radii: Some(vec![0.5; n]),
            margin: 0.1,
            periodicity: Periodicity([Some(100.0), None, None]),
        }
    }

    #[test]
    fn a_block_torn_from_both_bodies_is_one_wear_particle_of_its_size() {
        let (cols, rows) = (20, 12);
        let first = grid(cols, rows);
        let n = first.len();
        let bodies: Vec<usize> = (0..cols).chain((rows - 1) * cols..n).collect();
        let layer: Vec<usize> = (cols..(rows - 1) * cols).collect();
        // A 4 x 4 block (columns 5-8, rows 4-7) is carried 3 along x and 0.5 up: it keeps its inner
        // bonds and loses those to the rest, which stays in place.
        let block = |i: usize| (5..9).contains(&(i % cols)) && (4..8).contains(&(i / cols));
        let later: Vec<[f64; 3]> = first
            .iter()
            .enumerate()
            .map(|(i, p)| {
                if block(i) {
                    [p[0] + 3.0, p[1] + 0.5, 0.0]
                } else {
                    *p
                }
            })
            .collect();
        let volume = vec![1.0; n];
        let geo = LayerGeometry {
            volume: &volume,
            volume_fraction: 0.5,
            thickness: 2.0,
        };
        let w = wear_particles(&first, &later, &bonding(n), &layer, &bodies, &geo, 5).unwrap();
        assert_eq!(w.largest, 16);
        assert_eq!(w.count, 1);
        assert_eq!(w.detached, 16.0 / layer.len() as f64);
        assert_eq!(w.largest_fraction, w.detached);
        // 16 volumes at phi_0 = 1/2 through B = 2 fill a cross-section of 16.
        let d = (4.0 * 16.0 / std::f64::consts::PI).sqrt();
        assert!((w.largest_diameter - d).abs() < 1e-12);
        assert_eq!(w.wear_particle_diameter(16), w.largest_diameter);
        // Below the size threshold it is still the largest loose cluster, but not a wear particle.
        let w = wear_particles(&first, &later, &bonding(n), &layer, &bodies, &geo, 17).unwrap();
        assert_eq!((w.count, w.largest), (0, 16));
        assert_eq!(w.wear_particle_diameter(17), 0.0);
    }

    #[test]
    fn an_intact_layer_has_no_wear_particle_and_a_sheared_one_only_crumbs() {
        let (cols, rows) = (20, 12);
        let first = grid(cols, rows);
        let n = first.len();
        let bodies: Vec<usize> = (0..cols).chain((rows - 1) * cols..n).collect();
        let layer: Vec<usize> = (cols..(rows - 1) * cols).collect();
        let volume = vec![1.0; n];
        let geo = LayerGeometry {
            volume: &volume,
            volume_fraction: 0.6,
            thickness: 1.0,
        };
        let w = wear_particles(&first, &first, &bonding(n), &layer, &bodies, &geo, 5).unwrap();
        assert_eq!((w.detached, w.count, w.largest), (0.0, 0, 0));
        assert_eq!(w.largest_diameter, 0.0);
        // Simple shear of the rows between the bodies, one column per row: every vertical bond
        // breaks, every row keeps its horizontal ones and so stays a chain of 20 spanning the
        // period; a scramble of each row's order on top breaks them too. What is left are single
        // particles: many loose, none a wear particle.
        let later: Vec<[f64; 3]> = first
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let (c, r) = (i % cols, i / cols);
                if r == 0 || r == rows - 1 {
                    *p
                } else {
                    let c2 = (c * 7) % cols;
                    [c2 as f64 + r as f64 * 0.5, p[1], 0.0]
                }
            })
            .collect();
        let w = wear_particles(&first, &later, &bonding(n), &layer, &bodies, &geo, 5).unwrap();
        assert_eq!(w.count, 0);
        assert!(w.detached > 0.9, "{}", w.detached);
        assert!(w.largest < 5, "{}", w.largest);
    }

    #[test]
    fn bad_geometry_is_an_error() {
        let first = grid(4, 4);
        let volume = vec![1.0; 16];
        let geo = |phi: f64, b: f64| LayerGeometry {
            volume: &volume,
            volume_fraction: phi,
            thickness: b,
        };
        let b = bonding(16);
        let layer: Vec<usize> = (4..12).collect();
        assert!(wear_particles(&first, &first, &b, &layer, &[0], &geo(0.0, 1.0), 5).is_err());
        assert!(wear_particles(&first, &first, &b, &layer, &[0], &geo(0.5, -1.0), 5).is_err());
        assert!(wear_particles(&first, &first, &b, &layer, &[0], &geo(0.5, 1.0), 0).is_err());
        assert!(wear_particles(&first, &first[..8], &b, &layer, &[0], &geo(0.5, 1.0), 5).is_err());
        let short = LayerGeometry {
            volume: &volume[..3],
            ..geo(0.5, 1.0)
        };
        assert!(wear_particles(&first, &first, &b, &layer, &[0], &short, 5).is_err());
    }
}
