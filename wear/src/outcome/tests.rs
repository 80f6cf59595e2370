//! Constructed cases with known answers: a rigid ball rolling between two walls, a junction smeared
//! by simple shear, an intact junction, a single loose particle, and malformed frames.

use super::cluster::{bonds_within, bonds_within_radii, clusters, Periodicity};
use super::*;

/// Points on a disc (radius r, spacing ~h) centred at the origin.
fn disc(r: f64, h: f64) -> Vec<[f64; 3]> {
    let n = (r / h).ceil() as i64;
    let mut v = Vec::new();
    for i in -n..=n {
        for j in -n..=n {
            let (x, y) = (i as f64 * h, j as f64 * h);
            if x * x + y * y <= r * r {
                v.push([x, y, 0.0]);
            }
        }
    }
    v
}

/// A square block of points, spacing h, x in [x0, x1), y in [y0, y1).
fn block(x0: f64, x1: f64, y0: f64, y1: f64, h: f64) -> Vec<[f64; 3]> {
    let mut v = Vec::new();
    let mut y = y0;
    while y < y1 - 1e-9 {
        let mut x = x0;
        while x < x1 - 1e-9 {
            v.push([x, y, 0.0]);
            x += h;
        }
        y += h;
    }
    v
}

/// Deterministic pseudo-noise in [-1, 1] (no RNG crate needed for a fixed test pattern).
fn noise(i: usize, k: usize) -> f64 {
    (((i * 7919 + k * 104_729) % 1000) as f64 / 500.0) - 1.0
}

const TURNS: f64 = 1.5;

/// A disc of radius 5 rolling without slip between a fixed bottom wall (y = -5.5) and a top wall
/// (y = 5.5) moving at twice the disc's speed, over `frames` frames, with thermal jitter; tracked
/// particles: the disc's members first, then the two walls (rows at spacing 0.5, long enough to stay under the disc).
fn rolling_between_walls(frames: usize) -> (Vec<Vec<[f64; 3]>>, usize, Vec<usize>) {
    let ball = disc(5.0, 0.5);
    let n_ball = ball.len();
    let wall = |y: f64| block(-150.0, 150.0, y, y + 0.5, 0.5);
    let (bottom, top) = (wall(-5.5), wall(5.5));
    let frames: Vec<Vec<[f64; 3]>> = (0..frames)
        .map(|k| {
            // Clockwise by dx / r: the centre advances by r |theta|, the top wall by 2 r |theta|.
            let th = -(k as f64) * TURNS * std::f64::consts::TAU / 59.0;
            let (s, c) = th.sin_cos();
            let mut f: Vec<[f64; 3]> = ball
                .iter()
                .enumerate()
                .map(|(i, p)| {
                    let jitter = 0.02 * noise(i, k);
                    [
                        c * p[0] - s * p[1] + 5.0 * -th + jitter,
                        s * p[0] + c * p[1] - jitter,
                        0.0,
                    ]
                })
                .collect();
            f.extend(bottom.iter().copied());
            f.extend(top.iter().map(|p| [p[0] + 10.0 * -th, p[1], p[2]]));
            f
        })
        .collect();
    let anchors = (n_ball..frames[0].len()).collect();
    (frames, n_ball, anchors)
}

fn members_only(frames: &[Vec<[f64; 3]>], n: usize) -> Vec<Vec<[f64; 3]>> {
    frames.iter().map(|f| f[..n].to_vec()).collect()
}

fn atoms(margin: f64) -> Bonding {
    Bonding {
        radii: None,
        margin,
        periodicity: Periodicity::default(),
    }
}

#[test]
fn rigid_ball_rolling_between_two_walls_is_a_detached_wear_particle() {
    let (frames, n, anchors) = rolling_between_walls(60);
    let force: Vec<f64> = (0..60)
        .map(|k| if k < 10 { k as f64 } else { 2.0 })
        .collect();
    let members: Vec<usize> = (0..n).collect();
    let d = detachment(&frames[0], &frames[59], &atoms(0.75), &members, &anchors).unwrap();
    let v = classify(
        &members_only(&frames, n),
        &force,
        Some(d.clone()),
        &ClassifyParams::default(),
    )
    .unwrap();
    assert_eq!(v.outcome, Outcome::WearParticle, "{v:?}");
    assert!(v.reason.contains("rigid body"), "{}", v.reason);
    assert!(
        (v.turn + TURNS * std::f64::consts::TAU).abs() < 1e-3,
        "turn {}",
        v.turn
    );
    assert!(v.rigidity < 0.1, "rigidity {}", v.rigidity);
    assert!(v.force_late_over_peak.unwrap() < 0.3);
    // The ball touches both walls in the first frame (bonded at its contacts) and again in the last
    // (at other points): only its inner bonds survive, so all of it is one loose body.
    assert!(d.initial_bonds > d.surviving_bonds, "{d:?}");
    assert_eq!(d.detached_fraction, 1.0, "{d:?}");
    assert_eq!(d.debris_fraction, 1.0, "{d:?}");
    assert_eq!(d.debris_size, n);
    assert_eq!(v.detachment, Some(d));
}

/// The rolling ball of [`rolling_between_walls`], squashed and stretched along its own axes by 30 %
/// every other frame: it rolls, but not rigidly.
fn deforming(frames: &[Vec<[f64; 3]>], n: usize, turns_kept: usize) -> Vec<Vec<[f64; 3]>> {
    frames[..turns_kept]
        .iter()
        .enumerate()
        .map(|(k, f)| {
            let (cx, cy) = f[..n].iter().fold((0.0, 0.0), |a, p| {
                (a.0 + p[0] / n as f64, a.1 + p[1] / n as f64)
            });
            let s = if k % 2 == 0 { 1.3 } else { 1.0 };
            f[..n]
                .iter()
                .map(|p| [cx + (p[0] - cx) * s, cy + (p[1] - cy) / s, 0.0])
                .collect()
        })
        .collect()
}

#[test]
fn a_detached_body_that_deforms_as_it_rolls_is_a_wear_particle_by_the_cluster_rule() {
    let (frames, n, anchors) = rolling_between_walls(60);
    let members: Vec<usize> = (0..n).collect();
    let d = detachment(&frames[0], &frames[59], &atoms(0.75), &members, &anchors).unwrap();
    let soft = deforming(&frames, n, 60);
    let p = ClassifyParams::default();
    // Without the cluster analysis the rigid rule alone says no: the residual is as large as the turn.
    let v = classify(&soft, &[], None, &p).unwrap();
    assert!(v.rigidity > p.max_rigidity, "rigidity {}", v.rigidity);
    assert_eq!(v.outcome, Outcome::PlasticSmoothing, "{}", v.reason);
    // With it: one loose body that turned beyond pi/2.
    let v = classify(&soft, &[], Some(d.clone()), &p).unwrap();
    assert_eq!(v.outcome, Outcome::WearParticle, "{}", v.reason);
    assert!(v.reason.contains("one body"), "{}", v.reason);
    // A loose body that turned less than shear can turn material is not a wear particle: 7 frames of
    // the 59 are a turn of about 1.1 rad.
    let short = deforming(&frames, n, 8);
    let v = classify(&short, &[], Some(d), &p).unwrap();
    assert!(
        v.turn.abs() < std::f64::consts::FRAC_PI_2,
        "turn {}",
        v.turn
    );
    assert_eq!(v.outcome, Outcome::PlasticSmoothing, "{}", v.reason);
}

#[test]
fn junction_smeared_by_simple_shear_is_plastic_and_leaves_no_debris() {
    // A junction (10 x 5) between a bottom body and a top body, sheared homogeneously up to
    // gamma = 8 with the top body carried along.
    let h = 0.5;
    let junction = block(-5.0, 5.0, 0.0, 5.0, h);
    let bottom = block(-20.0, 20.0, -2.0, 0.0, h);
    let top = block(-20.0, 20.0, 5.0, 7.0, h);
    let nj = junction.len();
    let frames: Vec<Vec<[f64; 3]>> = (0..80)
        .map(|k| {
            let g = 8.0 * k as f64 / 79.0;
            let mut f: Vec<[f64; 3]> = junction
                .iter()
                .map(|p| [p[0] + g * p[1], p[1], 0.0])
                .collect();
            f.extend(bottom.iter().copied());
            f.extend(top.iter().map(|p| [p[0] + g * 5.0, p[1], 0.0]));
            f
        })
        .collect();
    let v = classify(
        &members_only(&frames, nj),
        &[],
        None,
        &ClassifyParams::default(),
    )
    .unwrap();
    // The material's shape turns towards the flow direction and stops: bounded by a quarter turn.
    assert!(
        v.turn.abs() > 0.5 && v.turn.abs() < std::f64::consts::FRAC_PI_2,
        "turn {}",
        v.turn
    );
    assert!(v.rigidity > 0.5, "rigidity {}", v.rigidity);
    assert_eq!(v.outcome, Outcome::PlasticSmoothing);
    assert_eq!(v.force_peak, None);
    // Only the bonds along the flow survive: the smeared members fall apart into rows, none of which
    // is a body (the largest loose cluster is one row of the junction, 20 of its 200 members).
    let anchors: Vec<usize> = (nj..frames[0].len()).collect();
    let members: Vec<usize> = (0..nj).collect();
    let d = detachment(&frames[0], &frames[79], &atoms(0.6), &members, &anchors).unwrap();
    assert!((d.detached_fraction - 0.9).abs() < 1e-12, "{d:?}");
    assert!((d.debris_fraction - 0.1).abs() < 1e-12, "{d:?}");
}

#[test]
fn intact_junction_is_plastic_and_stays_attached() {
    // The junction and both bodies translate together, with jitter: nothing turns, nothing breaks.
    let junction = block(-3.0, 3.0, 0.0, 3.0, 0.5);
    let bodies = block(-10.0, 10.0, -2.0, 0.0, 0.5);
    let nj = junction.len();
    let frames: Vec<Vec<[f64; 3]>> = (0..10)
        .map(|k| {
            junction
                .iter()
                .chain(&bodies)
                .enumerate()
                .map(|(i, p)| [p[0] + k as f64 + 0.01 * noise(i, k), p[1], 0.0])
                .collect()
        })
        .collect();
    let v = classify(
        &members_only(&frames, nj),
        &[1.0; 10],
        None,
        &ClassifyParams::default(),
    )
    .unwrap();
    assert_eq!(v.outcome, Outcome::PlasticSmoothing);
    assert!(v.turn.abs() < 0.01, "turn {}", v.turn);
    let anchors: Vec<usize> = (nj..frames[0].len()).collect();
    let members: Vec<usize> = (0..nj).collect();
    let d = detachment(&frames[0], &frames[9], &atoms(0.6), &members, &anchors).unwrap();
    assert_eq!(d.initial_bonds, d.surviving_bonds);
    assert_eq!(
        (d.detached_fraction, d.debris_fraction, d.debris_size),
        (0.0, 0.0, 0)
    );
}

#[test]
fn a_single_loose_particle_is_never_debris() {
    // One member that rolls by itself: no body to speak of, whatever its rotation.
    let one: Vec<Vec<[f64; 3]>> = (0..60).map(|k| vec![[k as f64, 0.0, 0.0]]).collect();
    let v = classify(&one, &[], None, &ClassifyParams::default()).unwrap();
    assert_eq!(v.outcome, Outcome::PlasticSmoothing);
    // An intact junction from which one particle came loose and rolled off: the group does not turn,
    // and the debris is that one particle.
    let junction = block(-3.0, 3.0, 0.0, 3.0, 0.5);
    let nj = junction.len();
    let frames: Vec<Vec<[f64; 3]>> = (0..30)
        .map(|k| {
            let mut f = junction.clone();
            f[nj - 1] = [3.0 + 0.5 * k as f64, 3.0, 0.0];
            f
        })
        .collect();
    let v = classify(&frames, &[], None, &ClassifyParams::default()).unwrap();
    assert_eq!(v.outcome, Outcome::PlasticSmoothing, "{v:?}");
    let members: Vec<usize> = (0..nj).collect();
    let d = detachment(&frames[0], &frames[29], &atoms(0.6), &members, &[0]).unwrap();
    assert_eq!(d.debris_size, 1);
    assert!(
        (d.detached_fraction - 1.0 / nj as f64).abs() < 1e-12,
        "{d:?}"
    );
}

#[test]
fn frames_of_unequal_length_are_an_error_not_a_truncation() {
    let mut frames: Vec<Vec<[f64; 3]>> = (0..5).map(|_| disc(2.0, 0.5)).collect();
    frames[3].pop();
    let e = classify(&frames, &[], None, &ClassifyParams::default()).unwrap_err();
    assert!(e.to_string().contains("frame 3"), "{e}");
    assert!(classify(&frames[..1], &[], None, &ClassifyParams::default()).is_err());
    let good: Vec<Vec<[f64; 3]>> = (0..5).map(|_| disc(2.0, 0.5)).collect();
    assert!(classify(&good, &[1.0; 4], None, &ClassifyParams::default()).is_err());
    assert!(classify(&good, &[f64::NAN; 5], None, &ClassifyParams::default()).is_err());
    let mut nan = good.clone();
    nan[2][0][1] = f64::NAN;
    assert!(classify(&nan, &[], None, &ClassifyParams::default()).is_err());
    let bad = ClassifyParams {
        axes: (1, 1),
        ..ClassifyParams::default()
    };
    assert!(classify(&good, &[], None, &bad).is_err());
    let (a, b) = (&good[0], &good[1][..3]);
    assert!(detachment(a, b, &atoms(0.6), &[0], &[1]).is_err());
    assert!(detachment(a, a, &atoms(0.6), &[a.len()], &[1]).is_err());
    assert!(unwrap_frame(a, &mut good[1][..3].to_vec(), &Periodicity::default()).is_err());
}

#[test]
fn unwrapping_restores_continuous_paths_across_the_period() {
    let per = Periodicity([Some(10.0), None, Some(4.0)]);
    let prev = vec![[9.8, 1.0, 3.9], [0.1, 2.0, 0.2]];
    let mut cur = vec![[0.3, 1.5, 0.1], [9.9, 2.5, 3.8]];
    unwrap_frame(&prev, &mut cur, &per).unwrap();
    let want = [[10.3, 1.5, 4.1], [-0.1, 2.5, -0.2]];
    for (c, w) in cur.iter().zip(&want) {
        for k in 0..3 {
            assert!((c[k] - w[k]).abs() < 1e-12, "{cur:?}");
        }
    }
}

#[test]
fn clusters_follow_bonds_across_periodic_boundaries() {
    // Chain A along x crossing the periodic boundary at x = 10; chain B far away in y.
    let pos = vec![
        [9.5, 0.0, 0.0],
        [0.3, 0.0, 0.0], // bonded to 0 through the boundary (distance 0.8)
        [1.1, 0.0, 0.0],
        [5.0, 5.0, 0.0],
        [5.0, 5.9, 0.0],
    ];
    let per = Periodicity([Some(10.0), None, None]);
    let b = bonds_within(&pos, 1.0, &per);
    assert_eq!(b, vec![(0, 1), (1, 2), (3, 4)]);
    let labels = clusters(pos.len(), &b);
    assert_eq!(labels, vec![0, 0, 0, 3, 3]);
    // Without periodicity the boundary bond disappears.
    let open = bonds_within(&pos, 1.0, &Periodicity::default());
    assert_eq!(open, vec![(1, 2), (3, 4)]);
    // Junction members 3 and 4 are loose when only atom 0 is anchored; 1 and 2 are not.
    let bonding = Bonding {
        radii: None,
        margin: 1.0,
        periodicity: per,
    };
    let d = detachment(&pos, &pos, &bonding, &[1, 2, 3, 4], &[0]).unwrap();
    assert_eq!(
        (d.detached_fraction, d.debris_fraction, d.debris_size),
        (0.5, 0.5, 2)
    );
}

#[test]
fn a_ball_that_rolls_once_round_the_periodic_box_has_lost_its_original_bonds() {
    // One turn of a ball of radius r rolling on the bottom wall moves its centre by 2 pi r; with that
    // period along x its bottom members come back next to the wall particles they started bonded to,
    // and the top wall (twice as fast) brings its own particles back over its top members. Those pairs
    // parted and met again one period further on: new contacts, so the ball is loose. Compared by
    // minimum image instead, they would look as if they had never parted and anchor it.
    let r = 5.0;
    let period = std::f64::consts::TAU * r;
    let ball = disc(r, 0.5);
    let n = ball.len();
    let row = |y: f64| -> Vec<[f64; 3]> {
        (0..63)
            .map(|i| [i as f64 * period / 63.0, y, 0.0])
            .collect()
    };
    let (bottom, top) = (row(-5.5), row(5.5));
    let frame = |turn: f64| -> Vec<[f64; 3]> {
        // Clockwise by `turn` turns: the centre advances by r theta, the top wall by 2 r theta
        // (unwrapped: the positions run on past the period).
        let th = -turn * std::f64::consts::TAU;
        let (s, c) = th.sin_cos();
        let mut f: Vec<[f64; 3]> = ball
            .iter()
            .map(|p| [c * p[0] - s * p[1] - r * th, s * p[0] + c * p[1], 0.0])
            .collect();
        f.extend(bottom.iter().copied());
        f.extend(top.iter().map(|p| [p[0] - 2.0 * r * th, p[1], p[2]]));
        f
    };
    let (first, last) = (frame(0.0), frame(1.0));
    let members: Vec<usize> = (0..n).collect();
    let anchors: Vec<usize> = (n..first.len()).collect();
    let bonding = Bonding {
        radii: None,
        margin: 0.75,
        periodicity: Periodicity([Some(period), None, None]),
    };
    let d = detachment(&first, &last, &bonding, &members, &anchors).unwrap();
    assert!(d.initial_bonds > d.surviving_bonds, "{d:?}");
    assert_eq!(
        (d.detached_fraction, d.debris_fraction),
        (1.0, 1.0),
        "{d:?}"
    );
    assert_eq!(d.debris_size, n);
    // The case does test the lap: by minimum image, ball-wall pairs of the first frame are bonds
    // again in the last.
    let per = bonding.periodicity;
    let ball_wall = |b: &[(usize, usize)]| -> Vec<(usize, usize)> {
        b.iter()
            .copied()
            .filter(|&(i, j)| i < n && j >= n)
            .collect()
    };
    let before = ball_wall(&bonds_within(&first, 0.75, &per));
    let again = ball_wall(&bonds_within(&last, 0.75, &per));
    assert!(!before.is_empty());
    assert!(
        before.iter().all(|b| again.contains(b)),
        "{before:?} {again:?}"
    );
}

#[test]
fn a_bond_that_crosses_the_boundary_together_survives() {
    // Two bonded atoms straddle x = 10 (first frame wrapped: 9.5 and 0.3); both then drift by +1.0 on
    // their continuous paths (10.5 and 1.3): the same bond in the same image.
    let per = Periodicity([Some(10.0), None, None]);
    let bonding = Bonding {
        radii: Some(vec![0.2, 0.2]),
        margin: 0.5,
        periodicity: per,
    };
    let first = vec![[9.5, 0.0, 0.0], [0.3, 0.0, 0.0]];
    let drifted = vec![[10.5, 0.0, 0.0], [1.3, 0.0, 0.0]];
    let d = detachment(&first, &drifted, &bonding, &[1], &[0]).unwrap();
    assert_eq!((d.initial_bonds, d.surviving_bonds), (1, 1), "{d:?}");
    assert_eq!(d.detached_fraction, 0.0);
    // Atom 1 instead runs a whole period ahead and stops beside atom 0 again: a new contact.
    let lapped = vec![[9.5, 0.0, 0.0], [10.3, 0.0, 0.0]];
    let d = detachment(&first, &lapped, &bonding, &[1], &[0]).unwrap();
    assert_eq!((d.initial_bonds, d.surviving_bonds), (1, 0), "{d:?}");
    assert_eq!(d.detached_fraction, 1.0);
}

#[test]
fn cell_list_matches_brute_force() {
    let mut pos = Vec::new();
    let mut radii = Vec::new();
    for i in 0..400 {
        pos.push([
            (noise(i, 1) + 1.0) * 6.0,
            (noise(i, 2) + 1.0) * 6.0,
            (noise(i, 3) + 1.0) * 6.0,
        ]);
        radii.push(0.3 + 0.2 * (noise(i, 4) + 1.0));
    }
    for per in [
        Periodicity::default(),
        Periodicity([Some(12.0), Some(12.0), None]),
    ] {
        let fast = bonds_within(&pos, 1.3, &per);
        let fast_r = bonds_within_radii(&pos, &radii, 0.1, &per);
        let (mut slow, mut slow_r) = (Vec::new(), Vec::new());
        for i in 0..pos.len() {
            for j in i + 1..pos.len() {
                let d = per.delta(&pos[i], &pos[j]);
                let d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                if d2 < 1.69 {
                    slow.push((i, j));
                }
                if d2 < (radii[i] + radii[j] + 0.1).powi(2) {
                    slow_r.push((i, j));
                }
            }
        }
        assert!(
            fast == slow,
            "cell list found {} pairs, brute force {}",
            fast.len(),
            slow.len()
        );
        assert_eq!(fast_r, slow_r);
        assert!(!fast.is_empty() && !fast_r.is_empty());
    }
}
