//! Two-particle physics against closed forms: oscillation period, stability limit (paper 000 A.1.1),
//! restitution (A.35-A.46), bond work (A.31-A.34), tangential saturation (eqs 4-5).

mod common;

use common::*;
use dem::force::{normal_force, tangential_cap};
use dem::{
    DampingModel, Group, Interactions, Material, PairModel, Parallelism, RigidMotion, RunConfig,
    Simulation, TimeStep, Vec3,
};

/// Centre distance minus radii of the first two particles.
fn gap(s: &Simulation) -> f64 {
    let p = &s.particles;
    (p.pos[1] - p.pos[0]).norm() - p.radius[0] - p.radius[1]
}

#[test]
fn hookean_pair_oscillates_with_the_analytic_period() {
    let model = PairModel::cohesive(undamped(0.15));
    let r = 45.0;
    let pp = model.params(r, r, 1.0, 1.0);
    let mut s = sim(
        pair_of(r, 0.05 * pp.delta_e),
        open_box(1e3),
        model,
        config(0.01),
    );
    let (m, k) = (s.particles.mass[0], s.model().params(r, r, 1.0, 1.0).k_n);
    let period = 2.0 * std::f64::consts::PI * (0.5 * m / k).sqrt();
    let dt = s.dt();
    // Upward zero crossings of delta_N, linearly interpolated.
    let mut crossings = Vec::new();
    let mut prev = gap(&s);
    while crossings.len() < 6 {
        s.step().unwrap();
        let g = gap(&s);
        if prev < 0.0 && g >= 0.0 {
            crossings.push(s.time() - dt * g / (g - prev));
        }
        prev = g;
    }
    let measured = (crossings[5] - crossings[0]) / 5.0;
    let err = (measured - period).abs() / period;
    eprintln!("period: measured {measured:.6e}, analytic {period:.6e}, error {err:.2e}");
    assert!(
        err < 0.005,
        "period {measured} vs 2 pi sqrt(m_eff/k_N) = {period}: error {err:.2e}"
    );
}

fn max_excursion(frac: f64, steps: usize) -> (f64, f64) {
    let model = PairModel::cohesive(undamped(0.15));
    let de = model.params(45.0, 45.0, 1.0, 1.0).delta_e;
    let cfg = RunConfig {
        allow_supercritical_dt: true,
        ..config(frac)
    };
    let mut s = sim(pair_of(45.0, 0.02 * de), open_box(1e6), model, cfg);
    let mut max: f64 = 0.0;
    for _ in 0..steps {
        if s.step().is_err() {
            return (f64::INFINITY, de);
        }
        max = max.max(gap(&s).abs());
    }
    (max, de)
}

#[test]
fn integration_is_bounded_below_and_diverges_above_the_critical_step() {
    // Eq (6) / A.17: |lambda| = 1 up to dt_c; beyond, one eigenvalue exceeds 1 in modulus.
    let (bounded, de) = max_excursion(0.99, 20_000);
    // At 0.99 dt_c the amplitude of x is amplified by 1/sqrt(1 - (dt^/2)^2) ~ 7.1, but stays bounded.
    assert!(
        bounded < 0.02 * de * 8.0,
        "0.99 dt_c: excursion {bounded} for an initial 0.02 delta_e = {}",
        0.02 * de
    );
    let (diverged, de) = max_excursion(1.01, 2_000);
    assert!(
        diverged > 10.0 * de,
        "1.01 dt_c: excursion {diverged} should blow up past delta_f"
    );
}

#[test]
fn time_step_above_critical_is_refused() {
    let model = PairModel::cohesive(undamped(0.15));
    let cfg = RunConfig {
        time_step: TimeStep::FractionOfCritical(1.01),
        ..Default::default()
    };
    let err = Simulation::new(
        pair_of(45.0, 0.0),
        open_box(1e3),
        model,
        vec![],
        cfg,
        Parallelism::Sequential,
    )
    .unwrap_err();
    assert!(err.to_string().contains("critical time step"), "{err}");
}

fn restitution(eta: f64, damping: DampingModel) -> f64 {
    let mut mat = Material::table4(0.15);
    mat.restitution = eta;
    let mut model = PairModel::cohesive(mat);
    model.interactions = Interactions::REPULSIVE;
    model.damping = damping;
    let mut p = pair_of(45.0, 1.0);
    let v0 = 0.01;
    p.vel[0].x = 0.5 * v0;
    p.vel[1].x = -0.5 * v0;
    let mut s = sim(p, open_box(1e4), model, config(0.002));
    let mut touched = false;
    for _ in 0..10_000_000 {
        s.step().unwrap();
        let g = gap(&s);
        touched |= g < 0.0;
        if touched && g > 1.0 {
            break;
        }
    }
    assert!(touched);
    (s.particles.vel[1].x - s.particles.vel[0].x) / v0
}

#[test]
fn linearised_damping_gives_exp_of_minus_one_minus_eta() {
    // A.41 writes eta = v0 / vf, inverted: the restitution is the rebound over the impact speed.
    for eta in [0.5, 0.9, 0.95] {
        let e = restitution(eta, DampingModel::Linearised);
        let expect = (-(1.0 - eta)).exp();
        eprintln!("restitution, eta {eta}: measured {e:.5}, exp(-(1-eta)) {expect:.5}");
        assert!(
            ((e - expect) / expect).abs() < 0.01,
            "eta {eta}: restitution {e} vs exp(-(1-eta)) = {expect}"
        );
    }
}

#[test]
fn exact_damping_hits_the_target_restitution() {
    let e = restitution(0.5, DampingModel::Exact);
    eprintln!("restitution with exact damping for eta 0.5: {e:.5}");
    assert!(
        ((e - 0.5) / 0.5).abs() < 0.01,
        "restitution {e} for target 0.5"
    );
}

/// Pulls particle 1 away from a frozen particle 0 at a tiny speed; returns (wall work, params).
fn pull_apart(ri: f64, rj: f64, mat: Material) -> (f64, dem::PairParams) {
    let model = PairModel::cohesive(mat);
    let mut p = dem::Particles::default();
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
    let mut s = Simulation::new(
        p,
        open_box(1e4),
        model,
        groups,
        config(0.1),
        Parallelism::Sequential,
    )
    .unwrap();
    while gap(&s) < 1.05 * pp.delta_f {
        s.step().unwrap();
    }
    (s.energy().wall_work, pp)
}

#[test]
fn work_to_separate_a_bond_is_the_area_under_eq3() {
    for (ri, rj) in [(45.0, 45.0), (30.0, 45.0)] {
        let mat = undamped(0.15);
        let (w, pp) = pull_apart(ri, rj, mat.clone());
        let area = 0.5 * pp.k_n * pp.delta_e * pp.delta_f;
        eprintln!(
            "bond work r = ({ri}, {rj}): {w:.6e} vs area {area:.6e} (rel {:.2e})",
            (w - area) / area
        );
        assert!(
            ((w - area) / area).abs() < 1e-3,
            "work {w} vs 1/2 k delta_e delta_f = {area}"
        );
        // r_i + r_j <= d_c: the bond energy is 2 gamma A_N (A.33), A_N from r_eff = min(r_i, r_j).
        let a_n = std::f64::consts::SQRT_2 * ri.min(rj).powi(2) / (1.0 - 2.0 * mat.poisson_ratio);
        let two_gamma_a = 2.0 * mat.surface_energy * a_n;
        assert!(
            ((w - two_gamma_a) / two_gamma_a).abs() < 1e-3,
            "work {w} vs 2 gamma A_N = {two_gamma_a}"
        );
    }
}

#[test]
fn s_half_keeps_the_surface_energy_above_d_c() {
    let mut mat = undamped(0.15);
    mat.scaling = 0.5;
    let (ri, rj) = (150.0, 150.0); // r_i + r_j = 2 d_c
    let (w, pp) = pull_apart(ri, rj, mat.clone());
    assert_eq!(
        pp.delta_e, pp.delta_f,
        "above d_c with s = 1/2 the elastic limit is delta_f"
    );
    let a_n = std::f64::consts::SQRT_2 * ri * ri / (1.0 - 2.0 * mat.poisson_ratio);
    let two_gamma_a = 2.0 * mat.surface_energy * a_n;
    assert!(
        ((w - two_gamma_a) / two_gamma_a).abs() < 1e-3,
        "work {w} vs 2 gamma A_N = {two_gamma_a}"
    );
}

#[test]
fn shear_force_saturates_at_the_eq5_cap() {
    let model = PairModel::cohesive(undamped(0.15));
    let r = 45.0;
    let pp = model.params(r, r, 1.0, 1.0);
    for dn in [-0.5 * pp.delta_e, 0.3 * pp.delta_f, 0.7 * pp.delta_f] {
        let mut p = pair_of(r, dn);
        p.group = vec![1, 2];
        let dt = 0.1 * model.critical_time_step(r, p.mass[0]);
        let cap0 = tangential_cap(&pp, dn);
        // Slide far enough for k_T delta_T to reach the cap, in small steps.
        let v = 2.0 * cap0 / pp.k_t / (2e4 * dt);
        let groups = vec![
            Group::free("all"),
            Group::rigid("anchor", RigidMotion::frozen()),
            Group::rigid("slider", RigidMotion::with_velocity(Vec3::new(0.0, v, 0.0))),
        ];
        let mut s = Simulation::new(
            p,
            open_box(1e4),
            model.clone(),
            groups,
            config(0.1),
            Parallelism::Sequential,
        )
        .unwrap();
        let mut saturated = 0;
        for _ in 0..20_000 {
            // Separation and force are both taken at the start of the step.
            let d = s.particles.pos[1] - s.particles.pos[0];
            let n = d.normalize();
            let g = d.norm() - 2.0 * r;
            s.step().unwrap();
            let f = s.forces()[1];
            let ft = (f - f.dot(&n) * n).norm();
            let cap = tangential_cap(&pp, g);
            assert!(
                ft <= cap * (1.0 + 1e-9),
                "tangential force {ft} above the cap {cap}"
            );
            assert!(
                (f.dot(&n) + normal_force(&pp, g)).abs() <= 1e-9 * pp.k_n * pp.delta_f,
                "normal force is eq 3"
            );
            if (ft - cap).abs() <= 1e-9 * cap {
                saturated += 1;
            }
        }
        assert!(
            saturated > 1000,
            "delta_N = {dn}: the force reached F'_mT on {saturated} steps only"
        );
    }
}
