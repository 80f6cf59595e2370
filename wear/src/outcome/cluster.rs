//! Bonds from distances (cell list, minimum image on periodic axes), connected components
//! (union-find), and the detachment of a junction from them. Plain data in, plain data out: MD atoms
//! and DEM particles alike.
//!
//! Detachment (the cluster analysis of the verdict's evidence). A wear particle is junction material
//! that has lost every bond chain to the bodies it joined, and holds together as one body. Bonds that
//! merely touch do not tell it: a rolling particle is pressed against both surfaces and bonded to them
//! at its contacts, which move as it rolls. So the analysis keeps only the *original* bonds that
//! *survive*: pairs bonded in the first frame and still bonded in the last. A rolling particle keeps
//! its inner bonds and has lost the ones at its roots, and its contacts are new: its cluster holds no
//! wall particle.
//!
//! Decision (what "still bonded" means on a periodic axis): bonded *in the same periodic image* as in
//! the first frame, read from unwrapped positions (each particle on its continuous path). A pair that
//! stayed together keeps the image offset it started with; a pair that parted and met again after one
//! of them travelled a box length has moved to another image, and that is a new contact. Why: a wear
//! particle rolls at half the sliding speed, so in the paper's junction (100 nm of sliding in a 60 nm
//! box) it comes back over the spot it tore from, and its bottom members lie again next to the surface
//! particles they were bonded to. By minimum image those pairs looked as if they had never parted and
//! anchored the rolling body (measured, docs/junction.md: 13 such pairs kept a rolled D = 20 nm ridge
//! at 0.5 % detached, 97 % once they are counted as new).
//!
//! Plastic flow breaks bonds too, but the flowed material stays bonded to one of the bodies or falls
//! into many small clusters; so two numbers are reported: the fraction of members
//! with no surviving chain to an anchor, and the fraction in the largest such cluster (the debris).

use std::collections::HashMap;

use serde::{Deserialize, Serialize};

use crate::error::{Result, WearError};

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
    pairs_within(pos, cutoff, per, |_, _, d2| d2 < cutoff * cutoff)
}

/// All pairs (i < j) with centres closer than r_i + r_j + `margin` (DEM particles: `margin` the largest
/// cohesive range, so that every interacting pair is a bond).
pub fn bonds_within_radii(
    pos: &[[f64; 3]],
    radii: &[f64],
    margin: f64,
    per: &Periodicity,
) -> Vec<(usize, usize)> {
    let r_max = radii.iter().cloned().fold(0.0, f64::max);
    pairs_within(pos, 2.0 * r_max + margin, per, |i, j, d2| {
        let c = radii[i] + radii[j] + margin;
        d2 < c * c
    })
}

/// Pairs (i < j) within `cutoff` that `accept(i, j, distance^2)` keeps.
fn pairs_within(
    pos: &[[f64; 3]],
    cutoff: f64,
    per: &Periodicity,
    accept: impl Fn(usize, usize, f64) -> bool,
) -> Vec<(usize, usize)> {
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
                            if accept(i, j, d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) {
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

/// Which pairs count as bonded: centres closer than r_i + r_j + `margin` (radii zero for atoms, where
/// `margin` is then the bond cut-off), with minimum images on the periodic axes in the first frame and
/// the same images in the last (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Bonding {
    /// Particle radii, one per tracked particle; `None` for atoms (all zero).
    pub radii: Option<Vec<f64>>,
    pub margin: f64,
    pub periodicity: Periodicity,
}

impl Bonding {
    fn bonds(&self, pos: &[[f64; 3]]) -> Vec<(usize, usize)> {
        match &self.radii {
            Some(r) => bonds_within_radii(pos, r, self.margin, &self.periodicity),
            None => bonds_within(pos, self.margin, &self.periodicity),
        }
    }

    /// Whether the pair (i, j), bonded in `first`, is bonded in `last` in the same periodic image: the
    /// image is the minimum one of the first frame, and `last` continues `first` unwrapped.
    fn still_bonded(&self, first: &[[f64; 3]], last: &[[f64; 3]], i: usize, j: usize) -> bool {
        let r = |k: usize| self.radii.as_ref().map_or(0.0, |r| r[k]);
        let reach = r(i) + r(j) + self.margin;
        let mut d2 = 0.0;
        for k in 0..3 {
            let shift = match self.periodicity.0[k] {
                Some(l) => l * ((first[j][k] - first[i][k]) / l).round(),
                None => 0.0,
            };
            let d = last[j][k] - last[i][k] - shift;
            d2 += d * d;
        }
        d2 < reach * reach
    }
}

/// The cluster analysis of a sheared junction (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Detachment {
    /// Fraction of the junction members with no chain of surviving bonds to an anchor.
    pub detached_fraction: f64,
    /// Fraction of the members in the largest cluster that holds no anchor: the debris.
    pub debris_fraction: f64,
    /// Particles (members or not) in that cluster.
    pub debris_size: usize,
    /// Bonds in the first frame, and how many of them are still bonds in the last (same image).
    pub initial_bonds: usize,
    pub surviving_bonds: usize,
}

/// One cluster of surviving bonds that holds no anchor.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LooseCluster {
    /// Its label in [`LooseClusters::labels`] (the smallest particle index in it).
    pub label: usize,
    /// Members in it, and particles (members or not).
    pub members: usize,
    pub particles: usize,
}

/// Every cluster of surviving bonds between two frames that holds members and no anchor: what
/// [`detachment`] reads for a junction and the sliding layer reads for its wear particles.
#[derive(Debug, Clone, PartialEq)]
pub struct LooseClusters {
    /// Cluster label of every tracked particle (the smallest index in its cluster).
    pub labels: Vec<usize>,
    /// The loose clusters, most members first (ties: the smaller label first), so the order is
    /// unique.
    pub clusters: Vec<LooseCluster>,
    /// Members with no chain of surviving bonds to an anchor.
    pub detached_members: usize,
    /// Bonds in the first frame, and how many of them are still bonds in the last (same image).
    pub initial_bonds: usize,
    pub surviving_bonds: usize,
}

/// The loose clusters between the `first` and `last` frames of every tracked particle, anchored at
/// `anchors`: bonds of the first frame that survive to the last in the same periodic image (module
/// docs). `last` must continue `first` without wrapping (unwrapped positions,
/// [`crate::outcome::unwrap_frame`] frame by frame, or the engine's image counts).
pub fn loose_clusters(
    first: &[[f64; 3]],
    last: &[[f64; 3]],
    bonding: &Bonding,
    members: &[usize],
    anchors: &[usize],
) -> Result<LooseClusters> {
    let n = first.len();
    if last.len() != n {
        return Err(WearError::Frames(format!(
            "first frame has {n} particles, last frame {}",
            last.len()
        )));
    }
    if let Some(r) = &bonding.radii {
        if r.len() != n {
            return Err(WearError::Frames(format!(
                "{} radii for {n} particles",
                r.len()
            )));
        }
    }
    if !(bonding.margin.is_finite() && bonding.margin >= 0.0) {
        return Err(WearError::Setting(format!(
            "bond margin {} must be a finite non-negative length",
            bonding.margin
        )));
    }
    if let Some(&i) = members.iter().chain(anchors).find(|&&i| i >= n) {
        return Err(WearError::Frames(format!(
            "index {i} is not one of the {n} tracked particles"
        )));
    }
    if members.is_empty() {
        return Err(WearError::Frames(
            "a cluster analysis without members".into(),
        ));
    }
    let initial = bonding.bonds(first);
    let surviving: Vec<(usize, usize)> = initial
        .iter()
        .copied()
        .filter(|&(i, j)| bonding.still_bonded(first, last, i, j))
        .collect();
    let labels = clusters(n, &surviving);
    let anchored: std::collections::HashSet<usize> = anchors.iter().map(|&a| labels[a]).collect();
    let mut loose: HashMap<usize, usize> = HashMap::new();
    for &m in members {
        if !anchored.contains(&labels[m]) {
            *loose.entry(labels[m]).or_default() += 1;
        }
    }
    let mut particles: HashMap<usize, usize> = HashMap::new();
    for &l in &labels {
        if loose.contains_key(&l) {
            *particles.entry(l).or_default() += 1;
        }
    }
    let mut found: Vec<LooseCluster> = loose
        .iter()
        .map(|(&label, &members)| LooseCluster {
            label,
            members,
            particles: particles[&label],
        })
        .collect();
    found.sort_unstable_by(|a, b| b.members.cmp(&a.members).then(a.label.cmp(&b.label)));
    Ok(LooseClusters {
        detached_members: loose.values().sum(),
        labels,
        clusters: found,
        initial_bonds: initial.len(),
        surviving_bonds: surviving.len(),
    })
}

/// Cluster analysis between the `first` and `last` frames of every tracked particle (junction members,
/// the bodies and the walls; indices into the frames), anchored at `anchors` (the wall particles):
/// the detached fraction and the largest loose cluster, the debris, of [`loose_clusters`].
pub fn detachment(
    first: &[[f64; 3]],
    last: &[[f64; 3]],
    bonding: &Bonding,
    members: &[usize],
    anchors: &[usize],
) -> Result<Detachment> {
    let loose = loose_clusters(first, last, bonding, members, anchors)?;
    let (debris_members, debris_size) = loose
        .clusters
        .first()
        .map_or((0, 0), |c| (c.members, c.particles));
    Ok(Detachment {
        detached_fraction: loose.detached_members as f64 / members.len() as f64,
        debris_fraction: debris_members as f64 / members.len() as f64,
        debris_size,
        initial_bonds: loose.initial_bonds,
        surviving_bonds: loose.surviving_bonds,
    })
}
