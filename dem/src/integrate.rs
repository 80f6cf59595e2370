//! Symplectic (semi-implicit) Euler, paper 000 eq (1):
//!
//! v_{n+1} = v_n + F_n / m dt,   x_{n+1} = x_n + v_{n+1} dt,   omega_{n+1} = omega_n + T_n / I dt.
//!
//! Decision: eq (1c) as printed omits the moment of inertia (omega_{n+1} = omega_n + T_n dt), which is
//! dimensionally wrong; we divide by I (2/5 m r^2 for a solid sphere), as LAMMPS's `fix nve/sphere`
//! that the paper used does. `tests::spin_up_uses_moment_of_inertia` pins it.
//!
//! Planar motion (`RunConfig::planar`, the quasi-2D monolayer): the z components of F, v and the x, y
//! components of T, omega of a free particle are set to zero before its update, so x_z stays bit for bit
//! and the particle turns about z only; the constraint's reaction does no work.
//!
//! Global viscous damping (paper 000 eq 21, "a fraction of c_c"): a force -c v on every free particle,
//! and a torque -c (I/m) omega, so that spin relaxes at the same rate as translation.

use crate::force::{IntegratorView, Kin};
use crate::state::Particles;
use crate::Vec3;

/// Particles per leaf of the integrator's tree. The leaves fix the order of the kinetic-energy and
/// damping-power sums, so they depend on the particle count alone; 256 lets a 1 000-particle system
/// split over two threads (with 1 024 it was one leaf and ran on one core).
const CHUNK: usize = 256;

/// What one integration step reports.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct StepSums {
    /// Kinetic energy at v_n (0 unless asked for).
    pub kinetic: f64,
    /// Power dissipated by global damping (0 unless asked for).
    pub damping_power: f64,
    /// Every position and velocity (rigid ones included) is finite afterwards. A cheap screen, folded
    /// into the pass that touches them anyway; `false` can also mean an overflowing sum, so the caller
    /// scans for the culprit before it reports an error.
    pub finite: bool,
    /// The largest squared distance of a particle from the list's reference positions (0 without
    /// them).
    pub max_displacement2: f64,
}

impl StepSums {
    /// Adds the sums of the next range (always along the same tree, so the totals are deterministic).
    fn then(self, b: &StepSums) -> StepSums {
        StepSums {
            kinetic: self.kinetic + b.kinetic,
            damping_power: self.damping_power + b.damping_power,
            finite: self.finite && b.finite,
            max_displacement2: self.max_displacement2.max(b.max_displacement2),
        }
    }
}

/// What one step of the integrator applies, besides the particles and forces.
#[derive(Debug, Clone, Copy)]
pub(crate) struct StepParams {
    pub damping: f64,
    pub dt: f64,
    /// Sum the kinetic energy and the damping power.
    pub energy: bool,
    pub planar: bool,
    pub parallel: bool,
}

/// Advances free particles one step; with `energy`, also sums the kinetic energy and the damping
/// power (two chains of dependent additions, a few per cent of a step, skipped when nobody reads
/// them). The same pass, while each particle is in registers, does two jobs of other phases, each of
/// which was a pass over the particles and, on a pool, a join per step (issue 21):
/// - it writes every particle's new state (rigid ones' as the walls left it) to `forces.kin`, the
///   force phase's records, so the next step need not gather them;
/// - it returns the largest squared distance from `reference`, the list's positions at its last
///   build (the rebuild test; exact in any order since it is a max; 0 when the list has none yet).
pub(crate) fn advance_free(
    parts: &mut Particles,
    forces: IntegratorView,
    is_rigid: &[bool],
    reference: &[Vec3],
    p: &StepParams,
) -> StepSums {
    let Particles {
        pos,
        vel,
        omega,
        mass,
        inertia,
        ..
    } = parts;
    let (mass, inertia) = (&*mass, &*inertia);
    let IntegratorView { force, torque, kin } = forces;
    let n = pos.len();
    assert!(
        kin.len() == n && force.len() == n && torque.len() == n,
        "one force and kinematics record per particle"
    );
    let reference = (reference.len() == n).then_some(reference);
    let StepParams {
        damping,
        dt,
        energy,
        planar,
        parallel,
    } = *p;
    let run = |start: usize, s: Slices| -> StepSums {
        let Slices { x, v, w, kin } = s;
        let (mut ke, mut pd, mut screen, mut d2) = (0.0, 0.0, 0.0, 0.0f64);
        for k in 0..x.len() {
            let i = start + k;
            let (m, inr) = (mass[i], inertia[i]);
            if energy {
                ke += 0.5 * (m * v[k].norm_squared() + inr * w[k].norm_squared());
            }
            if is_rigid[i] {
                // Moved by the walls already: only screened.
                screen += 0.0 * (x[k].sum() + v[k].sum() + w[k].sum());
            } else {
                if planar {
                    v[k].z = 0.0;
                    w[k].x = 0.0;
                    w[k].y = 0.0;
                }
                let cw = damping * inr / m;
                if energy {
                    pd += damping * v[k].norm_squared() + cw * w[k].norm_squared();
                }
                let mut f = force[i] - damping * v[k];
                let mut t = torque[i] - cw * w[k];
                if planar {
                    f.z = 0.0;
                    t.x = 0.0;
                    t.y = 0.0;
                }
                v[k] += f * (dt / m);
                x[k] += v[k] * dt;
                w[k] += t * (dt / inr);
                // Zero times the state is zero unless some component is infinite or NaN.
                screen += 0.0 * (x[k].sum() + v[k].sum() + w[k].sum());
            }
            (kin[k].x, kin[k].v, kin[k].w) = (x[k], v[k], w[k]);
            if let Some(r) = reference {
                d2 = d2.max((x[k] - r[i]).norm_squared());
            }
        }
        StepSums {
            kinetic: ke,
            damping_power: pd,
            finite: screen.is_finite(),
            max_displacement2: d2,
        }
    };
    let all = Slices {
        x: pos,
        v: vel,
        w: omega,
        kin,
    };
    tree(0, all, &run, parallel)
}

/// The arrays one leaf of the tree advances.
struct Slices<'a> {
    x: &'a mut [Vec3],
    v: &'a mut [Vec3],
    w: &'a mut [Vec3],
    kin: &'a mut [Kin],
}

impl<'a> Slices<'a> {
    fn split_at(self, mid: usize) -> (Slices<'a>, Slices<'a>) {
        let (x0, x1) = self.x.split_at_mut(mid);
        let (v0, v1) = self.v.split_at_mut(mid);
        let (w0, w1) = self.w.split_at_mut(mid);
        let (k0, k1) = self.kin.split_at_mut(mid);
        (
            Slices {
                x: x0,
                v: v0,
                w: w0,
                kin: k0,
            },
            Slices {
                x: x1,
                v: v1,
                w: w1,
                kin: k1,
            },
        )
    }
}

/// Runs `run` on chunks of `CHUNK` particles, halving the range (rayon::join when `parallel`) and
/// combining the sums along the same fixed tree on any thread count: deterministic totals, and no
/// per-step allocation.
fn tree<R>(start: usize, s: Slices, run: &R, parallel: bool) -> StepSums
where
    R: Fn(usize, Slices) -> StepSums + Sync,
{
    let len = s.x.len();
    if len <= CHUNK {
        return run(start, s);
    }
    let mid = len.div_ceil(CHUNK) / 2 * CHUNK;
    let (s0, s1) = s.split_at(mid);
    let (a, b) = if parallel {
        rayon::join(
            || tree(start, s0, run, true),
            || tree(start + mid, s1, run, true),
        )
    } else {
        (
            tree(start, s0, run, false),
            tree(start + mid, s1, run, false),
        )
    };
    a.then(&b)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One free particle under `force` and `torque` for one step of `dt`; returns its record.
    fn advance_one(p: &mut Particles, force: Vec3, torque: Vec3, dt: f64) -> (Kin, StepSums) {
        let mut kin = [Kin::default()];
        let reference = [Vec3::zeros()];
        let view = IntegratorView {
            force: &[force],
            torque: &[torque],
            kin: &mut kin,
        };
        let params = StepParams {
            damping: 0.0,
            dt,
            energy: true,
            planar: false,
            parallel: false,
        };
        let sums = advance_free(p, view, &[false], &reference, &params);
        (kin[0], sums)
    }

    #[test]
    fn spin_up_uses_moment_of_inertia() {
        let mut p = Particles::default();
        p.push_sphere(Vec3::zeros(), 2.0, 3.0);
        let dt = 1e-3;
        for _ in 0..1000 {
            advance_one(&mut p, Vec3::zeros(), Vec3::new(0.0, 0.0, 5.0), dt);
        }
        let expect = 5.0 / p.inertia[0] * 1.0;
        assert!(
            (p.omega[0].z - expect).abs() < 1e-12 * expect,
            "{} vs {expect}",
            p.omega[0].z
        );
    }

    #[test]
    fn free_fall_is_symplectic_euler() {
        let mut p = Particles::default();
        p.push_sphere(Vec3::zeros(), 1.0, 1.0);
        let m = p.mass[0];
        let (kin, sums) = advance_one(&mut p, Vec3::new(m, 0.0, 0.0), Vec3::zeros(), 0.5);
        // v1 = 0.5, x1 = v1 dt = 0.25 (the new velocity moves the particle).
        assert!((p.vel[0].x - 0.5).abs() < 1e-15 && (p.pos[0].x - 0.25).abs() < 1e-15);
        // The force phase's record holds the new state, and the displacement from the reference
        // (the origin) is measured after the move.
        assert_eq!((kin.x, kin.v), (p.pos[0], p.vel[0]));
        assert_eq!(sums.max_displacement2, 0.25 * 0.25);
    }
}
