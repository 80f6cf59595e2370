//! Same input, same output: bit-identical trajectories for 1 and 2 threads, and across checkpoint/resume.

mod common;

use common::*;
use dem::sample::hcp::hcp_lattice;
use dem::{Group, PairModel, Parallelism, RigidMotion, Simulation, Vec3};
use rand::seq::SliceRandom;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

fn scene(par: Parallelism) -> Simulation {
    // A sheared slab with walls, sliding and breaking bonds: every code path of the step. 4 800 particles:
    // three force blocks, so both colours of blocks run and pairs cross block boundaries.
    slab(par, 20, 12)
}

/// The sheared slab of `n` x `n` x `layers` HCP sites.
fn slab(par: Parallelism, n: usize, layers: usize) -> Simulation {
    slab_with(par, n, layers, false)
}

/// [`slab`], with local neighbour rebuilds when `local`.
fn slab_with(par: Parallelism, n: usize, layers: usize, local: bool) -> Simulation {
    let mut mat = dem::Material::table4(0.15);
    mat.restitution = 0.9;
    let (mut p, bx) = hcp_lattice(n, n, layers, 90.0, 1.0, [true, true, false]).unwrap();
    let z = |i: usize| p.pos[i].z;
    let zmax = (0..p.len()).map(z).fold(f64::MIN, f64::max);
    let zmin = (0..p.len()).map(z).fold(f64::MAX, f64::min);
    for i in 0..p.len() {
        p.group[i] = if p.pos[i].z < zmin + 10.0 {
            1
        } else if p.pos[i].z > zmax - 10.0 {
            2
        } else {
            0
        };
    }
    thermalise(&mut p, 0.5, 0.01, 1);
    let groups = vec![
        Group::free("all"),
        Group::rigid("bottom", RigidMotion::frozen()),
        Group::rigid("top", RigidMotion::with_velocity(Vec3::new(3.0, 0.0, 0.5))),
    ];
    let cfg = dem::RunConfig {
        global_damping: 0.01,
        local_rebuilds: local,
        ..config(0.1)
    };
    Simulation::new(p, bx, PairModel::cohesive(mat), groups, cfg, par).unwrap()
}

fn fingerprint(s: &Simulation) -> Vec<u64> {
    let p = &s.particles;
    let mut v = Vec::new();
    for i in 0..p.len() {
        v.extend(
            p.pos[i]
                .iter()
                .chain(p.vel[i].iter())
                .chain(p.omega[i].iter())
                .map(|x| x.to_bits()),
        );
    }
    v.extend(
        s.neighbors()
            .hist
            .iter()
            .flat_map(|h| [h.x, h.y, h.z].map(f64::to_bits)),
    );
    v.push(s.energy().balance().to_bits());
    v
}

#[test]
fn a_small_system_steps_alike_on_the_pool_and_on_the_adaptive_single_thread() {
    // Below SERIAL_BELOW, Adaptive(2) steps on the calling thread; Threads(2) still uses the pool.
    let mut seq = slab(Parallelism::Sequential, 6, 8);
    assert!(
        seq.particles.len() < dem::sim::SERIAL_BELOW,
        "{}",
        seq.particles.len()
    );
    let mut pool = slab(Parallelism::Threads(2), 6, 8);
    let mut adaptive = slab(Parallelism::Adaptive(2), 6, 8);
    for s in [&mut seq, &mut pool, &mut adaptive] {
        s.run(300).unwrap();
    }
    assert!(seq.energy().sliding > 0.0, "the scene should slide");
    assert_eq!(fingerprint(&seq), fingerprint(&pool));
    assert_eq!(fingerprint(&seq), fingerprint(&adaptive));
    // Above it, Adaptive(2) runs on its pool, to the same bits.
    let mut big = scene(Parallelism::Adaptive(2));
    let mut one = scene(Parallelism::Sequential);
    big.run(50).unwrap();
    one.run(50).unwrap();
    assert_eq!(fingerprint(&big), fingerprint(&one));
    assert_eq!(
        [
            Parallelism::Sequential.threads(),
            Parallelism::Threads(0).threads(),
            Parallelism::Adaptive(3).threads()
        ],
        [1, 1, 3]
    );
}

#[test]
fn one_and_two_threads_give_identical_trajectories() {
    let mut a = scene(Parallelism::Sequential);
    let mut b = scene(Parallelism::Threads(2));
    a.run(400).unwrap();
    b.run(400).unwrap();
    assert!(a.energy().sliding > 0.0, "the scene should slide");
    assert!(a.neighbor_builds() > 1, "the scene should rebuild its list");
    assert_eq!(fingerprint(&a), fingerprint(&b));
}

#[test]
fn local_rebuilds_give_identical_trajectories_on_any_thread_count_and_across_resume() {
    // The sheared slab with local neighbour rebuilds: the rebuilt set depends on positions only.
    let mut a = slab_with(Parallelism::Sequential, 20, 12, true);
    let mut b = slab_with(Parallelism::Threads(2), 20, 12, true);
    a.run(200).unwrap();
    let dir = std::env::temp_dir().join(format!("cgdem-ckpt-local-{}", std::process::id()));
    let path = dir.join("state.json");
    a.save_checkpoint(&path).unwrap();
    drop(a);
    let mut a = Simulation::load_checkpoint(&path, Parallelism::Threads(2)).unwrap();
    std::fs::remove_dir_all(&dir).ok();
    a.run(200).unwrap();
    b.run(400).unwrap();
    assert!(
        b.neighbors().local_builds > 0,
        "the scene should rebuild locally ({} builds)",
        b.neighbor_builds()
    );
    assert_eq!(fingerprint(&a), fingerprint(&b));
}

#[test]
fn checkpoint_and_resume_is_bit_identical() {
    let mut straight = scene(Parallelism::Threads(2));
    straight.run(400).unwrap();

    let mut first = scene(Parallelism::Sequential);
    first.run(170).unwrap();
    let dir = std::env::temp_dir().join(format!("cgdem-ckpt-{}", std::process::id()));
    let path = dir.join("state.json");
    first.save_checkpoint(&path).unwrap();
    drop(first);
    let mut resumed = Simulation::load_checkpoint(&path, Parallelism::Threads(2)).unwrap();
    resumed.run(230).unwrap();
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(resumed.step_count(), 400);
    assert_eq!(fingerprint(&straight), fingerprint(&resumed));
}

/// A periodic HCP packing in contact, stored in lattice order or shuffled; the shuffled copy stores
/// lattice particle `order[k]` at index `k`.
fn packing(shuffled: bool, par: Parallelism) -> (Simulation, Vec<usize>) {
    let (mut p, bx) = hcp_lattice(24, 24, 16, 90.0, 1.0, [true; 3]).unwrap();
    for r in p.radius.iter_mut() {
        *r *= 1.002;
    }
    thermalise(&mut p, 0.5, 0.01, 7);
    let mut order: Vec<usize> = (0..p.len()).collect();
    if shuffled {
        order.shuffle(&mut ChaCha8Rng::seed_from_u64(7));
        p.permute(&order).unwrap();
    }
    let model = PairModel::cohesive(dem::Material::table4(0.15));
    let sim = Simulation::new(p, bx, model, vec![], config(0.1), par).unwrap();
    (sim, order)
}

#[test]
fn storage_order_changes_no_force_and_threads_agree() {
    // 9 216 particles: five force blocks. In lattice order every pair reaches at most one block on (the
    // direct path); shuffled, most pairs reach two blocks or more and are parked. Both must give the
    // same forces up to the order of the sums, and the shuffled run the same bits on 1 and 2 threads.
    let (mut sorted, _) = packing(false, Parallelism::Sequential);
    let (mut shuffled, order) = packing(true, Parallelism::Sequential);
    let (mut shuffled2, _) = packing(true, Parallelism::Threads(2));
    for s in [&mut sorted, &mut shuffled, &mut shuffled2] {
        s.run(49).unwrap();
        s.request_virial();
        s.step().unwrap();
    }
    assert_eq!(fingerprint(&shuffled), fingerprint(&shuffled2));
    let scale = sorted.forces().iter().map(|f| f.norm()).fold(0.0, f64::max);
    assert!(scale > 0.0);
    let mut worst = 0.0f64;
    for (k, &at) in order.iter().enumerate() {
        worst = worst.max((sorted.forces()[at] - shuffled.forces()[k]).norm());
        worst = worst.max((sorted.torques()[at] - shuffled.torques()[k]).norm() / 90.0);
    }
    assert!(
        worst <= 1e-9 * scale,
        "largest difference {worst:e} of {scale:e}"
    );
    // Per-particle virials, summed over a region (parked pairs add theirs to the second particle).
    let left = |s: &Simulation| {
        let mid = 0.5 * (s.sim_box.lo.x + s.sim_box.hi.x);
        s.virial_stress(Some(&|i: usize| s.particles.pos[i].x < mid), None)
    };
    let (a, b) = (left(&sorted), left(&shuffled));
    assert!(a.norm() > 0.0);
    assert!((a - b).norm() <= 1e-9 * a.norm(), "virials {a} and {b}");
    assert_eq!(left(&shuffled), left(&shuffled2));
    assert!(
        sorted.energy().tangential > 0.0,
        "tangential history should build up"
    );
}

/// Paper 000's silica (Table 5 in nm, ag, ns) with sizes from 0.75 d0 to 5 d0 at d0 = 1.5 nm, as the
/// bench's amorphous workload and the junction runs have it, freshly inserted (overlapping, moving,
/// forming and breaking bonds) in a periodic cube of `l_over_d0` d0.
fn silica_scene(l_over_d0: f64, par: Parallelism) -> Simulation {
    use dem::sample::{random_insertion, InsertionConfig, SizeDistribution};
    let silica = dem::Material::from_si(&dem::SiMaterial::table5(), dem::UnitSystem::NANO);
    let d0 = 0.877 * silica.critical_diameter();
    let sample = random_insertion(&InsertionConfig {
        lengths: Vec3::repeat(l_over_d0 * d0),
        sizes: SizeDistribution::paper000(d0, 0.75 * d0, 5.0 * d0),
        volume_fraction: 0.6,
        density: silica.density,
        seed: 3,
    })
    .unwrap();
    let mut p = sample.particles;
    thermalise(&mut p, 20.0, 1.0, 9);
    let cfg = dem::RunConfig {
        global_damping: 0.05,
        ..config(0.1)
    };
    Simulation::new(
        p,
        sample.sim_box,
        PairModel::cohesive(silica),
        vec![],
        cfg,
        par,
    )
    .unwrap()
}

#[test]
fn wide_size_distributions_give_identical_trajectories_on_any_thread_count() {
    // About 1 500 particles of 0.75-5 d0: the force phase cuts them into four blocks of equal pair
    // counts (not 2 048-particle blocks), the large particles' rows are long, pairs across the
    // periodic boundaries are parked, and the lists are rebuilt as bonds form and break. One, two
    // and three threads (more threads than units per colour) must give the same bits.
    let mut runs: Vec<Simulation> = [
        Parallelism::Sequential,
        Parallelism::Threads(2),
        Parallelism::Threads(3),
    ]
    .into_iter()
    .map(|par| silica_scene(20.0, par))
    .collect();
    for s in runs.iter_mut() {
        s.run(300).unwrap();
    }
    let a = &runs[0];
    let n = a.particles.len();
    assert!((1000..3000).contains(&n), "{n} particles");
    let r = &a.particles.radius;
    let (lo, hi) = r
        .iter()
        .fold((f64::MAX, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
    assert!(
        hi > 3.0 * lo,
        "sizes {lo}..{hi} should span the wide distribution"
    );
    assert!(a.energy().sliding > 0.0, "the scene should slide");
    assert!(a.neighbor_builds() > 2, "the scene should rebuild its list");
    for b in &runs[1..] {
        assert_eq!(fingerprint(a), fingerprint(b));
    }
}

#[test]
fn the_integrators_share_of_other_phases_changes_no_bit() {
    // Within one `run`, the integrator writes the force phase's kinematics records and measures the
    // displacement the list's rebuild test needs, and the next step reuses both; `step` starts every
    // step afresh (records gathered, displacement measured by the list). Both must give the same
    // bits and the same rebuilds. The wide silica scene rebuilds as bonds form and break; a slab of
    // it is one rigid body moving under its pair forces, so that the walls move particles between
    // the force phase and the integrator.
    let scene = |par| {
        let mut s = silica_scene(20.0, par);
        let l = s.sim_box.lengths();
        let lo = s.sim_box.lo;
        for i in 0..s.particles.len() {
            s.particles.group[i] = u32::from(s.particles.pos[i].z - lo.z > 0.85 * l.z);
        }
        let free_body = dem::RigidMotion {
            axes: [dem::AxisControl::Force(0.0); 3],
            velocity: Vec3::zeros(),
        };
        s.set_groups(vec![Group::free("all"), Group::rigid("slab", free_body)])
            .unwrap();
        s
    };
    let mut in_one_run = scene(Parallelism::Threads(2));
    in_one_run.run(300).unwrap();
    let mut stepped = scene(Parallelism::Threads(2));
    for _ in 0..300 {
        stepped.step().unwrap();
    }
    assert!(
        stepped.neighbor_builds() > 2,
        "the scene should rebuild its list"
    );
    let slab = stepped.group_index("slab").unwrap();
    let body = stepped.groups[slab].rigid.unwrap().velocity;
    assert!(
        body.norm() > 0.0,
        "the slab should move under its pair forces"
    );
    assert_eq!(in_one_run.neighbor_builds(), stepped.neighbor_builds());
    assert_eq!(fingerprint(&in_one_run), fingerprint(&stepped));
}
