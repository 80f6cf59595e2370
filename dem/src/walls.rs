//! Groups and rigid bodies (walls).
//!
//! Every particle belongs to one group. Free groups follow their pair forces; a rigid group moves as one
//! body in translation only (no rotation, as the papers' walls), each axis either at a prescribed velocity
//! (constant, or ramped towards a target at a bounded acceleration), or driven by its pair forces plus a
//! prescribed external force, or plus a prescribed traction times the box cross-section (a
//! pressure-controlled wall). A frozen wall is a rigid group at zero velocity.
//!
//! The work the outside world does on the walls is booked in the energy ledger: for a constant-velocity
//! axis the constraint force is minus the pair force on the group, for a ramped one that plus the mass
//! times the ramp's acceleration, for a force-controlled one it is the prescribed force.

use serde::{Deserialize, Serialize};

use crate::domain::SimBox;
use crate::error::{DemError, Result};
use crate::state::Particles;
use crate::Vec3;

/// How one axis of a rigid group moves.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AxisControl {
    /// Prescribed velocity along the axis.
    Velocity(f64),
    /// Prescribed velocity that moves from the body's current one towards `to` by at most
    /// `acceleration` dt per step, then stays at `to`: a start without the stress wave of a velocity
    /// step (rho c v on the face), which can exceed a material's strength.
    Ramp { to: f64, acceleration: f64 },
    /// Moves under its pair forces plus this external force.
    Force(f64),
    /// Moves under its pair forces plus this traction times the box cross-section normal to the axis
    /// (negative pushes towards lower coordinates: a top wall pressed down with pressure p uses -p).
    Traction(f64),
}

/// Motion of a rigid group.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RigidMotion {
    /// Per-axis control.
    pub axes: [AxisControl; 3],
    /// Current velocity of the body.
    pub velocity: Vec3,
}

impl RigidMotion {
    /// A wall that does not move.
    pub fn frozen() -> Self {
        Self::with_velocity(Vec3::zeros())
    }
    /// A wall moving at constant velocity.
    pub fn with_velocity(v: Vec3) -> Self {
        RigidMotion {
            axes: [
                AxisControl::Velocity(v.x),
                AxisControl::Velocity(v.y),
                AxisControl::Velocity(v.z),
            ],
            velocity: v,
        }
    }
}

/// A named group of particles.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Group {
    /// Name used in configs and dumps.
    pub name: String,
    /// `None`: free particles; `Some`: a rigid body.
    pub rigid: Option<RigidMotion>,
}

impl Group {
    /// A group of free particles.
    pub fn free(name: &str) -> Self {
        Group {
            name: name.to_string(),
            rigid: None,
        }
    }
    /// A rigid group.
    pub fn rigid(name: &str, motion: RigidMotion) -> Self {
        Group {
            name: name.to_string(),
            rigid: Some(motion),
        }
    }
}

/// Members of each rigid group, precomputed so that their sums run in a fixed order.
#[derive(Debug, Clone, Default)]
pub(crate) struct RigidIndex {
    /// (group index, member particle indices, total mass).
    pub bodies: Vec<(usize, Vec<u32>, f64)>,
    /// Whether particle i belongs to a rigid group.
    pub is_rigid: Vec<bool>,
}

impl RigidIndex {
    pub fn new(groups: &[Group], parts: &Particles) -> Result<Self> {
        for (i, &g) in parts.group.iter().enumerate() {
            if g as usize >= groups.len() {
                return Err(DemError::InvalidParticle {
                    index: i,
                    reason: format!("group {g} does not exist"),
                });
            }
        }
        let mut bodies = Vec::new();
        let mut is_rigid = vec![false; parts.len()];
        for (gi, g) in groups.iter().enumerate() {
            if let Some(m) = &g.rigid {
                for (a, c) in m.axes.iter().enumerate() {
                    let v = match c {
                        AxisControl::Velocity(v)
                        | AxisControl::Force(v)
                        | AxisControl::Traction(v) => *v,
                        AxisControl::Ramp { to, acceleration } => {
                            if !(acceleration.is_finite() && *acceleration > 0.0) {
                                return Err(DemError::InvalidConfig(format!(
                                    "group '{}' axis {a}: ramp acceleration {acceleration} must be \
                                     positive and finite",
                                    g.name
                                )));
                            }
                            *to
                        }
                    };
                    if !v.is_finite() {
                        return Err(DemError::InvalidConfig(format!(
                            "group '{}' axis {a}: value {v} not finite",
                            g.name
                        )));
                    }
                }
                let members: Vec<u32> = (0..parts.len())
                    .filter(|&i| parts.group[i] as usize == gi)
                    .map(|i| i as u32)
                    .collect();
                let mass = members.iter().map(|&i| parts.mass[i as usize]).sum();
                for &i in &members {
                    is_rigid[i as usize] = true;
                }
                bodies.push((gi, members, mass));
            }
        }
        Ok(RigidIndex { bodies, is_rigid })
    }

    /// Refuses rigid groups that occupy the same region: the bounding boxes of their particle centres
    /// intersect (closed intervals) on every axis. Walls facing each other, and rigid bodies merely in
    /// contact (even pressed into each other, as when probing a pair), pass; two walls placed in the
    /// same slab, or interleaved, do not.
    pub fn check_overlaps(&self, groups: &[Group], parts: &Particles) -> Result<()> {
        let bounds: Vec<Option<(Vec3, Vec3)>> = self
            .bodies
            .iter()
            .map(|(_, m, _)| {
                m.iter().fold(None, |acc: Option<(Vec3, Vec3)>, &i| {
                    let x = parts.pos[i as usize];
                    Some(match acc {
                        None => (x, x),
                        Some((a, b)) => (a.inf(&x), b.sup(&x)),
                    })
                })
            })
            .collect();
        let fmt = |v: Vec3| format!("({:.4e}, {:.4e}, {:.4e})", v.x, v.y, v.z);
        for a in 0..bounds.len() {
            for b in a + 1..bounds.len() {
                if let (Some((alo, ahi)), Some((blo, bhi))) = (bounds[a], bounds[b]) {
                    if (0..3).all(|k| alo[k] <= bhi[k] && blo[k] <= ahi[k]) {
                        return Err(DemError::OverlappingRigidGroups {
                            a: groups[self.bodies[a].0].name.clone(),
                            b: groups[self.bodies[b].0].name.clone(),
                            detail: format!(
                                "their particle centres span {} to {} and {} to {}, which intersect on every axis",
                                fmt(alo),
                                fmt(ahi),
                                fmt(blo),
                                fmt(bhi)
                            ),
                        });
                    }
                }
            }
        }
        Ok(())
    }

    /// Advances every rigid body by one step; returns the work done on them by the outside this step.
    pub fn advance(
        &self,
        groups: &mut [Group],
        parts: &mut Particles,
        force: &[Vec3],
        bx: &SimBox,
        dt: f64,
    ) -> f64 {
        let mut work = 0.0;
        let l = bx.lengths();
        for (gi, members, mass) in &self.bodies {
            let Some(motion) = groups[*gi].rigid.as_mut() else {
                continue;
            };
            let mut fsum = Vec3::zeros();
            for &i in members {
                fsum += force[i as usize];
            }
            for a in 0..3 {
                let area = l[(a + 1) % 3] * l[(a + 2) % 3];
                let external = match motion.axes[a] {
                    AxisControl::Velocity(v) => {
                        motion.velocity[a] = v;
                        -fsum[a]
                    }
                    AxisControl::Ramp { to, acceleration } => {
                        let dv =
                            (to - motion.velocity[a]).clamp(-acceleration * dt, acceleration * dt);
                        motion.velocity[a] += dv;
                        // What holds the body on its ramp: minus the pair force, plus what changes
                        // its momentum.
                        mass * dv / dt - fsum[a]
                    }
                    AxisControl::Force(f) => {
                        motion.velocity[a] += (fsum[a] + f) / mass * dt;
                        f
                    }
                    AxisControl::Traction(s) => {
                        motion.velocity[a] += (fsum[a] + s * area) / mass * dt;
                        s * area
                    }
                };
                work += external * motion.velocity[a] * dt;
            }
            let v = motion.velocity;
            for &i in members {
                let i = i as usize;
                parts.vel[i] = v;
                parts.omega[i] = Vec3::zeros();
                parts.pos[i] += v * dt;
            }
        }
        work
    }
}
