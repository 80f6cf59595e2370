//! Sample statistics: volume fraction and coordination numbers (paper 000 section 3.2, Fig. 7).
//!
//! Two coordination numbers are reported, both as 2 (number of pairs) / (number of particles):
//! - *interacting*: pairs within their interaction range, delta_N < delta_f (12 in an HCP lattice);
//! - *contacts*: pairs touching or overlapping, delta_N <= `contact_tolerance` * (r_i + r_j).
//!
//! Decision: in a relaxed amorphous sample most bonded pairs sit at small positive delta_N (paper 000
//! section 3.2 explains the lower strengths by it), so the contact count depends on the tolerance while
//! the interacting count does not; the latter is the one that controls the elastic properties.

use serde::{Deserialize, Serialize};

use crate::domain::SimBox;
use crate::error::Result;
use crate::material::{PairCoefficients, PairModel};
use crate::neighbor::NeighborList;
use crate::state::Particles;

/// Coordination statistics of a particle set.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Coordination {
    /// Mean number of partners within the interaction range.
    pub interacting: f64,
    /// Mean number of partners in contact (within the tolerance).
    pub contacts: f64,
    /// Particles with no partner in range.
    pub isolated: usize,
}

/// Coordination numbers of `particles` in `bx` under the cohesive ranges of `model`.
pub fn coordination(
    particles: &Particles,
    bx: &SimBox,
    model: &PairModel,
    contact_tolerance: f64,
) -> Result<Coordination> {
    model.validate()?;
    let coef = PairCoefficients::new(model);
    let mut pos = particles.pos.clone();
    let mut list = NeighborList::new(0.0)?;
    list.build(&mut pos, &particles.radius, bx, &coef)?;
    let n = particles.len();
    let mut degree = vec![0u32; n];
    let (mut inter, mut contact) = (0usize, 0usize);
    for p in 0..list.len() {
        let (i, j) = (list.i[p] as usize, list.j[p] as usize);
        let (ri, rj) = (particles.radius[i], particles.radius[j]);
        let dist = (pos[j] + bx.shift(list.image[p]) - pos[i]).norm();
        if dist < coef.cutoff(ri, rj) {
            inter += 1;
            degree[i] += 1;
            degree[j] += 1;
            if dist - ri - rj <= contact_tolerance * (ri + rj) {
                contact += 1;
            }
        }
    }
    let nf = n.max(1) as f64;
    Ok(Coordination {
        interacting: 2.0 * inter as f64 / nf,
        contacts: 2.0 * contact as f64 / nf,
        isolated: degree.iter().filter(|&&d| d == 0).count(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Material;
    use crate::sample::hcp::hcp_lattice;

    #[test]
    fn hcp_has_twelve() {
        let (p, bx) = hcp_lattice(6, 6, 4, 90.0, 1.0, [true; 3]).unwrap();
        let c = coordination(&p, &bx, &PairModel::cohesive(Material::table4(0.15)), 1e-9).unwrap();
        assert!(
            (c.interacting - 12.0).abs() < 1e-12 && (c.contacts - 12.0).abs() < 1e-12,
            "{c:?}"
        );
        assert_eq!(c.isolated, 0);
    }
}
