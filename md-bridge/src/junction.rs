//! MD junction shear for the 2D model material (paper 000 section 4 geometry, scaled): two crystal
//! slabs joined by a junction of width D and height D/2, bottom wall fixed, top wall driven at
//! constant velocity under a constant normal load, periodic along the sliding direction. Junction
//! atom positions and the tangential force are sampled and handed to [`wear::classify`], the same
//! classifier that judges the DEM junctions, with the cluster analysis of [`wear::outcome::detachment`]
//! (bonds: pairs within the LJ cut-off; anchors: the wall atoms) as evidence.
//! Units are reduced LJ (sigma, epsilon, tau); atoms interact through the model material's
//! shifted LJ pair with the configured cut-off.

use crate::error::{MdError, Result};
use crate::lammps::Lammps;
use crate::model::{lattice_commands, lattice_spacing, pair_commands};
use serde::{Deserialize, Serialize};
use wear::outcome::{detachment, unwrap_frame, Bonding, Periodicity};
use wear::{classify, ClassifyParams, Verdict};

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct JunctionConfig {
    /// Junction width D (sigma).
    pub width: f64,
    /// Pair cut-off (sigma), as in [`crate::model::ModelConfig`]; 1.3 gives d* ~ 25 sigma.
    pub cutoff: f64,
    /// Period along x in units of D; 3 D keeps the junction's images apart (paper: 3-6 D).
    pub length_factor: f64,
    /// Slab thickness in units of D; 0.5 D is enough to carry the load to the walls.
    pub slab_factor: f64,
    /// Temperature of the thermostatted layer above the bottom wall (epsilon/k_B); cold.
    pub temperature: f64,
    pub timestep: f64,
    /// Top wall speed (sigma/tau); ~1 % of the sound speed, like the paper's 10 m/s vs 5760 m/s.
    pub velocity: f64,
    /// Normal pressure on the top wall (epsilon/sigma^2); ~0.15 % of E, the paper's 100 MPa ratio.
    pub normal_pressure: f64,
    /// Sliding distance in units of D; a particle rolling between the walls turns by about
    /// slide / D rad, so 2.5 D gives ~2.5 rad, clear of the classifier's 2 rad threshold.
    pub slide_factor: f64,
    /// Number of sampled frames; few enough that a frame's turn dominates thermal jitter.
    pub frames: usize,
    /// Seeds the thermal velocities (`velocity create`) and the Langevin bath.
    pub seed: u64,
    /// Lateral position of the junction in the crystal, as a fraction of the lattice spacing in
    /// [0, 1): shifts which lattice columns the junction's edges cut, so that runs that differ by it
    /// are different junctions of the same width (as two DEM packings are), not only different
    /// thermal noise on the same one. 0 (the default) keeps the junction centred in the period.
    #[serde(skip_serializing_if = "is_zero")]
    pub lattice_offset: f64,
    pub classify: ClassifyParams,
    /// LAMMPS dump of every frame (OVITO reads it), relative to the working directory (the job
    /// directory for worker jobs); None writes nothing.
    pub dump_file: Option<String>,
}

impl Default for JunctionConfig {
    fn default() -> Self {
        Self {
            width: 12.0,
            cutoff: 1.3,
            length_factor: 3.0,
            slab_factor: 0.5,
            temperature: 0.01,
            timestep: 0.005,
            velocity: 0.1,
            normal_pressure: 0.1,
            slide_factor: 2.5,
            frames: 60,
            seed: 777,
            lattice_offset: 0.0,
            classify: ClassifyParams::default(),
            dump_file: Some("junction.dump".into()),
        }
    }
}

impl JunctionConfig {
    pub fn validate(&self) -> Result<()> {
        MdError::require_positive(
            "junction config",
            &[
                ("width", self.width),
                ("cutoff", self.cutoff),
                ("length_factor", self.length_factor),
                ("slab_factor", self.slab_factor),
                ("temperature", self.temperature),
                ("timestep", self.timestep),
                ("velocity", self.velocity),
                ("slide_factor", self.slide_factor),
            ],
        )?;
        if !(0.0..1.0).contains(&self.lattice_offset) {
            return Err(MdError::config(
                "junction config",
                format!("lattice_offset {} must lie in [0, 1)", self.lattice_offset),
            ));
        }
        if self.length_factor < 1.5 || self.frames < 2 || self.width < 4.0 || self.cutoff < 1.2 {
            return Err(MdError::config(
                "junction config",
                "need length_factor >= 1.5, frames >= 2, width >= 4 sigma, cutoff >= 1.2",
            ));
        }
        Ok(())
    }
}

/// Serde: a zero offset is left out of the job, so the cache keys of the jobs made before the field
/// existed stay valid.
fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JunctionResult {
    pub n_atoms: u64,
    pub junction_atoms: usize,
    /// Sampled times (tau), top-wall tangential force (epsilon/sigma), wall displacement (sigma).
    pub time: Vec<f64>,
    pub tangential_force: Vec<f64>,
    pub verdict: Verdict,
}

/// Builds the two-slab geometry, shears it, classifies the outcome.
pub fn run(lmp: &Lammps, cfg: &JunctionConfig) -> Result<JunctionResult> {
    cfg.validate()?;
    let a = lattice_spacing();
    let d = cfg.width;
    let nx = (cfg.length_factor * d / a).round().max(4.0);
    let lx = nx * a;
    let row = 3f64.sqrt() / 2.0 * a;
    // Heights snapped to lattice rows so every region boundary falls between rows.
    let snap = |h: f64| (h / row).round().max(2.0) * row;
    let (hs, gap) = (snap(cfg.slab_factor * d), snap(d / 2.0));
    let (y1, y2, y3) = (hs, hs + gap, 2.0 * hs + gap);
    let centre = lx / 2.0 + cfg.lattice_offset * a;
    let (xl, xr) = (centre - d / 2.0, centre + d / 2.0);
    let wall = 2.0 * row + 0.1;
    let s = crate::lammps::lammps_seed(cfg.seed, 1);
    lmp.commands(&format!(
        "{lattice}
region box block 0 {lx} -0.25 {ytop} -0.5 0.5 units box
create_box 1 box
region lower block INF INF -0.25 {yb} INF INF units box
region junc block {xl} {xr} {yb} {yc} INF INF units box
region upper block INF INF {yc} {ytop} INF INF units box
create_atoms 1 region lower
create_atoms 1 region junc
create_atoms 1 region upper
{pair}
region rbot block INF INF INF {wb} INF INF units box
region rtop block INF INF {wt} INF INF INF units box
region rbath block INF INF {wb} {bath} INF INF units box
group bot region rbot
group top region rtop
group bath region rbath
group junction region junc
group mobile subtract all bot top
variable ntop equal count(top)",
        lattice = lattice_commands("p s p"),
        pair = pair_commands(cfg.cutoff, cfg.timestep),
        ytop = y3 + 0.25,
        yb = y1 - 0.01,
        yc = y2 - 0.01,
        wb = wall,
        wt = y3 - wall,
        bath = wall + 3.0 * row,
    ))?;
    let ntop = lmp.variable("ntop")?;
    if ntop < 1.0 {
        return Err(MdError::measurement("junction", "empty top wall group"));
    }
    lmp.commands(&format!(
        "velocity mobile create {t2} {s} mom yes rot yes dist gaussian
velocity bot set 0.0 0.0 0.0
velocity top set {v} 0.0 0.0
fix fbot bot setforce 0.0 0.0 0.0
fix ftop top setforce 0.0 NULL 0.0
fix load top aveforce NULL {fy} NULL
fix integ all nve
fix bath bath langevin {t} {t} 1.0 {s2}
fix e2d all enforce2d
variable ft equal f_ftop[1]
thermo_style custom step temp pe f_ftop[1]
thermo 0",
        t2 = 2.0 * cfg.temperature,
        t = cfg.temperature,
        s2 = s + 1,
        v = cfg.velocity,
        fy = -cfg.normal_pressure * lx / ntop,
    ))?;
    if let Some(f) = &cfg.dump_file {
        lmp.command(&format!("dump frames all atom {} {f}", frame_steps(cfg, d)))?;
    }
    let n = lmp.natoms()? as usize;
    let ids = lmp.gather_i32("id", 1)?;
    let x0 = lmp.gather_f64("x", 3)?;
    // Junction members: atoms created inside the junction region (gathered in id order).
    let members: Vec<usize> = (0..n)
        .filter(|&i| {
            let (x, y) = (x0[3 * i], x0[3 * i + 1]);
            x >= xl && x < xr && y >= y1 - 0.01 && y < y2 - 0.01
        })
        .collect();
    if members.len() < 10 || ids.len() != n {
        return Err(MdError::measurement(
            "junction",
            format!("only {} junction atoms", members.len()),
        ));
    }
    let wear_err = |e: wear::WearError| MdError::measurement("junction", e.to_string());
    let per = Periodicity([Some(lx), None, None]);
    let (mut time, mut force) = (vec![0.0], vec![0.0]);
    let every = frame_steps(cfg, d);
    // Every atom on its continuous path, unwrapped along the periodic x by the displacement since
    // the previous frame (< Lx/2): the members' frames are read from it, and the cluster analysis
    // follows each bond's periodic image from the first frame to the last.
    let all =
        |x: &[f64]| -> Vec<[f64; 3]> { (0..n).map(|i| [x[3 * i], x[3 * i + 1], 0.0]).collect() };
    let pick = |path: &[[f64; 3]]| -> Vec<[f64; 3]> { members.iter().map(|&i| path[i]).collect() };
    let mut path = all(&x0);
    let mut frames = vec![pick(&path)];
    for k in 1..=cfg.frames {
        lmp.command(&format!(
            "run {every} pre {} post no",
            if k == 1 { "yes" } else { "no" }
        ))?;
        let x = lmp.gather_f64("x", 3)?;
        let mut now = all(&x);
        unwrap_frame(&path, &mut now, &per).map_err(wear_err)?;
        path = now;
        frames.push(pick(&path));
        time.push(k as f64 * every as f64 * cfg.timestep);
        force.push(lmp.variable("ft")?);
    }
    // Cluster analysis over every atom, anchored at the two walls (the atoms in the wall slabs).
    let anchors: Vec<usize> = (0..n)
        .filter(|&i| x0[3 * i + 1] < wall || x0[3 * i + 1] >= y3 - wall)
        .collect();
    let bonding = Bonding {
        radii: None,
        margin: cfg.cutoff,
        periodicity: per,
    };
    let detached = detachment(&all(&x0), &path, &bonding, &members, &anchors).map_err(wear_err)?;
    let verdict = classify(&frames, &force, Some(detached), &cfg.classify).map_err(wear_err)?;
    Ok(JunctionResult {
        n_atoms: n as u64,
        junction_atoms: members.len(),
        time,
        tangential_force: force,
        verdict,
    })
}

fn frame_steps(cfg: &JunctionConfig, d: f64) -> u64 {
    let total = cfg.slide_factor * d / cfg.velocity / cfg.timestep;
    ((total / cfg.frames as f64).round() as u64).max(1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_lattice_offset_is_checked_and_a_zero_one_stays_out_of_the_job() {
        let ok = JunctionConfig {
            lattice_offset: 0.618,
            ..JunctionConfig::default()
        };
        assert!(ok.validate().is_ok());
        for bad in [1.0, -0.1, f64::NAN] {
            let c = JunctionConfig {
                lattice_offset: bad,
                ..JunctionConfig::default()
            };
            let e = c.validate().unwrap_err().to_string();
            assert!(e.contains("lattice_offset"), "{e}");
        }
        // Zero is omitted (the cache keys of older jobs hold), anything else is written and read back.
        let zero = serde_json::to_string(&JunctionConfig::default()).unwrap();
        assert!(!zero.contains("lattice_offset"), "{zero}");
        let text = serde_json::to_string(&ok).unwrap();
        let back: JunctionConfig = serde_json::from_str(&text).unwrap();
        assert_eq!(back, ok);
    }
}
