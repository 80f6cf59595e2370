//! A derivative-free trust region for noisy least squares, built on a local response surface
//! (in the spirit of DFO-LS: Cartis, Fiala, Marteau & Roberts 2019, and POUNDERS: Wild 2017; the
//! model-based trust-region framework of Conn, Scheinberg & Vicente 2009, ch. 10-11).
//!
//! Around the centre x_c the residuals are modelled as affine, r(x_c + h) ~ c + J h, and (c, J) is
//! the least-squares fit over every evaluated point within `2 Delta` of x_c (the regression
//! averages the noise of the points instead of differencing two of them, and rejected trials teach the
//! model as much as accepted ones). The step minimises |c + J h|^2 within |h| <= Delta, the damped
//! Gauss-Newton step of [`crate::lm`] with the damping set so that the step meets the radius. When the
//! points do not span every direction well, new points are placed at x_c + Delta q along the
//! uncovered directions (geometry points; at the start these are forward differences over Delta).
//!
//! Everything here is plain linear algebra on small matrices, solved with faer's QR (never normal
//! equations); the loop that evaluates points lives in [`crate::executor`].

use faer::prelude::*;
use faer::Mat;
use serde::{Deserialize, Serialize};

use crate::lm;

/// One evaluated point of the model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Sample {
    pub x: Vec<f64>,
    pub r: Vec<f64>,
}

/// The affine model c + J h of the residuals around a centre.
#[derive(Debug, Clone, PartialEq)]
pub struct Model {
    pub c: Vec<f64>,
    /// Rows = residuals.
    pub j: Vec<Vec<f64>>,
    /// How many points the fit used.
    pub points: usize,
}

/// Euclidean distance.
pub fn dist(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| (p - q).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// The points within `reach` of `centre`, in their order.
pub fn near<'a>(points: &'a [Sample], centre: &[f64], reach: f64) -> Vec<&'a Sample> {
    points
        .iter()
        .filter(|p| dist(&p.x, centre) <= reach * (1.0 + 1e-12))
        .collect()
}

/// Unit directions (n of them at most) that the displacements of `points` from `centre`, scaled by
/// `radius`, leave uncovered: a greedy Gram-Schmidt over the displacements takes, one at a time, the
/// one with the largest part orthogonal to those already taken; a direction counts as covered when
/// that part is at least `theta` (in units of the radius). The missing directions are the coordinate
/// axes projected on the uncovered subspace, the best-covered first, normalised.
pub fn missing_directions(
    points: &[&Sample],
    centre: &[f64],
    radius: f64,
    theta: f64,
) -> Vec<Vec<f64>> {
    let n = centre.len();
    let mut rest: Vec<Vec<f64>> = points
        .iter()
        .map(|p| {
            p.x.iter()
                .zip(centre)
                .map(|(a, b)| (a - b) / radius)
                .collect()
        })
        .collect();
    let mut basis: Vec<Vec<f64>> = Vec::new();
    while basis.len() < n {
        let best = rest
            .iter()
            .enumerate()
            .map(|(k, v)| (k, lm::norm2(v).sqrt()))
            .filter(|(_, len)| *len >= theta)
            .fold(None, |acc: Option<(usize, f64)>, (k, len)| match acc {
                Some((_, l)) if l >= len => acc,
                _ => Some((k, len)),
            });
        let Some((k, len)) = best else { break };
        let q: Vec<f64> = rest[k].iter().map(|v| v / len).collect();
        rest.remove(k);
        for v in rest.iter_mut() {
            project_out(v, &q);
        }
        basis.push(q);
    }
    let mut out = Vec::new();
    while basis.len() < n {
        let best = (0..n)
            .map(|k| {
                let mut e = vec![0.0; n];
                e[k] = 1.0;
                for q in &basis {
                    project_out(&mut e, q);
                }
                let len = lm::norm2(&e).sqrt();
                (e, len)
            })
            .fold(None, |acc: Option<(Vec<f64>, f64)>, (e, len)| match acc {
                Some((_, l)) if l >= len => acc,
                _ => Some((e, len)),
            });
        let Some((e, len)) = best else { break };
        if len < 1e-9 {
            break;
        }
        let q: Vec<f64> = e.iter().map(|v| v / len).collect();
        basis.push(q.clone());
        out.push(q);
    }
    out
}

fn project_out(v: &mut [f64], q: &[f64]) {
    let d: f64 = v.iter().zip(q).map(|(a, b)| a * b).sum();
    v.iter_mut().zip(q).for_each(|(a, b)| *a -= d * b);
}

/// Least-squares affine fit r(x) ~ c + J (x - centre) over `points` (at least one). Directions the
/// points do not span get zero slope: the system is solved with a tiny ridge on the slopes (relative
/// 1e-10 of the displacements' scale), which leaves a well-posed fit unchanged to ~1e-10 and keeps a
/// rank-deficient one finite. With n + 1 affinely independent points the fit interpolates.
pub fn fit(points: &[&Sample], centre: &[f64]) -> Model {
    let n = centre.len();
    let m = points.first().map_or(0, |p| p.r.len());
    let p = points.len();
    let scale = points
        .iter()
        .map(|q| dist(&q.x, centre))
        .fold(0.0f64, f64::max)
        .max(1e-300);
    let ridge = 1e-10f64.sqrt();
    // Unknowns: intercept and slopes per unit of scaled displacement (better conditioned).
    let a = Mat::<f64>::from_fn(p + n, n + 1, |i, k| {
        if i < p {
            if k == 0 {
                1.0
            } else {
                (points[i].x[k - 1] - centre[k - 1]) / scale
            }
        } else if k == i - p + 1 {
            ridge
        } else {
            0.0
        }
    });
    let b = Mat::<f64>::from_fn(p + n, m, |i, k| if i < p { points[i].r[k] } else { 0.0 });
    let sol = a.qr().solve_lstsq(&b);
    let c = (0..m).map(|k| sol[(0, k)]).collect();
    let j = (0..m)
        .map(|row| (0..n).map(|k| sol[(k + 1, row)] / scale).collect())
        .collect();
    Model { c, j, points: p }
}

/// The step minimising |c + J h| with |h| <= radius: the Gauss-Newton step (minimum-norm, lambda ->
/// 0) when it fits, otherwise the damped step whose length is the radius (lambda found by bisection
/// in log space; |h(lambda)| decreases monotonically with lambda).
pub fn step(model: &Model, radius: f64) -> Option<Vec<f64>> {
    let n = model.j.first().map_or(0, Vec::len);
    let d = vec![1.0; n];
    let len = |h: &[f64]| lm::norm2(h).sqrt();
    let gn = lm::damped_step(&model.j, &model.c, 1e-12, &d)?;
    if len(&gn) <= radius {
        return Some(gn);
    }
    let (mut lo, mut hi) = (1e-12f64.ln(), 1e12f64.ln());
    let mut best = None;
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        let h = lm::damped_step(&model.j, &model.c, mid.exp(), &d)?;
        if len(&h) > radius {
            lo = mid;
        } else {
            hi = mid;
            best = Some(h);
        }
        if hi - lo < 1e-6 {
            break;
        }
    }
    best
}

/// Predicted reduction of 1/2 |r|^2 by the model along h: 1/2 (|c|^2 - |c + J h|^2).
pub fn predicted(model: &Model, h: &[f64]) -> f64 {
    lm::predicted_reduction(&model.j, &model.c, h)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pt(x: &[f64], f: impl Fn(&[f64]) -> Vec<f64>) -> Sample {
        Sample {
            x: x.to_vec(),
            r: f(x),
        }
    }

    #[test]
    fn an_affine_map_is_recovered_exactly_and_noise_is_averaged() {
        let f = |x: &[f64]| vec![1.0 + 2.0 * x[0] - x[1], -0.5 + 0.25 * x[1]];
        let pts: Vec<Sample> = [
            [0.0, 0.0],
            [0.1, 0.0],
            [0.0, 0.1],
            [0.1, 0.1],
            [-0.05, 0.02],
        ]
        .iter()
        .map(|x| pt(x, f))
        .collect();
        let refs: Vec<&Sample> = pts.iter().collect();
        let m = fit(&refs, &[0.0, 0.0]);
        assert!((m.c[0] - 1.0).abs() < 1e-8 && (m.c[1] + 0.5).abs() < 1e-8);
        assert!((m.j[0][0] - 2.0).abs() < 1e-7 && (m.j[0][1] + 1.0).abs() < 1e-7);
        assert!((m.j[1][0]).abs() < 1e-7 && (m.j[1][1] - 0.25).abs() < 1e-7);
        // Alternating noise of +-0.01 on 8 points around a line: the fitted slope is the line's,
        // while a forward difference over 0.1 between two of them is off by 0.2.
        let g = |x: &[f64]| vec![x[0]];
        let pts: Vec<Sample> = (0..8)
            .map(|i| {
                let x = [0.1 * f64::from(i) / 7.0 - 0.05];
                let mut s = pt(&x, g);
                s.r[0] += if i % 2 == 0 { 0.01 } else { -0.01 };
                s
            })
            .collect();
        let refs: Vec<&Sample> = pts.iter().collect();
        let m = fit(&refs, &[0.0]);
        assert!((m.j[0][0] - 1.0).abs() < 0.25, "{:?}", m.j);
    }

    #[test]
    fn an_unspanned_direction_gets_zero_slope_and_is_reported_missing() {
        let f = |x: &[f64]| vec![x[0] + 3.0 * x[1]];
        let pts = [pt(&[0.0, 0.0], f), pt(&[0.1, 0.0], f), pt(&[-0.1, 0.0], f)];
        let refs: Vec<&Sample> = pts.iter().collect();
        let m = fit(&refs, &[0.0, 0.0]);
        assert!(
            (m.j[0][0] - 1.0).abs() < 1e-7 && m.j[0][1].abs() < 1e-6,
            "{:?}",
            m.j
        );
        let miss = missing_directions(&refs, &[0.0, 0.0], 0.1, 0.3);
        assert_eq!(miss.len(), 1);
        assert!((miss[0][1].abs() - 1.0).abs() < 1e-12 && miss[0][0].abs() < 1e-12);
        // Nothing evaluated yet but the centre: every axis is missing, in order.
        let miss = missing_directions(&refs[..1], &[0.0, 0.0], 0.1, 0.3);
        assert_eq!(miss, vec![vec![1.0, 0.0], vec![0.0, 1.0]]);
        // A short displacement (below theta) does not count.
        let short = [pt(&[0.0, 0.0], f), pt(&[0.01, 0.0], f)];
        let refs: Vec<&Sample> = short.iter().collect();
        assert_eq!(missing_directions(&refs, &[0.0, 0.0], 0.1, 0.3).len(), 2);
    }

    #[test]
    fn the_step_is_gauss_newton_inside_the_radius_and_meets_it_outside() {
        let m = Model {
            c: vec![-0.05, 0.02],
            j: vec![vec![1.0, 0.0], vec![0.0, 2.0]],
            points: 3,
        };
        let h = step(&m, 1.0).unwrap();
        assert!((h[0] - 0.05).abs() < 1e-9 && (h[1] + 0.01).abs() < 1e-9);
        assert!((predicted(&m, &h) - 0.5 * (0.05f64.powi(2) + 0.02f64.powi(2))).abs() < 1e-12);
        let h = step(&m, 0.02).unwrap();
        assert!((lm::norm2(&h).sqrt() - 0.02).abs() < 1e-6, "{h:?}");
        assert!(predicted(&m, &h) > 0.0);
    }
}
