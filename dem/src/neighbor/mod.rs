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
//!   edges exceeds the skin (no pair can then have crossed into range unseen). With
//!   [`NeighborList::local`], only the rows of the particles that moved are searched again (`local`).
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

use grid::{Binned, Steps};
pub use local::{Rebuild, LOCAL_SHARE};

mod grid;
mod local;

/// Particles per task of a parallel search (and per run of rows sorted together).
const CHUNK: usize = 512;

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
    /// Rebuild only the rows of the particles that moved ([`NeighborList::update`]); default false,
    /// the whole list at once, which is cheaper where everything moves (relaxations, patch tests).
    #[serde(default)]
    pub local: bool,
    /// Whether some particles were searched later than others (a local rebuild since the last full
    /// build): the rebuild trigger is then a third of the skin per particle, not half of it.
    #[serde(default)]
    mixed: bool,
    /// How many of the `builds` were local.
    #[serde(default)]
    pub local_builds: u64,
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
        self.needs_rebuild_known(pos, bx, parallel, None)
    }

    /// [`NeighborList::needs_rebuild`] with the largest displacement already known (see
    /// [`NeighborList::update_known`]).
    fn needs_rebuild_known(
        &self,
        pos: &[Vec3],
        bx: &SimBox,
        parallel: bool,
        known: Option<f64>,
    ) -> bool {
        if self.ref_pos.len() != pos.len() || self.row_start.len() != pos.len() + 1 {
            return true;
        }
        let dl = (bx.lengths() - self.ref_lengths).norm();
        let max_d = known.unwrap_or_else(|| self.max_displacement(pos, parallel));
        2.0 * max_d + dl > self.skin
    }

    /// The positions at the last build, for a pass that measures the displacement as it moves the
    /// particles (the integrator).
    pub(crate) fn reference_positions(&self) -> &[Vec3] {
        &self.ref_pos
    }

    /// The largest distance of a particle from its reference position (`pos` and the references
    /// must have the same length).
    fn max_displacement(&self, pos: &[Vec3], parallel: bool) -> f64 {
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
        max_d2.sqrt()
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
        self.wrap(pos, bx)?;
        let skin = self.skin;
        let binned = Binned::new(pos, radius, bx, range, skin)?;
        // Each pair is found from its larger particle (ties: the higher index).
        let search = |c: usize| {
            let mut out: Vec<(u32, u32, Image)> = Vec::new();
            let mut steps = Steps::default();
            for i in c * CHUNK..((c + 1) * CHUNK).min(n) {
                binned.smaller_partners(i, pos, radius, bx, range, skin, &mut steps, |j, img| {
                    out.push(ordered(i, j, img))
                });
            }
            out
        };
        let found = in_chunks(n, parallel, search);
        self.assemble(n, &found, parallel);
        self.ref_pos.clear();
        self.ref_pos.extend_from_slice(pos);
        self.ref_lengths = bx.lengths();
        self.mixed = false;
        self.builds += 1;
        Ok(())
    }

    /// Wraps `pos` into the box, counting the wraps, and corrects the images of the listed pairs by
    /// them (so their separations, and the history lookups, stay those of the same pairs).
    fn wrap(&mut self, pos: &mut [Vec3], bx: &SimBox) -> Result<()> {
        let n = pos.len();
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
        // The reference positions move with their particles, so a local rebuild's displacement of a
        // particle it did not search stays its real displacement.
        if self.ref_pos.len() == n {
            for (r, w) in self.ref_pos.iter_mut().zip(&wraps) {
                *r -= Vec3::new(
                    f64::from(w[0]) * l.x,
                    f64::from(w[1]) * l.y,
                    f64::from(w[2]) * l.z,
                );
            }
        }
        for (total, w) in self.wraps.iter_mut().zip(&wraps) {
            for a in 0..3 {
                total[a] += i32::from(w[a]);
            }
        }
        if self.row_start.len() == n + 1 {
            for p in 0..self.i.len() {
                let (wi, wj) = (wraps[self.i[p] as usize], wraps[self.j[p] as usize]);
                for a in 0..3 {
                    self.image[p][a] = self.image[p][a].saturating_add(wj[a]).saturating_sub(wi[a]);
                }
            }
        }
        Ok(())
    }

    /// Replaces the pairs by `found` (distinct `(i, j, image)` with `i <= j`, in any order and split):
    /// rows by counting sort on the first particle, each sorted by (second particle, image), so the
    /// order is the same however the search was split; the history of every pair that was already
    /// listed is carried over; the reverse index is rebuilt.
    fn assemble(&mut self, n: usize, found: &[Vec<(u32, u32, Image)>], parallel: bool) {
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
        if self.row_start.len() == n + 1 {
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
    }

    /// Forces a rebuild at the next step (the cutoffs changed), keeping the history.
    pub fn mark_stale(&mut self) {
        self.ref_pos.clear();
    }

    /// Forgets all pairs and history (after particles were added or removed).
    pub fn invalidate(&mut self) {
        let (skin, local) = (self.skin, self.local);
        *self = NeighborList {
            skin,
            local,
            ..Default::default()
        };
    }
}

/// A pair found from particle `i` with partner `j` at image `img`, stored as (lower index, higher
/// index, image of the higher seen from the lower).
fn ordered(i: usize, j: usize, img: Image) -> (u32, u32, Image) {
    if j < i {
        (j as u32, i as u32, img.map(|s| -s))
    } else {
        (i as u32, j as u32, img)
    }
}

/// The pairs found by `search` over the chunks of `count` searching particles, on the current rayon
/// pool when `parallel`, in chunk order either way.
fn in_chunks(
    count: usize,
    parallel: bool,
    search: impl Fn(usize) -> Vec<(u32, u32, Image)> + Sync + Send,
) -> Vec<Vec<(u32, u32, Image)>> {
    let chunks = count.div_ceil(CHUNK);
    if parallel {
        (0..chunks).into_par_iter().map(search).collect()
    } else {
        (0..chunks).map(search).collect()
    }
}

/// Keeps one of the two equivalent self-image pairs (s and -s).
fn positive_image(s: Image) -> bool {
    s > [0, 0, 0]
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
