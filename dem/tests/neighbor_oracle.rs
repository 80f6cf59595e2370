//! The neighbour list against a brute-force O(N^2) search over periodic images, for random polydisperse
//! configurations in periodic (including slabs thinner than two interaction ranges) and open boxes.

use std::collections::BTreeSet;

use dem::neighbor::{Image, NeighborList, PairRange, Rebuild, LOCAL_SHARE};
use dem::{SimBox, Vec3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A cutoff that, like the cohesive law, grows with the radii: r_i + r_j + 0.3 min(r_i, r_j).
struct Range;
impl PairRange for Range {
    fn cutoff(&self, ri: f64, rj: f64) -> f64 {
        ri + rj + 0.3 * ri.min(rj)
    }
    fn max_cutoff(&self, r_max: f64) -> f64 {
        2.6 * r_max
    }
}

fn brute_force(
    pos: &[Vec3],
    radius: &[f64],
    bx: &SimBox,
    skin: f64,
) -> BTreeSet<(u32, u32, Image)> {
    brute_force_with(&Range, pos, radius, bx, skin)
}

fn listed(list: &NeighborList) -> BTreeSet<(u32, u32, Image)> {
    (0..list.len())
        .map(|p| (list.i[p], list.j[p], list.image[p]))
        .collect()
}

fn random_system(
    rng: &mut ChaCha8Rng,
    n: usize,
    lengths: Vec3,
    periodic: [bool; 3],
) -> (Vec<Vec3>, Vec<f64>, SimBox) {
    let bx = SimBox::new(Vec3::zeros(), lengths, periodic).unwrap();
    let pos = (0..n)
        .map(|_| {
            Vec3::new(
                rng.gen_range(0.0..lengths.x),
                rng.gen_range(0.0..lengths.y),
                rng.gen_range(0.0..lengths.z),
            )
        })
        .collect();
    let radius = (0..n).map(|_| rng.gen_range(0.375..0.625)).collect();
    (pos, radius, bx)
}

#[test]
fn list_matches_brute_force_in_many_random_boxes() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let cases = [
        (Vec3::new(8.0, 8.0, 8.0), [true, true, true]),
        (Vec3::new(10.0, 10.0, 3.0), [true, true, true]), // the papers' L x L x 3 d0 slab
        (Vec3::new(6.0, 1.8, 6.0), [true, true, false]),  // one cell across, self-images
        (Vec3::new(9.0, 7.0, 5.0), [false, false, false]),
        (Vec3::new(9.0, 7.0, 3.0), [true, false, true]),
    ];
    for (case, (lengths, periodic)) in cases.iter().enumerate() {
        for trial in 0..5 {
            let n = rng.gen_range(20..250);
            let (mut pos, radius, bx) = random_system(&mut rng, n, *lengths, *periodic);
            let skin = 0.1;
            let mut list = NeighborList::new(skin).unwrap();
            list.build(&mut pos, &radius, &bx, &Range).unwrap();
            let want = brute_force(&pos, &radius, &bx, skin);
            assert_eq!(listed(&list), want, "case {case} trial {trial}: n = {n}");
            // Move everything (across boundaries too) and rebuild: still exact.
            for x in pos.iter_mut() {
                *x += Vec3::new(
                    rng.gen_range(-1.0..1.0),
                    rng.gen_range(-1.0..1.0),
                    rng.gen_range(-1.0..1.0),
                );
            }
            list.build(&mut pos, &radius, &bx, &Range).unwrap();
            assert_eq!(
                listed(&list),
                brute_force(&pos, &radius, &bx, skin),
                "case {case} trial {trial} after moves"
            );
            // Reverse index covers each pair once, by its second particle.
            let mut seen = vec![0u32; list.len()];
            for j in 0..n {
                for &p in &list.rev_pair[list.rev_start[j] as usize..list.rev_start[j + 1] as usize]
                {
                    assert_eq!(list.j[p as usize] as usize, j);
                    seen[p as usize] += 1;
                }
            }
            assert!(seen.iter().all(|&c| c == 1));
        }
    }
}

#[test]
fn without_rebuild_the_list_still_covers_every_interacting_pair() {
    // The displacement criterion: while needs_rebuild() is false, no pair within the cutoff is missing.
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let (mut pos, radius, bx) =
        random_system(&mut rng, 200, Vec3::new(8.0, 8.0, 4.0), [true, true, true]);
    let skin = 0.2;
    let mut list = NeighborList::new(skin).unwrap();
    list.build(&mut pos, &radius, &bx, &Range).unwrap();
    let mut checked = 0;
    for _ in 0..200 {
        let trial: Vec<Vec3> = pos
            .iter()
            .map(|x| x + Vec3::new(rng.gen_range(-0.06..0.06), rng.gen_range(-0.06..0.06), 0.0))
            .collect();
        if list.needs_rebuild(&trial, &bx, false) {
            break;
        }
        pos = trial;
        let present = listed(&list);
        for pair in brute_force(&pos, &radius, &bx, 0.0) {
            assert!(
                present.contains(&pair),
                "pair {pair:?} interacts but is not listed"
            );
        }
        checked += 1;
    }
    assert!(checked > 0);
}

#[test]
fn history_follows_pairs_across_rebuilds_and_wraps() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let (mut pos, radius, bx) =
        random_system(&mut rng, 150, Vec3::new(7.0, 7.0, 3.0), [true, true, true]);
    let mut list = NeighborList::new(0.3).unwrap();
    list.build(&mut pos, &radius, &bx, &Range).unwrap();
    // Tag each pair's history with its identity, in unwrapped terms: x_j + s L - x_i.
    let tag = |pos: &[Vec3], list: &NeighborList, p: usize| {
        pos[list.j[p] as usize] + bx.shift(list.image[p]) - pos[list.i[p] as usize]
    };
    for p in 0..list.len() {
        let h = tag(&pos, &list, p);
        list.hist.set(p, h);
    }
    // Translate everything by most of a box (all particles wrap), then rebuild.
    let t = Vec3::new(5.3, -4.1, 2.2);
    for x in pos.iter_mut() {
        *x += t;
    }
    list.build(&mut pos, &radius, &bx, &Range).unwrap();
    let mut carried = 0;
    for p in 0..list.len() {
        let sep = tag(&pos, &list, p);
        let h = list.hist.get(p);
        if h != Vec3::zeros() {
            assert!(
                (h - sep).norm() < 1e-9,
                "pair {p}: history {h:?} belongs to {sep:?}"
            );
            carried += 1;
        }
    }
    assert_eq!(
        carried,
        list.len(),
        "every pair persisted, so every history must have been carried"
    );
}

#[test]
fn boxes_thinner_than_one_range_are_refused() {
    let bx = SimBox::new(
        Vec3::zeros(),
        Vec3::new(10.0, 10.0, 0.5),
        [true, true, true],
    )
    .unwrap();
    let mut pos = vec![Vec3::new(1.0, 1.0, 0.2)];
    let err = NeighborList::new(0.1)
        .unwrap()
        .build(&mut pos, &[0.5], &bx, &Range)
        .unwrap_err();
    assert!(
        err.to_string()
            .contains("shorter than one interaction range"),
        "{err}"
    );
}

/// A range that grows like the s = 1/2 scaling of eq (10), delta_f ~ sqrt(r_i + r_j), and says how far
/// beyond contact it reaches (the screen the builds use before the exact cutoff).
struct SqrtRange;
impl PairRange for SqrtRange {
    fn cutoff(&self, ri: f64, rj: f64) -> f64 {
        ri + rj + 0.3 * (ri + rj).sqrt()
    }
    fn max_cutoff(&self, r_max: f64) -> f64 {
        2.0 * r_max + 0.3 * (2.0 * r_max).sqrt()
    }
    fn beyond_contact(&self, r: f64) -> f64 {
        0.3 * (2.0 * r).sqrt()
    }
}

#[test]
fn list_matches_brute_force_for_wide_size_distributions() {
    // Radii over a factor 6.7 (paper 000's d_s = 0.75 d0 to d_l = 5 d0): the largest particles search
    // several cells around them, the small ones only their 27. Both ranges, exact either way.
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    let cases = [
        (Vec3::new(14.0, 14.0, 14.0), [true, true, true]),
        (Vec3::new(16.0, 12.0, 6.0), [true, true, false]),
        (Vec3::new(12.0, 12.0, 12.0), [false, false, false]),
    ];
    for (case, (lengths, periodic)) in cases.iter().enumerate() {
        for trial in 0..3 {
            let n = rng.gen_range(100..400);
            let (mut pos, _, bx) = random_system(&mut rng, n, *lengths, *periodic);
            // Mostly small radii and a few large ones, as a log-normal of mode d0 draws them.
            let radius: Vec<f64> = (0..n)
                .map(|_| 0.375 * (1.0 + 5.7 * rng.gen::<f64>().powi(4)))
                .collect();
            let skin = 0.05;
            let mut a = NeighborList::new(skin).unwrap();
            a.build(&mut pos, &radius, &bx, &Range).unwrap();
            assert_eq!(
                listed(&a),
                brute_force(&pos, &radius, &bx, skin),
                "case {case} trial {trial}: n = {n}"
            );
            let mut b = NeighborList::new(skin).unwrap();
            b.build(&mut pos, &radius, &bx, &SqrtRange).unwrap();
            let want = brute_force_with(&SqrtRange, &pos, &radius, &bx, skin);
            assert!(want.len() > n, "case {case}: too few pairs to test");
            assert_eq!(listed(&b), want, "case {case} trial {trial}: n = {n}");
            for p in 1..b.len() {
                assert!(
                    (b.i[p - 1], b.j[p - 1], b.image[p - 1]) < (b.i[p], b.j[p], b.image[p]),
                    "pairs in (i, j, image) order"
                );
            }
        }
    }
}

fn brute_force_with(
    range: &impl PairRange,
    pos: &[Vec3],
    radius: &[f64],
    bx: &SimBox,
    skin: f64,
) -> BTreeSet<(u32, u32, Image)> {
    let mut set = BTreeSet::new();
    let reach = |a: usize| if bx.periodic[a] { -2i8..=2 } else { 0i8..=0 };
    for i in 0..pos.len() {
        for j in i..pos.len() {
            for sx in reach(0) {
                for sy in reach(1) {
                    for sz in reach(2) {
                        let s = [sx, sy, sz];
                        if i == j && s <= [0, 0, 0] {
                            continue;
                        }
                        let d = pos[j] + bx.shift(s) - pos[i];
                        if d.norm() < range.cutoff(radius[i], radius[j]) + skin {
                            set.insert((i as u32, j as u32, s));
                        }
                    }
                }
            }
        }
    }
    set
}

/// Moves the particles `fast` by up to `step` along each axis (a few fast particles in a still
/// packing, as in a sliding layer's shear band).
fn agitate(rng: &mut ChaCha8Rng, pos: &mut [Vec3], fast: &[usize], step: f64) {
    for &k in fast {
        pos[k] += Vec3::new(
            rng.gen_range(-step..step),
            rng.gen_range(-step..step),
            rng.gen_range(-step..step),
        );
    }
}

#[test]
fn local_rebuilds_keep_every_pair_in_range_and_search_the_moved_rows_exactly() {
    // A few particles move fast, a slab moves as one (a body dragged along), and now and then
    // everything moves: local rebuilds, full ones, and none, each checked against brute force.
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    for (lengths, periodic) in [
        (Vec3::new(10.0, 10.0, 3.0), [true, false, true]),
        (Vec3::new(8.0, 8.0, 8.0), [true, true, true]),
    ] {
        let (mut pos, radius, bx) = random_system(&mut rng, 400, lengths, periodic);
        let fast: Vec<usize> = (0..8).map(|_| rng.gen_range(0..pos.len())).collect();
        let everyone: Vec<usize> = (0..pos.len()).collect();
        let skin = 0.3;
        let mut list = NeighborList::new(skin).unwrap();
        list.local = true;
        let (mut local, mut full) = (0, 0);
        for step in 0..400 {
            agitate(&mut rng, &mut pos, &fast, 0.05);
            if step % 3 == 0 {
                for x in pos.iter_mut().filter(|x| x.y > lengths.y - 0.6) {
                    *x += Vec3::new(0.02, 0.0, 0.0);
                }
            }
            if step % 97 == 50 {
                agitate(&mut rng, &mut pos, &everyone, 0.3);
            }
            let what = list
                .update(&mut pos, &radius, &bx, &Range, step % 2 == 0)
                .unwrap();
            list.check(pos.len()).unwrap();
            let present = listed(&list);
            for pair in brute_force(&pos, &radius, &bx, 0.0) {
                assert!(
                    present.contains(&pair),
                    "step {step} ({what:?}): {pair:?} interacts but is not listed"
                );
            }
            match what {
                Rebuild::Local(moved) => {
                    local += 1;
                    assert!(!moved.is_empty() && moved.len() * LOCAL_SHARE <= pos.len());
                    // The searched particles' pairs are exactly those within cutoff plus skin now.
                    let searched = |&(i, j, _): &(u32, u32, Image)| {
                        moved.binary_search(&i).is_ok() || moved.binary_search(&j).is_ok()
                    };
                    let want: BTreeSet<_> = brute_force(&pos, &radius, &bx, skin)
                        .into_iter()
                        .filter(searched)
                        .collect();
                    let got: BTreeSet<_> = present.iter().cloned().filter(searched).collect();
                    assert_eq!(
                        got,
                        want,
                        "step {step}: the rows of {} moved particles",
                        moved.len()
                    );
                }
                Rebuild::Full => {
                    full += 1;
                    assert_eq!(
                        present,
                        brute_force(&pos, &radius, &bx, skin),
                        "step {step}: full build"
                    );
                }
                Rebuild::None => {}
            }
        }
        assert!(
            local > 20 && full >= 3,
            "{local} local and {full} full rebuilds: the test must see both"
        );
        assert_eq!(list.local_builds, local as u64);
    }
}

#[test]
fn local_rebuilds_survive_the_worst_case_of_their_bound() {
    // The bound of `neighbor::local`: a pair searched when a moved may since have closed by
    // D_a + D_b + D_b(then) <= 2 theta_a + theta_s = skin. Here b steps 0.134 away while a steps
    // out of line (a is searched, the pair dropped at exactly cutoff + skin), then b comes back 0.268
    // and a closes 0.134: 0.402 of closing from a skin of 0.3, every displacement below theta_a =
    // 0.135. b's first step is above theta_s = 0.03, so it was searched with a and again when it came
    // back; a selection at the trigger itself (b left out at the first rebuild) would miss the pair.
    let skin = 0.3;
    let bx = SimBox::new(Vec3::zeros(), Vec3::new(20.0, 20.0, 20.0), [false; 3]).unwrap();
    let (x0, y) = (1.30822, 0.151);
    let mut pos = vec![Vec3::new(2.0, 5.0, 5.0), Vec3::new(2.0 + x0, 5.0, 5.0)];
    // Still particles far away, so that two moving ones are a local share.
    for k in 0..30 {
        pos.push(Vec3::new(
            10.0 + 1.5 * (k % 5) as f64,
            10.0 + 1.5 * (k / 5) as f64,
            5.0,
        ));
    }
    let radius = vec![0.5; pos.len()];
    let mut list = NeighborList::new(skin).unwrap();
    list.local = true;
    assert_eq!(
        list.update(&mut pos, &radius, &bx, &Range, false).unwrap(),
        Rebuild::Full
    );
    assert!(listed(&list).contains(&(0, 1, [0, 0, 0])));
    pos[0].y += y;
    pos[1].x += 0.134;
    let sep = (pos[1] - pos[0]).norm();
    assert!(
        (sep - (1.15 + skin)).abs() < 1e-3,
        "the pair sits at cutoff plus skin: {sep}"
    );
    list.update(&mut pos, &radius, &bx, &Range, false).unwrap();
    pos[1].x -= 0.268;
    pos[0].x += 0.134;
    list.update(&mut pos, &radius, &bx, &Range, false).unwrap();
    assert!((pos[1] - pos[0]).norm() < 1.15, "the pair interacts");
    assert!(
        listed(&list).contains(&(0, 1, [0, 0, 0])),
        "the pair closed by 0.402 > skin without a search of it"
    );
}

#[test]
fn local_rebuilds_carry_history_and_agree_serial_and_parallel_for_wide_sizes() {
    // Radii over a factor 6.7 with the s = 1/2 range: a small moved particle finds its larger
    // partners in their own reach. Serial and parallel updates give the same list, history kept.
    let mut rng = ChaCha8Rng::seed_from_u64(41);
    let (mut pos, _, bx) = random_system(
        &mut rng,
        400,
        Vec3::new(16.0, 12.0, 6.0),
        [true, false, true],
    );
    let radius: Vec<f64> = (0..pos.len())
        .map(|_| 0.375 * (1.0 + 5.7 * rng.gen::<f64>().powi(4)))
        .collect();
    let fast: Vec<usize> = (0..12).map(|_| rng.gen_range(0..pos.len())).collect();
    let skin = 0.15;
    let mut a = NeighborList::new(skin).unwrap();
    a.local = true;
    a.update(&mut pos, &radius, &bx, &SqrtRange, false).unwrap();
    // Each pair's history is tagged with its particles.
    let tag =
        |list: &NeighborList, p: usize| Vec3::new(f64::from(list.i[p]), f64::from(list.j[p]), 1.0);
    for p in 0..a.len() {
        let h = tag(&a, p);
        a.hist.set(p, h);
    }
    let mut b = a.clone();
    let mut pos_b = pos.clone();
    let mut local = 0;
    for step in 0..150 {
        agitate(&mut rng, &mut pos, &fast, 0.04);
        pos_b.clone_from(&pos);
        let what = a.update(&mut pos, &radius, &bx, &SqrtRange, false).unwrap();
        let what_b = b
            .update(&mut pos_b, &radius, &bx, &SqrtRange, true)
            .unwrap();
        assert_eq!(what, what_b, "step {step}");
        assert_eq!(a, b, "step {step}: serial and parallel lists differ");
        assert_eq!(pos, pos_b);
        local += usize::from(matches!(what, Rebuild::Local(_)));
        let present = listed(&a);
        for pair in brute_force_with(&SqrtRange, &pos, &radius, &bx, 0.0) {
            assert!(
                present.contains(&pair),
                "step {step}: {pair:?} interacts but is not listed"
            );
        }
        // Every history belongs to its own pair, and a pair listed from the start kept its own.
        let mut carried = 0;
        for p in 0..a.len() {
            let h = a.hist.get(p);
            if h != Vec3::zeros() {
                assert_eq!(h, tag(&a, p), "step {step}: pair {p} has another's history");
                carried += 1;
            }
        }
        assert!(
            carried * 2 > a.len(),
            "step {step}: only {carried} of {} histories kept",
            a.len()
        );
    }
    assert!(local > 10, "{local} local rebuilds");
}
