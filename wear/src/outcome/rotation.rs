//! Rigid-body fit in a plane: how much a group of atoms/particles turned between two frames and
//! how much of its motion is *not* rigid. Rolling debris turns with a small non-rigid residual;
//! a junction smeared by plastic flow turns by the flow's vorticity with a residual as large as
//! the turn itself (simple shear: strain and spin parts have equal magnitude).

/// Best rigid motion from `prev` to `cur` in the plane of `axes`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneFit {
    /// Rotation angle (rad, counter-clockwise from axes.0 towards axes.1).
    pub angle: f64,
    /// RMS in-plane displacement left after removing translation and rotation.
    pub residual: f64,
    /// RMS in-plane distance from the centroid in `prev` (the group's radius of gyration).
    pub radius: f64,
}

/// 2D Kabsch fit between matching point sets (same order, unwrapped coordinates).
pub fn plane_fit(prev: &[[f64; 3]], cur: &[[f64; 3]], axes: (usize, usize)) -> PlaneFit {
    let n = prev.len().min(cur.len());
    if n == 0 {
        return PlaneFit {
            angle: 0.0,
            residual: 0.0,
            radius: 0.0,
        };
    }
    let (a, b) = axes;
    let centroid = |s: &[[f64; 3]]| {
        let (mut x, mut y) = (0.0, 0.0);
        for p in &s[..n] {
            x += p[a];
            y += p[b];
        }
        (x / n as f64, y / n as f64)
    };
    let (pa, pb) = centroid(prev);
    let (qa, qb) = centroid(cur);
    let (mut sin, mut cos, mut r2) = (0.0, 0.0, 0.0);
    for i in 0..n {
        let (px, py) = (prev[i][a] - pa, prev[i][b] - pb);
        let (qx, qy) = (cur[i][a] - qa, cur[i][b] - qb);
        sin += px * qy - py * qx;
        cos += px * qx + py * qy;
        r2 += px * px + py * py;
    }
    let angle = sin.atan2(cos);
    let (s, c) = angle.sin_cos();
    let mut res2 = 0.0;
    for i in 0..n {
        let (px, py) = (prev[i][a] - pa, prev[i][b] - pb);
        let (qx, qy) = (cur[i][a] - qa, cur[i][b] - qb);
        let (rx, ry) = (c * px - s * py, s * px + c * py);
        res2 += (qx - rx).powi(2) + (qy - ry).powi(2);
    }
    PlaneFit {
        angle,
        residual: (res2 / n as f64).sqrt(),
        radius: (r2 / n as f64).sqrt(),
    }
}
