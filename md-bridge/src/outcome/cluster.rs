//! Bonds from distances (cell list, minimum image on periodic axes) and connected components
//! (union-find). Plain data in, plain data out: MD atoms and DEM particles alike.

use std::collections::HashMap;

/// Axis periods: `Some(L)` for a periodic axis of length L, `None` for an open one.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Periodicity(pub [Option<f64>; 3]);

impl Periodicity {
    /// Minimum-image separation vector b - a.
    pub fn delta(&self, a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
        let mut d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        for (k, p) in self.0.iter().enumerate() {
            if let Some(l) = p {
                d[k] -= l * (d[k] / l).round();
            }
        }
        d
    }
}

/// All pairs (i < j) closer than `cutoff`, found with a cell list (O(N) for bounded density).
pub fn bonds_within(pos: &[[f64; 3]], cutoff: f64, per: &Periodicity) -> Vec<(usize, usize)> {
    if pos.is_empty() || cutoff.is_nan() || cutoff <= 0.0 {
        return Vec::new();
    }
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in pos {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    // Cells of side >= cutoff; a periodic axis with fewer than 3 cells degenerates to 1 cell
    // (every pair then tested by minimum image), which keeps the neighbour stencil correct.
    let mut ncell = [1i64; 3];
    for k in 0..3 {
        let span = per.0[k].unwrap_or(hi[k] - lo[k]).max(cutoff);
        let n = (span / cutoff).floor() as i64;
        ncell[k] = if n >= 3 { n.min(1 << 10) } else { 1 };
    }
    let cell_of = |p: &[f64; 3]| -> [i64; 3] {
        let mut c = [0i64; 3];
        for k in 0..3 {
            let span = per.0[k].unwrap_or(hi[k] - lo[k]).max(cutoff);
            let f = match per.0[k] {
                Some(_) => ((p[k] - lo[k]) / span).rem_euclid(1.0),
                None => ((p[k] - lo[k]) / span).clamp(0.0, 1.0),
            };
            c[k] = ((f * ncell[k] as f64) as i64).min(ncell[k] - 1);
        }
        c
    };
    let mut cells: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for (i, p) in pos.iter().enumerate() {
        cells.entry(cell_of(p)).or_default().push(i);
    }
    let c2 = cutoff * cutoff;
    let mut bonds = Vec::new();
    for (i, p) in pos.iter().enumerate() {
        let c = cell_of(p);
        let mut seen: Vec<[i64; 3]> = Vec::with_capacity(27);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let mut n = [c[0] + dx, c[1] + dy, c[2] + dz];
                    for k in 0..3 {
                        if per.0[k].is_some() || ncell[k] == 1 {
                            n[k] = n[k].rem_euclid(ncell[k]);
                        }
                    }
                    if seen.contains(&n) {
                        continue;
                    }
                    seen.push(n);
                    for &j in cells.get(&n).into_iter().flatten() {
                        if j > i {
                            let d = per.delta(p, &pos[j]);
                            if d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < c2 {
                                bonds.push((i, j));
                            }
                        }
                    }
                }
            }
        }
    }
    bonds.sort_unstable();
    bonds
}

/// Connected components: `labels[i]` is the smallest index in i's component.
pub fn clusters(n: usize, bonds: &[(usize, usize)]) -> Vec<usize> {
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(p: &mut [usize], mut i: usize) -> usize {
        while p[i] != i {
            p[i] = p[p[i]];
            i = p[i];
        }
        i
    }
    for &(a, b) in bonds {
        if a >= n || b >= n {
            continue;
        }
        let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
        if ra != rb {
            let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
            parent[hi] = lo;
        }
    }
    (0..n).map(|i| find(&mut parent, i)).collect()
}

/// Fraction of `members` whose cluster holds none of the `anchors` (e.g. wall atoms): the part
/// of a junction that has come loose from both bodies.
pub fn detached_fraction(labels: &[usize], members: &[usize], anchors: &[usize]) -> f64 {
    if members.is_empty() {
        return 0.0;
    }
    let anchored: std::collections::HashSet<usize> = anchors
        .iter()
        .filter_map(|&a| labels.get(a).copied())
        .collect();
    let loose = members
        .iter()
        .filter(|&&m| labels.get(m).is_some_and(|l| !anchored.contains(l)))
        .count();
    loose as f64 / members.len() as f64
}
