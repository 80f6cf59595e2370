//! LAMMPS decks of the same contact loop without wear: paper 001 ran LAMMPS's granular package, and
//! these inputs set up what our loop computes when no sphere flows, for a cross-check of the contact
//! law (tests) and for the cost comparison (`cgdem bench-plastic`).
//!
//! The surface spheres are granular atoms of type 1 that nothing integrates (frozen), the projectile
//! is one atom of type 2 integrated by `fix nve/sphere` (impact) or moved by `fix move linear V_x 0
//! NULL` under `fix addforce` (slide: x and y prescribed, z free under the load, no rotation).
//! `pair_style granular` with `hertz/material E 0 nu` (no normal damping) and `tangential
//! linear_history k_t 0 mu` (no tangential damping); surface-surface pairs are excluded from the
//! neighbour list. LAMMPS mixes the two types' moduli: it is given E for our default contact modulus
//! and 2E for the rigid-projectile one, so that both meet the same E*. Units SI. The last line prints
//! the projectile's velocity and spin as `RESULT vx vy vz wx wy wz`.

use std::fmt::Write as _;

use super::impact::{impact_rig, ImpactConfig};
use super::model::{ContactModulus, PlasticModel};
use super::rig::Rig;
use super::scratch::{scratch_rig, ScratchConfig};
use crate::error::Result;

/// A LAMMPS input with its data file (the input reads `data_file`).
#[derive(Debug, Clone, PartialEq)]
pub struct LammpsDeck {
    pub input: String,
    pub data: String,
    /// Steps the input runs and its time step (s).
    pub steps: u64,
    pub dt: f64,
}

/// The file name the input reads its atoms from.
pub const DATA_FILE: &str = "surface.data";

/// The elastic impact of `cfg` (LAMMPS cannot wear) for `steps` steps.
pub fn impact_deck(cfg: &ImpactConfig, steps: u64) -> Result<LammpsDeck> {
    let rig = impact_rig(cfg)?;
    let fixes = "fix move proj nve/sphere\n".to_string();
    Ok(deck(
        &rig,
        &cfg.model,
        cfg.projectile.density,
        &fixes,
        steps,
    ))
}

/// The slide of `cfg` under `load` (N) with the indenter `depth` (m) below first touch at the start,
/// for `steps` steps.
pub fn slide_deck(cfg: &ScratchConfig, load: f64, depth: f64, steps: u64) -> Result<LammpsDeck> {
    let (mut rig, _) = scratch_rig(cfg, load)?;
    let u = rig.q.units;
    rig.st.body.pos.z = rig.st.surface.top() + rig.q.reach - u.length_from_m(depth);
    rig.st.body.vel = crate::Vec3::zeros();
    let fixes = format!(
        "fix move proj move linear {v:e} 0.0 NULL\nfix load proj addforce 0.0 0.0 {f:e}\n",
        v = cfg.slide.speed,
        f = -load
    );
    Ok(deck(&rig, &cfg.model, cfg.indenter.density, &fixes, steps))
}

fn deck(rig: &Rig, model: &PlasticModel, density: f64, fixes: &str, steps: u64) -> LammpsDeck {
    let u = rig.q.units;
    let m = |x: f64| u.length_to_m(x);
    let s = &rig.st.surface;
    let b = &rig.st.body;
    let n = s.len();
    let top = m(b.pos.z) + 2.0 * m(rig.q.radius);
    let mut data = format!(
        "# paper 001 surface and projectile (cgdem)\n\n{} atoms\n2 atom types\n\n\
         {:e} {:e} xlo xhi\n{:e} {:e} ylo yhi\n{:e} {:e} zlo zhi\n\nAtoms # sphere\n\n",
        n + 1,
        0.0,
        m(s.length()),
        0.0,
        m(s.width()),
        m(s.z0 - 2.0 * s.radius) - 0.01,
        top
    );
    // Surface spheres: their density only sets a mass nothing uses (they are never integrated).
    for i in 0..n {
        let _ = writeln!(
            data,
            "{} 1 {:e} 8000 {:e} {:e} {:e}",
            i + 1,
            2.0 * m(s.radius),
            m(s.x[i]),
            m(s.y[i]),
            m(s.z[i])
        );
    }
    let _ = writeln!(
        data,
        "{} 2 {:e} {:e} {:e} {:e} {:e}",
        n + 1,
        2.0 * m(rig.q.radius),
        density,
        m(b.pos.x),
        m(b.pos.y),
        m(b.pos.z)
    );
    let e_lmp = match model.contact_modulus {
        ContactModulus::Lammps => model.young_modulus,
        ContactModulus::Rigid => 2.0 * model.young_modulus,
    };
    let k_t = u.force_to_n(rig.q.k_t) / u.length_to_m(1.0);
    let dt = u.time_to_s(rig.dt);
    let v = u.velocity_to_m_s(1.0);
    let id = n + 1;
    let input = format!(
        "# The contact loop of paper 001 without wear (cgdem)\n\
units si\n\
atom_style sphere\n\
atom_modify map array\n\
boundary f f f\n\
comm_modify vel yes\n\
read_data {DATA_FILE}\n\
group proj type 2\n\
pair_style granular\n\
pair_coeff * * hertz/material {e_lmp:e} 0.0 {nu} tangential linear_history {k_t:e} 0.0 {mu} damping viscoelastic\n\
neighbor {skin:e} bin\n\
neigh_modify exclude type 1 1 delay 0 every 1 check yes\n\
velocity proj set {vx:e} {vy:e} {vz:e} units box\n\
{fixes}\
timestep {dt:e}\n\
compute om proj property/atom omegax omegay omegaz\n\
compute spin proj reduce sum c_om[1] c_om[2] c_om[3]\n\
variable vx equal vx[{id}]\n\
variable vy equal vy[{id}]\n\
variable vz equal vz[{id}]\n\
variable wx equal c_spin[1]\n\
variable wy equal c_spin[2]\n\
variable wz equal c_spin[3]\n\
thermo_style custom step v_vx v_vz v_wy\n\
thermo {thermo}\n\
run {steps}\n\
print \"RESULT ${{vx}} ${{vy}} ${{vz}} ${{wx}} ${{wy}} ${{wz}}\"\n",
        nu = model.poisson_ratio,
        mu = model.friction,
        skin = 0.5 * m(s.radius),
        vx = b.vel.x * v,
        vy = b.vel.y * v,
        vz = b.vel.z * v,
        thermo = (steps / 10).max(1),
    );
    LammpsDeck {
        input,
        data,
        steps,
        dt,
    }
}

/// The projectile's velocity and spin from LAMMPS's `RESULT` line (SI).
pub fn read_result(log: &str) -> Option<[f64; 6]> {
    let line = log.lines().rev().find(|l| l.starts_with("RESULT "))?;
    let v: Vec<f64> = line
        .split_whitespace()
        .skip(1)
        .filter_map(|w| w.parse().ok())
        .collect();
    v.try_into().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_impact_deck_holds_the_surface_and_the_projectile() {
        let cfg: ImpactConfig = toml::from_str(
            "[projectile]\nradius = 0.003\ndensity = 2500.0\n[impact]\nspeed = 35.0\nangle_deg = 45.0\n",
        )
        .unwrap();
        let d = impact_deck(&cfg, 1000).unwrap();
        let atoms: Vec<&str> = d
            .data
            .lines()
            .skip_while(|l| !l.starts_with("Atoms"))
            .skip(2)
            .collect();
        assert_eq!(atoms.len(), 4961);
        assert!(
            atoms[4960].starts_with("4961 2 6e-3 2.5e3 "),
            "{}",
            atoms[4960]
        );
        assert!(atoms[0].starts_with("1 1 5e-4 8000 "), "{}", atoms[0]);
        assert!(d
            .input
            .contains("hertz/material 2e11 0.0 0.3 tangential linear_history"));
        assert!(d.input.contains("run 1000"));
        // 35 m/s at 45 degrees.
        let v = 35.0 / 2f64.sqrt();
        let line = d
            .input
            .lines()
            .find(|l| l.starts_with("velocity proj set"))
            .unwrap();
        let w: Vec<f64> = line
            .split_whitespace()
            .skip(3)
            .take(3)
            .map(|x| x.parse().unwrap())
            .collect();
        assert!(
            (w[0] - v).abs() < 1e-9 && w[1] == 0.0 && (w[2] + v).abs() < 1e-9,
            "{line}"
        );
        assert_eq!(
            read_result("x\nRESULT 1 2 3 4 5 6\n"),
            Some([1.0, 2.0, 3.0, 4.0, 5.0, 6.0])
        );
        assert_eq!(read_result("RESULT 1 2\n"), None);
    }
}
