//! Two-particle physics against closed forms: oscillation period, stability limit (paper 000 A.1.1),
//! restitution (A.35-A.46), bond work (A.31-A.34), tangential saturation (eqs 4-5).

mod common;

use common::*;
use dem::force::{normal_force, tangential_cap};
use dem::scenario::pair::{largest_excursion, oscillation, pull_apart, restitution};
use dem::{
    DampingModel, Group, Material, PairModel, Parallelism, RigidMotion, RunConfig, Simulation,
    TimeStep, Vec3,
};

#[test]
fn hookean_pair_oscillates_with_the_analytic_period() {
    let o = oscillation(PairModel::cohesive(undamped(0.15)), 45.0).unwrap();
    let err = (o.period_over_analytic - 1.0).abs();
    eprintln!(
        "period over 2 pi sqrt(m_eff / k_N): {:.6}",
        o.period_over_analytic
    );
    assert!(err < 0.005, "period error {err:.2e}");
    // The trace starts at x0 and swings to -x0 and back: a Hookean pair at rest about contact.
    let lowest = o.trace.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
    assert!((lowest + 1.0).abs() < 0.01, "lowest delta_N / x0 {lowest}");
}

#[test]
fn integration_is_bounded_below_and_diverges_above_the_critical_step() {
    // Eq (6) / A.17: |lambda| = 1 up to dt_c; beyond, one eigenvalue exceeds 1 in modulus.
    let excursion = |fraction, steps| {
        largest_excursion(PairModel::cohesive(undamped(0.15)), 45.0, fraction, steps).unwrap()
    };
    // At 0.99 dt_c the amplitude of x is amplified by 1/sqrt(1 - (dt^/2)^2) ~ 7.1, but stays bounded.
    let bounded = excursion(0.99, 20_000);
    assert!(bounded < 8.0, "0.99 dt_c: excursion {bounded} x0");
    let diverged = excursion(1.01, 2_000);
    assert!(
        diverged > 500.0,
        "1.01 dt_c: excursion {diverged} x0 should blow up past delta_f"
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

fn restitution_of(eta: f64, damping: DampingModel) -> f64 {
    let mut model = PairModel::cohesive(Material {
        restitution: eta,
        ..Material::table4(0.15)
    });
    model.damping = damping;
    restitution(model, 45.0).unwrap()
}

#[test]
fn linearised_damping_gives_exp_of_minus_one_minus_eta() {
    // A.41 writes eta = v0 / vf, inverted: the restitution is the rebound over the impact speed.
    for eta in [0.5, 0.9, 0.95] {
        let e = restitution_of(eta, DampingModel::Linearised);
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
    let e = restitution_of(0.5, DampingModel::Exact);
    eprintln!("restitution with exact damping for eta 0.5: {e:.5}");
    assert!(
        ((e - 0.5) / 0.5).abs() < 0.01,
        "restitution {e} for target 0.5"
    );
}

/// The wall work of pulling a bond apart, and the pair's parameters.
fn pull(ri: f64, rj: f64, mat: Material) -> (f64, dem::PairParams) {
    let b = pull_apart(PairModel::cohesive(mat), ri, rj).unwrap();
    (b.wall_work, b.params)
}

#[test]
fn work_to_separate_a_bond_is_the_area_under_eq3() {
    for (ri, rj) in [(45.0, 45.0), (30.0, 45.0)] {
        let mat = undamped(0.15);
        let (w, pp) = pull(ri, rj, mat.clone());
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
    let (w, pp) = pull(ri, rj, mat.clone());
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
