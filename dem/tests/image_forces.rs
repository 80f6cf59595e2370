//! Pair forces in periodic boxes thinner than two interaction ranges, against a brute-force sum over
//! every periodic image. There a pair can interact through two images at once (directly and across
//! the boundary), as in paper 004's L x L x 3 d0 samples with delta_f = 0.4 d0 (ranges up to
//! 1.65 d0, above 1.5 d0); the neighbour list keeps one entry per (i, j, image), and this checks that the forces
//! and the virial count each image within range exactly once, for one thread and several.

use dem::force::normal_force;
use dem::{
    Group, Material, PairModel, Parallelism, Particles, RigidMotion, RunConfig, SimBox, Simulation,
    Vec3,
};
use nalgebra::Matrix3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Normal-only law (paper 004) with E = 1, sigma_m = 0.2 and d_c = 2: delta_f = 0.4 for every pair
/// of diameter sum below 2, so a pair of radii 0.6 reaches 1.6.
fn model() -> PairModel {
    let (sigma, d_c) = (0.2, 2.0);
    PairModel::normal_only(Material {
        young_modulus: 1.0,
        poisson_ratio: 0.25,
        tensile_strength: sigma,
        shear_strength: 0.0,
        surface_energy: d_c * sigma * sigma / 4.0,
        restitution: 0.95,
        density: 1.0,
        scaling: 0.0,
    })
}

/// Engine forces and virial stress at `p` (one step of a frozen rigid group moves nothing).
fn engine(p: &Particles, bx: &SimBox, par: Parallelism) -> (Vec<Vec3>, Matrix3<f64>) {
    let mut p = p.clone();
    p.group.iter_mut().for_each(|g| *g = 0);
    let mut sim = Simulation::new(
        p,
        *bx,
        model(),
        vec![Group::rigid("all", RigidMotion::frozen())],
        RunConfig::default(),
        par,
    )
    .unwrap();
    sim.request_virial();
    sim.step().unwrap();
    (sim.forces().to_vec(), sim.virial_stress(None, None))
}

/// Brute force over images in {-2..2} along each periodic axis (beyond the reach of any pair here),
/// none along the others: the force on each
/// particle, the virial stress (tension positive) and the number of pairs (i < j) interacting through
/// more than one image.
fn brute(p: &Particles, bx: &SimBox) -> (Vec<Vec3>, Matrix3<f64>, usize) {
    let m = model();
    let n = p.len();
    let mut f = vec![Vec3::zeros(); n];
    let mut w = Matrix3::zeros();
    let mut multi = 0;
    let reach = |a: usize| if bx.periodic[a] { -2i8..=2 } else { 0i8..=0 };
    for i in 0..n {
        for j in 0..n {
            let pp = m.params(p.radius[i], p.radius[j], 1.0, 1.0);
            let mut images = 0;
            for sx in reach(0) {
                for sy in reach(1) {
                    for sz in reach(2) {
                        if i == j && [sx, sy, sz] == [0, 0, 0] {
                            continue;
                        }
                        let d = p.pos[j] + bx.shift([sx, sy, sz]) - p.pos[i];
                        let r = d.norm();
                        let gap = r - p.radius[i] - p.radius[j];
                        if gap > pp.delta_f {
                            continue;
                        }
                        // F_N > 0 pulls the pair together (eq 3).
                        let fi = normal_force(&pp, gap) * d / r;
                        f[i] += fi;
                        // Each pair image is met twice (from i and from j): half each time.
                        w += 0.5 * d * fi.transpose();
                        images += 1;
                    }
                }
            }
            if i < j && images > 1 {
                multi += 1;
            }
        }
    }
    (f, w / bx.volume(), multi)
}

#[test]
fn forces_count_every_image_within_range_in_thin_periodic_boxes() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    // z periodic at 2.4 (three of the sample's 0.8-d0 layers): ranges up to 1.6 exceed L_z / 2 = 1.2.
    // The second box is also thin along y, and the third open along z (a slab between walls).
    let cases = [
        (Vec3::new(6.0, 6.0, 2.4), [true, true, true]),
        (Vec3::new(6.0, 2.5, 2.4), [true, true, true]),
        (Vec3::new(6.0, 2.5, 2.4), [true, true, false]),
    ];
    let mut multi_total = 0;
    for (case, (l, periodic)) in cases.iter().enumerate() {
        let bx = SimBox::new(Vec3::zeros(), *l, *periodic).unwrap();
        let mut p = Particles::default();
        for _ in 0..30 {
            let x = Vec3::new(
                rng.gen_range(0.0..l.x),
                rng.gen_range(0.0..l.y),
                rng.gen_range(0.0..l.z),
            );
            p.push_sphere(x, rng.gen_range(0.4..0.6), 1.0);
        }
        let (fb, sb, multi) = brute(&p, &bx);
        multi_total += multi;
        let (f1, s1) = engine(&p, &bx, Parallelism::Sequential);
        let (f3, s3) = engine(&p, &bx, Parallelism::Threads(3));
        assert_eq!(f1, f3, "case {case}: forces depend on the thread count");
        assert_eq!(s1, s3, "case {case}: virial depends on the thread count");
        let fmax = fb.iter().fold(0.0f64, |a, v| a.max(v.norm()));
        for i in 0..p.len() {
            assert!(
                (f1[i] - fb[i]).norm() <= 1e-12 * fmax,
                "case {case}, particle {i}: engine {:?}, brute force over images {:?}",
                f1[i],
                fb[i]
            );
        }
        assert!(
            (s1 - sb).abs().max() <= 1e-12 * sb.abs().max(),
            "case {case}: virial stress engine {s1} brute force {sb}"
        );
    }
    // The point of the test: some pairs do interact through two images.
    assert!(multi_total > 0, "no pair met through two images");
    eprintln!("pairs interacting through more than one image: {multi_total}");
}
