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
}

impl StepSums {
    /// Adds the sums of the next range (always along the same tree, so the totals are deterministic).
    fn then(self, b: &StepSums) -> StepSums {
        StepSums {
            kinetic: self.kinetic + b.kinetic,
            damping_power: self.damping_power + b.damping_power,
            finite: self.finite && b.finite,
        }
    }
}

/// Advances free particles one step; with `energy`, also sums the kinetic energy and the damping
/// power (two chains of dependent additions, a few per cent of a step, skipped when nobody reads
/// them).
#[allow(clippy::too_many_arguments)]
pub(crate) fn advance_free(
    parts: &mut Particles,
    force: &[Vec3],
    torque: &[Vec3],
    is_rigid: &[bool],
    damping: f64,
    dt: f64,
    energy: bool,
    planar: bool,
    parallel: bool,
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
    let run = |start: usize, x: &mut [Vec3], v: &mut [Vec3], w: &mut [Vec3]| -> StepSums {
        let (mut ke, mut pd, mut screen) = (0.0, 0.0, 0.0);
        for k in 0..x.len() {
            let i = start + k;
            let (m, inr) = (mass[i], inertia[i]);
            if energy {
                ke += 0.5 * (m * v[k].norm_squared() + inr * w[k].norm_squared());
            }
            if is_rigid[i] {
                // Moved by the walls already: only screened.
                screen += 0.0 * (x[k].sum() + v[k].sum() + w[k].sum());
                continue;
            }
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
        StepSums {
            kinetic: ke,
            damping_power: pd,
            finite: screen.is_finite(),
        }
    };
    tree(0, pos, vel, omega, &run, parallel)
}

/// Runs `run` on chunks of `CHUNK` particles, halving the range (rayon::join when `parallel`) and
/// combining the sums along the same fixed tree on any thread count: deterministic totals, and no
/// per-step allocation.
fn tree<R>(
    start: usize,
    x: &mut [Vec3],
    v: &mut [Vec3],
    w: &mut [Vec3],
    run: &R,
    parallel: bool,
) -> StepSums
where
    R: Fn(usize, &mut [Vec3], &mut [Vec3], &mut [Vec3]) -> StepSums + Sync,
{
    if x.len() <= CHUNK {
        return run(start, x, v, w);
    }
    let mid = x.len().div_ceil(CHUNK) / 2 * CHUNK;
    let (x0, x1) = x.split_at_mut(mid);
    let (v0, v1) = v.split_at_mut(mid);
    let (w0, w1) = w.split_at_mut(mid);
    let (a, b) = if parallel {
        rayon::join(
            || tree(start, x0, v0, w0, run, true),
            || tree(start + mid, x1, v1, w1, run, true),
        )
    } else {
        (
            tree(start, x0, v0, w0, run, false),
            tree(start + mid, x1, v1, w1, run, false),
        )
    };
    a.then(&b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spin_up_uses_moment_of_inertia() {
        let mut p = Particles::default();
        p.push_sphere(Vec3::zeros(), 2.0, 3.0);
        let torque = vec![Vec3::new(0.0, 0.0, 5.0)];
        let dt = 1e-3;
        for _ in 0..1000 {
            advance_free(
                &mut p,
                &[Vec3::zeros()],
                &torque,
                &[false],
                0.0,
                dt,
                true,
                false,
                false,
            );
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
        let f = vec![Vec3::new(m, 0.0, 0.0)];
        advance_free(
            &mut p,
            &f,
            &[Vec3::zeros()],
            &[false],
            0.0,
            0.5,
            true,
            false,
            false,
        );
        // v1 = 0.5, x1 = v1 dt = 0.25 (the new velocity moves the particle).
        assert!((p.vel[0].x - 0.5).abs() < 1e-15 && (p.pos[0].x - 0.25).abs() < 1e-15);
    }
}
