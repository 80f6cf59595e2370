//! The contact loop of the plastic-wear model: one rigid sphere against the surface spheres under it.
//!
//! A step at level n (projectile at x_n with the velocity v_n that brought it there, surface at z_n):
//! 1. contacts: every sphere within r = R_p + r_s of the projectile's centre (found through the
//!    grid, never by a scan of the surface); Hertz normal force and the tangential spring advanced by
//!    the relative displacement of the step that reached x_n (projectile translation and spin at the
//!    contact point, lever R_p - delta / 2 as in LAMMPS, minus the sphere's own last displacement);
//! 2. flow indexes (eqs 7-8) from each sphere's vertical force and its force along the horizontal
//!    motion, with the effective area of App. A;
//! 3. symplectic Euler (paper 000 eq 1, the engine's scheme): v_{n+1} = v_n + F_n / m dt,
//!    x_{n+1} = x_n + v_{n+1} dt, omega likewise with I = 2/5 m R^2; prescribed axes keep their
//!    velocity (the drive of a scratch or an indentation), the others feel the contacts and the load;
//! 4. flow (eq 9): every sphere with i_V = 1 goes down by the projectile's downward displacement of
//!    the step, every sphere with i_L = 1 by eq (5) with the projectile's advance along its horizontal
//!    motion; wear dissipation eq (21) and wear volume eq (6) follow.
//!
//! Decision (eqs 3-4 under symplectic Euler): paper 001 writes the surface displacement as the
//! projectile's velocity-Verlet displacement, dz = V_z dt + F_z dt^2 / (2m), and then drops the second
//! term. Here a flowing sphere moves by the projectile's own displacement of the step,
//! v_{z,n+1} dt = v_{z,n} dt + F_z dt^2 / m: under this scheme that is the displacement, so a flowing
//! sphere keeps its overlap, and its force stays at the threshold, exactly, as eqs 7-9 intend. The
//! two differ by F_z dt^2 / (2m) per step, O(dt) over a run: `tests/plastic_impact.rs` shows the wear
//! volume converging as dt halves and the ledger closing to the integrator's accuracy.
//! Decision: spheres move only down and only before an advancing projectile (a flow index set while
//! the projectile rises or recedes displaces nothing): wear never refills the surface.

use serde::{Deserialize, Serialize};

use super::flow::{
    effective_area, flows_laterally, flows_vertically, lateral_displacement, LateralOffset,
};
use super::ledger::PlasticLedger;
use super::model::Params;
use super::surface::Surface;
use crate::error::{DemError, Result};
use crate::force::hertz::tangential_step;
use crate::Vec3;

/// How the projectile moves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Drive {
    /// Axes whose velocity is prescribed (kept as it is); the others move under the forces.
    pub fixed: [bool; 3],
    /// Constant external force (engine units), e.g. the normal load of a scratch.
    pub load: Vec3,
    /// Whether the projectile rotates.
    pub spin: bool,
}

impl Drive {
    /// A free projectile (impact).
    pub fn free(spin: bool) -> Self {
        Drive {
            fixed: [false; 3],
            load: Vec3::zeros(),
            spin,
        }
    }
    /// Every axis prescribed, no rotation (indentation at constant velocity).
    pub fn kinematic() -> Self {
        Drive {
            fixed: [true; 3],
            load: Vec3::zeros(),
            spin: false,
        }
    }
}

/// Position and velocities of the rigid sphere.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub(crate) struct Body {
    pub pos: Vec3,
    pub vel: Vec3,
    pub omega: Vec3,
}

/// Everything that evolves (what a progress file keeps).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub(crate) struct RigState {
    pub surface: Surface,
    pub body: Body,
    pub step: u64,
    /// Cumulative friction and wear dissipation, external work (engine units).
    pub friction: f64,
    pub wear: f64,
    pub external_work: f64,
    /// Wear volume by vertical (i_V) and lateral (i_L) flow: the normal and scratch parts of Fig. 5b.
    pub wear_normal: f64,
    pub wear_lateral: f64,
    /// Spheres in contact at the last step, increasing.
    pub active: Vec<u32>,
}

/// What a step measured at its level n.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct StepReport {
    pub contacts: usize,
    /// Contact force on the projectile.
    pub force: Vec3,
    /// A_z: spheres in contact times a_s (section 3.1).
    pub area_contact: f64,
    /// A_LB^V (eq 19) and A_LB^L (eq 20).
    pub area_vertical: f64,
    pub area_lateral: f64,
    /// Wear volume (eq 6) since the drive was set, at this level (before the step's flow).
    pub wear_volume: f64,
    pub ledger: PlasticLedger,
}

/// One contact of the step (scratch, reused).
#[derive(Debug, Clone, Copy)]
struct Contact {
    sphere: u32,
    /// Vertical force on the sphere, positive down.
    f_z: f64,
    /// r - h_i = Z - z_i.
    vertical: f64,
    /// The sphere's horizontal offset from the projectile's centre along the motion.
    along: f64,
    flows_v: bool,
    flows_l: bool,
}

/// The loop and its state.
#[derive(Debug, Clone)]
pub(crate) struct Rig {
    pub q: Params,
    pub drive: Drive,
    pub dt: f64,
    pub st: RigState,
    /// Refuse steps above the stable step of the contacts met (on when any axis is free).
    check_stability: bool,
    candidates: Vec<u32>,
    contacts: Vec<Contact>,
    active_next: Vec<u32>,
}

impl Rig {
    pub fn new(q: Params, surface: Surface, body: Body, drive: Drive, dt: f64) -> Rig {
        Rig::resume(
            q,
            RigState {
                surface,
                body,
                step: 0,
                friction: 0.0,
                wear: 0.0,
                external_work: 0.0,
                wear_normal: 0.0,
                wear_lateral: 0.0,
                active: Vec::new(),
            },
            drive,
            dt,
        )
    }

    /// A loop continuing from a saved state.
    pub fn resume(q: Params, st: RigState, drive: Drive, dt: f64) -> Rig {
        let check_stability = drive.fixed.iter().any(|f| !f) || drive.spin;
        Rig {
            q,
            drive,
            dt,
            st,
            check_stability,
            candidates: Vec::new(),
            contacts: Vec::new(),
            active_next: Vec::new(),
        }
    }

    /// Changes the drive (indentation -> sliding) and restarts the cumulative terms from zero.
    pub fn set_drive(&mut self, drive: Drive) {
        self.set_drive_keeping(drive);
        self.st.friction = 0.0;
        self.st.wear = 0.0;
        self.st.external_work = 0.0;
        self.st.wear_normal = 0.0;
        self.st.wear_lateral = 0.0;
    }

    /// Changes the drive and keeps the cumulative terms (a resumed run).
    pub fn set_drive_keeping(&mut self, drive: Drive) {
        self.drive = drive;
        self.check_stability = drive.fixed.iter().any(|f| !f) || drive.spin;
    }

    /// Time of the current level.
    pub fn time(&self) -> f64 {
        self.st.step as f64 * self.dt
    }

    /// Horizontal distance within which a sphere of the surface can touch the projectile (None when
    /// it is too high to touch any).
    pub fn reach(&self) -> Option<f64> {
        let h = self.st.body.pos.z - self.st.surface.top();
        (h < self.q.reach).then(|| (self.q.reach * self.q.reach - h * h).sqrt())
    }

    /// Whether the projectile overlaps a sphere now.
    pub fn overlaps(&mut self) -> bool {
        let p = self.st.body.pos;
        let Some(reach) = self.reach() else {
            return false;
        };
        self.candidates.clear();
        let s = &self.st.surface;
        s.candidates(p.x, p.y, reach, &mut self.candidates);
        self.candidates.iter().any(|&i| {
            let i = i as usize;
            (p - Vec3::new(s.x[i], s.y[i], s.z[i])).norm() < self.q.reach
        })
    }

    /// Advances one step (see the module).
    pub fn step(&mut self) -> Result<StepReport> {
        let (q, dt) = (self.q, self.dt);
        let now = q.units.time_to_s(self.time());
        let Body {
            pos: p,
            vel: v,
            omega: w,
        } = self.st.body;
        let heading = {
            let h = Vec3::new(v.x, v.y, 0.0);
            let n = h.norm();
            (n > 0.0).then(|| h / n)
        };
        self.candidates.clear();
        self.contacts.clear();
        if let Some(reach) = self.reach() {
            let s = &self.st.surface;
            if !s.holds_disk(p.x, p.y, reach) {
                return Err(DemError::InvalidConfig(format!(
                    "the projectile reached the edge of the surface at t = {now:.6e} s (centre at \
                     x = {:.4e} m, y = {:.4e} m on a {:.4e} x {:.4e} m strip): enlarge the surface or \
                     aim nearer its centre",
                    q.units.length_to_m(p.x),
                    q.units.length_to_m(p.y),
                    q.units.length_to_m(s.length()),
                    q.units.length_to_m(s.width()),
                )));
            }
            s.candidates(p.x, p.y, reach, &mut self.candidates);
        }

        let mut force = Vec3::zeros();
        let mut torque = Vec3::zeros();
        let (mut u_n, mut u_t, mut friction) = (0.0, 0.0, 0.0);
        let (mut stiff_n, mut stiff_t) = (0.0, 0.0);
        let (mut area_v, mut area_l) = (0.0, 0.0);
        let s = &mut self.st.surface;
        for &i in &self.candidates {
            let k = i as usize;
            let c = Vec3::new(s.x[k], s.y[k], s.z[k]);
            let d = p - c;
            let dist = d.norm();
            let delta = q.reach - dist;
            if delta <= 0.0 {
                continue;
            }
            let n = d / dist;
            let f_n = q.hertz.force(delta);
            let arm = -(q.radius - 0.5 * delta) * n;
            let slip = (v + w.cross(&arm) - Vec3::new(0.0, 0.0, s.dz_last[k] / dt)) * dt;
            let xi = Vec3::new(s.xi[0][k], s.xi[1][k], s.xi[2][k]);
            let t = tangential_step(xi, &n, &slip, q.k_t, q.friction, f_n);
            s.xi[0][k] = t.xi.x;
            s.xi[1][k] = t.xi.y;
            s.xi[2][k] = t.xi.z;
            friction += t.dissipated;
            let f = n * f_n + t.force;
            force += f;
            torque += arm.cross(&t.force);
            u_n += q.hertz.energy(delta);
            u_t += 0.5 * q.k_t * t.xi.norm_squared();
            stiff_n += q.hertz.stiffness(delta);
            stiff_t += q.k_t;

            let vertical = p.z - c.z;
            let a_i = effective_area(q.cell_area, q.reach, vertical);
            let f_z = f.z; // the sphere is pushed down by what pushes the projectile up
            let flows_v = flows_vertically(f_z, a_i, q.hardness);
            let (along, flows_l) = match heading {
                Some(e) => (
                    (c - p).dot(&e),
                    flows_laterally(-f.dot(&e), a_i, q.shear_hardness),
                ),
                None => (0.0, false),
            };
            if flows_v {
                area_v += a_i;
            }
            if flows_l {
                area_l += a_i;
            }
            self.contacts.push(Contact {
                sphere: i,
                f_z,
                vertical,
                along,
                flows_v,
                flows_l,
            });
        }
        // Contacts that opened: the spring's energy goes to friction (its cap mu F_n went to zero).
        self.active_next.clear();
        self.active_next
            .extend(self.contacts.iter().map(|c| c.sphere));
        let mut next = self.active_next.iter().peekable();
        for &i in &self.st.active {
            while next.peek().is_some_and(|&&j| j < i) {
                next.next();
            }
            if next.peek() != Some(&&i) {
                let k = i as usize;
                let xi2 = s.xi[0][k].powi(2) + s.xi[1][k].powi(2) + s.xi[2][k].powi(2);
                friction += 0.5 * q.k_t * xi2;
                s.xi[0][k] = 0.0;
                s.xi[1][k] = 0.0;
                s.xi[2][k] = 0.0;
                s.dz_last[k] = 0.0;
            }
        }
        std::mem::swap(&mut self.st.active, &mut self.active_next);

        if self.check_stability && !self.contacts.is_empty() {
            let k = stiff_n.max(stiff_t * if self.drive.spin { 3.5 } else { 1.0 });
            let stable = 2.0 * (q.mass / k).sqrt();
            if dt > stable {
                return Err(DemError::InvalidConfig(format!(
                    "time step {:.4e} s exceeds the stable step {:.4e} s of the {} Hertzian \
                     contacts met at t = {now:.6e} s; lower the time step",
                    q.units.time_to_s(dt),
                    q.units.time_to_s(stable),
                    self.contacts.len(),
                )));
            }
        }

        // Symplectic Euler.
        let body = &mut self.st.body;
        for a in 0..3 {
            if !self.drive.fixed[a] {
                body.vel[a] += (force[a] + self.drive.load[a]) / q.mass * dt;
            }
        }
        if self.drive.spin {
            body.omega += torque / q.inertia * dt;
        }
        let dx = body.vel * dt;
        body.pos += dx;
        if !(body.pos.iter().all(|x| x.is_finite()) && body.vel.iter().all(|x| x.is_finite())) {
            return Err(DemError::NonFinite {
                step: self.st.step,
                index: 0,
                what: "projectile position or velocity",
            });
        }
        self.st.friction += friction;
        let ledger = PlasticLedger {
            kinetic: 0.5 * q.mass * v.dot(&body.vel) + 0.5 * q.inertia * w.dot(&body.omega),
            strain_normal: u_n,
            strain_tangential: u_t,
            friction: self.st.friction,
            wear: self.st.wear,
            external_work: self.st.external_work,
        };
        for a in 0..3 {
            let f_ext = if self.drive.fixed[a] {
                -force[a]
            } else {
                self.drive.load[a]
            };
            self.st.external_work += f_ext * dx[a];
        }

        // Flow (eq 9) and wear (eqs 6, 21).
        let wear_volume = self.st.wear_normal + self.st.wear_lateral;
        let down = (-dx.z).max(0.0);
        let advance = heading.map_or(0.0, |e| dx.dot(&e));
        for c in &self.contacts {
            let k = c.sphere as usize;
            let mut dz = 0.0;
            if c.flows_v {
                dz += down;
                self.st.wear_normal += q.cell_area * down;
            }
            if c.flows_l {
                let along = match q.lateral {
                    LateralOffset::AlongMotion => c.along,
                    LateralOffset::Paper => (q.reach * q.reach - c.vertical * c.vertical)
                        .max(0.0)
                        .sqrt(),
                };
                let dzx = lateral_displacement(c.vertical, along, advance);
                dz += dzx;
                self.st.wear_lateral += q.cell_area * dzx;
            }
            s.z[k] -= dz;
            s.dz_last[k] = -dz;
            self.st.wear += c.f_z * dz;
        }
        self.st.step += 1;
        let n = self.contacts.len();
        Ok(StepReport {
            contacts: n,
            force,
            area_contact: n as f64 * q.cell_area,
            area_vertical: area_v,
            area_lateral: area_l,
            wear_volume,
            ledger,
        })
    }
}
