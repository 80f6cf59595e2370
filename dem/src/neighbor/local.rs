//! Local rebuilds: when only some particles have moved far, search the partners of those particles
//! alone and keep every other pair as it is.
//!
//! A full build lists every pair within cutoff plus skin; the classic trigger rebuilds everything
//! once twice the largest displacement exceeds the skin. In a sliding layer whose shear band lies
//! against a body, a few per cent of the particles (the band, and the body dragged along) move and
//! the rest stand still, yet each fast particle of the band rebuilds all rows (paper 004's L = 100 d0
//! box: a rebuild every 4 steps, 80 % of the run in the search, docs/sliding.md). With
//! [`NeighborList::local`] set, each particle keeps its own reference position, and:
//!
//! - once any particle has moved more than theta_a = 0.45 skin since its own last search, every
//!   particle that moved more than theta_s = 0.1 skin (the set S) has all its partners searched
//!   again; pairs of two particles outside S are kept. Selecting well below the trigger batches the
//!   searches: a band whose particles cross theta_a one after the other is searched about as rarely
//!   as full builds come, not at every step (a selection at the trigger, theta = skin / 3 for both,
//!   rebuilt 29 107 times in 29 127 steps of a 10 150-particle layer and took 2.3 times as long);
//! - if S holds more than one particle in [`LOCAL_SHARE`], everything is rebuilt (cheaper then);
//! - with every reference from one full build, nothing is done until twice the largest displacement
//!   exceeds the skin (the classic trigger, so scenarios where everything moves rebuild exactly as
//!   before).
//!
//! Why a pair (a, b) that is not listed cannot reach its cutoff: let t* be the last search that
//! covered it (a full build, or a local one with a or b in S). It was then at least cutoff + skin
//! apart. If both were searched at t*, it has since closed by at most D_a + D_b (D: displacement from
//! the own reference), below the skin under either trigger. Otherwise a was in S at t* and b was not,
//! so D_b(t*) <= theta_s, and the pair has closed by at most D_a + D_b + D_b(t*) <= 2 theta_a +
//! theta_s = skin. A box that changes size breaks the second bound (an image moves with the box),
//! so a box change since the last full build falls back to full builds.
//!
//! The set S depends on positions only, the searches are sorted into rows as a full build's are, and
//! pairs beyond the cutoff add exact zeros: the result is the same for any thread count, and it
//! differs from full builds only where positions are wrapped (round-off).

use rayon::prelude::*;

use super::grid::{Binned, Steps};
use super::{in_chunks, ordered, Image, NeighborList, PairRange, CHUNK};
use crate::domain::SimBox;
use crate::error::Result;
use crate::Vec3;

/// A local rebuild is done when at most one particle in `LOCAL_SHARE` has moved beyond theta_s;
/// above that a full build is cheaper: a local rebuild searches its particles in both directions
/// (partners smaller and larger) and copies every kept pair. Measured on paper 004's L = 100 d0
/// layer with its band at the top body (40 621 particles, 2 threads, 90 s from one checkpoint):
/// 10 300 steps at 8, 9 808 at 4 (full builds 8 825).
pub const LOCAL_SHARE: usize = 8;

/// theta_s over the skin: particles that moved more are searched at a local rebuild. The same
/// measurement: 10 300 steps at 0.1, 9 994 at 0.2 (a later trigger, 0.45 skin against 0.4, beats a
/// smaller selection).
pub const SELECT: f64 = 0.1;

/// theta_a over the skin: a particle that moved more triggers a rebuild (2 theta_a + theta_s = 1).
const TRIGGER: f64 = (1.0 - SELECT) / 2.0;

/// What [`NeighborList::update`] did.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Rebuild {
    /// The list still holds every pair in range.
    None,
    /// Every row was searched again.
    Full,
    /// The rows of these particles (ascending indices) were searched again.
    Local(Vec<u32>),
}

impl NeighborList {
    /// Brings the list up to date for `pos`: nothing, a full build ([`NeighborList::build`]), or,
    /// when [`NeighborList::local`] is set, a rebuild of the rows of the particles that moved (module
    /// docs). Without `local`, this is `needs_rebuild` then `build`, as before.
    pub fn update(
        &mut self,
        pos: &mut [Vec3],
        radius: &[f64],
        bx: &SimBox,
        range: &impl PairRange,
        parallel: bool,
    ) -> Result<Rebuild> {
        self.update_known(pos, radius, bx, range, parallel, None)
    }

    /// [`NeighborList::update`] with the largest displacement from the reference positions already
    /// known, `known_max_d` (the integrator measures it as it moves the particles, which saves a pass
    /// over them and, on a pool, a join per step). It must be exactly what `max_displacement` would
    /// return: a max is exact in any order, so the same squares give the same value.
    pub(crate) fn update_known(
        &mut self,
        pos: &mut [Vec3],
        radius: &[f64],
        bx: &SimBox,
        range: &impl PairRange,
        parallel: bool,
        known_max_d: Option<f64>,
    ) -> Result<Rebuild> {
        let n = pos.len();
        let stale = self.ref_pos.len() != n || self.row_start.len() != n + 1;
        if !self.local || stale {
            if self.needs_rebuild_known(pos, bx, parallel, known_max_d) {
                self.build(pos, radius, bx, range)?;
                return Ok(Rebuild::Full);
            }
            return Ok(Rebuild::None);
        }
        let max_d = known_max_d.unwrap_or_else(|| self.max_displacement(pos, parallel));
        let dl = (bx.lengths() - self.ref_lengths).norm();
        let skin = self.skin;
        if dl > 0.0 {
            if self.mixed || 2.0 * max_d + dl > skin {
                self.build(pos, radius, bx, range)?;
                return Ok(Rebuild::Full);
            }
            return Ok(Rebuild::None);
        }
        let act = if self.mixed {
            max_d > TRIGGER * skin
        } else {
            2.0 * max_d > skin
        };
        if !act {
            return Ok(Rebuild::None);
        }
        let far = |k: &usize| (pos[*k] - self.ref_pos[*k]).norm() > SELECT * skin;
        let moved: Vec<u32> = if parallel {
            (0..n)
                .into_par_iter()
                .with_min_len(1024)
                .filter(far)
                .map(|k| k as u32)
                .collect()
        } else {
            (0..n).filter(far).map(|k| k as u32).collect()
        };
        if moved.len() * LOCAL_SHARE > n {
            self.build(pos, radius, bx, range)?;
            return Ok(Rebuild::Full);
        }
        self.rebuild_rows(&moved, pos, radius, bx, range, parallel)?;
        Ok(Rebuild::Local(moved))
    }

    /// Searches the partners of the `moved` particles (ascending indices) again and keeps every pair
    /// of two particles that are not among them.
    fn rebuild_rows(
        &mut self,
        moved: &[u32],
        pos: &mut [Vec3],
        radius: &[f64],
        bx: &SimBox,
        range: &impl PairRange,
        parallel: bool,
    ) -> Result<()> {
        let n = pos.len();
        let _span = tracing::trace_span!("neighbor_local_build", n, moved = moved.len()).entered();
        self.wrap(pos, bx)?;
        let pos: &[Vec3] = pos;
        let skin = self.skin;
        let binned = Binned::new(pos, radius, bx, range, skin)?;
        let mut is_moved = vec![false; n];
        for &k in moved {
            is_moved[k as usize] = true;
        }
        let kept: Vec<(u32, u32, Image)> = (0..self.len())
            .filter(|&p| !(is_moved[self.i[p] as usize] || is_moved[self.j[p] as usize]))
            .map(|p| (self.i[p], self.j[p], self.image[p]))
            .collect();
        // A moved particle finds its smaller partners as a full build does (its own images too), and
        // its larger ones unless they moved as well: those find the pair from their side.
        let search = |c: usize| {
            let mut out: Vec<(u32, u32, Image)> = Vec::new();
            let mut steps = Steps::default();
            for &i in &moved[c * CHUNK..((c + 1) * CHUNK).min(moved.len())] {
                let i = i as usize;
                binned.smaller_partners(i, pos, radius, bx, range, skin, &mut steps, |j, img| {
                    out.push(ordered(i, j, img))
                });
                binned.larger_partners(i, pos, radius, bx, range, skin, &mut steps, |j, img| {
                    if !is_moved[j] {
                        out.push(ordered(i, j, img))
                    }
                });
            }
            out
        };
        let mut found = in_chunks(moved.len(), parallel, search);
        found.push(kept);
        self.assemble(n, &found, parallel);
        for &k in moved {
            self.ref_pos[k as usize] = pos[k as usize];
        }
        self.mixed = true;
        self.builds += 1;
        self.local_builds += 1;
        Ok(())
    }
}
