//! Patch tests of paper 000 section 3 (Fig. 4): a periodic sample (HCP lattice or relaxed amorphous
//! solid) gets two rigid walls, the particles within `wall_thickness` of the bottom and top faces normal
//! to y; x and z stay periodic, y becomes open.
//!
//! - [`elastic`](mod@elastic): confined uniaxial compression (Fig. 4a): the top wall pressed with traction 0.01 E,
//!   dt = 0.1 dt_c, global damping 0.2 c_c; at rest, C11 = d sigma_yy / d eps_yy and
//!   C12 = d sigma_xx / d eps_yy give nu = C12 / (C11 + C12) and E = C11 (1 + nu)(1 - 2 nu) / (1 - nu).
//! - [`strength`](mod@strength): the top wall driven at strain rate 1e-5 / dt along y (tension) or x (shear), damping
//!   0.01 c_c; the strength is the peak virial stress of the deformable part (Fig. 4b-c). The tensile
//!   run continues to complete separation and gives the fracture energy.
//! - [`compaction`](mod@compaction): not in the paper: the top wall pressed with 0.01 E and dragged along x, to see
//!   whether the packing holds its volume when it flows (the check the junction needs of a card).
//!
//! Conventions shared by the tests:
//! - strain: eps = (change of the wall separation) / L0, with L0 the gap between the innermost wall
//!   particle centres (the length the deformation acts on; the walls are rigid);
//! - stress: virial stress (tension positive) of the free particles, over their share of the sample
//!   volume V_free = V_box N_free / N, stretched by (1 + eps_yy). For an HCP lattice this is exactly the
//!   bond-layer stress: the half-weighted wall bonds complete the free rows.

pub mod compaction;
pub mod curve;
pub mod elastic;
pub mod strength;
pub mod suite;

use serde::{Deserialize, Serialize};

use crate::material::{PairCoefficients, PairModel};
use crate::sample::Sample;
use crate::scenario::rig::RigSpec;

pub use crate::io::progress::ProgressFile;
pub use compaction::{compaction, CompactionConfig, CompactionResult};
pub use curve::{Curve, CurvePoint};
pub use elastic::{elastic, ElasticConfig, ElasticResult};
pub use strength::{
    strength, strength_resumable, FractureResult, StrengthConfig, StrengthMode, StrengthResult,
};
pub use suite::{run_suite, ModelSource, PatchReport, PatchSuite};

/// The two rigid walls of every patch test.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct WallConfig {
    /// Wall thickness in units of the largest interaction range (d_max + delta_f,max); default 1.05: a
    /// free particle then never sees past a wall, and the walls stay as thin as that allows.
    pub thickness: f64,
}

impl WallConfig {
    /// The rig of the patch tests: walls normal to y, shear along x, `thickness` times the largest
    /// interaction range of `sample` under `model`.
    pub(crate) fn rig_spec(&self, sample: &Sample, model: &PairModel) -> RigSpec {
        let r_max = sample.particles.radius.iter().cloned().fold(0.0, f64::max);
        RigSpec::y_normal(self.thickness * PairCoefficients::new(model).max_cutoff(r_max))
    }
}

impl Default for WallConfig {
    fn default() -> Self {
        WallConfig { thickness: 1.05 }
    }
}

/// Target strength of eq (20) for particles of diameter d0: sigma (d0 / d_c)^(-s) above d_c.
pub fn target_strength(strength: f64, d0: f64, d_c: f64, s: f64) -> f64 {
    if d0 > d_c {
        strength * (d0 / d_c).powf(-s)
    } else {
        strength
    }
}
