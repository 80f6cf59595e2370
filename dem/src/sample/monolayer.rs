//! A quasi-2D monolayer: one triangular (hex) layer of spheres in the x-y plane, all centres at the
//! mid-plane z = L_z / 2 of a box periodic on every axis, run with `RunConfig::planar` so that nothing
//! leaves the plane. It is the DEM counterpart of the MD model material (a 2D LJ hex crystal,
//! `md-bridge::model`), whose nu = 1/3 no 3D packing with tangential springs reaches (nu <= 1/4).
//!
//! Lattice: spacing d0 along x, rows d0 sqrt(3)/2 apart along y (the close-packed rows along x, as
//! LAMMPS's `lattice hex` of the MD crystal), `nx` sites per row, `ny` rows (even, so that y is
//! periodic). With `polydispersity` p > 0 each diameter is d0 (1 + p u), u uniform in [-1, 1] from a
//! ChaCha8 stream of `seed`, on the same sites: the seed-to-seed disorder of a search (the MD's seeds
//! draw thermal velocities; a DEM run starts at rest). A polydisperse layer is prestressed until
//! relaxed (`scenario::monolayer::relax`).
//!
//! Mass: spheres of density `rho`. [`sphere_density`] gives the rho at which a d0 particle carries a
//! given areal density (mass per unit area) over its cell, sqrt(3)/2 d0^2, so that the DEM layer and
//! the MD crystal have the same mass per area and, with the same 2D modulus, the same sound speed.
//!
//! Thickness: L_z must keep a particle clear of its own periodic image (L_z >= 2 d_max, beyond any
//! pair's reach r_i + r_j + delta_f when delta_f < d). 2D stresses (force per length, as the MD card's)
//! are the 3D virial stresses times L_z.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::Sample;
use crate::domain::{BoxControl, SimBox};
use crate::error::{DemError, Result};
use crate::material::PairModel;
use crate::sim::{Parallelism, RunConfig, Simulation, TimeStep};
use crate::state::{Particles, MAX_PARTICLES};
use crate::Vec3;

/// Largest in-plane stress component over E (3D virial, the law's E) at which a relaxed layer is
/// taken as stress-free: far below the 1e-3 of the elastic measurements' strain.
pub const RELAX_TOLERANCE: f64 = 1e-9;
/// Steps a relaxation may take before it is reported as not converged (an error).
pub const RELAX_MAX_STEPS: u64 = 200_000;

/// Relaxes a (polydisperse) monolayer in the plane to zero in-plane stress: planar motion, global
/// damping 0.2 c_c (any damping reaches the same rest state; 0.2 settles a layer of 100 rows in a few
/// thousand steps), the box lengths along x and y driven by the in-plane stress (the relaxation phase 2
/// controller of paper 000 section 3.2), until |sigma_xx|, |sigma_yy| < [`RELAX_TOLERANCE`] E. A
/// monodisperse layer is already at rest and stress-free and is returned as it is.
pub fn relax_planar(sample: &Sample, model: &PairModel, par: Parallelism) -> Result<Sample> {
    let r = &sample.particles.radius;
    if r.iter().all(|&x| x == r[0]) {
        return Ok(sample.clone());
    }
    let e = model.material.young_modulus;
    let run = RunConfig {
        time_step: TimeStep::FractionOfCritical(0.1),
        global_damping: 0.2,
        planar: true,
        ..RunConfig::default()
    };
    let mut sim = Simulation::new(
        sample.particles.clone(),
        sample.sim_box,
        model.clone(),
        vec![],
        run,
        par,
    )?;
    sim.set_box_control(BoxControl::Stress {
        target: Vec3::zeros(),
        axes: [true, true, false],
        modulus: e,
        gain: 0.05,
        max_strain_step: 1e-4,
    })?;
    let mut worst = f64::INFINITY;
    while sim.step_count() < RELAX_MAX_STEPS {
        sim.run(200)?;
        let s = sim.virial_stress(None, None);
        worst = s[(0, 0)].abs().max(s[(1, 1)].abs()) / e;
        if worst < RELAX_TOLERANCE {
            break;
        }
    }
    if worst >= RELAX_TOLERANCE {
        return Err(DemError::InvalidConfig(format!(
            "hex monolayer: the relaxation did not reach |sigma| < {RELAX_TOLERANCE} E in \
             {RELAX_MAX_STEPS} steps (last {worst:.3e} E)"
        )));
    }
    let mut out = sample.clone();
    out.particles = sim.particles.clone();
    out.particles
        .vel
        .iter_mut()
        .for_each(|v| *v = Vec3::zeros());
    out.sim_box = sim.sim_box;
    out.kind = "relaxed hex monolayer".into();
    Ok(out)
}

/// Sphere density that gives a d0 particle the mass of its hex cell at `areal_density`.
pub fn sphere_density(areal_density: f64, d0: f64) -> f64 {
    areal_density * 3f64.sqrt() / 2.0 * d0 * d0 / (std::f64::consts::PI / 6.0 * d0.powi(3))
}

/// Site counts (nx, ny) whose periodic hex layer is closest to `lx` x `ly` (ny even, both >= 2).
pub fn counts_for(lx: f64, ly: f64, d0: f64) -> (usize, usize) {
    let nx = (lx / d0).round().max(2.0) as usize;
    let rows = ly / (d0 * 3f64.sqrt() / 2.0);
    let ny = ((rows / 2.0).round().max(1.0) as usize) * 2;
    (nx, ny)
}

/// The hex monolayer of about `lx` x `ly` (see the module docs), centres at z = `thickness` / 2.
pub fn hex_monolayer(
    lx: f64,
    ly: f64,
    d0: f64,
    thickness: f64,
    rho: f64,
    polydispersity: f64,
    seed: u64,
) -> Result<Sample> {
    let bad = |m: String| Err(DemError::InvalidConfig(format!("hex monolayer: {m}")));
    for (name, v) in [
        ("lx", lx),
        ("ly", ly),
        ("d0", d0),
        ("thickness", thickness),
        ("rho", rho),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return bad(format!("{name} = {v} must be positive"));
        }
    }
    if !(polydispersity.is_finite() && (0.0..0.5).contains(&polydispersity)) {
        return bad(format!(
            "polydispersity = {polydispersity} must lie in [0, 0.5)"
        ));
    }
    let d_max = d0 * (1.0 + polydispersity);
    if thickness < 2.0 * d_max {
        return bad(format!(
            "thickness {thickness} is below twice the largest diameter {d_max}: a particle would meet \
             its own periodic image across z"
        ));
    }
    let (nx, ny) = counts_for(lx, ly, d0);
    if nx.saturating_mul(ny) > MAX_PARTICLES {
        return bad(format!("{nx} x {ny} sites exceed {MAX_PARTICLES}"));
    }
    let dy = d0 * 3f64.sqrt() / 2.0;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut p = Particles::with_capacity(nx * ny);
    for j in 0..ny {
        let row_x = if j % 2 == 0 { 0.0 } else { 0.5 * d0 };
        for i in 0..nx {
            let x = Vec3::new(
                (i as f64 + 0.25) * d0 + row_x,
                (j as f64 + 0.25) * dy,
                0.5 * thickness,
            );
            let d = if polydispersity > 0.0 {
                d0 * (1.0 + polydispersity * rng.gen_range(-1.0..=1.0))
            } else {
                d0
            };
            p.push_sphere(x, 0.5 * d, rho);
        }
    }
    let bx = SimBox::new(
        Vec3::zeros(),
        Vec3::new(nx as f64 * d0, ny as f64 * dy, thickness),
        [true; 3],
    )?;
    let mut s = Sample::new(p, bx, d0, "hex monolayer");
    s.seed = (polydispersity > 0.0).then_some(seed);
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lattice_sites_areal_mass_and_plane() {
        let s = hex_monolayer(10.0, 9.0, 1.0, 3.0, sphere_density(0.9, 1.0), 0.0, 1).unwrap();
        let (nx, ny) = counts_for(10.0, 9.0, 1.0);
        assert_eq!((nx, ny), (10, 10));
        assert_eq!(s.particles.len(), 100);
        // Mass per area equals the areal density.
        let l = s.sim_box.lengths();
        let m: f64 = s.particles.mass.iter().sum();
        assert!((m / (l.x * l.y) - 0.9).abs() < 1e-12, "{}", m / (l.x * l.y));
        assert!(s.particles.pos.iter().all(|x| x.z == 1.5));
        // Every site has six neighbours at d0 across the periodic box.
        for i in [0, 37, 99] {
            let near = (0..100)
                .filter(|&j| {
                    j != i
                        && (s
                            .sim_box
                            .min_image(&s.particles.pos[i], &s.particles.pos[j])
                            .norm()
                            - 1.0)
                            .abs()
                            < 1e-9
                })
                .count();
            assert_eq!(near, 6);
        }
        let p = hex_monolayer(10.0, 9.0, 1.0, 3.0, 0.9, 0.05, 7).unwrap();
        let q = hex_monolayer(10.0, 9.0, 1.0, 3.0, 0.9, 0.05, 7).unwrap();
        assert_eq!(p.particles.radius, q.particles.radius);
        assert!(p
            .particles
            .radius
            .iter()
            .all(|&r| (0.475..=0.525).contains(&r)));
        assert!(hex_monolayer(10.0, 9.0, 1.0, 1.5, 0.9, 0.0, 1).is_err());
        assert!(hex_monolayer(10.0, 9.0, 1.0, 3.0, 0.9, 0.6, 1).is_err());
    }
}
