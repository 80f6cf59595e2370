//! The model material: a 2D Lennard-Jones hexagonal crystal whose d* (paper 000 eq 22) is small
//! enough for a junction that brackets it to fit on one machine. Same measurements as silica, in
//! reduced LJ units (length sigma, energy epsilon; stresses epsilon/sigma^2, surface energy
//! epsilon/sigma per unit length of 2D surface). The pair cut-off tunes brittleness: a shorter
//! range lowers the surface energy relative to strength and so lowers d*.

use crate::error::{MdError, Result};
use crate::lammps::{BoxState, Lammps};
use crate::loading::{load_curve, peak_of, simple_shear, Ramp, Strength};
use serde::{Deserialize, Serialize};

/// Settings of the model-material measurements (reduced LJ units).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ModelConfig {
    /// Rectangular hex cells (2 atoms each) along x and y; 24 x 14 = 672 atoms, seconds per test.
    pub cells: [usize; 2],
    /// Pair cut-off (sigma); 2.5 is the common LJ choice, shorter is more brittle.
    pub cutoff: f64,
    /// Temperature (epsilon/k_B) of the strength tests; cold, so strengths are near-ideal.
    pub temperature: f64,
    /// Time step (tau); 0.005 is standard for LJ.
    pub timestep: f64,
    /// Engineering strain rate (1/tau); slow next to the sound speed (~10 sigma/tau).
    pub strain_rate: f64,
    pub elastic_strain: f64,
    /// Largest tensile strain; an LJ crystal fails well before.
    pub max_tensile_strain: f64,
    /// Largest shear strain; below 0.5 so the triclinic box never flips.
    pub max_shear_strain: f64,
    /// Vacuum (sigma) opened to cleave; beyond the cut-off.
    pub surface_vacuum: f64,
    /// sigma in nm, to print lengths in nm (0.34 nm: argon).
    pub sigma_nm: f64,
    /// Seed of the thermal velocities.
    pub seed: u64,
}

impl Default for ModelConfig {
    fn default() -> Self {
        Self {
            cells: [24, 14],
            cutoff: 2.5,
            temperature: 0.01,
            timestep: 0.005,
            strain_rate: 1e-3,
            elastic_strain: 1e-3,
            max_tensile_strain: 0.3,
            max_shear_strain: 0.45,
            surface_vacuum: 5.0,
            sigma_nm: 0.34,
            seed: 4242,
        }
    }
}

impl ModelConfig {
    pub fn validate(&self) -> Result<()> {
        MdError::require_positive(
            "model config",
            &[
                ("cutoff", self.cutoff),
                ("temperature", self.temperature),
                ("timestep", self.timestep),
                ("strain_rate", self.strain_rate),
                ("elastic_strain", self.elastic_strain),
                ("max_tensile_strain", self.max_tensile_strain),
                ("max_shear_strain", self.max_shear_strain),
                ("surface_vacuum", self.surface_vacuum),
                ("sigma_nm", self.sigma_nm),
            ],
        )?;
        let bad = |m: String| Err(MdError::config("model config", m));
        if self.cutoff < 1.2 {
            return bad(format!(
                "cutoff {} is inside the first neighbour shell (1.12)",
                self.cutoff
            ));
        }
        if self.cells[0] < 4 || self.cells[1] < 4 {
            return bad("cells must be at least 4 x 4".into());
        }
        if self.max_shear_strain >= 0.5 {
            return bad("max_shear_strain must stay below 0.5".into());
        }
        if self.surface_vacuum <= self.cutoff {
            return bad("surface_vacuum must exceed the cutoff".into());
        }
        Ok(())
    }
    fn steps(&self, tau: f64) -> u64 {
        ((tau / self.timestep).round() as u64).max(1)
    }
}

/// Measured properties (reduced units) and the paper 000 length scales.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModelResult {
    pub n_atoms: u64,
    /// Atoms per sigma^2 and per nm^2.
    pub number_density: f64,
    pub atoms_per_nm2: f64,
    pub c11: f64,
    pub c12: f64,
    pub c66: f64,
    /// 2D isotropic moduli from C11, C12, C66.
    pub young_modulus: f64,
    pub poisson_ratio: f64,
    pub shear_modulus: f64,
    pub tension: Strength,
    pub shear: Strength,
    /// epsilon / sigma.
    pub surface_energy: f64,
    /// Paper 000 eqs 19, 18, 22 in sigma.
    pub d_min: f64,
    pub d_c: f64,
    pub d_star: f64,
    /// d* in nm with `sigma_nm`.
    pub d_star_nm: f64,
}

struct Reference {
    cell: BoxState,
    x: Vec<f64>,
    pe: f64,
}

impl Reference {
    fn restore(&self, lmp: &Lammps) -> Result<()> {
        lmp.set_box(&self.cell)?;
        lmp.scatter_f64("x", 3, &self.x)?;
        lmp.command("velocity all set 0.0 0.0 0.0")
    }
}

fn stress2(lmp: &Lammps) -> Result<[f64; 3]> {
    Ok([
        -lmp.thermo("pxx")?,
        -lmp.thermo("pyy")?,
        -lmp.thermo("pxy")?,
    ])
}

/// Nearest-neighbour distance of the model crystal (sigma): the LJ pair minimum 2^(1/6).
pub(crate) fn lattice_spacing() -> f64 {
    2f64.powf(1.0 / 6.0)
}

/// The model material's set-up before any atom exists: 2D, LJ units, atom map, LAMMPS `boundary`
/// flags (e.g. `p p p`) and the hex lattice of [`lattice_spacing`].
pub(crate) fn lattice_commands(boundary: &str) -> String {
    let a = lattice_spacing();
    let rho = 2.0 / (3f64.sqrt() * a * a);
    format!(
        "dimension 2
units lj
atom_style atomic
atom_modify map array
boundary {boundary}
lattice hex {rho}"
    )
}

/// The model material's interaction once the atoms exist: unit mass, the LJ pair cut at `cutoff`
/// and shifted to zero there, neighbour lists, and the time step.
pub(crate) fn pair_commands(cutoff: f64, timestep: f64) -> String {
    format!(
        "mass 1 1.0
pair_style lj/cut {cutoff}
pair_modify shift yes
pair_coeff 1 1 1.0 1.0 {cutoff}
neighbor 0.3 bin
neigh_modify every 1 delay 0 check yes
timestep {timestep}"
    )
}

/// Builds the relaxed crystal and measures everything.
pub fn run(lmp: &Lammps, cfg: &ModelConfig) -> Result<ModelResult> {
    cfg.validate()?;
    lmp.commands(&format!(
        "{lattice}
region cell prism 0 {nx} 0 {ny} -0.5 0.5 0 0 0 units lattice
create_box 1 cell
create_atoms 1 box
{pair}
thermo_style custom step temp pe press pxx pyy pxy lx ly
thermo 0
fix relax all box/relax x 0.0 y 0.0 xy 0.0 vmax 0.001
fix e2d all enforce2d
minimize 0.0 1.0e-10 10000 100000
unfix relax
minimize 0.0 1.0e-10 10000 100000",
        lattice = lattice_commands("p p p"),
        nx = cfg.cells[0],
        ny = cfg.cells[1],
        pair = pair_commands(cfg.cutoff, cfg.timestep),
    ))?;
    let r = Reference {
        cell: lmp.box_state()?,
        x: lmp.gather_f64("x", 3)?,
        pe: lmp.thermo("pe")?,
    };
    let n = lmp.natoms()?;
    let l = r.cell.lengths();
    let number_density = n as f64 / (l[0] * l[1]);
    // Elastic constants: +- strain, relaxed ions, Voigt order (xx, yy, xy).
    let e = cfg.elastic_strain;
    let mut c = [[0.0; 3]; 3];
    for j in 0..3 {
        let mut s = [[0.0; 3]; 2];
        for (k, sign) in [1.0, -1.0].into_iter().enumerate() {
            r.restore(lmp)?;
            let d = sign * e;
            lmp.command(&match j {
                0 => format!("change_box all x scale {} remap units box", 1.0 + d),
                1 => format!("change_box all y scale {} remap units box", 1.0 + d),
                _ => format!("change_box all xy delta {} remap units box", d * l[1]),
            })?;
            lmp.command("minimize 0.0 1.0e-10 10000 100000")?;
            s[k] = stress2(lmp)?;
        }
        for (i, row) in c.iter_mut().enumerate() {
            row[j] = (s[0][i] - s[1][i]) / (2.0 * e);
        }
    }
    let (c11, c12, c66) = (
        (c[0][0] + c[1][1]) / 2.0,
        (c[0][1] + c[1][0]) / 2.0,
        c[2][2],
    );
    let k2 = (c11 + c12) / 2.0;
    let g = ((c11 - c12) / 2.0 + c66) / 2.0;
    let young = 4.0 * k2 * g / (k2 + g);
    let poisson = (k2 - g) / (k2 + g);
    let tension = strength(lmp, cfg, &r, true)?;
    let shear = strength(lmp, cfg, &r, false)?;
    // Cleave along y; energy per unit length of the two new 2D surfaces.
    r.restore(lmp)?;
    lmp.commands(&format!(
        "change_box all y final {} {} units box\nminimize 0.0 1.0e-10 10000 100000",
        r.cell.lo[1],
        r.cell.hi[1] + cfg.surface_vacuum
    ))?;
    let gamma = (lmp.thermo("pe")? * n as f64 - r.pe * n as f64) / (2.0 * l[0]);
    r.restore(lmp)?;
    if gamma.is_nan() || gamma <= 0.0 {
        return Err(MdError::measurement(
            "model surface energy",
            format!("non-positive {gamma}"),
        ));
    }
    let ls = crate::card::length_scales(
        young,
        poisson,
        tension.peak_stress,
        shear.peak_stress,
        gamma,
    );
    Ok(ModelResult {
        n_atoms: n,
        number_density,
        atoms_per_nm2: number_density / (cfg.sigma_nm * cfg.sigma_nm),
        c11,
        c12,
        c66,
        young_modulus: young,
        poisson_ratio: poisson,
        shear_modulus: g,
        tension,
        shear,
        surface_energy: gamma,
        d_min: ls.d_min,
        d_c: ls.d_c,
        d_star: ls.d_star,
        d_star_nm: ls.d_star * cfg.sigma_nm,
    })
}

/// Uniaxial tension along x (y stress-free) or simple shear xy, at `temperature`, to the peak.
fn strength(lmp: &Lammps, cfg: &ModelConfig, r: &Reference, tension: bool) -> Result<Strength> {
    r.restore(lmp)?;
    let t = cfg.temperature;
    lmp.commands(&format!(
        "reset_timestep 0
velocity all create {t2} {seed} mom yes rot yes dist gaussian
fix md all npt temp {t} {t} 0.5 x 0.0 0.0 5.0 y 0.0 0.0 5.0 xy 0.0 0.0 5.0
run {n}
unfix md
reset_timestep 0",
        t2 = 2.0 * t,
        seed = crate::lammps::lammps_seed(cfg.seed, if tension { 1 } else { 2 }),
        n = cfg.steps(20.0),
    ))?;
    let b = lmp.box_state()?;
    let max = if tension {
        cfg.max_tensile_strain
    } else {
        cfg.max_shear_strain
    };
    let per_point = cfg.steps(0.0025 / cfg.strain_rate).max(10);
    let ramp = Ramp {
        steps_per_point: per_point,
        points: cfg.steps(max / cfg.strain_rate) / per_point + 1,
        stress_scale: 1.0,
    };
    let curve = if tension {
        lmp.commands(&format!(
            "variable lx0 equal {lx0}
variable strain equal lx/v_lx0-1.0
variable sxx equal -pxx
fix md all npt temp {t} {t} 0.5 y 0.0 0.0 5.0
fix def all deform 1 x erate {rate} remap x",
            lx0 = b.lengths()[0],
            rate = cfg.strain_rate
        ))?;
        let c = load_curve(lmp, &ramp, "sxx", "strain", max, 0.5)?;
        lmp.commands("unfix def\nunfix md")?;
        c
    } else {
        simple_shear(lmp, b.tilt[0], cfg.strain_rate, t, 0.5, &ramp, max, 0.5)?
    };
    peak_of(
        curve,
        if tension {
            "model tensile strength"
        } else {
            "model shear strength"
        },
    )
}
