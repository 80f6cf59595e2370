//! Two-particle experiments, the rigs of paper 000's closed forms: each is a full [`Simulation`] of two
//! spheres in an open box, measured the way the closed form states it.
//! - [`oscillation`]: a Hookean pair oscillates about contact with period 2 pi sqrt(m_eff / k_N)
//!   (appendix A.1, eq A.38);
//! - [`largest_excursion`]: symplectic Euler is bounded below the critical step dt_c = sqrt(2 m / k_N)
//!   of eq (6), its amplitude growing as 1 / sqrt(1 - (dt / dt_c)^2) (A.16), and diverges above;
//! - [`restitution`]: a head-on impact of repulsive spheres rebounds at exp(-(1 - eta)) of the impact
//!   speed with the damping of eqs (12)-(13), at eta with the exact one (A.35-A.46);
//! - [`pull_apart`]: the work to break a bond is the area under eq (3), 1/2 k_N delta_e delta_f
//!   (A.31), which is 2 gamma A_N for r_i + r_j <= d_c (A.33), and its force-separation curve is Fig. 2.
//!
//! The engine's tests assert these against the closed forms; the validation report runs the same
//! functions and plots them.

use crate::error::{DemError, Result};
use crate::material::{Interactions, PairModel, PairParams};
use crate::sim::{Parallelism, RunConfig, Simulation, TimeStep};
use crate::state::Particles;
use crate::walls::{Group, RigidMotion};
use crate::{SimBox, Vec3};

/// Two spheres of radius `r` on the x axis, centres 2 r + `gap` apart.
pub fn pair_of(r: f64, gap: f64) -> Particles {
    let mut p = Particles::default();
    p.push_sphere(Vec3::new(-(r + 0.5 * gap), 0.0, 0.0), r, 1.0);
    p.push_sphere(Vec3::new(r + 0.5 * gap, 0.0, 0.0), r, 1.0);
    p
}

/// Centre distance minus radii of the first two particles: delta_N.
pub fn gap(s: &Simulation) -> f64 {
    let p = &s.particles;
    (p.pos[1] - p.pos[0]).norm() - p.radius[0] - p.radius[1]
}

/// A two-sphere simulation at `fraction` of dt_c, energy tracked, in an open box far larger than any
/// excursion (a diverging pair reaches 1e3 times its start before the measure stops it); `groups` empty
/// means one free group. Above dt_c the step is allowed, since measuring the divergence is the point.
pub fn two_sphere_sim(
    p: Particles,
    model: PairModel,
    fraction: f64,
    groups: Vec<Group>,
) -> Result<Simulation> {
    let groups = if groups.is_empty() {
        vec![Group::free("all")]
    } else {
        groups
    };
    let config = RunConfig {
        time_step: TimeStep::FractionOfCritical(fraction),
        allow_supercritical_dt: fraction > 1.0,
        track_energy: true,
        ..Default::default()
    };
    let open = SimBox::new(Vec3::repeat(-1e6), Vec3::repeat(1e6), [false; 3])?;
    Simulation::new(p, open, model, groups, config, Parallelism::Sequential)
}

/// A free oscillation: the measured period over the analytic one, and the trace delta_N / x0
/// against t / T over the first two periods.
#[derive(Debug, Clone, PartialEq)]
pub struct Oscillation {
    pub period_over_analytic: f64,
    pub trace: Vec<(f64, f64)>,
}

/// Two spheres of radius `r` released 0.05 delta_e apart (inside the Hookean branch) oscillate at
/// 0.01 dt_c; the period is timed over five upward zero crossings of delta_N, linearly interpolated.
pub fn oscillation(model: PairModel, r: f64) -> Result<Oscillation> {
    let x0 = 0.05 * model.params(r, r, 1.0, 1.0).delta_e;
    let mut s = two_sphere_sim(pair_of(r, x0), model, 0.01, vec![])?;
    let m = s.particles.mass[0];
    let k = s.model().params(r, r, m, m).k_n;
    let t_an = 2.0 * std::f64::consts::PI * (0.5 * m / k).sqrt();
    let dt = s.dt();
    let mut crossings = Vec::new();
    let mut prev = gap(&s);
    let mut trace = vec![(0.0, 1.0)];
    while crossings.len() < 6 {
        s.step()?;
        let g = gap(&s);
        if s.time() <= 2.0 * t_an {
            trace.push((s.time() / t_an, g / x0));
        }
        if prev < 0.0 && g >= 0.0 {
            crossings.push(s.time() - dt * g / (g - prev));
        }
        prev = g;
    }
    Ok(Oscillation {
        period_over_analytic: (crossings[5] - crossings[0]) / 5.0 / t_an,
        trace,
    })
}

/// Largest |delta_N| over `steps` steps at `fraction` of dt_c, over the initial x0 = 0.02 delta_e
/// (spheres of radius `r`): bounded below dt_c, infinite when the engine stops a diverged state, and
/// at least 1e3 once it passes 1e3 x0 (the run stops there).
pub fn largest_excursion(model: PairModel, r: f64, fraction: f64, steps: u64) -> Result<f64> {
    let x0 = 0.02 * model.params(r, r, 1.0, 1.0).delta_e;
    let mut s = two_sphere_sim(pair_of(r, x0), model, fraction, vec![])?;
    let mut max: f64 = x0;
    for _ in 0..steps {
        if s.step().is_err() {
            return Ok(f64::INFINITY);
        }
        max = max.max(gap(&s).abs());
        if max > 1e3 * x0 {
            break;
        }
    }
    Ok(max / x0)
}

/// Head-on impact of two spheres of radius `r` under the repulsive part of `model` (its damping model
/// as given): released r / 45 apart (1 length unit at paper 000's r = 45) closing at 0.01 sqrt(E / rho),
/// stepped at 0.002 dt_c until they have separated again by that gap; the rebound over the impact
/// speed.
pub fn restitution(mut model: PairModel, r: f64) -> Result<f64> {
    model.interactions = Interactions::REPULSIVE;
    let v0 = 0.01 * (model.material.young_modulus / model.material.density).sqrt();
    let g0 = r / 45.0;
    let mut p = pair_of(r, g0);
    p.vel[0].x = 0.5 * v0;
    p.vel[1].x = -0.5 * v0;
    let mut s = two_sphere_sim(p, model, 0.002, vec![])?;
    let mut touched = false;
    // The contact lasts pi sqrt(m_eff / k_N), about 1 000 steps of 0.002 dt_c; the approach and the
    // way back ~100 contact times at most for any restitution that rebounds.
    for _ in 0..10_000_000 {
        s.step()?;
        let g = gap(&s);
        touched |= g < 0.0;
        if touched && g > g0 {
            return Ok((s.particles.vel[1].x - s.particles.vel[0].x) / v0);
        }
    }
    Err(DemError::InvalidConfig(format!(
        "the spheres did not {} within 1e7 steps (restitution {})",
        if touched { "separate again" } else { "meet" },
        s.model().material.restitution
    )))
}

/// A bond pulled apart: the wall work, the pair's parameters, and the force-separation curve
/// F_N / (k_N delta_e) against delta_N / delta_e.
#[derive(Debug, Clone, PartialEq)]
pub struct BondPull {
    pub wall_work: f64,
    pub params: PairParams,
    pub curve: Vec<(f64, f64)>,
}

/// Sphere j (radius `rj`) pulled along x away from a frozen sphere i (`ri`), from contact, at delta_f
/// per 40 000 steps of 0.1 dt_c (quasi-static: the kinetic energy left is negligible against the
/// bond's), until the gap is 1.05 delta_f; the curve has a point every 200 steps.
pub fn pull_apart(model: PairModel, ri: f64, rj: f64) -> Result<BondPull> {
    let mut p = Particles::default();
    p.push_sphere(Vec3::zeros(), ri, 1.0);
    p.push_sphere(Vec3::new(ri + rj, 0.0, 0.0), rj, 1.0);
    p.group = vec![1, 2];
    let pp = model.params(ri, rj, p.mass[0], p.mass[1]);
    let dt = 0.1 * model.critical_time_step(ri.min(rj), p.mass[0].min(p.mass[1]));
    let v = pp.delta_f / (4e4 * dt);
    let groups = vec![
        Group::free("all"),
        Group::rigid("anchor", RigidMotion::frozen()),
        Group::rigid("puller", RigidMotion::with_velocity(Vec3::new(v, 0.0, 0.0))),
    ];
    let mut s = two_sphere_sim(p, model, 0.1, groups)?;
    let mut curve = Vec::new();
    let mut k = 0u64;
    while gap(&s) < 1.05 * pp.delta_f {
        let g = gap(&s);
        s.step()?;
        if k.is_multiple_of(200) {
            // The force on j at the start of the step (the gap g): cohesion pulls j towards i (-x).
            curve.push((g / pp.delta_e, -s.forces()[1].x / (pp.k_n * pp.delta_e)));
        }
        k += 1;
    }
    Ok(BondPull {
        wall_work: s.energy().wall_work,
        params: pp,
        curve,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Material;

    #[test]
    fn the_pair_starts_at_the_gap_asked_for() {
        let model = PairModel::cohesive(Material::table4(0.15));
        let s = two_sphere_sim(pair_of(45.0, 0.7), model, 0.1, vec![]).unwrap();
        assert!((gap(&s) - 0.7).abs() < 1e-12);
        assert_eq!(s.particles.len(), 2);
    }

    #[test]
    fn a_bad_model_is_an_error_not_a_panic() {
        let mut m = Material::table4(0.15);
        m.young_modulus = -1.0;
        let model = PairModel::cohesive(m);
        assert!(oscillation(model.clone(), 45.0).is_err());
        assert!(pull_apart(model, 45.0, 45.0).is_err());
    }
}
