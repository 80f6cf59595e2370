//! Bad input is a clear error, never a panic or a silent NaN.

mod common;

use common::*;
use dem::{
    DemError, Group, Material, PairModel, Parallelism, RigidMotion, RunConfig, Simulation, Vec3,
};

fn try_new(
    p: dem::Particles,
    model: PairModel,
    groups: Vec<Group>,
) -> Result<Simulation, DemError> {
    Simulation::new(
        p,
        open_box(1e3),
        model,
        groups,
        RunConfig::default(),
        Parallelism::Sequential,
    )
}

#[test]
fn invalid_materials() {
    let e = try_new(
        pair_of(1.0, 0.0),
        PairModel::cohesive(Material::table4(0.3)),
        vec![],
    )
    .unwrap_err();
    assert!(matches!(e, DemError::InvalidMaterial(_)), "{e}");
    let mut m = Material::table4(0.1);
    m.shear_strength = -0.1;
    assert!(try_new(pair_of(1.0, 0.0), PairModel::cohesive(m), vec![]).is_err());
    let mut m = Material::table4(0.1);
    m.poisson_ratio = -1.0;
    assert!(try_new(pair_of(1.0, 0.0), PairModel::cohesive(m), vec![]).is_err());
    // Finite fields whose derived critical diameter overflows.
    let mut m = Material::table4(0.1);
    m.young_modulus = 1e308;
    let e = try_new(pair_of(1.0, 0.0), PairModel::cohesive(m), vec![]).unwrap_err();
    assert!(e.to_string().contains("critical diameter"), "{e}");
}

#[test]
fn invalid_particles() {
    let mut p = pair_of(1.0, 0.0);
    p.radius[1] = -1.0;
    let e = try_new(p, PairModel::cohesive(Material::table4(0.1)), vec![]).unwrap_err();
    assert!(
        matches!(e, DemError::InvalidParticle { index: 1, .. }),
        "{e}"
    );
    let mut p = pair_of(1.0, 0.0);
    p.pos[0].x = f64::NAN;
    let e = try_new(p, PairModel::cohesive(Material::table4(0.1)), vec![]).unwrap_err();
    assert!(e.to_string().contains("position"), "{e}");
}

#[test]
fn overlapping_walls() {
    // Two walls assigned to the same bottom slab, interleaved particle by particle.
    let (mut p, bx) =
        dem::sample::hcp::hcp_lattice(4, 4, 6, 2.0, 1.0, [true, true, false]).unwrap();
    for i in 0..p.len() {
        if p.pos[i].z < 3.0 {
            p.group[i] = 1 + (i % 2) as u32;
        }
    }
    let groups = vec![
        Group::free("all"),
        Group::rigid("floor", RigidMotion::frozen()),
        Group::rigid("lid", RigidMotion::frozen()),
    ];
    let e = Simulation::new(
        p,
        bx,
        PairModel::cohesive(Material::table4(0.1)),
        groups,
        RunConfig::default(),
        Parallelism::Sequential,
    )
    .unwrap_err();
    assert!(matches!(e, DemError::OverlappingRigidGroups { .. }), "{e}");
    assert!(e.to_string().contains("'floor' and 'lid'"), "{e}");
}

#[test]
fn unknown_group() {
    let mut p = pair_of(1.0, 0.0);
    p.group[0] = 7;
    assert!(try_new(p, PairModel::cohesive(Material::table4(0.1)), vec![]).is_err());
}

#[test]
fn divergence_is_reported_not_propagated() {
    // Forced far above dt_c, two overlapping particles explode; the step must say so.
    let cfg = RunConfig {
        time_step: dem::TimeStep::FractionOfCritical(50.0),
        allow_supercritical_dt: true,
        ..Default::default()
    };
    let mut s = Simulation::new(
        pair_of(1.0, -0.5),
        open_box(1e300),
        PairModel::cohesive(Material::table4(0.1)),
        vec![],
        cfg,
        Parallelism::Sequential,
    )
    .unwrap();
    let mut err = None;
    for _ in 0..100_000 {
        if let Err(e) = s.step() {
            err = Some(e);
            break;
        }
    }
    // Either it flew apart harmlessly (finite) or the error names the non-finite value.
    match err {
        Some(e) => assert!(matches!(e, DemError::NonFinite { .. }), "{e}"),
        None => assert!(s
            .particles
            .pos
            .iter()
            .all(|x| x.iter().all(|v| v.is_finite()))),
    }
    let _ = Vec3::zeros();
}

#[test]
fn damaged_checkpoint_neighbour_list_is_refused() {
    // A bonded pair, stepped once so that the checkpoint carries a neighbour list.
    let mut s = try_new(
        pair_of(1.0, 0.0),
        PairModel::cohesive(Material::table4(0.1)),
        vec![],
    )
    .unwrap();
    s.step().unwrap();
    let dir = std::env::temp_dir().join(format!("cgdem-badckpt-{}", std::process::id()));
    let path = dir.join("state.json");
    s.save_checkpoint(&path).unwrap();
    let good: serde_json::Value = serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
    assert_eq!(
        good["list"]["j"],
        serde_json::json!([1]),
        "the pair (0, 1) is listed"
    );
    // The intact file resumes; each damage is a format error naming the list, not a panic later.
    assert!(Simulation::load_checkpoint(&path, Parallelism::Sequential).is_ok());
    let damages: [(&str, serde_json::Value); 4] = [
        ("/list/j", serde_json::json!([5])),
        ("/list/image", serde_json::json!([[2, 0, 0]])),
        ("/list/rev_pair", serde_json::json!([3])),
        ("/list/hist/y", serde_json::json!([])),
    ];
    for (field, value) in damages {
        let mut bad = good.clone();
        *bad.pointer_mut(field).unwrap() = value;
        std::fs::write(&path, serde_json::to_vec(&bad).unwrap()).unwrap();
        let e = Simulation::load_checkpoint(&path, Parallelism::Sequential).unwrap_err();
        assert!(
            matches!(&e, DemError::Format { reason, .. } if reason.contains("neighbour list")),
            "{field}: {e}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn particles_added_without_notice_are_an_error_not_a_panic() {
    let mut sim = try_new(
        pair_of(1.0, 0.0),
        PairModel::cohesive(Material::table4(0.1)),
        vec![],
    )
    .unwrap();
    sim.run(3).unwrap();
    sim.particles
        .push_sphere(Vec3::new(10.0, 0.0, 0.0), 1.0, 1.0);
    let e = sim.step().unwrap_err();
    assert!(e.to_string().contains("particles_changed"), "{e}");
    sim.particles_changed().unwrap();
    sim.run(3).unwrap();
    assert_eq!(sim.forces().len(), 3);
}
