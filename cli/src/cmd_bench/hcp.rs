//! The HCP workload: a periodic HCP packing of equal spheres compressed by 0.1 % of a diameter, so
//! that every sphere overlaps its 12 neighbours and nothing else lies within range (the next shell is
//! at sqrt(2) d), with small seeded random velocities. Table 4 material at nu = 0.15, d = 0.6 d_c.
//! LAMMPS gets the same spheres (their overlaps are its contacts), k_N and k_T of the pair.

use anyhow::Result;
use dem::RunConfig;
use validation::bench::{model, packing, SPACING};

use super::Prepared;
use validation::bench::lammps::System;

pub(super) fn prepare(cells: usize) -> Result<Prepared> {
    // The same packing as the report's performance section (validation::bench).
    let (p, bx) = packing(cells)?;
    let model = model();
    let r = p.radius[0];
    let pp = model.params(r, r, p.mass[0], p.mass[0]);
    let lammps = System {
        radius: p.radius.clone(),
        density: 1.0,
        k_n: pp.k_n,
        k_t: pp.k_t,
        skin: RunConfig::default().skin_fraction * SPACING,
    };
    Ok(Prepared {
        title: "cgdem bench: periodic HCP packing, 12 contacts per sphere, cohesive force with tangential history".into(),
        noun: "spheres",
        expect_pairs: Some(6 * p.len()),
        particles: p,
        sim_box: bx,
        model,
        lammps,
    })
}
