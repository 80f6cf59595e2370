//! The individual silica measurements. Each starts from the 0 K [`Reference`] state (restored by
//! scattering saved positions into the saved box), so they are independent of each other's order.

use super::{SilicaConfig, Strength, BAR_TO_PA, EV_PER_A2_TO_J_PER_M2};
use crate::error::{MdError, Result};
use crate::lammps::{lammps_seed, BoxState, Lammps};
use crate::loading::{load_curve, peak_of, simple_shear, Ramp};
use std::path::Path;

const MASS_SI: f64 = 28.0855;
const MASS_O: f64 = 15.9994;
const AVOGADRO: f64 = 6.022_140_76e23;

/// The relaxed 0 K glass: box, positions and potential energy (eV).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Reference {
    pub cell: BoxState,
    pub x: Vec<f64>,
    pub pe: f64,
}

impl Reference {
    /// Puts box, positions and zero velocities back; first deletes the copies a [`replicated`]
    /// cell added (atom ids above this reference's count), so any measurement can follow it.
    pub(super) fn restore(&self, lmp: &Lammps) -> Result<()> {
        let n = self.x.len() / 3;
        if lmp.natoms()? as usize > n {
            lmp.commands(&format!(
                "group copies id > {n}\ndelete_atoms group copies compress no\ngroup copies delete"
            ))?;
        }
        lmp.set_box(&self.cell)?;
        lmp.scatter_f64("x", 3, &self.x)?;
        lmp.command("velocity all set 0.0 0.0 0.0")
    }
}

/// Commands that set up an empty LAMMPS instance with the silica cell `b`: units, box, masses,
/// `formula_units` Si then twice as many O atoms placed at random (ids 1..n are Si, the rest O;
/// `si_options` / `o_options` are extra `create_atoms` keywords), the potential and the run
/// settings every stage shares.
fn cell(
    potential: &Path,
    cfg: &SilicaConfig,
    b: &BoxState,
    si_options: &str,
    o_options: &str,
) -> String {
    let n = cfg.formula_units;
    let s = lammps_seed(cfg.seed, 1);
    format!(
        "units metal
atom_style atomic
atom_modify map array
boundary p p p
region cell prism {} {} {} {} {} {} {} {} {} units box
create_box 2 cell
mass 1 {MASS_SI}
mass 2 {MASS_O}
create_atoms 1 random {n} {s} NULL {si_options}
create_atoms 2 random {n2} {s2} NULL {o_options}
pair_style vashishta
pair_coeff * * {pot} Si O
neighbor 1.0 bin
neigh_modify every 1 delay 0 check yes
timestep {dt}
thermo_style custom step temp pe press density pxx pyy pzz pyz pxz pxy lx ly lz
thermo 0
",
        b.lo[0],
        b.hi[0],
        b.lo[1],
        b.hi[1],
        b.lo[2],
        b.hi[2],
        b.tilt[0],
        b.tilt[1],
        b.tilt[2],
        n2 = 2 * n,
        s2 = s + 1,
        pot = potential.display(),
        dt = cfg.timestep_fs / 1000.0,
    )
}

/// Replaces whatever the instance holds by a fresh cell holding the glass `g` (`clear`, then
/// `cell` in `g`'s box, then `g`'s exact positions, zero velocities).
///
/// Every measurement stage starts here, in an uninterrupted run as in one resumed from stage
/// files: the stages are then independent of what ran before them in this process (LAMMPS's
/// atom order in memory, fix and neighbour-list state), so a resumed job reproduces an
/// uninterrupted one bit for bit. The cost is one `clear` and a neighbour build per stage.
pub fn rebuild(lmp: &Lammps, potential: &Path, cfg: &SilicaConfig, g: &super::Glass) -> Result<()> {
    lmp.command("clear")?;
    lmp.commands(&cell(potential, cfg, &g.reference.cell, "", ""))?;
    let types = lmp.gather_i32("type", 1)?;
    if types != g.types {
        return Err(MdError::measurement(
            "rebuilding the glass",
            "atom types by id differ from the saved glass (a different formula_units or LAMMPS id order)",
        ));
    }
    g.reference.restore(lmp)
}

/// Builds the random melt, melts, quenches, anneals; returns the mean anneal density in kg/m^3.
///
/// Choices: the melt runs at fixed volume (the start density), so the random start cannot blow
/// the box up before it has mixed; the quench and anneal run NPT at zero pressure (`iso`), so the
/// glass finds its own ambient density: the melt stays cohesive at zero pressure (measured:
/// ~2.0 g/cm^3 at 5000 K) and densifies continuously on cooling. Thermostat damping 0.1 ps (100
/// steps) and barostat damping 1 ps (1000 steps, LAMMPS's recommended ~1000 steps) follow the
/// quench without ringing. The density is averaged over the second half of the anneal, after the
/// barostat has settled.
pub fn melt_quench(lmp: &Lammps, potential: &Path, cfg: &SilicaConfig) -> Result<f64> {
    let mass_g = cfg.formula_units as f64 * (MASS_SI + 2.0 * MASS_O) / AVOGADRO;
    let side = (mass_g / cfg.initial_density * 1e24).cbrt(); // Angstrom
    let (tm, tq) = (cfg.melt_temperature, cfg.quench_end_temperature);
    let quench_steps = cfg.steps((tm - tq) / cfg.quench_rate);
    // ave/time output lands on multiples of Nfreq: reset the step so the anneal ends on one.
    let anneal = cfg.steps(cfg.anneal_ps).max(20) / 20 * 20;
    let cube = BoxState {
        lo: [0.0; 3],
        hi: [side; 3],
        tilt: [0.0; 3],
    };
    lmp.commands(&cell(
        potential,
        cfg,
        &cube,
        "overlap 2.2 maxtry 1000",
        "overlap 1.3 maxtry 1000",
    ))?;
    lmp.commands(&format!(
        "minimize 0.0 1.0e-3 200 2000
velocity all create {tm} {s3} mom yes rot yes dist gaussian
fix md all nvt temp {tm} {tm} 0.1
run {melt}
unfix md
fix md all npt temp {tm} {tq} 0.1 iso 0.0 0.0 1.0
run {quench_steps}
unfix md
reset_timestep 0
fix md all npt temp {tq} {tq} 0.1 iso 0.0 0.0 1.0
variable rho equal density
fix rhoavg all ave/time 10 {nrep} {anneal} v_rho
run {anneal}
variable rhoavg equal f_rhoavg
",
        s3 = lammps_seed(cfg.seed, 3),
        melt = cfg.steps(cfg.melt_ps),
        nrep = anneal / 20,
    ))?;
    let rho = lmp.variable("rhoavg")? * 1000.0;
    lmp.commands("unfix rhoavg\nunfix md")?;
    Ok(rho)
}

/// Relaxes box (all six stress components to zero, so a small glass carries no residual shear
/// stress into the strength tests) and atoms to 0 K, and saves the reference state.
pub fn relax_0k(lmp: &Lammps, cfg: &SilicaConfig) -> Result<Reference> {
    lmp.commands(&format!(
        "velocity all set 0.0 0.0 0.0
fix relax all box/relax tri 0.0 vmax 0.001
minimize 0.0 {f} 20000 200000
unfix relax
minimize 0.0 {f} 20000 200000",
        f = cfg.min_ftol
    ))?;
    Ok(Reference {
        cell: lmp.box_state()?,
        x: lmp.gather_f64("x", 3)?,
        pe: lmp.thermo("pe")?,
    })
}

/// Stress (Voigt order xx yy zz yz xz xy) in Pa from LAMMPS pressures (bar, opposite sign).
fn stress(lmp: &Lammps) -> Result<[f64; 6]> {
    let mut s = [0.0; 6];
    for (i, k) in ["pxx", "pyy", "pzz", "pyz", "pxz", "pxy"]
        .iter()
        .enumerate()
    {
        s[i] = -lmp.thermo(k)? * BAR_TO_PA;
    }
    Ok(s)
}

/// Elastic constants and their isotropic (Voigt) average.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Elastic {
    pub c: [[f64; 6]; 6],
    pub c11: f64,
    pub c12: f64,
    pub c44: f64,
    pub bulk: f64,
    pub shear: f64,
    pub young: f64,
    pub poisson: f64,
}

/// Isotropic moduli from cubic-averaged constants (Voigt average: uses C11, C12 and C44 alike).
pub fn isotropic(c11: f64, c12: f64, c44: f64) -> (f64, f64, f64, f64) {
    let k = (c11 + 2.0 * c12) / 3.0;
    let g = (c11 - c12 + 3.0 * c44) / 5.0;
    let e = 9.0 * k * g / (3.0 * k + g);
    let nu = (3.0 * k - 2.0 * g) / (2.0 * (3.0 * k + g));
    (k, g, e, nu)
}

/// C_ij at 0 K by central differences: strain component j by +-e from the 0 K reference, relax the
/// ions at fixed box (non-affine relaxation: a glass's static stiffness, well below the affine
/// Born term), read stress i. The minimiser's force tolerance is on the global force norm.
pub fn elastic(lmp: &Lammps, cfg: &SilicaConfig, r: &Reference) -> Result<Elastic> {
    let e = cfg.elastic_strain;
    let l = r.cell.lengths();
    let mut c = [[0.0; 6]; 6];
    for j in 0..6 {
        let mut s = [[0.0; 6]; 2];
        for (k, sign) in [1.0, -1.0].into_iter().enumerate() {
            r.restore(lmp)?;
            lmp.command(&strain_command(j, sign * e, l))?;
            lmp.command(&format!("minimize 0.0 {} 20000 200000", cfg.min_ftol))?;
            s[k] = stress(lmp)?;
        }
        for (i, row) in c.iter_mut().enumerate() {
            row[j] = (s[0][i] - s[1][i]) / (2.0 * e);
        }
    }
    r.restore(lmp)?;
    Ok(Elastic::from_stiffness(c))
}

impl Elastic {
    /// Cubic averages of a measured 6x6 stiffness and their isotropic (Voigt) moduli.
    pub fn from_stiffness(c: [[f64; 6]; 6]) -> Self {
        let avg = |idx: &[(usize, usize)]| {
            idx.iter().map(|&(i, j)| c[i][j]).sum::<f64>() / idx.len() as f64
        };
        let c11 = avg(&[(0, 0), (1, 1), (2, 2)]);
        let c12 = avg(&[(0, 1), (1, 0), (0, 2), (2, 0), (1, 2), (2, 1)]);
        let c44 = avg(&[(3, 3), (4, 4), (5, 5)]);
        let (bulk, shear, young, poisson) = isotropic(c11, c12, c44);
        Self {
            c,
            c11,
            c12,
            c44,
            bulk,
            shear,
            young,
            poisson,
        }
    }
}

/// C_ij at `elastic_temperature` > 0: the glass is thermalised stress-free at T (NPT, 2 ps), then
/// for each strain component and sign the box is deformed by +-`elastic_strain` from that same
/// thermal state (positions, velocities, box), equilibrated 0.5 ps in NVT and the stress averaged
/// over `elastic_md_ps`. Central differences cancel the residual stress of the base state.
/// This is the isothermal, thermally averaged stiffness (ions relax by thermal motion, and the
/// anharmonic softening at T is included), the counterpart of the 0 K relaxed-ion [`elastic`].
/// Statistical error ~ stress noise / (2 strain): use a strain of ~0.01 and >= 2 ps on small cells.
pub fn elastic_thermal(lmp: &Lammps, cfg: &SilicaConfig, r: &Reference) -> Result<Elastic> {
    let t = cfg.elastic_temperature;
    thermalise(lmp, cfg, r, t, 3)?;
    let base = (
        lmp.box_state()?,
        lmp.gather_f64("x", 3)?,
        lmp.gather_f64("v", 3)?,
    );
    let l = base.0.lengths();
    let e = cfg.elastic_strain;
    let (eq, avg) = (cfg.steps(0.5), cfg.steps(cfg.elastic_md_ps));
    let mut c = [[0.0; 6]; 6];
    for j in 0..6 {
        let mut s = [[0.0; 6]; 2];
        for (k, sign) in [1.0, -1.0].into_iter().enumerate() {
            lmp.set_box(&base.0)?;
            lmp.scatter_f64("x", 3, &base.1)?;
            lmp.scatter_f64("v", 3, &base.2)?;
            lmp.command(&strain_command(j, sign * e, l))?;
            // compute thermo_press vector order: xx yy zz xy xz yz.
            lmp.commands(&format!(
                "fix md all nvt temp {t} {t} 0.1
run {eq}
reset_timestep 0
fix sav all ave/time 1 {avg} {avg} c_thermo_press[1] c_thermo_press[2] c_thermo_press[3] c_thermo_press[6] c_thermo_press[5] c_thermo_press[4]
run {avg}"
            ))?;
            for (i, si) in s[k].iter_mut().enumerate() {
                lmp.command(&format!("variable sav equal f_sav[{}]", i + 1))?;
                *si = -lmp.variable("sav")? * BAR_TO_PA;
            }
            lmp.commands("unfix sav\nunfix md\nreset_timestep 0")?;
        }
        for (i, row) in c.iter_mut().enumerate() {
            row[j] = (s[0][i] - s[1][i]) / (2.0 * e);
        }
    }
    r.restore(lmp)?;
    Ok(Elastic::from_stiffness(c))
}

/// `change_box` applying Voigt strain component `j` of size `d` to a box of lengths `l`
/// (engineering shear strains: tilt = d x the length normal to the sheared face).
fn strain_command(j: usize, d: f64, l: [f64; 3]) -> String {
    match j {
        0 => format!("change_box all x scale {} remap units box", 1.0 + d),
        1 => format!("change_box all y scale {} remap units box", 1.0 + d),
        2 => format!("change_box all z scale {} remap units box", 1.0 + d),
        3 => format!("change_box all yz delta {} remap units box", d * l[2]),
        4 => format!("change_box all xz delta {} remap units box", d * l[2]),
        _ => format!("change_box all xy delta {} remap units box", d * l[1]),
    }
}

/// Loading ramp of the strength tests: 0.25 % strain per recorded point, up to `max_strain`.
fn ramp(cfg: &SilicaConfig, max_strain: f64) -> Ramp {
    let per_point = cfg.steps(0.0025 / cfg.strain_rate).max(10);
    Ramp {
        steps_per_point: per_point,
        points: cfg.steps(max_strain / cfg.strain_rate) / per_point + 1,
        stress_scale: BAR_TO_PA,
    }
}

/// Thermalises the reference state at `t` and zero stress (all six components) for 2 ps, so the
/// loading starts from a stress-free state at temperature.
fn thermalise(
    lmp: &Lammps,
    cfg: &SilicaConfig,
    r: &Reference,
    t: f64,
    seed_offset: u64,
) -> Result<()> {
    r.restore(lmp)?;
    lmp.commands(&format!(
        "reset_timestep 0
velocity all create {t2} {s} mom yes rot yes dist gaussian
fix md all npt temp {t} {t} 0.1 tri 0.0 0.0 0.5
run {n}
unfix md
reset_timestep 0",
        t2 = 2.0 * t, // a 0 K solid shares kinetic energy with potential energy: start at 2T
        s = lammps_seed(cfg.seed, 10 + seed_offset),
        n = cfg.steps(2.0),
    ))
}

/// Uniaxial tension along x, lateral faces stress-free, to failure: the ideal tensile strength.
pub fn tension(lmp: &Lammps, cfg: &SilicaConfig, r: &Reference) -> Result<Strength> {
    thermalise(lmp, cfg, r, cfg.strength_temperature, 1)?;
    let t = cfg.strength_temperature;
    lmp.commands(&format!(
        "variable lx0 equal {lx0}
variable strain equal lx/v_lx0-1.0
variable sxx equal -pxx
fix md all npt temp {t} {t} 0.1 y 0.0 0.0 1.0 z 0.0 0.0 1.0
fix def all deform 1 x erate {rate} remap x",
        lx0 = lmp.box_state()?.lengths()[0],
        rate = cfg.strain_rate,
    ))?;
    let curve = load_curve(
        lmp,
        &ramp(cfg, cfg.max_tensile_strain),
        "sxx",
        "strain",
        cfg.max_tensile_strain,
        0.5,
    )?;
    lmp.commands("unfix def\nunfix md")?;
    peak_of(curve, "tensile strength")
}

/// Simple shear in xy at constant volume to past the peak: the shear strength.
pub fn shear(lmp: &Lammps, cfg: &SilicaConfig, r: &Reference) -> Result<Strength> {
    thermalise(lmp, cfg, r, cfg.strength_temperature, 2)?;
    let t = cfg.strength_temperature;
    // Glass flows after the peak rather than dropping: stop at 80 % of the peak.
    let curve = simple_shear(
        lmp,
        lmp.box_state()?.tilt[0],
        cfg.strain_rate,
        t,
        0.1,
        &ramp(cfg, cfg.max_shear_strain),
        cfg.max_shear_strain,
        0.8,
    )?;
    peak_of(curve, "shear strength")
}

/// The 0 K reference replicated `surface_replicate` times (LAMMPS `replicate`, atom ids of the
/// original cell unchanged, copies numbered after them); `r` itself if that is [1, 1, 1]. Leaves
/// the instance holding the replicated cell. Its energy is the copies' sum (the periodic images
/// are the same), so a replicated bulk is still a minimum at the same energy per atom.
pub fn replicated(lmp: &Lammps, cfg: &SilicaConfig, r: &Reference) -> Result<Reference> {
    r.restore(lmp)?;
    let [nx, ny, nz] = cfg.surface_replicate;
    if [nx, ny, nz] == [1, 1, 1] {
        return Ok(r.clone());
    }
    lmp.commands(&format!(
        "replicate {nx} {ny} {nz}
run 0"
    ))?;
    Ok(Reference {
        cell: lmp.box_state()?,
        x: lmp.gather_f64("x", 3)?,
        pe: lmp.thermo("pe")?,
    })
}

/// Surface energy of one glass, J/m^2: one value per cleave plane and their means.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Surface {
    /// (cleaved and minimised, after the surface anneal) for each plane, in order.
    pub cleaves: Vec<[f64; 2]>,
    /// Mean over the planes of the cleaved and minimised values.
    pub unrelaxed: f64,
    /// Mean over the planes of the annealed values (= `unrelaxed` without an anneal).
    pub annealed: f64,
}

/// Cleaves the cell open along z (`surface_vacuum`) at `surface_cleaves` planes, z = lo + k Lz / n
/// (the atoms are shifted down by k Lz / n, periodically, and the cell opened at its boundary),
/// relaxes each slab and returns the surface energies. Several planes sample several surfaces of
/// the same glass: one plane of a 648-atom glass scatters by ~20 % (5 glasses, docs/md-bridge.md).
/// The cell is first replicated `surface_replicate` times ([`replicated`]), slab and bulk
/// reference alike. Leaves the instance with the last (replicated) slab; restore the reference
/// to reuse it.
pub fn surface_energy(lmp: &Lammps, cfg: &SilicaConfig, r: &Reference) -> Result<Surface> {
    let r = &replicated(lmp, cfg, r)?;
    let b = r.cell;
    let area = (b.hi[0] - b.lo[0]) * (b.hi[1] - b.lo[1]);
    let to_gamma =
        |pe_slab: f64, pe_bulk: f64| (pe_slab - pe_bulk) / (2.0 * area) * EV_PER_A2_TO_J_PER_M2;
    let anneal = cfg.surface_anneal_ps > 0.0;
    // The annealed slab is compared with a bulk reference given the same anneal (temperature,
    // duration, thermostat, velocities) and minimisation, not with the 0 K bulk: the anneal also
    // relaxes the slab's interior, which made the annealed gamma too low (default card: by 0.07
    // J/m^2; 0.002 on another glass). The bulk is free along z and fixed laterally, like the slab.
    // A periodic bulk shifted along z is the same bulk: one reference serves every plane.
    let pe_bulk = if anneal {
        r.restore(lmp)?;
        let pe = anneal_and_minimise(lmp, cfg, true)?;
        tracing::info!(
            "surface energy: the annealed bulk reference lies {:.3} eV ({:.3} J/m^2) below the 0 K one",
            r.pe - pe,
            to_gamma(r.pe, pe)
        );
        pe
    } else {
        r.pe
    };
    let n = cfg.surface_cleaves;
    let mut cleaves = Vec::with_capacity(n as usize);
    for k in 0..n {
        r.restore(lmp)?;
        if k > 0 {
            // displace_atoms wraps the atoms back into the periodic cell.
            let shift = -f64::from(k) * (b.hi[2] - b.lo[2]) / f64::from(n);
            lmp.command(&format!(
                "displace_atoms all move 0 0 {shift:.17e} units box"
            ))?;
        }
        lmp.commands(&format!(
            "change_box all z final {zlo} {zhi} units box
minimize 0.0 {f} 20000 200000",
            zlo = b.lo[2],
            zhi = b.hi[2] + cfg.surface_vacuum,
            f = cfg.min_ftol
        ))?;
        let g0 = to_gamma(lmp.thermo("pe")?, r.pe);
        let g1 = if anneal {
            to_gamma(anneal_and_minimise(lmp, cfg, false)?, pe_bulk)
        } else {
            g0
        };
        if !(g0 > 0.0 && g1 > 0.0) {
            return Err(MdError::measurement(
                "surface energy",
                format!("non-positive values {g0} / {g1} J/m^2 at cleave plane {k} of {n}"),
            ));
        }
        tracing::info!("surface energy, plane {k} of {n}: {g0:.3} J/m^2 cleaved, {g1:.3} annealed");
        cleaves.push([g0, g1]);
    }
    let mean = |i: usize| cleaves.iter().map(|c| c[i]).sum::<f64>() / f64::from(n);
    Ok(Surface {
        unrelaxed: mean(0),
        annealed: mean(1),
        cleaves,
    })
}

/// The surface anneal: NVT at `surface_anneal_temperature` for `surface_anneal_ps` from velocities
/// of a fixed seed, then minimisation (first with the box length along z relaxed to zero stress
/// if `relax_z`); returns the minimised potential energy (eV).
fn anneal_and_minimise(lmp: &Lammps, cfg: &SilicaConfig, relax_z: bool) -> Result<f64> {
    let t = cfg.surface_anneal_temperature;
    lmp.commands(&format!(
        "velocity all create {t2} {s} mom yes rot yes dist gaussian
fix md all nvt temp {t} {t} 0.1
run {n}
unfix md
velocity all set 0.0 0.0 0.0",
        t2 = 2.0 * t,
        s = lammps_seed(cfg.seed, 20),
        n = cfg.steps(cfg.surface_anneal_ps),
    ))?;
    let minimize = format!("minimize 0.0 {} 20000 200000", cfg.min_ftol);
    if relax_z {
        lmp.commands(&format!(
            "fix zrel all box/relax z 0.0 vmax 0.001\n{minimize}\nunfix zrel"
        ))?;
    }
    lmp.command(&minimize)?;
    lmp.thermo("pe")
}
