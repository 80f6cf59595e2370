//! The wall rig shared by the patch tests (see the parent module for the conventions).

use nalgebra::Matrix3;

use super::WallConfig;
use crate::domain::SimBox;
use crate::error::{DemError, Result};
use crate::material::{PairCoefficients, PairModel};
use crate::sample::Sample;
use crate::sim::{Parallelism, RunConfig, Simulation};
use crate::walls::{Group, RigidMotion};
use crate::Vec3;

/// Group indices of the rig.
pub(crate) const BOTTOM: u32 = 1;
pub(crate) const TOP: u32 = 2;

/// A sample between two rigid walls, with what the measurements need.
#[derive(Debug)]
pub(crate) struct Rig {
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
    /// Cross-section normal to y.
    pub area: f64,
    /// Volume of the deformable part before straining.
    pub v_free0: f64,
    /// Initial positions (for the fitted strain).
    pub pos0: Vec<Vec3>,
}

impl Rig {
    /// Builds the rig from a periodic sample; both walls frozen, free particles at rest.
    pub fn new(
        sample: &Sample,
        model: &PairModel,
        walls: &WallConfig,
        run: RunConfig,
        par: Parallelism,
    ) -> Result<Self> {
        let bx0 = sample.sim_box;
        if !(bx0.periodic[0] && bx0.periodic[2]) {
            return Err(DemError::InvalidBox(
                "patch tests need a sample periodic along x and z".into(),
            ));
        }
        if !(walls.thickness.is_finite() && walls.thickness > 0.0) {
            return Err(DemError::InvalidConfig(format!(
                "wall thickness {} must be positive",
                walls.thickness
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
        let t = walls.thickness * range;
        let (lo, hi) = (bx0.lo.y, bx0.hi.y);
        if hi - lo < 2.0 * t + range {
            return Err(DemError::InvalidBox(format!(
                "sample height {:.4e} too small for two walls of {t:.4e} and a free part",
                hi - lo
            )));
        }
        for i in 0..p.len() {
            p.group[i] = if p.pos[i].y < lo + t {
                BOTTOM
            } else if p.pos[i].y >= hi - t {
                TOP
            } else {
                0
            };
        }
        let free: Vec<bool> = p.group.iter().map(|&g| g == 0).collect();
        let n_free = free.iter().filter(|&&f| f).count();
        let members =
            |g: u32| -> Vec<usize> { (0..p.len()).filter(|&i| p.group[i] == g).collect() };
        let (bottom, top) = (members(BOTTOM), members(TOP));
        if n_free == 0 || bottom.is_empty() || top.is_empty() {
            return Err(DemError::InvalidConfig(
                "patch rig needs particles in both walls and between".into(),
            ));
        }
        let y_bot = bottom
            .iter()
            .map(|&i| p.pos[i].y)
            .fold(f64::NEG_INFINITY, f64::max);
        let y_top = top
            .iter()
            .map(|&i| p.pos[i].y)
            .fold(f64::INFINITY, f64::min);
        let offset0 = p.pos[top[0]] - p.pos[bottom[0]];
        let bx = SimBox::new(bx0.lo, bx0.hi, [true, false, true])?;
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
            area: l.x * l.z,
            v_free0,
            pos0,
        })
    }

    /// Top-wall displacement relative to the bottom wall over L0: (shear along x, normal along y).
    pub fn strains(&self) -> (f64, f64) {
        let p = &self.sim.particles;
        let d = p.pos[self.top_ref] - p.pos[self.bottom_ref] - self.offset0;
        (d.x / self.l0, d.y / self.l0)
    }

    /// Strain of the deformable part from its own displacements: least-squares slopes of u_x and u_y
    /// against the initial y of the free particles (shear, normal). Unlike [`Rig::strains`] it does not
    /// see the ragged wall faces, so it is the better measure while the deformation is homogeneous.
    pub fn fitted_strains(&self) -> (f64, f64) {
        let p = &self.sim.particles;
        let bx = &self.sim.sim_box;
        let idx = (0..p.len()).filter(|&i| self.free[i]);
        let n = self.free.iter().filter(|&&f| f).count() as f64;
        let y_mean = idx.clone().map(|i| self.pos0[i].y).sum::<f64>() / n;
        let (mut sxx, mut sux, mut suy, mut ux_m, mut uy_m) = (0.0, 0.0, 0.0, 0.0, 0.0);
        // Displacements by minimum image: positions are wrapped along x and z at list rebuilds.
        let disp: Vec<(f64, Vec3)> = idx
            .map(|i| {
                (
                    self.pos0[i].y - y_mean,
                    bx.min_image(&self.pos0[i], &p.pos[i]),
                )
            })
            .collect();
        for (_, u) in &disp {
            ux_m += u.x / n;
            uy_m += u.y / n;
        }
        for (dy, u) in &disp {
            sxx += dy * dy;
            sux += dy * (u.x - ux_m);
            suy += dy * (u.y - uy_m);
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

    /// Pair force of the sample on the top wall, per unit area (the traction the wall transmits).
    pub fn top_traction(&self) -> Vec3 {
        let f = self.sim.forces();
        self.top_members
            .iter()
            .fold(Vec3::zeros(), |a, &i| a + f[i])
            / self.area
    }

    /// Sets the top wall's motion.
    pub fn set_top(&mut self, motion: RigidMotion) {
        self.sim.groups[TOP as usize].rigid = Some(motion);
    }
}
