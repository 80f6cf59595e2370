//! The wall rig every scenario shares (DESIGN.md section 7): a sample between two rigid walls facing
//! each other along a chosen *normal* axis, made of the particles within `thickness` of the two faces
//! normal to it; the box stays periodic along the other two axes and becomes open along the normal.
//! Each wall starts frozen; a scenario drives it per axis (velocity, force or traction, see
//! [`crate::walls`]). The patch tests use it with the normal along y and the shear along x, as do the
//! junction and the sliding layer.
//!
//! Conventions of its measures:
//! - strain: (change of the wall separation, or offset along the shear axis) / L0, with L0 the gap
//!   between the innermost wall particle centres;
//! - stress: virial stress (tension positive) of the free particles over their share of the sample
//!   volume, V_free = V_box N_free / N, stretched by (1 + eps_normal) (see the patch tests).

use nalgebra::Matrix3;

use crate::domain::SimBox;
use crate::error::{DemError, Result};
use crate::material::{PairCoefficients, PairModel};
use crate::sample::Sample;
use crate::sim::{Parallelism, RunConfig, Simulation};
use crate::walls::{Group, RigidMotion};
use crate::Vec3;

/// Group indices of the rig: free particles, bottom wall, top wall.
pub const FREE: u32 = 0;
pub const BOTTOM: u32 = 1;
pub const TOP: u32 = 2;

/// Where the walls are and which way the rig shears.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigSpec {
    /// Axis normal to the walls.
    pub normal: usize,
    /// Axis of the shear measures (the top wall's sliding direction).
    pub shear: usize,
    /// Wall thickness (box length units): particles whose centres lie this close to a face.
    pub thickness: f64,
}

impl RigSpec {
    /// Walls normal to y, shear along x, as in paper 000 Fig. 4.
    pub fn y_normal(thickness: f64) -> Self {
        RigSpec {
            normal: 1,
            shear: 0,
            thickness,
        }
    }
}

/// A sample between two rigid walls, with what the measurements need.
#[derive(Debug)]
pub struct Rig {
    pub sim: Simulation,
    /// Whether each particle is free (the deformable part).
    pub free: Vec<bool>,
    /// One member of each wall, to read the wall positions.
    pub bottom_ref: usize,
    pub top_ref: usize,
    /// Members of the top wall.
    pub top_members: Vec<usize>,
    /// Initial offset top - bottom reference.
    pub offset0: Vec3,
    /// Gap between the innermost wall particle centres (the strained length).
    pub l0: f64,
    /// Cross-section normal to the normal axis.
    pub area: f64,
    /// The axes.
    pub spec: RigSpec,
    /// Volume of the deformable part before straining.
    pub v_free0: f64,
    /// Initial positions (for the fitted strain).
    pub pos0: Vec<Vec3>,
}

impl Rig {
    /// Builds the rig from a sample periodic along the two axes other than the normal; both walls
    /// frozen, free particles at rest.
    pub fn new(
        sample: &Sample,
        model: &PairModel,
        spec: RigSpec,
        run: RunConfig,
        par: Parallelism,
    ) -> Result<Self> {
        let bx0 = sample.sim_box;
        let (n, s) = (spec.normal, spec.shear);
        if n > 2 || s > 2 || n == s {
            return Err(DemError::InvalidConfig(format!(
                "rig axes: normal {n} and shear {s} must be two different axes among 0, 1, 2"
            )));
        }
        let other = 3 - n - s;
        if !(bx0.periodic[s] && bx0.periodic[other]) {
            return Err(DemError::InvalidBox(format!(
                "a wall rig needs a sample periodic along axes {s} and {other}"
            )));
        }
        if !(spec.thickness.is_finite() && spec.thickness > 0.0) {
            return Err(DemError::InvalidConfig(format!(
                "wall thickness {} must be positive",
                spec.thickness
            )));
        }
        model.validate()?;
        let mut p = sample.particles.clone();
        p.validate()?;
        p.vel.iter_mut().for_each(|v| *v = Vec3::zeros());
        p.omega.iter_mut().for_each(|v| *v = Vec3::zeros());
        for x in p.pos.iter_mut() {
            bx0.wrap(x);
        }
        let r_max = p.radius.iter().cloned().fold(0.0, f64::max);
        let range = PairCoefficients::new(model).max_cutoff(r_max);
        let t = spec.thickness;
        let (lo, hi) = (bx0.lo[n], bx0.hi[n]);
        if hi - lo < 2.0 * t + range {
            return Err(DemError::InvalidBox(format!(
                "sample height {:.4e} too small for two walls of {t:.4e} and a free part",
                hi - lo
            )));
        }
        for i in 0..p.len() {
            p.group[i] = if p.pos[i][n] < lo + t {
                BOTTOM
            } else if p.pos[i][n] >= hi - t {
                TOP
            } else {
                FREE
            };
        }
        let free: Vec<bool> = p.group.iter().map(|&g| g == FREE).collect();
        let n_free = free.iter().filter(|&&f| f).count();
        let members =
            |g: u32| -> Vec<usize> { (0..p.len()).filter(|&i| p.group[i] == g).collect() };
        let (bottom, top) = (members(BOTTOM), members(TOP));
        if n_free == 0 || bottom.is_empty() || top.is_empty() {
            return Err(DemError::InvalidConfig(
                "a wall rig needs particles in both walls and between".into(),
            ));
        }
        let y_bot = bottom
            .iter()
            .map(|&i| p.pos[i][n])
            .fold(f64::NEG_INFINITY, f64::max);
        let y_top = top
            .iter()
            .map(|&i| p.pos[i][n])
            .fold(f64::INFINITY, f64::min);
        let offset0 = p.pos[top[0]] - p.pos[bottom[0]];
        let mut periodic = [true; 3];
        periodic[n] = false;
        let bx = SimBox::new(bx0.lo, bx0.hi, periodic)?;
        let l = bx.lengths();
        let groups = vec![
            Group::free("free"),
            Group::rigid("bottom", RigidMotion::frozen()),
            Group::rigid("top", RigidMotion::frozen()),
        ];
        let v_free0 = bx0.volume() * n_free as f64 / p.len() as f64;
        let pos0 = p.pos.clone();
        let sim = Simulation::new(p, bx, model.clone(), groups, run, par)?;
        Ok(Rig {
            sim,
            free,
            bottom_ref: bottom[0],
            top_ref: top[0],
            top_members: top,
            offset0,
            l0: y_top - y_bot,
            area: l[s] * l[other],
            spec,
            v_free0,
            pos0,
        })
    }

    /// Top-wall displacement relative to the bottom wall: (along the shear axis, along the normal).
    /// From the unwrapped positions: the stored ones jump by a box length when the top wall's reference
    /// particle crosses the periodic boundary, which turned a shear test's strain from +0.31 to -1.26
    /// and kept it from ever reaching its stop (the silica calibration's endless shear tests).
    pub fn wall_offset(&self) -> (f64, f64) {
        let d = self.sim.unwrapped_position(self.top_ref)
            - self.sim.unwrapped_position(self.bottom_ref)
            - self.offset0;
        (d[self.spec.shear], d[self.spec.normal])
    }

    /// Top-wall displacement relative to the bottom wall over L0: (shear, normal).
    pub fn strains(&self) -> (f64, f64) {
        let (s, n) = self.wall_offset();
        (s / self.l0, n / self.l0)
    }

    /// Strain of the deformable part from its own displacements: least-squares slopes of the shear and
    /// normal displacements against the initial normal coordinate of the free particles (shear, normal). Unlike [`Rig::strains`] it does not
    /// see the ragged wall faces, so it is the better measure while the deformation is homogeneous.
    pub fn fitted_strains(&self) -> (f64, f64) {
        let p = &self.sim.particles;
        let bx = &self.sim.sim_box;
        let idx = (0..p.len()).filter(|&i| self.free[i]);
        let n = self.free.iter().filter(|&&f| f).count() as f64;
        let (a, b) = (self.spec.shear, self.spec.normal);
        let y_mean = idx.clone().map(|i| self.pos0[i][b]).sum::<f64>() / n;
        let (mut sxx, mut sux, mut suy, mut ux_m, mut uy_m) = (0.0, 0.0, 0.0, 0.0, 0.0);
        // Displacements by minimum image: positions are wrapped along the periodic axes at list rebuilds.
        let disp: Vec<(f64, Vec3)> = idx
            .map(|i| {
                (
                    self.pos0[i][b] - y_mean,
                    bx.min_image(&self.pos0[i], &p.pos[i]),
                )
            })
            .collect();
        for (_, u) in &disp {
            ux_m += u[a] / n;
            uy_m += u[b] / n;
        }
        for (dy, u) in &disp {
            sxx += dy * dy;
            sux += dy * (u[a] - ux_m);
            suy += dy * (u[b] - uy_m);
        }
        (sux / sxx, suy / sxx)
    }

    /// One step that also computes the virials, then the stress of the deformable part.
    pub fn step_with_stress(&mut self) -> Result<Matrix3<f64>> {
        self.sim.request_virial();
        self.sim.step()?;
        Ok(self.stress())
    }

    /// Virial stress of the deformable part (needs virials from the last step).
    pub fn stress(&self) -> Matrix3<f64> {
        let (_, eyy) = self.strains();
        let free = &self.free;
        self.sim
            .virial_stress(Some(&|i| free[i]), Some(self.v_free0 * (1.0 + eyy)))
    }

    /// Pair force of the sample on the top wall at the last step (summed in member order).
    pub fn top_force(&self) -> Vec3 {
        let f = self.sim.forces();
        self.top_members
            .iter()
            .fold(Vec3::zeros(), |a, &i| a + f[i])
    }

    /// Pair force of the sample on the top wall, per unit area (the traction the wall transmits).
    pub fn top_traction(&self) -> Vec3 {
        self.top_force() / self.area
    }

    /// Sets the top wall's motion.
    pub fn set_top(&mut self, motion: RigidMotion) {
        self.sim.groups[TOP as usize].rigid = Some(motion);
    }
}
