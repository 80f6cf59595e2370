//! Sample generators and editors (paper 000 sections 3.1-3.3):
//! - [`hcp`]: HCP lattices of equal spheres for the crystalline patch tests;
//! - [`sizes`]: seeded log-normal size distributions (paper 000, paper 004 variant);
//! - [`insert`]: random insertion into a periodic box up to a volume fraction;
//! - [`relax`](mod@relax): the two-phase relaxation of section 3.2 that turns an insertion into an amorphous solid;
//! - [`carve`]: keep or remove particles by shape and assign groups (walls, junctions);
//! - [`stats`]: volume fraction and coordination number;
//! - [`spec`]: sample recipes ([`SampleSpec`]) as scenarios and calibrations ask for them;
//! - [`Sample`]: a particle set with its box, saved and loaded as JSON so a relaxed sample is made once.

pub mod carve;
pub mod hcp;
pub mod insert;
pub mod monolayer;
pub mod relax;
pub mod sizes;
pub mod spec;
pub mod stats;

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::domain::SimBox;
use crate::error::{DemError, Result};
use crate::io::checkpoint::write_atomic;
use crate::state::Particles;

pub use carve::Shape;
pub use insert::{random_insertion, InsertionConfig};
pub use relax::{amorphous, relax, RelaxConfig, RelaxReport};
pub use sizes::SizeDistribution;
pub use spec::{make_sample, make_sample_resumable, SampleSpec};

/// Sample file format version, bumped when the layout changes.
const SAMPLE_VERSION: u32 = 1;

/// A particle set and its box, with how it was made.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Sample {
    /// File format version.
    pub version: u32,
    /// Particles (positions wrapped into the box, at rest once relaxed).
    pub particles: Particles,
    /// The box; fully periodic for generated samples.
    pub sim_box: SimBox,
    /// Nominal diameter d0 (the mode of the size distribution, or the lattice diameter).
    pub d0: f64,
    /// How the sample was made: "hcp", "random insertion", "relaxed" ...
    pub kind: String,
    /// Seed of the random generator, when one was used.
    #[serde(default)]
    pub seed: Option<u64>,
    /// Relaxation report, for relaxed samples.
    #[serde(default)]
    pub relaxation: Option<RelaxReport>,
}

impl Sample {
    /// A sample from its parts.
    pub fn new(particles: Particles, sim_box: SimBox, d0: f64, kind: &str) -> Self {
        Sample {
            version: SAMPLE_VERSION,
            particles,
            sim_box,
            d0,
            kind: kind.into(),
            seed: None,
            relaxation: None,
        }
    }

    /// An HCP block of about `lengths` (in box units) of spheres of diameter `d`: the counts are rounded to
    /// the nearest lattice-compatible values (even rows and layers). Fully periodic.
    pub fn hcp(lengths: crate::Vec3, d: f64, density: f64) -> Result<Self> {
        let (nx, ny, nz) = hcp::counts_for(lengths, d)?;
        let (p, bx) = hcp::hcp_lattice(nx, ny, nz, d, density, [true; 3])?;
        Ok(Sample::new(p, bx, d, "hcp"))
    }

    /// Volume fraction: solid volume over box volume.
    pub fn volume_fraction(&self) -> f64 {
        self.particles.solid_volume() / self.sim_box.volume()
    }

    /// Writes the sample as JSON (atomically; shortest round-trip floats, so loading is exact).
    pub fn save(&self, path: &Path) -> Result<()> {
        let bytes = serde_json::to_vec(self).map_err(|e| DemError::Format {
            path: path.display().to_string(),
            reason: e.to_string(),
        })?;
        write_atomic(path, &bytes)
    }

    /// Reads a sample written by [`Sample::save`], checking the version and the particles.
    pub fn load(path: &Path) -> Result<Self> {
        let bytes = std::fs::read(path).map_err(|e| DemError::io(path, e))?;
        let s: Sample = serde_json::from_slice(&bytes).map_err(|e| DemError::Format {
            path: path.display().to_string(),
            reason: e.to_string(),
        })?;
        if s.version != SAMPLE_VERSION {
            return Err(DemError::Format {
                path: path.display().to_string(),
                reason: format!(
                    "sample version {} but this build reads {SAMPLE_VERSION}",
                    s.version
                ),
            });
        }
        s.particles.validate()?;
        Ok(s)
    }
}
