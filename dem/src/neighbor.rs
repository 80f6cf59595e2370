//! Neighbour search: a cell list builds a half Verlet list (each pair once) with a skin; the list is
//! rebuilt only when particles (or the box) have moved enough to bring a new pair into range.
//!
//! - Pairs are `(i, j, image)` with `i < j`, or `i == j` for a particle facing its own periodic image
//!   (thin boxes such as the L x L x 3 d0 slabs of the papers need this). The separation vector is
//!   `x_j + image * L - x_i`; images are explicit, so a box only has to be longer than one interaction
//!   range along a periodic axis (minimum-image would need two).
//! - A pair enters the list when its centre distance is below `r_i + r_j + delta_f + skin`, the
//!   per-pair range: correct for polydisperse sizes.
//! - Rebuild criterion: twice the largest displacement since the last build plus the change of the box
//!   edges exceeds the skin (no pair can then have crossed into range unseen).
//! - Positions are wrapped into the box only at a rebuild. The tangential history of a pair survives:
//!   the old images are corrected by the wraps, then each new pair looks its history up in the old row
//!   of the same particle (rows hold a dozen pairs, so a linear scan beats any hash map).
//! - The list is stored as flat arrays (pair-major), plus a reverse index (for each particle, the pairs
//!   where it is `j`) so forces are gathered per particle in a fixed order: deterministic for any
//!   thread count.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::domain::SimBox;
use crate::error::{DemError, Result};
use crate::history::PairHistory;
use crate::Vec3;

/// Periodic image of a pair, in box lengths along each axis.
pub type Image = [i8; 3];

/// Half neighbour list with per-pair tangential history.
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
pub struct NeighborList {
    /// Extra range beyond the interaction cutoff.
    pub skin: f64,
    /// First particle of each pair.
    pub i: Vec<u32>,
    /// Second particle of each pair.
    pub j: Vec<u32>,
    /// Image of `j` seen from `i`.
    pub image: Vec<Image>,
    /// Tangential sliding displacement of each pair (zero when out of interaction range).
    pub hist: PairHistory,
    /// `row_start[i]..row_start[i+1]` are the pairs whose first particle is `i`.
    pub row_start: Vec<u32>,
    /// `rev_start[j]..rev_start[j+1]` index `rev_pair`, the pairs whose second particle is `j`.
    pub rev_start: Vec<u32>,
    /// Pair indices sorted by second particle, then pair index.
    pub rev_pair: Vec<u32>,
    /// Positions at the last build.
    ref_pos: Vec<Vec3>,
    /// Box lengths at the last build.
    ref_lengths: Vec3,
    /// Number of builds so far.
    pub builds: u64,
    /// Box lengths each particle has been wrapped by since the first build (LAMMPS's image flags):
    /// `pos + wraps * L` is the continuous, unwrapped trajectory. Empty until the first build (and in
    /// checkpoints written before it existed, whose particles then count from their next build).
    #[serde(default)]
    pub wraps: Vec<[i32; 3]>,
}

/// Per-pair interaction range, provided by the force model.
pub trait PairRange: Sync {
    /// Centre distance below which the pair (r_i, r_j) interacts.
    fn cutoff(&self, ri: f64, rj: f64) -> f64;
    /// Largest cutoff for any pair of radii up to `r_max`.
    fn max_cutoff(&self, r_max: f64) -> f64;
    /// An upper bound of `cutoff(r_i, r_j) - r_i - r_j` over partners with `r_j <= r_i <= r` (how far
    /// beyond contact a pair reaches); it screens candidates before [`PairRange::cutoff`] is called.
    /// The default, `max_cutoff(r)`, is always one; a model that knows better makes builds cheaper.
    fn beyond_contact(&self, r: f64) -> f64 {
        self.max_cutoff(r)
    }
}

impl NeighborList {
    /// An empty list with the given skin (build it before use).
    pub fn new(skin: f64) -> Result<Self> {
        if !(skin.is_finite() && skin >= 0.0) {
            return Err(DemError::InvalidConfig(format!(
                "neighbour skin {skin} must be >= 0"
            )));
        }
        Ok(NeighborList {
            skin,
            ..Default::default()
        })
    }

    /// Number of pairs.
    pub fn len(&self) -> usize {
        self.i.len()
    }

    /// Whether the list holds no pair.
    pub fn is_empty(&self) -> bool {
        self.i.is_empty()
    }

    /// Checks the invariants the force loop relies on for a list that did not come from
    /// [`NeighborList::build`] (a checkpoint): consistent lengths, rows in order, `i <= j < n`,
    /// images in {-1, 0, 1} (all a build makes: neighbour cells are at most one box away), and a
    /// reverse index holding each pair once under its second particle. Returns what is wrong.
    pub fn check(&self, n: usize) -> std::result::Result<(), String> {
        let np = self.len();
        let h = &self.hist;
        if [
            self.j.len(),
            self.image.len(),
            h.x.len(),
            h.y.len(),
            h.z.len(),
        ]
        .iter()
        .any(|&len| len != np)
        {
            return Err("pair arrays of different lengths".into());
        }
        let rows_ok = self.row_start.len() == n + 1
            && self.row_start[0] == 0
            && self.row_start[n] as usize == np
            && self.row_start.windows(2).all(|w| w[0] <= w[1]);
        if !rows_ok {
            return Err("row starts not increasing from 0 to the pair count".into());
        }
        if !(self.wraps.is_empty() || self.wraps.len() == n) {
            return Err(format!(
                "{} wrap counters for {n} particles",
                self.wraps.len()
            ));
        }
        for i in 0..n {
            for p in self.row_start[i] as usize..self.row_start[i + 1] as usize {
                let j = self.j[p] as usize;
                if self.i[p] as usize != i || j < i || j >= n {
                    return Err(format!("pair {p} is not (i, j) with {i} = i <= j < {n}"));
                }
                if self.image[p].iter().any(|s| s.abs() > 1) {
                    return Err(format!("pair {p} has image {:?}", self.image[p]));
                }
            }
        }
        let rev_ok = self.rev_start.len() == n + 1
            && self.rev_start[0] == 0
            && self.rev_start[n] as usize == np
            && self.rev_pair.len() == np
            && self.rev_start.windows(2).all(|w| w[0] <= w[1])
            && {
                let mut seen = vec![false; np];
                (0..n).all(|j| {
                    self.rev_pair[self.rev_start[j] as usize..self.rev_start[j + 1] as usize]
                        .iter()
                        .all(|&p| {
                            let p = p as usize;
                            p < np
                                && self.j[p] as usize == j
                                && !std::mem::replace(&mut seen[p], true)
                        })
                })
            };
        if !rev_ok {
            return Err("reverse index does not match the pairs".into());
        }
        Ok(())
    }

    /// Whether the particles or the box have moved enough since the last build to need a new list.
    pub fn needs_rebuild(&self, pos: &[Vec3], bx: &SimBox, parallel: bool) -> bool {
        if self.ref_pos.len() != pos.len() || self.row_start.len() != pos.len() + 1 {
            return true;
        }
        let d2 = |(a, b): (&Vec3, &Vec3)| (a - b).norm_squared();
        // max is exact in any order, so both branches agree.
        let max_d2 = if parallel {
            pos.par_iter()
                .with_min_len(1024)
                .zip(self.ref_pos.par_iter())
                .map(d2)
                .reduce(|| 0.0, f64::max)
        } else {
            pos.iter()
                .zip(self.ref_pos.iter())
                .map(d2)
                .fold(0.0, f64::max)
        };
        let dl = (bx.lengths() - self.ref_lengths).norm();
        2.0 * max_d2.sqrt() + dl > self.skin
    }

    /// Rebuilds the list for `pos` (wrapped into the box in place), keeping the history of pairs that
    /// persist.
    pub fn build(
        &mut self,
        pos: &mut [Vec3],
        radius: &[f64],
        bx: &SimBox,
        range: &impl PairRange,
    ) -> Result<()> {
        self.build_with(pos, radius, bx, range, true)
    }

    /// [`NeighborList::build`], on the current rayon pool when `parallel`, else on this thread only.
    pub fn build_with(
        &mut self,
        pos: &mut [Vec3],
        radius: &[f64],
        bx: &SimBox,
        range: &impl PairRange,
        parallel: bool,
    ) -> Result<()> {
        let n = pos.len();
        let _span = tracing::trace_span!("neighbor_build", n).entered();
        // Wrap, remembering by how many box lengths each particle moved, to correct the old images.
        let l = bx.lengths();
        let mut wraps: Vec<[i8; 3]> = vec![[0; 3]; n];
        for (x, w) in pos.iter_mut().zip(wraps.iter_mut()) {
            let before = *x;
            bx.wrap(x);
            for a in 0..3 {
                if bx.periodic[a] {
                    let k = ((before[a] - x[a]) / l[a]).round();
                    if k.abs() > 100.0 {
                        return Err(DemError::InvalidConfig(format!(
                            "a particle moved {k} box lengths between two neighbour-list builds"
                        )));
                    }
                    w[a] = k as i8;
                }
            }
        }
        if self.wraps.len() != n {
            self.wraps = vec![[0; 3]; n];
        }
        for (total, w) in self.wraps.iter_mut().zip(&wraps) {
            for a in 0..3 {
                total[a] += i32::from(w[a]);
            }
        }
        let old_valid = self.row_start.len() == n + 1;
        if old_valid {
            for p in 0..self.i.len() {
                let (wi, wj) = (wraps[self.i[p] as usize], wraps[self.j[p] as usize]);
                for a in 0..3 {
                    self.image[p][a] = self.image[p][a].saturating_add(wj[a]).saturating_sub(wi[a]);
                }
            }
        }

        let r_max = radius.iter().cloned().fold(0.0, f64::max);
        let skin = self.skin;
        let rc = range.max_cutoff(r_max) + skin;
        let grid = CellGrid::new(pos, bx, rc, cell_edge(radius, range, skin))?;
        let (cell_start, mut cell_particles) = grid.bin(pos);
        // Each cell's particles by ascending radius (ties by index), so that a particle's scan of a
        // cell stops at the first larger partner: those pairs are found from the other side.
        for w in cell_start.windows(2) {
            cell_particles[w[0] as usize..w[1] as usize].sort_unstable_by(|&a, &b| {
                radius[a as usize]
                    .total_cmp(&radius[b as usize])
                    .then(a.cmp(&b))
            });
        }
        // Positions and radii in cell order, so that a cell's candidates are read from one run of
        // memory.
        let cell_xr: Vec<[f64; 4]> = cell_particles
            .iter()
            .map(|&j| {
                let (x, r) = (pos[j as usize], radius[j as usize]);
                [x.x, x.y, x.z, r]
            })
            .collect();

        // Each pair is found from its larger particle (ties: the higher index), which searches the
        // cells within its own reach only: a small particle never scans for the largest partner's range.
        const CHUNK: usize = 512;
        let search = |c: usize| {
            let mut out: Vec<(u32, u32, Image)> = Vec::new();
            let mut steps: [Vec<AxisStep>; 3] = Default::default();
            for i in c * CHUNK..((c + 1) * CHUNK).min(n) {
                let (xi, ri) = (pos[i], radius[i]);
                // Every partner's cutoff is below this reach; the cheap bound ri + rj + beyond
                // screens candidates before the exact (possibly powf) cutoff is evaluated.
                let reach = range.max_cutoff(ri) + skin;
                let beyond = range.beyond_contact(ri) + skin;
                grid.for_each_cell_within(grid.cell_of(&xi), reach, &mut steps, |cell, img| {
                    let o = bx.shift(img) - xi;
                    let (s, e) = (cell_start[cell] as usize, cell_start[cell + 1] as usize);
                    for (&j, &[x, y, z, rj]) in cell_particles[s..e].iter().zip(&cell_xr[s..e]) {
                        // A cell's particles are in ascending radius: the rest are all larger.
                        if rj > ri {
                            break;
                        }
                        let j = j as usize;
                        let larger = rj < ri || (rj == ri && j < i);
                        if !(larger || (j == i && positive_image(img))) {
                            continue;
                        }
                        let (dx, dy, dz) = (x + o.x, y + o.y, z + o.z);
                        let d2 = dx * dx + dy * dy + dz * dz;
                        // (Rounded up by a part in 1e12, so that rounding never lets the screen
                        // drop a pair the exact cutoff keeps.)
                        let rough = (ri + rj + beyond) * (1.0 + 1e-12);
                        if d2 >= rough * rough {
                            continue;
                        }
                        // The exact test on the separation as the force loop computes it.
                        let d2 = (pos[j] + bx.shift(img) - xi).norm_squared();
                        let cut = range.cutoff(ri, rj) + skin;
                        if d2 < cut * cut {
                            // Stored as (lower index, higher index, image of the higher seen from
                            // the lower).
                            out.push(if j < i {
                                (j as u32, i as u32, img.map(|s| -s))
                            } else {
                                (i as u32, j as u32, img)
                            });
                        }
                    }
                });
            }
            out
        };
        let chunks = n.div_ceil(CHUNK);
        let found: Vec<Vec<(u32, u32, Image)>> = if parallel {
            (0..chunks).into_par_iter().map(search).collect()
        } else {
            (0..chunks).map(search).collect()
        };
        // Rows by counting sort on the first particle, each sorted by (second particle, image): the
        // pairs are distinct, so the order is the same however the search was split.
        let total: usize = found.iter().map(Vec::len).sum();
        let mut row_start = vec![0u32; n + 1];
        for &(i, _, _) in found.iter().flatten() {
            row_start[i as usize + 1] += 1;
        }
        for k in 0..n {
            row_start[k + 1] += row_start[k];
        }
        let mut fill = row_start.clone();
        let mut slots = vec![(0u32, [0i8; 3]); total];
        for &(i, j, img) in found.iter().flatten() {
            slots[fill[i as usize] as usize] = (j, img);
            fill[i as usize] += 1;
        }
        let sort_rows = |(c, rows): (usize, &mut [(u32, Image)])| {
            let base = row_start[c * CHUNK] as usize;
            for i in c * CHUNK..((c + 1) * CHUNK).min(n) {
                let (s, e) = (
                    row_start[i] as usize - base,
                    row_start[i + 1] as usize - base,
                );
                rows[s..e].sort_unstable();
            }
        };
        let row_chunks = split_rows(&mut slots, &row_start, CHUNK);
        if parallel {
            row_chunks.into_par_iter().enumerate().for_each(sort_rows);
        } else {
            row_chunks.into_iter().enumerate().for_each(sort_rows);
        }
        let new_i: Vec<u32> = (0..n)
            .flat_map(|i| std::iter::repeat_n(i as u32, (row_start[i + 1] - row_start[i]) as usize))
            .collect();
        let new_j: Vec<u32> = slots.iter().map(|s| s.0).collect();
        let new_img: Vec<Image> = slots.iter().map(|s| s.1).collect();
        // Carry the history over: same (i, j, image) in the old row of i.
        let mut new_hist = PairHistory::zeros(total);
        if old_valid {
            for i in 0..n {
                let (ns, ne) = (row_start[i] as usize, row_start[i + 1] as usize);
                let (os, oe) = (self.row_start[i] as usize, self.row_start[i + 1] as usize);
                for p in ns..ne {
                    if let Some(q) =
                        (os..oe).find(|&q| self.j[q] == new_j[p] && self.image[q] == new_img[p])
                    {
                        new_hist.set(p, self.hist.get(q));
                    }
                }
            }
        }
        // Reverse index by counting sort on j (stable: pair order within each particle).
        let mut rev_start = vec![0u32; n + 1];
        for &j in &new_j {
            rev_start[j as usize + 1] += 1;
        }
        for k in 0..n {
            rev_start[k + 1] += rev_start[k];
        }
        let mut fill = rev_start.clone();
        let mut rev_pair = vec![0u32; total];
        for (p, &j) in new_j.iter().enumerate() {
            rev_pair[fill[j as usize] as usize] = p as u32;
            fill[j as usize] += 1;
        }

        self.i = new_i;
        self.j = new_j;
        self.image = new_img;
        self.hist = new_hist;
        self.row_start = row_start;
        self.rev_start = rev_start;
        self.rev_pair = rev_pair;
        self.ref_pos.clear();
        self.ref_pos.extend_from_slice(pos);
        self.ref_lengths = l;
        self.builds += 1;
        Ok(())
    }

    /// Forces a rebuild at the next step (the cutoffs changed), keeping the history.
    pub fn mark_stale(&mut self) {
        self.ref_pos.clear();
    }

    /// Forgets all pairs and history (after particles were added or removed).
    pub fn invalidate(&mut self) {
        let skin = self.skin;
        *self = NeighborList {
            skin,
            ..Default::default()
        };
    }
}

/// Keeps one of the two equivalent self-image pairs (s and -s).
fn positive_image(s: Image) -> bool {
    s > [0, 0, 0]
}

/// The cell edge of a build: the reach of a pair of median particles. Cells sized for the largest
/// range (one cell across it) would hold hundreds of the small particles of a wide size distribution,
/// all of them candidates of every neighbour; with this edge, most particles search their 27 cells
/// and only the larger ones reach further ([`CellGrid::for_each_cell_within`]). Equal spheres get
/// the largest range, as before.
fn cell_edge(radius: &[f64], range: &impl PairRange, skin: f64) -> f64 {
    if radius.is_empty() {
        return 0.0;
    }
    let mut r = radius.to_vec();
    let mid = r.len() / 2;
    let (_, median, _) = r.select_nth_unstable_by(mid, f64::total_cmp);
    range.max_cutoff(*median) + skin
}

/// `slots` cut at the first pair of every `chunk`-th row (for sorting the rows in parallel).
fn split_rows<'a, T>(mut slots: &'a mut [T], row_start: &[u32], chunk: usize) -> Vec<&'a mut [T]> {
    let n = row_start.len() - 1;
    let mut parts = Vec::with_capacity(n.div_ceil(chunk));
    for c in 0..n.div_ceil(chunk) {
        let len = (row_start[((c + 1) * chunk).min(n)] - row_start[c * chunk]) as usize;
        let (head, tail) = std::mem::take(&mut slots).split_at_mut(len);
        parts.push(head);
        slots = tail;
    }
    parts
}

/// Uniform cell grid over the box (periodic axes) or over the particles' extent (other axes).
struct CellGrid {
    lo: Vec3,
    size: Vec3,
    n: [usize; 3],
    periodic: [bool; 3],
}

impl CellGrid {
    /// A grid of cells of about `edge` (at least one per axis, at most about 8 per particle), over a
    /// box whose periodic axes must be longer than the largest reach `rc`.
    fn new(pos: &[Vec3], bx: &SimBox, rc: f64, edge: f64) -> Result<Self> {
        let mut lo = bx.lo;
        let mut ext = bx.lengths();
        let mut n = [1usize; 3];
        // Cap the grid at about 8 cells per particle so sparse non-periodic systems stay cheap.
        let cap = ((8 * pos.len().max(1)) as f64).cbrt().ceil() as usize + 2;
        for a in 0..3 {
            if bx.periodic[a] {
                if ext[a] < rc {
                    return Err(DemError::InvalidBox(format!(
                        "periodic axis {a} is {:.6e} long, shorter than one interaction range plus skin ({rc:.6e})",
                        ext[a]
                    )));
                }
            } else {
                let (mn, mx) = pos
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(mn, mx), x| {
                        (mn.min(x[a]), mx.max(x[a]))
                    });
                if pos.is_empty() {
                    lo[a] = 0.0;
                    ext[a] = rc;
                } else {
                    lo[a] = mn;
                    ext[a] = (mx - mn).max(rc) * (1.0 + 1e-9);
                }
            }
            n[a] = ((ext[a] / edge.max(1e-300 * ext[a])).floor() as usize).clamp(1, cap);
        }
        let size = Vec3::new(
            ext[0] / n[0] as f64,
            ext[1] / n[1] as f64,
            ext[2] / n[2] as f64,
        );
        Ok(CellGrid {
            lo,
            size,
            n,
            periodic: bx.periodic,
        })
    }

    fn count(&self) -> usize {
        self.n[0] * self.n[1] * self.n[2]
    }

    fn coords(&self, x: &Vec3) -> [usize; 3] {
        let mut c = [0usize; 3];
        for a in 0..3 {
            let k = ((x[a] - self.lo[a]) / self.size[a]).floor();
            c[a] = (k.max(0.0) as usize).min(self.n[a] - 1);
        }
        c
    }

    fn cell_of(&self, x: &Vec3) -> usize {
        let c = self.coords(x);
        c[0] + self.n[0] * (c[1] + self.n[1] * c[2])
    }

    /// Counting sort of particles into cells: (start offsets, particle indices), stable in index order.
    fn bin(&self, pos: &[Vec3]) -> (Vec<u32>, Vec<u32>) {
        let nc = self.count();
        let cells: Vec<usize> = pos.iter().map(|x| self.cell_of(x)).collect();
        let mut start = vec![0u32; nc + 1];
        for &c in &cells {
            start[c + 1] += 1;
        }
        for k in 0..nc {
            start[k + 1] += start[k];
        }
        let mut fill = start.clone();
        let mut parts = vec![0u32; pos.len()];
        for (p, &c) in cells.iter().enumerate() {
            parts[fill[c] as usize] = p as u32;
            fill[c] += 1;
        }
        (start, parts)
    }

    /// Calls `f(cell, image)` for every cell within `reach` of `cell` (27 cells when the reach is one
    /// cell edge) in the unwrapped tiling, with the image of each periodic copy; every (cell, image)
    /// combination is distinct even when an axis has one or two cells. Images beyond one box length
    /// are left out: positions lie in the box and every range is shorter than it. `steps` is scratch
    /// for the three axes' offsets, reused across calls: a large particle's stencil has hundreds of
    /// cells but only 2k + 1 offsets per axis, each costing an integer division once, not per cell.
    fn for_each_cell_within(
        &self,
        cell: usize,
        reach: f64,
        steps: &mut [Vec<AxisStep>; 3],
        mut f: impl FnMut(usize, Image),
    ) {
        let c = [
            cell % self.n[0],
            (cell / self.n[0]) % self.n[1],
            cell / (self.n[0] * self.n[1]),
        ];
        for (a, out) in steps.iter_mut().enumerate() {
            let k = (reach / self.size[a]).ceil().max(1.0) as i64;
            self.axis_steps(a, c[a], k, out);
        }
        // Cells of a large stencil whose nearest point lies beyond the reach are skipped (about
        // half of the cube for the largest particles); the 27 nearest always stay.
        let reach2 = reach * reach;
        let [xs, ys, zs] = &*steps;
        for sz in zs {
            for sy in ys {
                let gyz = sz.gap2 + sy.gap2;
                if gyz >= reach2 {
                    continue;
                }
                let row = self.n[0] * (sy.cell + self.n[1] * sz.cell);
                for sx in xs {
                    if gyz + sx.gap2 >= reach2 {
                        continue;
                    }
                    f(sx.cell + row, [sx.img, sy.img, sz.img]);
                }
            }
        }
    }

    /// The offsets -k..=k from cell coordinate `c` along axis `a` that exist: the cell, its image
    /// (periodic axes, at most one box length away) and the squared gap between the two cells.
    fn axis_steps(&self, a: usize, c: usize, k: i64, out: &mut Vec<AxisStep>) {
        out.clear();
        let na = self.n[a] as i64;
        for d in -k..=k {
            let u = c as i64 + d;
            let (cell, img) = if self.periodic[a] {
                let img = u.div_euclid(na);
                if img.abs() > 1 {
                    continue;
                }
                (u.rem_euclid(na) as usize, img as i8)
            } else if (0..na).contains(&u) {
                (u as usize, 0)
            } else {
                continue;
            };
            let gap = (d.abs() - 1).max(0) as f64 * self.size[a];
            out.push(AxisStep {
                cell,
                img,
                gap2: gap * gap,
            });
        }
    }
}

/// One offset of a stencil along one axis (see [`CellGrid::axis_steps`]).
struct AxisStep {
    cell: usize,
    img: i8,
    gap2: f64,
}
