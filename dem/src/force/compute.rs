//! The force phase. Particles are cut into blocks ([`block_bounds`]: fixed blocks of 2 048 in large
//! systems, four blocks of equal pair counts in small ones); each block walks its pairs in order and
//! evaluates them in batches of `LANES` (see [`super::cohesive::Batch`]). Blocks run in two colours
//! (even, then odd): while its colour runs, block `b` owns the sums of blocks `b` and `b + 1`, so a
//! pair whose second particle lies in either adds straight into both particles' sums; only pairs
//! reaching two blocks or more ahead park their output, added afterwards per particle in pair order.
//! Blocks and colours are the same for any thread count and every sum happens in the same order, so
//! one thread and many give bit-identical results. Energies combine block by block along a fixed tree.

use nalgebra::Matrix3;
use rayon::prelude::*;

use super::cohesive::Batch;
use super::pair_consts::{PairConst, PairConstArrays, LANES};
use crate::domain::SimBox;
use crate::history::HistoryMut;
use crate::material::PairCoefficients;
use crate::neighbor::NeighborList;
use crate::state::Particles;
use crate::Vec3;

/// Particles per block in systems of at least `4 BLOCK` particles: a block's pairs mostly stay inside
/// it or reach the next one (rows of neighbours in memory), and a 50 000-particle system still splits
/// into ~25 tasks for the cores.
const BLOCK: usize = 2048;

/// Blocks of a smaller system: cut at equal pair counts. Four blocks make two units per colour, so
/// two threads get equal halves of each colour; with 2 048-particle blocks a system below ~6 000
/// particles had one or two units per colour and ran on one core (issue 21). More blocks would let
/// more threads in but park more pairs (see [`block_bounds`]).
const SMALL_BLOCKS: usize = 4;

/// Where the blocks start, from the particle count and the list's rows alone: the same blocks, hence
/// the same order of every sum, for any thread count (which must not enter here: with blocks cut per
/// thread count, 1 and 2 threads would add the same terms in different orders and drift apart).
///
/// - From `4 BLOCK` particles on, fixed blocks of `BLOCK` (the decomposition of large systems,
///   unchanged).
/// - Below, `SMALL_BLOCKS` blocks of equal pair counts (a block's work is its pairs; in a wide size
///   distribution the large particles' rows are long). A pair reaching two blocks or more ahead is
///   parked (a per-pair store and a gather instead of a direct sum); with a quarter of the system per
///   block that stays rare in space order: in the bench's amorphous sample 90 % of the pairs reach
///   fewer than 800 particles ahead (blocks of ~1 600), in a 1 152-sphere HCP packing all reach at
///   most 157 (blocks of 288).
/// - Systems of fewer than `8 SMALL_BLOCKS` particles are one block.
fn block_bounds(n: usize, row_start: &[u32], out: &mut Vec<usize>) {
    out.clear();
    if n >= 4 * BLOCK {
        out.extend((0..n.div_ceil(BLOCK)).map(|b| b * BLOCK));
    } else if n >= 8 * SMALL_BLOCKS {
        let pairs = row_start[n] as u64;
        // Block b starts at the first particle whose row starts at or after b / SMALL_BLOCKS of the
        // pairs (a partition point of the increasing row starts), so blocks never overlap.
        out.push(0);
        for b in 1..SMALL_BLOCKS {
            let target = pairs * b as u64 / SMALL_BLOCKS as u64;
            let k = row_start[..n].partition_point(|&s| (s as u64) < target);
            out.push(k.max(*out.last().unwrap_or(&0)));
        }
    } else {
        out.push(0);
    }
    out.push(n);
}

/// Particles per task of the parked-pair gather.
const GATHER_CHUNK: usize = 512;

/// Scratch reused from step to step (resized only when the neighbour list changes size).
#[derive(Debug, Clone, Default)]
pub(crate) struct ForceBuffers {
    /// Outputs of the pairs that reach two blocks or more ahead, indexed by pair (other entries unused).
    out: Vec<Parked>,
    pub force: Vec<Vec3>,
    pub torque: Vec<Vec3>,
    /// Per-particle virial sum_j 1/2 (x_i - x_j) (x) F_ij (filled when requested).
    pub virial: Vec<Matrix3<f64>>,
    kin: Vec<Kin>,
    /// Per-pair constants, parallel to the neighbour list.
    consts: PairConstArrays,
    /// Per-pair periodic image as an index into the step's table of 27 shifts (see [`image_code`]):
    /// one byte read per pair and no conversion or multiplication in the pair loop.
    image_code: Vec<u8>,
    /// `parked_pair[parked_start[k]..parked_start[k + 1]]`: the pairs (j = k) whose first particle lies
    /// two blocks or more before k's, in pair order.
    parked_start: Vec<u32>,
    parked_pair: Vec<u32>,
    /// The particles that have parked pairs, ascending, and where each gather chunk's particles begin
    /// in that list: the gather visits these only (558 of the amorphous bench's 6 317 particles).
    parked_rows: Vec<u32>,
    parked_chunk: Vec<u32>,
    /// First particle of each block, then the particle count (see [`block_bounds`]).
    bounds: Vec<usize>,
    /// The neighbour-list build the constants, blocks and parked lists belong to (None: stale).
    built_for: Option<u64>,
}

/// The force phase's outputs as the integrator takes them (see [`ForceBuffers::for_integrator`]).
pub(crate) struct IntegratorView<'a> {
    pub force: &'a [Vec3],
    pub torque: &'a [Vec3],
    /// The kinematics records, for the integrator to write.
    pub kin: &'a mut [Kin],
}

/// What a pair reaching two blocks or more ahead leaves for its second particle.
#[derive(Debug, Clone, Copy, Default)]
struct Parked {
    /// Force on i (j receives its opposite).
    f: Vec3,
    /// Torque on j.
    tj: Vec3,
}

/// Sums of the per-pair energy terms of one evaluation.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct PairEnergyTotals {
    pub normal: f64,
    pub tangential: f64,
    pub damping_power: f64,
    pub slid: f64,
}

impl PairEnergyTotals {
    fn then(self, b: &PairEnergyTotals) -> PairEnergyTotals {
        PairEnergyTotals {
            normal: self.normal + b.normal,
            tangential: self.tangential + b.tangential,
            damping_power: self.damping_power + b.damping_power,
            slid: self.slid + b.slid,
        }
    }
}

/// What to compute besides forces and torques.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ForcePhase {
    pub energy: bool,
    pub virial: bool,
    pub parallel: bool,
}

/// Kinematics of one particle, gathered once per step so that a pair reads its partner from one place.
/// The integrator writes them as it updates each particle (see [`ForceBuffers::for_integrator`]);
/// the force phase gathers them itself only when something else moved the particles since.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Kin {
    pub x: Vec3,
    pub v: Vec3,
    pub w: Vec3,
}

/// The read-only pair arrays of the neighbour list, and the particle count.
struct Pairs<'a> {
    i: &'a [u32],
    j: &'a [u32],
    image: &'a [u8],
    row_start: &'a [u32],
    /// First particle of each block, then the particle count.
    bounds: &'a [usize],
}

impl Pairs<'_> {
    /// First particle of block `b` (or the particle count past the end).
    fn block_start(&self, b: usize) -> usize {
        self.bounds[b.min(self.bounds.len() - 1)]
    }
}

/// A run of units of one colour and the tails of the mutable arrays from the span's first block on.
/// Unit `u` of colour `c` is block `2 u + c`, which owns the sums of blocks `2 u + c` and
/// `2 u + c + 1` while its colour runs. Spans split in halves (rayon::join when parallel), so no task
/// list is allocated per step; the energy totals combine along the same fixed tree for any thread count.
struct Span<'a> {
    units: std::ops::Range<usize>,
    colour: usize,
    hist: HistoryMut<'a>,
    out: &'a mut [Parked],
    f: &'a mut [Vec3],
    t: &'a mut [Vec3],
    w: Option<&'a mut [Matrix3<f64>]>,
}

impl<'a> Span<'a> {
    fn first_block(&self, u: usize) -> usize {
        2 * u + self.colour
    }

    fn run<const T: bool, const E: bool>(
        self,
        ctx: &Ctx,
        pairs: &Pairs,
        parallel: bool,
    ) -> PairEnergyTotals {
        match self.units.len() {
            0 => PairEnergyTotals::default(),
            1 => self.block::<T, E>(ctx, pairs),
            len => {
                let mid = self.units.start + len / 2;
                let (left, right) = self.split(mid, pairs);
                let (a, b) = if parallel {
                    rayon::join(
                        || left.run::<T, E>(ctx, pairs, true),
                        || right.run::<T, E>(ctx, pairs, true),
                    )
                } else {
                    (
                        left.run::<T, E>(ctx, pairs, false),
                        right.run::<T, E>(ctx, pairs, false),
                    )
                };
                a.then(&b)
            }
        }
    }

    /// Splits before unit `mid`.
    fn split(self, mid: usize, pairs: &Pairs) -> (Span<'a>, Span<'a>) {
        let k0 = pairs.block_start(self.first_block(self.units.start));
        let km = pairs.block_start(self.first_block(mid));
        let pm = (pairs.row_start[km] - pairs.row_start[k0]) as usize;
        let (h0, h1) = self.hist.split_at_mut(pm);
        let (o0, o1) = self.out.split_at_mut(pm);
        let (f0, f1) = self.f.split_at_mut(km - k0);
        let (t0, t1) = self.t.split_at_mut(km - k0);
        let (w0, w1) = match self.w {
            Some(w) => {
                let (a, b) = w.split_at_mut(km - k0);
                (Some(a), Some(b))
            }
            None => (None, None),
        };
        let colour = self.colour;
        (
            Span {
                units: self.units.start..mid,
                colour,
                hist: h0,
                out: o0,
                f: f0,
                t: t0,
                w: w0,
            },
            Span {
                units: mid..self.units.end,
                colour,
                hist: h1,
                out: o1,
                f: f1,
                t: t1,
                w: w1,
            },
        )
    }

    /// One block: its rows in pair order, batched `LANES` pairs at a time across rows. A pair adds to
    /// its first particle and, when the second lies in this block or the next, to the second too;
    /// otherwise it parks the second's share in `out`.
    fn block<const T: bool, const E: bool>(self, ctx: &Ctx, pairs: &Pairs) -> PairEnergyTotals {
        let b = self.first_block(self.units.start);
        let zero_sums = self.colour == 0;
        let Span {
            mut hist,
            out,
            f,
            t,
            mut w,
            ..
        } = self;
        let (k0, k1) = (pairs.block_start(b), pairs.block_start(b + 1));
        // This span's slices end where the next unit starts: two blocks on (or the last particle).
        let owned = f.len();
        if zero_sums {
            f.fill(Vec3::zeros());
            t.fill(Vec3::zeros());
            if let Some(w) = w.as_deref_mut() {
                w.fill(Matrix3::zeros());
            }
        }
        let (li, lj, limg) = (pairs.i, pairs.j, pairs.image);
        let (p0, p1) = (pairs.row_start[k0] as usize, pairs.row_start[k1] as usize);
        let mut totals = PairEnergyTotals::default();
        let mut lanes = Batch::default();
        // The batch's particles relative to k0 (j - k0 >= f.len() for a parked pair), kept from the
        // loads for the sums.
        let mut local = [(0usize, 0usize); LANES];
        let mut p = p0;
        // The first particle's terms are summed in registers along its row (consecutive pairs) and
        // added to its sum once per row: no store-to-load chain through memory per pair.
        let (mut row, mut fi, mut ti) = (usize::MAX, Vec3::zeros(), Vec3::zeros());
        while p < p1 {
            let len = (p1 - p).min(LANES);
            for l in 0..len {
                let q = p + l;
                let (i, j) = (li[q] as usize, lj[q] as usize);
                local[l] = (i - k0, j - k0);
                let (ki, kj) = (&ctx.kin[i], &ctx.kin[j]);
                let d = ctx.separation(i, j, limg[q]);
                let dv = ki.v - kj.v;
                for a in 0..3 {
                    lanes.d[a][l] = d[a];
                    lanes.dv[a][l] = dv[a];
                    lanes.wi[a][l] = ki.w[a];
                    lanes.wj[a][l] = kj.w[a];
                }
            }
            hist.load(p - p0, len, &mut lanes.h);
            if p == p0 || !ctx.consts.is_uniform() {
                lanes.load_consts(&ctx.consts.window(p));
            }
            lanes.evaluate_loaded::<T, E>(ctx.dt);
            hist.store(p - p0, len, &lanes.h);
            for (l, &(i, j)) in local[..len].iter().enumerate() {
                let v3 = |a: &[[f64; LANES]; 3]| Vec3::new(a[0][l], a[1][l], a[2][l]);
                let (fp, tip, tjp) = (v3(&lanes.f), v3(&lanes.ti), v3(&lanes.tj));
                let direct = j < owned;
                if i != row {
                    if row != usize::MAX {
                        f[row] += fi;
                        t[row] += ti;
                    }
                    (row, fi, ti) = (i, fp, tip);
                } else {
                    fi += fp;
                    ti += tip;
                }
                if direct {
                    f[j] -= fp;
                    t[j] += tjp;
                } else {
                    out[p + l - p0] = Parked { f: fp, tj: tjp };
                }
                if let Some(w) = w.as_deref_mut() {
                    let wp = -0.5 * v3(&lanes.d) * fp.transpose();
                    w[i] += wp;
                    if direct {
                        w[j] += wp;
                    }
                }
                if E {
                    totals.normal += lanes.e_normal[l];
                    totals.tangential += lanes.e_tangential[l];
                    totals.damping_power += lanes.damping_power[l];
                    totals.slid += lanes.slid[l];
                }
            }
            p += len;
        }
        if row != usize::MAX {
            f[row] += fi;
            t[row] += ti;
        }
        totals
    }
}

/// Read-only inputs of the pair loop.
struct Ctx<'a> {
    kin: &'a [Kin],
    consts: &'a PairConstArrays,
    /// The periodic shift of each image code, for this step's box.
    shifts: [Vec3; 27],
    dt: f64,
}

impl Ctx<'_> {
    /// x_j + image L - x_i.
    #[inline(always)]
    fn separation(&self, i: usize, j: usize, image_code: u8) -> Vec3 {
        self.kin[j].x + self.shifts[image_code as usize] - self.kin[i].x
    }
}

/// Index of an image with components in {-1, 0, 1} (all the neighbour list makes, see
/// [`NeighborList::check`]) in the table of [`shift_table`].
fn image_code(s: [i8; 3]) -> u8 {
    (13 + 9 * s[2] + 3 * s[1] + s[0]) as u8
}

/// The shift image L of every image code: the same products the pair loop computed per pair
/// before, so the separations are unchanged to the bit.
fn shift_table(bx: &SimBox) -> [Vec3; 27] {
    std::array::from_fn(|c| {
        let c = c as i8;
        bx.shift([c % 3 - 1, c / 3 % 3 - 1, c / 9 - 1])
    })
}

impl ForceBuffers {
    /// What the integrator takes from the force phase: the forces and torques, and the kinematics
    /// records of `n` particles to write as it advances them, so that a step whose particles nothing
    /// moved after that skips the records' gather (`kin_fresh` of [`ForceBuffers::compute`]): one
    /// pass and one join fewer.
    pub fn for_integrator(&mut self, n: usize) -> IntegratorView<'_> {
        self.kin.resize(n, Kin::default());
        IntegratorView {
            force: &self.force,
            torque: &self.torque,
            kin: &mut self.kin,
        }
    }

    /// Marks the per-pair constants stale (after a change of particles, model or groups).
    pub fn invalidate(&mut self) {
        self.built_for = None;
    }

    /// Recomputes the per-pair constants and the parked lists when the neighbour list was rebuilt or
    /// they were invalidated. Element-wise and in pair order: deterministic for any thread count.
    fn refresh(&mut self, coef: &PairCoefficients, parts: &Particles, list: &NeighborList) {
        if self.built_for == Some(list.builds) && self.consts.len() == list.len() {
            return;
        }
        let _s = tracing::trace_span!("pair_constants").entered();
        let (radius, mass) = (&parts.radius, &parts.mass);
        self.consts.fill(coef, list.len(), |k| {
            let (i, j) = (list.i[k] as usize, list.j[k] as usize);
            PairConst::new(coef, radius[i], radius[j], mass[i], mass[j])
        });
        self.image_code.clear();
        self.image_code
            .extend(list.image.iter().map(|&s| image_code(s)));
        let n = parts.len();
        block_bounds(n, &list.row_start, &mut self.bounds);
        self.parked_start.clear();
        self.parked_pair.clear();
        self.parked_start.push(0);
        for b in 0..self.bounds.len() - 1 {
            // Pairs from this block and the one before are added directly (see `blocked`).
            let before = self.bounds[b.saturating_sub(1)];
            for k in self.bounds[b]..self.bounds[b + 1] {
                let rev =
                    &list.rev_pair[list.rev_start[k] as usize..list.rev_start[k + 1] as usize];
                self.parked_pair.extend(
                    rev.iter()
                        .filter(|&&p| (list.i[p as usize] as usize) < before),
                );
                self.parked_start.push(self.parked_pair.len() as u32);
            }
        }
        self.parked_rows.clear();
        self.parked_chunk.clear();
        for k in 0..n {
            if k % GATHER_CHUNK == 0 {
                self.parked_chunk.push(self.parked_rows.len() as u32);
            }
            if self.parked_start[k] < self.parked_start[k + 1] {
                self.parked_rows.push(k as u32);
            }
        }
        self.parked_chunk.push(self.parked_rows.len() as u32);
        self.built_for = Some(list.builds);
    }

    /// Evaluates all pairs and sums forces, torques (and optionally energies and virials). With
    /// `kin_fresh`, the kinematics records already hold `parts`' state (the integrator wrote them and
    /// nothing moved the particles since), so they are not gathered again.
    #[allow(clippy::too_many_arguments)]
    pub fn compute(
        &mut self,
        phase: ForcePhase,
        coef: &PairCoefficients,
        parts: &Particles,
        bx: &SimBox,
        list: &mut NeighborList,
        dt: f64,
        kin_fresh: bool,
    ) -> PairEnergyTotals {
        let n = parts.len();
        self.force.resize(n, Vec3::zeros());
        self.torque.resize(n, Vec3::zeros());
        if phase.virial {
            self.virial.resize(n, Matrix3::zeros());
        }
        self.refresh(coef, parts, list);
        let mut kin = std::mem::take(&mut self.kin);
        let kin_fresh = kin_fresh && kin.len() == n;
        kin.resize(n, Kin::default());
        // Copies (no sums): any chunking gives the same records.
        const KIN_CHUNK: usize = 512;
        let fill = |(c, ks): (usize, &mut [Kin])| {
            let at = c * KIN_CHUNK..c * KIN_CHUNK + ks.len();
            let (x, v, w) = (
                &parts.pos[at.clone()],
                &parts.vel[at.clone()],
                &parts.omega[at],
            );
            // Field by field: a whole `Kin` built first went through the stack and stalled on
            // store forwarding (4 % of a step on the amorphous workload).
            for (k, slot) in ks.iter_mut().enumerate() {
                slot.x = x[k];
                slot.v = v[k];
                slot.w = w[k];
            }
        };
        if kin_fresh {
            debug_assert!((0..n).all(|k| kin[k].x == parts.pos[k]
                && kin[k].v == parts.vel[k]
                && kin[k].w == parts.omega[k]));
        } else if phase.parallel {
            kin.par_chunks_mut(KIN_CHUNK).enumerate().for_each(fill);
        } else {
            kin.chunks_mut(KIN_CHUNK).enumerate().for_each(fill);
        }
        let consts = std::mem::take(&mut self.consts);
        let ctx = Ctx {
            kin: &kin,
            consts: &consts,
            shifts: shift_table(bx),
            dt,
        };
        let totals = {
            let _s = tracing::trace_span!("pairs", np = list.len()).entered();
            match (coef.tangential, phase.energy) {
                (true, true) => self.blocked::<true, true>(&ctx, list, phase),
                (true, false) => self.blocked::<true, false>(&ctx, list, phase),
                (false, true) => self.blocked::<false, true>(&ctx, list, phase),
                (false, false) => self.blocked::<false, false>(&ctx, list, phase),
            }
        };
        self.kin = kin;
        self.consts = consts;
        totals
    }

    /// The pair loop over the blocks of [`block_bounds`] (the same blocks for any thread count), in
    /// two colours. A block's pairs reach its own particles and, in a packing stored in space order,
    /// the next block's: so block `b` writes straight into the sums of blocks `b` and `b + 1`. Colour 0
    /// runs the even blocks (each owning the slice of blocks `b, b + 1`, which it zeroes first), colour
    /// 1 the odd ones, each colour's blocks in parallel; only the rare pairs reaching two blocks or more
    /// ahead are parked and added per particle afterwards. Every particle therefore receives its terms
    /// in one fixed order (its even block's, then its odd block's, then parked ones, each in pair order),
    /// whether the blocks run on one thread or many: bit-identical results.
    fn blocked<const T: bool, const E: bool>(
        &mut self,
        ctx: &Ctx,
        list: &mut NeighborList,
        phase: ForcePhase,
    ) -> PairEnergyTotals {
        self.out.resize(list.len(), Parked::default());
        if !phase.virial {
            self.virial.clear();
        }
        let nb = self.bounds.len() - 1;
        let pairs = Pairs {
            i: &list.i,
            j: &list.j,
            image: &self.image_code,
            row_start: &list.row_start,
            bounds: &self.bounds,
        };
        let mut totals = PairEnergyTotals::default();
        for colour in 0..2 {
            let k0 = pairs.block_start(colour);
            let p0 = list.row_start[k0] as usize;
            let w = (!self.virial.is_empty()).then(|| &mut self.virial[k0..]);
            let span = Span {
                units: 0..(nb + 1 - colour) / 2,
                colour,
                hist: list.hist.tail_mut(p0),
                out: &mut self.out[p0..],
                f: &mut self.force[k0..],
                t: &mut self.torque[k0..],
                w,
            };
            let part = span.run::<T, E>(ctx, &pairs, phase.parallel);
            totals = totals.then(&part);
        }
        // Added per particle in a pass of its own: folded into the integrator's pass (which visits
        // every particle anyway) it cost 5 % at two threads on both bench workloads (the scattered
        // loads stall the streaming update; docs/performance.md, 8 Dec).
        if !self.parked_pair.is_empty() {
            let _g = tracing::trace_span!("gather").entered();
            self.gather_parked(ctx, list, phase);
        }
        totals
    }

    /// Afterwards: each particle adds the outputs parked by pairs of blocks two or more before its own,
    /// in pair order (none in a packing stored in space order, whose pairs reach at most one block on).
    fn gather_parked(&mut self, ctx: &Ctx, list: &NeighborList, phase: ForcePhase) {
        let (out, start, parked) = (&self.out, &self.parked_start, &self.parked_pair);
        let codes = &self.image_code;
        let add = |kk: usize, f: &mut Vec3, t: &mut Vec3, mut w: Option<&mut Matrix3<f64>>| {
            for &p in &parked[start[kk] as usize..start[kk + 1] as usize] {
                let p = p as usize;
                let o = &out[p];
                *f -= o.f;
                *t += o.tj;
                if let Some(w) = w.as_deref_mut() {
                    let d = ctx.separation(list.i[p] as usize, kk, codes[p]);
                    *w += -0.5 * d * o.f.transpose();
                }
            }
        };
        // Per chunk of particles, each visiting only its particles with parked pairs (in space order
        // few have any, but for the periodic images). Each particle's sum is its own: any chunking
        // adds the same terms in the same order.
        const CHUNK: usize = GATHER_CHUNK;
        let (rows, chunk) = (&self.parked_rows, &self.parked_chunk);
        let block =
            |c: usize, f: &mut [Vec3], t: &mut [Vec3], mut w: Option<&mut [Matrix3<f64>]>| {
                let k0 = c * CHUNK;
                for &kk in &rows[chunk[c] as usize..chunk[c + 1] as usize] {
                    let k = kk as usize - k0;
                    add(
                        kk as usize,
                        &mut f[k],
                        &mut t[k],
                        w.as_deref_mut().map(|w| &mut w[k]),
                    );
                }
            };
        let (force, torque, virial) = (&mut self.force, &mut self.torque, &mut self.virial);
        let ft = force
            .par_chunks_mut(CHUNK)
            .zip(torque.par_chunks_mut(CHUNK));
        match (phase.virial, phase.parallel) {
            (true, true) => ft
                .zip(virial.par_chunks_mut(CHUNK))
                .enumerate()
                .for_each(|(c, ((f, t), w))| block(c, f, t, Some(w))),
            (false, true) => ft.enumerate().for_each(|(c, (f, t))| block(c, f, t, None)),
            (true, false) => {
                let it = force.chunks_mut(CHUNK).zip(torque.chunks_mut(CHUNK));
                it.zip(virial.chunks_mut(CHUNK))
                    .enumerate()
                    .for_each(|(c, ((f, t), w))| block(c, f, t, Some(w)))
            }
            (false, false) => {
                let it = force.chunks_mut(CHUNK).zip(torque.chunks_mut(CHUNK));
                it.enumerate().for_each(|(c, (f, t))| block(c, f, t, None))
            }
        }
    }
}
