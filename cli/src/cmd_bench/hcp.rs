//! The HCP workload: a periodic HCP packing of equal spheres compressed by 0.1 % of a diameter, so
//! that every sphere overlaps its 12 neighbours and nothing else lies within range (the next shell is
//! at sqrt(2) d), with small seeded random velocities. Table 4 material at nu = 0.15, d = 0.6 d_c.
//! LAMMPS gets the same spheres (their overlaps are its contacts), k_N and k_T of the pair.

use anyhow::Result;
use dem::sample::hcp::hcp_lattice;
use dem::state::{sphere_inertia, sphere_mass};
use dem::{Material, PairModel, RunConfig};
use rand::{Rng, SeedableRng};

use super::lammps::System;
use super::Prepared;

/// Sphere diameter (lattice spacing): 0.6 d_c for Table 4, so delta_f = d/3 reaches neither the
/// second shell nor beyond.
const SPACING: f64 = 90.0;
/// Overlap of touching neighbours, as a fraction of the spacing.
const SQUEEZE: f64 = 1e-3;

pub(super) fn prepare(cells: usize) -> Result<Prepared> {
    let nz = (cells * 4 / 5).max(2) & !1;
    let (mut p, bx) = hcp_lattice(cells, cells & !1, nz, SPACING, 1.0, [true; 3])?;
    let r = 0.5 * SPACING * (1.0 + SQUEEZE);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2024);
    for i in 0..p.len() {
        p.radius[i] = r;
        p.mass[i] = sphere_mass(1.0, r);
        p.inertia[i] = sphere_inertia(p.mass[i], r);
        for a in 0..3 {
            p.vel[i][a] = 0.01 * (2.0 * rng.gen::<f64>() - 1.0);
        }
    }
    let model = PairModel::cohesive(Material::table4(0.15));
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
