//! Constructed cases with known answers.

use super::cluster::{bonds_within, clusters, detached_fraction, Periodicity};
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

/// Deterministic pseudo-noise in [-1, 1] (no RNG crate needed for a fixed test pattern).
fn noise(i: usize, k: usize) -> f64 {
    (((i * 7919 + k * 104_729) % 1000) as f64 / 500.0) - 1.0
}

#[test]
fn rigid_rolling_disc_with_thermal_noise_is_a_wear_particle() {
    let base = disc(5.0, 0.5);
    // Rolling between plates: advance by v dt and turn clockwise by dx / r, 1.5 turns in total.
    let frames: Vec<Vec<[f64; 3]>> = (0..60)
        .map(|k| {
            let th = -(k as f64) * 1.5 * std::f64::consts::TAU / 59.0;
            let (s, c) = th.sin_cos();
            base.iter()
                .enumerate()
                .map(|(i, p)| {
                    let jitter = 0.02 * noise(i, k);
                    [
                        c * p[0] - s * p[1] + 5.0 * -th + jitter,
                        s * p[0] + c * p[1] - jitter,
                        0.0,
                    ]
                })
                .collect()
        })
        .collect();
    let force: Vec<f64> = (0..60)
        .map(|k| if k < 10 { k as f64 } else { 2.0 })
        .collect();
    let v = classify(&frames, &force, &ClassifyParams::default());
    assert_eq!(v.outcome, Outcome::WearParticle, "{v:?}");
    assert!(
        (v.turn + 1.5 * std::f64::consts::TAU).abs() < 1e-3,
        "turn {}",
        v.turn
    );
    assert!(v.rigidity < 0.1, "rigidity {}", v.rigidity);
    assert!(v.force_late_over_peak.unwrap() < 0.3);
}

#[test]
fn junction_in_large_simple_shear_is_plastic() {
    // Homogeneous simple shear up to gamma = 8 (a junction smeared along the interface).
    let base = disc(5.0, 0.5);
    let frames: Vec<Vec<[f64; 3]>> = (0..80)
        .map(|k| {
            let g = 8.0 * k as f64 / 79.0;
            base.iter().map(|p| [p[0] + g * p[1], p[1], 0.0]).collect()
        })
        .collect();
    let v = classify(&frames, &[], &ClassifyParams::default());
    // The material's shape turns towards the flow direction and stops: bounded by a quarter turn.
    assert!(
        v.turn.abs() > 0.5 && v.turn.abs() < std::f64::consts::FRAC_PI_2,
        "turn {}",
        v.turn
    );
    assert!(v.rigidity > 0.5, "rigidity {}", v.rigidity);
    assert_eq!(v.outcome, Outcome::PlasticSmoothing);
    assert_eq!(v.force_peak, None);
}

#[test]
fn junction_that_does_not_turn_is_plastic() {
    let base = disc(3.0, 0.5);
    let frames: Vec<Vec<[f64; 3]>> = (0..10)
        .map(|k| base.iter().map(|p| [p[0] + k as f64, p[1], 0.0]).collect())
        .collect();
    let v = classify(&frames, &[1.0; 10], &ClassifyParams::default());
    assert_eq!(v.outcome, Outcome::PlasticSmoothing);
    assert!(v.turn.abs() < 1e-12);
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
    // Junction members 3 and 4 are loose when only atom 0 is anchored; 1, 2 are not.
    assert_eq!(detached_fraction(&labels, &[1, 2, 3, 4], &[0]), 0.5);
}

#[test]
fn cell_list_matches_brute_force() {
    let mut pos = Vec::new();
    for i in 0..400 {
        pos.push([
            (noise(i, 1) + 1.0) * 6.0,
            (noise(i, 2) + 1.0) * 6.0,
            (noise(i, 3) + 1.0) * 6.0,
        ]);
    }
    for per in [
        Periodicity::default(),
        Periodicity([Some(12.0), Some(12.0), None]),
    ] {
        let fast = bonds_within(&pos, 1.3, &per);
        let mut slow = Vec::new();
        for i in 0..pos.len() {
            for j in i + 1..pos.len() {
                let d = per.delta(&pos[i], &pos[j]);
                if d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < 1.69 {
                    slow.push((i, j));
                }
            }
        }
        assert!(
            fast == slow,
            "cell list found {} pairs, brute force {}",
            fast.len(),
            slow.len()
        );
        assert!(!fast.is_empty());
    }
}
