//! Random insertion (paper 000 section 3.2): particles with sizes from a [`SizeDistribution`] are placed
//! at uniformly random positions in a periodic box until their total volume reaches the requested
//! volume fraction (0.75 in the paper).
//!
//! At 0.75 the particles necessarily overlap (non-overlapping random insertion jams near 0.38): removing
//! the overlaps is the job of the first relaxation phase ([`relax`](mod@super::relax)). Insertion stops before the
//! particle that would exceed the target, so the fraction reached is the largest one not above it.
//! Each particle draws its diameter, then its position, from one ChaCha8 stream seeded by `seed`.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use super::sizes::SizeDistribution;
use super::Sample;
use crate::domain::SimBox;
use crate::error::{DemError, Result};
use crate::state::{Particles, MAX_PARTICLES};
use crate::Vec3;

/// What to insert.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InsertionConfig {
    /// Box edge lengths (engine units); the box is [0, L) on every axis, periodic.
    pub lengths: Vec3,
    /// Diameters.
    pub sizes: SizeDistribution,
    /// Target volume fraction; default 0.75, paper 000 section 3.2.
    #[serde(default = "default_fraction")]
    pub volume_fraction: f64,
    /// Particle density (masses are rescaled after relaxation anyway); default 1, Table 4.
    #[serde(default = "default_density")]
    pub density: f64,
    /// Seed of the ChaCha8 generator; default 1 (never taken from the OS, so samples are reproducible).
    #[serde(default = "default_seed")]
    pub seed: u64,
}

fn default_fraction() -> f64 {
    0.75
}
fn default_density() -> f64 {
    1.0
}
fn default_seed() -> u64 {
    1
}

/// Inserts particles at random as described in the module docs; returns a fully periodic sample.
pub fn random_insertion(cfg: &InsertionConfig) -> Result<Sample> {
    let sampler = cfg.sizes.sampler()?;
    let bx = SimBox::new(Vec3::zeros(), cfg.lengths, [true; 3])?;
    if !(cfg.volume_fraction.is_finite() && cfg.volume_fraction > 0.0 && cfg.volume_fraction < 1.5)
    {
        return Err(DemError::InvalidConfig(format!(
            "volume fraction {} must lie in (0, 1.5)",
            cfg.volume_fraction
        )));
    }
    if !(cfg.density.is_finite() && cfg.density > 0.0) {
        return Err(DemError::InvalidConfig(format!(
            "density {} must be positive",
            cfg.density
        )));
    }
    let d_min = cfg.sizes.min_diameter();
    let target = cfg.volume_fraction * bx.volume();
    let estimate = target / (std::f64::consts::PI / 6.0 * d_min.powi(3));
    if estimate > MAX_PARTICLES as f64 {
        return Err(DemError::InvalidConfig(format!(
            "about {estimate:.3e} particles requested, above the limit of {MAX_PARTICLES}"
        )));
    }
    let mut rng = ChaCha8Rng::seed_from_u64(cfg.seed);
    let mut p = Particles::with_capacity(estimate as usize + 1);
    let mut solid = 0.0;
    loop {
        let d = sampler.draw(&mut rng);
        let v = std::f64::consts::PI / 6.0 * d.powi(3);
        if solid + v > target {
            break;
        }
        let x = Vec3::new(
            rng.gen::<f64>() * cfg.lengths.x,
            rng.gen::<f64>() * cfg.lengths.y,
            rng.gen::<f64>() * cfg.lengths.z,
        );
        p.push_sphere(x, 0.5 * d, cfg.density);
        solid += v;
    }
    if p.is_empty() {
        return Err(DemError::InvalidConfig(format!(
            "box {:?} too small for one particle at volume fraction {}",
            cfg.lengths, cfg.volume_fraction
        )));
    }
    let d0 = match cfg.sizes {
        SizeDistribution::Monodisperse { diameter } => diameter,
        SizeDistribution::LogNormal { mode, .. } => mode,
    };
    // Memory order = space order, for the speed of everything that runs on the sample afterwards.
    p.sort_by_cells(bx.lo, bx.lengths(), d0);
    let mut s = Sample::new(p, bx, d0, "random insertion");
    s.seed = Some(cfg.seed);
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn insertion_reaches_the_fraction_and_is_seeded() {
        let cfg = InsertionConfig {
            lengths: Vec3::new(10.0, 10.0, 3.0),
            sizes: SizeDistribution::paper000_default(1.0),
            volume_fraction: 0.75,
            density: 1.0,
            seed: 3,
        };
        let a = random_insertion(&cfg).unwrap();
        let vf = a.volume_fraction();
        assert!(vf <= 0.75 && vf > 0.74, "{vf}");
        assert_eq!(a, random_insertion(&cfg).unwrap());
        let b = random_insertion(&InsertionConfig { seed: 4, ..cfg }).unwrap();
        assert_ne!(a.particles.pos, b.particles.pos);
        assert!(a
            .particles
            .pos
            .iter()
            .all(|x| (0..3).all(|k| x[k] >= 0.0 && x[k] < cfg.lengths[k])));
    }

    #[test]
    fn bad_insertions_are_refused() {
        let cfg = InsertionConfig {
            lengths: Vec3::new(1.0, 1.0, 1.0),
            sizes: SizeDistribution::Monodisperse { diameter: 1e-4 },
            volume_fraction: 0.75,
            density: 1.0,
            seed: 1,
        };
        assert!(random_insertion(&cfg).is_err(), "too many particles");
        assert!(random_insertion(&InsertionConfig {
            volume_fraction: f64::NAN,
            ..cfg
        })
        .is_err());
        let big = SizeDistribution::Monodisperse { diameter: 5.0 };
        assert!(random_insertion(&InsertionConfig { sizes: big, ..cfg }).is_err());
    }
}
