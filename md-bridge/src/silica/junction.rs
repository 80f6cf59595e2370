//! The silica junction of paper 000 section 4 as a cluster job: this module writes the LAMMPS
//! input and data (it never runs the full-size job here; millions of atoms).
//!
//! Geometry (paper 000 section 4, in nm): a periodic box `box_nm` (60 x 40 x 40 in the paper) with
//! two solids joined by a vertical cylinder of diameter D (10 or 20 nm, bracketing d* = 18 nm) and
//! height H = D/2. x is the sliding direction; x and y are periodic, z is shrink-wrapped. The
//! outermost `wall_nm` of each solid is rigid: the bottom one fixed, the top one driven at
//! `velocity_m_s` along x (paper: 10 m/s) under a constant normal pressure (paper: 100 MPa) applied
//! as an equal per-atom force (`fix aveforce`, so the top wall moves rigidly along z). A `bath_nm`
//! layer next to each wall is held at `temperature` by a Langevin thermostat (the top one with its
//! centre-of-mass velocity removed), so the heat made in the junction leaves through the solids.
//!
//! Material: a relaxed amorphous block (a LAMMPS data file of the melt-quenched glass, see
//! [`write_glass`]) replicated to fill the box, then carved: atoms in the gap between the solids
//! and outside the cylinder are deleted. The junction is therefore bonded to both solids (perfect
//! adhesion, as in the paper's MD reference). Replication makes the glass periodic on the block
//! scale: use a block of several nm (a few 10^4 atoms) for production runs.
//!
//! The input file refers to its files through `${dir}` (default `.`) and its run lengths through
//! index variables, so `lmp -var shear_steps 100 ...` (or a `variable ... index` command before
//! `include`) shortens it without editing it.

use crate::error::{MdError, Result};
use crate::lammps::Lammps;
use crate::silica::{measure, SilicaConfig};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Single-core cost of the Vashishta silica force field measured here (DESIGN.md section 3):
/// about 16 microseconds per atom-step.
pub const SECONDS_PER_ATOM_STEP: f64 = 16e-6;

/// Input file name written by [`write_job`].
pub const INPUT_FILE: &str = "in.junction";
/// Glass block data file name.
pub const GLASS_FILE: &str = "glass.data";

/// Settings of the silica junction shear (SI-ish units as named; LAMMPS metal units inside).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SilicaJunctionConfig {
    /// Junction diameter D (nm); paper: 10 (plastic) and 20 (wear particle), d* = 18.
    pub diameter_nm: f64,
    /// Box lengths (nm): sliding x, periodic y, height z; paper: 60 x 40 x 40.
    pub box_nm: [f64; 3],
    /// Junction height over diameter (paper: H = D / 2).
    pub height_factor: f64,
    /// Thickness of each rigid wall (nm); at least the 1 nm cut-off, so mobile atoms never see
    /// the free outer faces.
    pub wall_nm: f64,
    /// Thickness of each thermostatted layer next to a wall (nm).
    pub bath_nm: f64,
    /// K of the baths and of the initial velocities; room temperature.
    pub temperature: f64,
    /// Langevin damping time of the baths (ps).
    pub bath_damping_ps: f64,
    /// Top wall speed (m/s); paper: 10 m/s, ~0.2 % of the sound speed.
    pub velocity_m_s: f64,
    /// Normal pressure on the top wall (MPa); paper: 100 MPa, keeps the walls from drifting apart.
    pub normal_pressure_mpa: f64,
    /// Sliding distance in units of D; a rolling particle turns by about slide / D rad.
    pub slide_factor: f64,
    /// fs; 1 fs as in the silica workflow.
    pub timestep_fs: f64,
    /// Maximum iterations of the minimisation of the freshly carved surfaces.
    pub min_iterations: u64,
    /// ps of thermostatted relaxation at fixed walls before shearing (the carved surfaces
    /// reconstruct).
    pub relax_ps: f64,
    /// ps between dump frames (OVITO reads them; 0 writes no dump).
    pub dump_every_ps: f64,
    /// Steps between thermo lines (tangential and normal wall force, slide distance).
    pub thermo_every: u64,
    pub seed: u64,
}

impl Default for SilicaJunctionConfig {
    fn default() -> Self {
        Self {
            diameter_nm: 20.0,
            box_nm: [60.0, 40.0, 40.0],
            height_factor: 0.5,
            wall_nm: 1.0,
            bath_nm: 1.0,
            temperature: 300.0,
            bath_damping_ps: 0.1,
            velocity_m_s: 10.0,
            normal_pressure_mpa: 100.0,
            slide_factor: 2.5,
            timestep_fs: 1.0,
            min_iterations: 2000,
            relax_ps: 20.0,
            dump_every_ps: 20.0,
            thermo_every: 1000,
            seed: 2022,
        }
    }
}

impl SilicaJunctionConfig {
    pub fn validate(&self) -> Result<()> {
        let bad = |m: String| Err(MdError::config("silica junction config", m));
        let positive = [
            ("diameter_nm", self.diameter_nm),
            ("box_nm[0]", self.box_nm[0]),
            ("box_nm[1]", self.box_nm[1]),
            ("box_nm[2]", self.box_nm[2]),
            ("height_factor", self.height_factor),
            ("wall_nm", self.wall_nm),
            ("bath_nm", self.bath_nm),
            ("temperature", self.temperature),
            ("bath_damping_ps", self.bath_damping_ps),
            ("velocity_m_s", self.velocity_m_s),
            ("slide_factor", self.slide_factor),
            ("timestep_fs", self.timestep_fs),
        ];
        for (n, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return bad(format!("{n} must be a positive number, got {v}"));
            }
        }
        for (n, v) in [
            ("normal_pressure_mpa", self.normal_pressure_mpa),
            ("relax_ps", self.relax_ps),
            ("dump_every_ps", self.dump_every_ps),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return bad(format!("{n} must be >= 0, got {v}"));
            }
        }
        if self.thermo_every == 0 {
            return bad("thermo_every must be >= 1".into());
        }
        let [lx, ly, _] = self.box_nm;
        if self.diameter_nm >= lx.min(ly) {
            return bad(format!(
                "diameter {} nm does not fit in the {lx} x {ly} nm cross-section (its periodic images would touch)",
                self.diameter_nm
            ));
        }
        let slab = self.slab_nm();
        if slab <= self.wall_nm + self.bath_nm {
            return bad(format!(
                "each solid is {slab:.2} nm thick (box height minus H, halved): no room for the {} nm wall and {} nm bath",
                self.wall_nm, self.bath_nm
            ));
        }
        Ok(())
    }

    /// Junction height H (nm).
    pub fn height_nm(&self) -> f64 {
        self.height_factor * self.diameter_nm
    }

    /// Thickness of each solid (nm) before snapping to the replicated box.
    pub fn slab_nm(&self) -> f64 {
        (self.box_nm[2] - self.height_nm()) / 2.0
    }

    fn steps(&self, ps: f64) -> u64 {
        (ps * 1000.0 / self.timestep_fs).round() as u64
    }

    /// Shear steps: the top wall slides `slide_factor` D.
    pub fn shear_steps(&self) -> u64 {
        let slide_m = self.slide_factor * self.diameter_nm * 1e-9;
        let seconds = slide_m / self.velocity_m_s;
        ((seconds / (self.timestep_fs * 1e-15)).round() as u64).max(1)
    }
}

/// The glass block read from a LAMMPS data file header.
#[derive(Debug, Clone, PartialEq)]
pub struct GlassBlock {
    pub atoms: u64,
    /// Angstrom.
    pub lo: [f64; 3],
    pub hi: [f64; 3],
}

impl GlassBlock {
    /// Parses the header of a LAMMPS data file (atoms, box bounds); refuses tilted boxes.
    pub fn parse(text: &str) -> Result<Self> {
        let bad = |m: &str| MdError::config("glass data file", m);
        let (mut atoms, mut lo, mut hi) = (None, [f64::NAN; 3], [f64::NAN; 3]);
        for line in text.lines().skip(1) {
            let w: Vec<&str> = line.split_whitespace().collect();
            let num = |i: usize| -> Result<f64> {
                w.get(i)
                    .and_then(|s| s.parse().ok())
                    .ok_or_else(|| bad(&format!("unreadable header line `{line}`")))
            };
            match w.as_slice() {
                [_, "atoms"] => atoms = Some(num(0)? as u64),
                [_, _, "xlo", "xhi"] => (lo[0], hi[0]) = (num(0)?, num(1)?),
                [_, _, "ylo", "yhi"] => (lo[1], hi[1]) = (num(0)?, num(1)?),
                [_, _, "zlo", "zhi"] => (lo[2], hi[2]) = (num(0)?, num(1)?),
                [a, b, c, "xy", "xz", "yz"] => {
                    let tilt: Vec<f64> = [a, b, c].iter().filter_map(|s| s.parse().ok()).collect();
                    if tilt.len() != 3 || tilt.iter().any(|t| t.abs() > 1e-9) {
                        return Err(bad("the glass block must be an orthogonal box (tilts 0)"));
                    }
                }
                [first, ..] if first.chars().next().is_some_and(char::is_alphabetic) => break,
                _ => {}
            }
        }
        let atoms = atoms.ok_or_else(|| bad("no `N atoms` line in the header"))?;
        if atoms == 0 || (0..3).any(|k| (hi[k] - lo[k]).is_nan() || hi[k] - lo[k] <= 0.0) {
            return Err(bad("empty block or missing box bounds"));
        }
        Ok(Self { atoms, lo, hi })
    }

    pub fn lengths(&self) -> [f64; 3] {
        [
            self.hi[0] - self.lo[0],
            self.hi[1] - self.lo[1],
            self.hi[2] - self.lo[2],
        ]
    }

    /// Atoms per cubic Angstrom.
    pub fn number_density(&self) -> f64 {
        let l = self.lengths();
        self.atoms as f64 / (l[0] * l[1] * l[2])
    }
}

/// What [`plan`] decided: replicas, actual dimensions, atom and cost estimates, the input text.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JunctionPlan {
    pub replicas: [u32; 3],
    /// Actual box (nm) after replication (integer multiples of the block).
    pub box_nm: [f64; 3],
    /// Solid thickness and junction height (nm) after snapping to the replicated box.
    pub slab_nm: f64,
    pub height_nm: f64,
    /// Atoms before carving and expected after (from the block's number density).
    pub atoms_replicated: u64,
    pub atoms_estimate: u64,
    pub relax_steps: u64,
    pub shear_steps: u64,
    /// Single-core CPU hours of relaxation plus shear at [`SECONDS_PER_ATOM_STEP`].
    pub core_hours_estimate: f64,
    pub input: String,
}

/// Plans the junction for `block`: replicas nearest to the requested box, carving planes, input.
pub fn plan(cfg: &SilicaJunctionConfig, block: &GlassBlock) -> Result<JunctionPlan> {
    cfg.validate()?;
    let bl = block.lengths();
    let mut rep = [0u32; 3];
    let mut l = [0.0; 3];
    for k in 0..3 {
        let n = (cfg.box_nm[k] * 10.0 / bl[k]).round().max(1.0);
        if n > 1e5 {
            return Err(MdError::config(
                "silica junction",
                format!("{n} replicas along axis {k}: the glass block is too small"),
            ));
        }
        rep[k] = n as u32;
        l[k] = n * bl[k];
    }
    let (lo, hi) = (
        block.lo,
        [block.lo[0] + l[0], block.lo[1] + l[1], block.lo[2] + l[2]],
    );
    let d = cfg.diameter_nm * 10.0;
    let h = cfg.height_nm() * 10.0;
    let slab = (l[2] - h) / 2.0;
    let (wall, bath) = (cfg.wall_nm * 10.0, cfg.bath_nm * 10.0);
    if d >= l[0].min(l[1]) || slab <= wall + bath {
        return Err(MdError::config(
            "silica junction",
            format!(
                "the replicated box {:.2} x {:.2} x {:.2} nm leaves no room for D = {} nm, H = {:.2} nm, walls and baths",
                l[0] / 10.0,
                l[1] / 10.0,
                l[2] / 10.0,
                cfg.diameter_nm,
                h / 10.0
            ),
        ));
    }
    let (zb, zt) = (lo[2] + slab, lo[2] + slab + h);
    let (cx, cy) = (lo[0] + l[0] / 2.0, lo[1] + l[1] / 2.0);
    let atoms_replicated = block.atoms * rep.iter().map(|&r| r as u64).product::<u64>();
    let kept = l[0] * l[1] * 2.0 * slab + std::f64::consts::PI * d * d / 4.0 * h;
    let atoms_estimate = (block.number_density() * kept).round() as u64;
    let relax_steps = cfg.steps(cfg.relax_ps);
    let shear_steps = cfg.shear_steps();
    let core_hours_estimate = atoms_estimate as f64
        * (relax_steps + shear_steps + cfg.min_iterations) as f64
        * SECONDS_PER_ATOM_STEP
        / 3600.0;
    // metal units: velocity in A/ps (1 m/s = 0.01 A/ps); pressure to eV/A^3 (1 eV/A^3 = 160.2177 GPa).
    let v = cfg.velocity_m_s * 0.01;
    let p = cfg.normal_pressure_mpa * 1e6 / 160.217_663_4e9;
    let dump_every = cfg.steps(cfg.dump_every_ps);
    let dump = if dump_every > 0 {
        format!("dump frames all custom {dump_every} ${{dir}}/junction.dump id type x y z vx vy vz\ndump_modify frames sort id")
    } else {
        "# no dump (dump_every_ps = 0)".to_owned()
    };
    let s = crate::lammps::lammps_seed(cfg.seed, 1);
    let t = cfg.temperature;
    let input = format!(
        "# Silica junction shear, paper 000 section 4 geometry; written by `cgdem md silica-junction`.
# D = {dnm} nm, H = {hnm:.3} nm, box {bx:.3} x {by:.3} x {bz:.3} nm ({rx} x {ry} x {rz} glass blocks),
# ~{atoms} atoms. Run from this directory: mpirun -np N lmp -in {INPUT_FILE}
# Shorten for a check: lmp -var relax_steps 10 -var shear_steps 10 -var min_iter 10 -in {INPUT_FILE}
variable dir index .
variable min_iter index {min_iter}
variable relax_steps index {relax_steps}
variable shear_steps index {shear_steps}
units metal
atom_style atomic
atom_modify map yes
boundary p p p
read_data ${{dir}}/{GLASS_FILE}
replicate {rx} {ry} {rz} bbox
# carve: the gap between the solids, except the cylindrical junction
region gap block INF INF INF INF {zb} {zt} units box
region outside cylinder z {cx} {cy} {r} {zb} {zt} side out units box
region cut intersect 2 gap outside
delete_atoms region cut
region pillar cylinder z {cx} {cy} {r} {zb} {zt} units box
# free outer faces (inside the rigid walls), periodic sideways
change_box all boundary p p s
pair_style vashishta
pair_coeff * * ${{dir}}/SiO.1990.vashishta Si O
neighbor 1.0 bin
neigh_modify every 1 delay 0 check yes
timestep {dt}
region rbot block INF INF INF INF INF {wb} units box
region rtop block INF INF INF INF {wt} INF units box
region rbbath block INF INF INF INF {wb} {bb} units box
region rtbath block INF INF INF INF {tb} {wt} units box
group bot region rbot
group top region rtop
group bbath region rbbath
group tbath region rtbath
group junction region pillar
group mobile subtract all bot top
variable n_bot equal count(bot)
variable n_top equal count(top)
variable n_junction equal count(junction)
variable n_mobile equal count(mobile)
print \"JUNCTION atoms $(atoms) bottom wall ${{n_bot}} top wall ${{n_top}} junction ${{n_junction}}\"
# 1. relax the carved surfaces: minimise, then thermostatted MD, walls fixed
fix fbot bot setforce 0.0 0.0 0.0
fix ftop top setforce 0.0 0.0 0.0
thermo_style custom step temp pe press
thermo {thermo}
minimize 0.0 1.0e-4 ${{min_iter}} $(10*v_min_iter)
velocity mobile create {t2} {s} mom yes rot no dist gaussian
velocity bot set 0.0 0.0 0.0
velocity top set 0.0 0.0 0.0
fix integ mobile nve
fix lbot bbath langevin {t} {t} {damp} {s2} zero yes
compute ttop tbath temp/com
fix ltop tbath langevin {t} {t} {damp} {s3}
fix_modify ltop temp ttop
run ${{relax_steps}}
# 2. shear: bottom fixed, top driven along x at {vms} m/s under {pmpa} MPa
unfix ftop
velocity top set {v} 0.0 0.0
fix ftop top setforce 0.0 0.0 NULL
variable fz equal -{p}*lx*ly/count(top)
fix load top aveforce NULL NULL ${{fz}}
fix integt top nve
variable x0 equal xcm(top,x)
variable x0top equal ${{x0}}
variable slide equal xcm(top,x)-v_x0top
variable ftx equal f_ftop[1]
variable ftz equal f_ftop[3]
reset_timestep 0
thermo_style custom step temp pe v_ftx v_ftz v_slide
{dump}
run ${{shear_steps}}
print \"JUNCTION done: slide $(v_slide) A, tangential force $(v_ftx) eV/A\"
write_restart ${{dir}}/junction.restart
",
        dnm = cfg.diameter_nm,
        hnm = h / 10.0,
        bx = l[0] / 10.0,
        by = l[1] / 10.0,
        bz = l[2] / 10.0,
        rx = rep[0],
        ry = rep[1],
        rz = rep[2],
        atoms = atoms_estimate,
        min_iter = cfg.min_iterations,
        r = d / 2.0,
        dt = cfg.timestep_fs / 1000.0,
        wb = lo[2] + wall,
        wt = hi[2] - wall,
        bb = lo[2] + wall + bath,
        tb = hi[2] - wall - bath,
        thermo = cfg.thermo_every,
        t2 = 2.0 * t,
        s2 = s + 1,
        s3 = s + 2,
        damp = cfg.bath_damping_ps,
        vms = cfg.velocity_m_s,
        pmpa = cfg.normal_pressure_mpa,
    );
    Ok(JunctionPlan {
        replicas: rep,
        box_nm: [l[0] / 10.0, l[1] / 10.0, l[2] / 10.0],
        slab_nm: slab / 10.0,
        height_nm: h / 10.0,
        atoms_replicated,
        atoms_estimate,
        relax_steps,
        shear_steps,
        core_hours_estimate,
        input,
    })
}

/// Melt-quenches a glass (per `cfg`, measurements are not run) and writes it as a LAMMPS data
/// file (orthogonal box, velocities at `quench_end_temperature`). Returns the mean density (kg/m^3).
pub fn write_glass(lmp: &Lammps, potential: &Path, cfg: &SilicaConfig, path: &Path) -> Result<f64> {
    let rho = measure::melt_quench(lmp, potential, cfg)?;
    lmp.commands(&format!(
        "change_box all ortho\nwrite_data {} nocoeff",
        path.display()
    ))?;
    Ok(rho)
}

/// Writes `in.junction`, `glass.data` (the given block text) and a copy of the potential into
/// `out`; returns the plan.
pub fn write_job(
    cfg: &SilicaJunctionConfig,
    glass_data: &str,
    potential: &Path,
    out: &Path,
) -> Result<JunctionPlan> {
    let block = GlassBlock::parse(glass_data)?;
    let plan = plan(cfg, &block)?;
    std::fs::create_dir_all(out).map_err(|e| MdError::io(out, e))?;
    let write = |name: &str, text: &str| -> Result<PathBuf> {
        let p = out.join(name);
        std::fs::write(&p, text).map_err(|e| MdError::io(&p, e))?;
        Ok(p)
    };
    write(GLASS_FILE, glass_data)?;
    write(INPUT_FILE, &plan.input)?;
    let pot = out.join(super::POTENTIAL);
    std::fs::copy(potential, &pot).map_err(|e| MdError::io(&pot, e))?;
    let toml = toml::to_string(cfg).map_err(|e| MdError::config("silica junction config", e))?;
    write("junction.toml", &toml)?;
    Ok(plan)
}

/// The cluster command line, to run from the job directory.
pub fn mpirun_command(np: u32) -> String {
    format!("mpirun -np {np} lmp -in {INPUT_FILE}")
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEADER: &str =
        "LAMMPS data file via write_data, version 22 Jul 2025, timestep = 4000, units = metal

648 atoms
2 atom types

0 20.2 xlo xhi
0.5 20.7 ylo yhi
-1 19.2 zlo zhi

Masses

1 28.0855
2 15.9994

Atoms # atomic

1 1 0.1 0.2 0.3 0 0 0
";

    #[test]
    fn header_is_parsed_and_tilted_or_broken_headers_are_refused() {
        let b = GlassBlock::parse(HEADER).unwrap();
        assert_eq!(b.atoms, 648);
        assert_eq!(b.lo, [0.0, 0.5, -1.0]);
        assert_eq!(b.lengths(), [20.2, 20.2, 20.2]);
        let tilted = HEADER.replace("-1 19.2 zlo zhi", "-1 19.2 zlo zhi\n0.3 0 0 xy xz yz");
        assert!(GlassBlock::parse(&tilted).is_err());
        assert!(GlassBlock::parse(&HEADER.replace("648 atoms", "")).is_err());
        assert!(GlassBlock::parse("garbage\n\nnot a data file").is_err());
    }

    #[test]
    fn paper_geometry_plans_millions_of_atoms_and_both_diameters() {
        let b = GlassBlock::parse(HEADER).unwrap();
        for d in [10.0, 20.0] {
            let cfg = SilicaJunctionConfig {
                diameter_nm: d,
                ..Default::default()
            };
            let p = plan(&cfg, &b).unwrap();
            assert_eq!(p.replicas, [30, 20, 20]);
            assert!((p.height_nm - d / 2.0).abs() < 1e-9);
            assert!(p.atoms_estimate > 4_000_000 && p.atoms_estimate < p.atoms_replicated);
            // 2.5 D at 10 m/s with 1 fs steps.
            assert_eq!(
                p.shear_steps,
                (2.5 * d * 1e-9 / 10.0 / 1e-15_f64).round() as u64
            );
            for must in [
                "replicate 30 20 20 bbox",
                "delete_atoms region cut",
                "fix load top aveforce NULL NULL",
                "velocity top set 0.1 0.0 0.0",
                "${dir}/SiO.1990.vashishta",
            ] {
                assert!(p.input.contains(must), "missing `{must}`");
            }
        }
    }

    #[test]
    fn impossible_geometries_are_config_errors() {
        let b = GlassBlock::parse(HEADER).unwrap();
        let too_wide = SilicaJunctionConfig {
            diameter_nm: 45.0,
            ..Default::default()
        };
        assert!(matches!(plan(&too_wide, &b), Err(MdError::Config { .. })));
        let too_flat = SilicaJunctionConfig {
            box_nm: [60.0, 40.0, 12.0],
            ..Default::default()
        };
        assert!(matches!(plan(&too_flat, &b), Err(MdError::Config { .. })));
        let nan = SilicaJunctionConfig {
            velocity_m_s: f64::NAN,
            ..Default::default()
        };
        assert!(nan.validate().is_err());
    }
}
