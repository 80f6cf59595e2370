//! The force phase. Particles are cut into fixed blocks; each block walks its pairs in order, evaluates
//! them in batches of `LANES` (see [`super::cohesive::Batch`]), and adds every pair that stays inside
//! the block straight into both particles' sums, parking only the pairs that reach into a later block,
//! which are added afterwards per particle in pair order. Blocks are the same for
//! any thread count and every sum happens in the same order, so one thread and many give bit-identical
//! results, while almost all pairs avoid the per-pair buffer. Energies are summed block by block in
//! block order.

use nalgebra::Matrix3;
use rayon::prelude::*;

use super::cohesive::Batch;
use super::pair_consts::{PairConst, PairConstArrays, LANES};
use crate::domain::SimBox;
use crate::material::PairCoefficients;
use crate::neighbor::NeighborList;
use crate::state::Particles;
use crate::Vec3;

/// Particles per block: a block's pairs mostly stay inside it (rows of neighbours in memory), and a
/// 50 000-particle system still splits into ~25 tasks for the cores. Fixed, so results never depend on
/// the thread count.
const BLOCK: usize = 2048;

/// Scratch reused from step to step (resized only when the neighbour list changes size).
#[derive(Debug, Clone, Default)]
pub(crate) struct ForceBuffers {
    /// Outputs of the pairs that reach into a later block, indexed by pair.
    out: Vec<Parked>,
    pub force: Vec<Vec3>,
    pub torque: Vec<Vec3>,
    /// Per-particle virial sum_j 1/2 (x_i - x_j) (x) F_ij (filled when requested).
    pub virial: Vec<Matrix3<f64>>,
    kin: Vec<Kin>,
    /// Per-pair constants, parallel to the neighbour list.
    consts: PairConstArrays,
    /// `parked_pair[parked_start[k]..parked_start[k + 1]]`: the pairs (j = k) whose first particle lies
    /// in an earlier block, in pair order.
    parked_start: Vec<u32>,
    parked_pair: Vec<u32>,
    /// The neighbour-list build the constants and parked lists belong to (None: stale).
    built_for: Option<u64>,
}

/// What a pair reaching into a later block leaves for its second particle.
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

/// What to compute besides forces and torques.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ForcePhase {
    pub energy: bool,
    pub virial: bool,
    pub parallel: bool,
}

/// Kinematics of one particle, gathered once per step so that a pair reads its partner from one place.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Kin {
    x: Vec3,
    v: Vec3,
    w: Vec3,
}

/// One block's share of the mutable arrays: its pairs' history and parked outputs, its particles' sums.
struct BlockTask<'a> {
    b: usize,
    hist: &'a mut [Vec3],
    out: &'a mut [Parked],
    f: &'a mut [Vec3],
    t: &'a mut [Vec3],
    w: Option<&'a mut [Matrix3<f64>]>,
}

/// Read-only inputs of the pair loop.
struct Ctx<'a> {
    kin: &'a [Kin],
    consts: &'a PairConstArrays,
    lengths: Vec3,
    dt: f64,
}

impl Ctx<'_> {
    #[inline(always)]
    fn separation(&self, i: usize, j: usize, image: [i8; 3]) -> Vec3 {
        let s = Vec3::new(image[0] as f64, image[1] as f64, image[2] as f64)
            .component_mul(&self.lengths);
        self.kin[j].x + s - self.kin[i].x
    }
}

impl ForceBuffers {
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
        self.consts.fill(list.len(), |k| {
            let (i, j) = (list.i[k] as usize, list.j[k] as usize);
            PairConst::new(coef, radius[i], radius[j], mass[i], mass[j])
        });
        let n = parts.len();
        self.parked_start.clear();
        self.parked_pair.clear();
        self.parked_start.push(0);
        for k in 0..n {
            let k0 = (k / BLOCK) * BLOCK;
            let rev = &list.rev_pair[list.rev_start[k] as usize..list.rev_start[k + 1] as usize];
            self.parked_pair
                .extend(rev.iter().filter(|&&p| (list.i[p as usize] as usize) < k0));
            self.parked_start.push(self.parked_pair.len() as u32);
        }
        self.built_for = Some(list.builds);
    }

    /// Evaluates all pairs and sums forces, torques (and optionally energies and virials).
    pub fn compute(
        &mut self,
        phase: ForcePhase,
        coef: &PairCoefficients,
        parts: &Particles,
        bx: &SimBox,
        list: &mut NeighborList,
        dt: f64,
    ) -> PairEnergyTotals {
        let n = parts.len();
        self.force.resize(n, Vec3::zeros());
        self.torque.resize(n, Vec3::zeros());
        if phase.virial {
            self.virial.resize(n, Matrix3::zeros());
        }
        self.refresh(coef, parts, list);
        let mut kin = std::mem::take(&mut self.kin);
        kin.resize(n, Kin::default());
        let fill = |(c, ks): (usize, &mut [Kin])| {
            for (k, slot) in ks.iter_mut().enumerate() {
                let i = c * BLOCK + k;
                *slot = Kin {
                    x: parts.pos[i],
                    v: parts.vel[i],
                    w: parts.omega[i],
                };
            }
        };
        if phase.parallel {
            kin.par_chunks_mut(BLOCK).enumerate().for_each(fill);
        } else {
            kin.chunks_mut(BLOCK).enumerate().for_each(fill);
        }
        let consts = std::mem::take(&mut self.consts);
        let ctx = Ctx {
            kin: &kin,
            consts: &consts,
            lengths: bx.lengths(),
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

    /// The pair loop over fixed blocks of `BLOCK` particles (the same blocks for any thread count).
    /// Phase 1, one task per block: rows are walked in order; a pair whose second particle lies in the
    /// same block adds to both particles at once, a pair reaching into a later block adds to its first
    /// particle and parks its output in `out`. Phase 2, per particle: the parked contributions of earlier
    /// blocks are added in pair order. The sums therefore happen in the same order whether the blocks run
    /// on one thread or many: bit-identical results.
    fn blocked<const T: bool, const E: bool>(
        &mut self,
        ctx: &Ctx,
        list: &mut NeighborList,
        phase: ForcePhase,
    ) -> PairEnergyTotals {
        let n = ctx.kin.len();
        self.out.resize(list.len(), Parked::default());
        // Each block zeroes its own sums (in parallel); only phase 2 writes across blocks.
        if !phase.virial {
            self.virial.clear();
        }
        // Split the pair arrays at block boundaries (rows are contiguous per particle).
        let nb = n.div_ceil(BLOCK);
        let mut tasks = Vec::with_capacity(nb);
        {
            let (mut hist, mut out) = (&mut list.hist[..], &mut self.out[..]);
            let mut force = self.force.chunks_mut(BLOCK);
            let mut torque = self.torque.chunks_mut(BLOCK);
            let mut virial = self.virial.chunks_mut(BLOCK);
            for b in 0..nb {
                let rows = list.row_start[(b * BLOCK).min(n)] as usize
                    ..list.row_start[((b + 1) * BLOCK).min(n)] as usize;
                let (h, hr) = std::mem::take(&mut hist).split_at_mut(rows.len());
                let (o, or) = std::mem::take(&mut out).split_at_mut(rows.len());
                hist = hr;
                out = or;
                tasks.push(BlockTask {
                    b,
                    hist: h,
                    out: o,
                    f: force.next().unwrap_or_default(),
                    t: torque.next().unwrap_or_default(),
                    w: virial.next(),
                });
            }
        }
        let (li, lj, limg, rows) = (&list.i, &list.j, &list.image, &list.row_start);
        let run = |BlockTask {
                       b,
                       hist,
                       out,
                       f,
                       t,
                       mut w,
                   }: BlockTask<'_>| {
            let (k0, k1) = (b * BLOCK, ((b + 1) * BLOCK).min(n));
            let (p0, p1) = (rows[k0] as usize, rows[k1] as usize);
            f.fill(Vec3::zeros());
            t.fill(Vec3::zeros());
            if let Some(w) = w.as_deref_mut() {
                w.fill(Matrix3::zeros());
            }
            let mut totals = PairEnergyTotals::default();
            let mut lanes = Batch::default();
            let mut p = p0;
            // Batches run across rows; the sums below still happen in pair order.
            while p < p1 {
                let len = (p1 - p).min(LANES);
                for l in 0..len {
                    let q = p + l;
                    let (i, j) = (li[q] as usize, lj[q] as usize);
                    let (ki, kj) = (&ctx.kin[i], &ctx.kin[j]);
                    let d = ctx.separation(i, j, limg[q]);
                    let dv = ki.v - kj.v;
                    let h = hist[q - p0];
                    for a in 0..3 {
                        lanes.d[a][l] = d[a];
                        lanes.dv[a][l] = dv[a];
                        lanes.wi[a][l] = ki.w[a];
                        lanes.wj[a][l] = kj.w[a];
                        lanes.h[a][l] = h[a];
                    }
                }
                lanes.evaluate::<T, E>(&ctx.consts.window(p), ctx.dt);
                for l in 0..len {
                    let q = p + l;
                    let (i, j) = (li[q] as usize, lj[q] as usize);
                    let v3 = |a: &[[f64; LANES]; 3]| Vec3::new(a[0][l], a[1][l], a[2][l]);
                    let (fp, tip, tjp) = (v3(&lanes.f), v3(&lanes.ti), v3(&lanes.tj));
                    hist[q - p0] = v3(&lanes.h);
                    f[i - k0] += fp;
                    t[i - k0] += tip;
                    if j == i {
                        f[i - k0] -= fp;
                        t[i - k0] += tjp;
                    } else if j < k1 {
                        f[j - k0] -= fp;
                        t[j - k0] += tjp;
                    } else {
                        out[q - p0] = Parked { f: fp, tj: tjp };
                    }
                    if let Some(w) = w.as_deref_mut() {
                        let wp = -0.5 * v3(&lanes.d) * fp.transpose();
                        w[i - k0] += wp;
                        if j < k1 {
                            w[j - k0] += wp;
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
            totals
        };
        let partial: Vec<PairEnergyTotals> = if phase.parallel {
            tasks.into_par_iter().map(run).collect()
        } else {
            tasks.into_iter().map(run).collect()
        };
        let mut totals = PairEnergyTotals::default();
        for p in &partial {
            totals.normal += p.normal;
            totals.tangential += p.tangential;
            totals.damping_power += p.damping_power;
            totals.slid += p.slid;
        }
        let _g = tracing::trace_span!("gather").entered();
        self.gather_parked(ctx, list, phase);
        totals
    }

    /// Phase 2: each particle adds the outputs parked by pairs of earlier blocks, in pair order.
    fn gather_parked(&mut self, ctx: &Ctx, list: &NeighborList, phase: ForcePhase) {
        let (out, start, parked) = (&self.out, &self.parked_start, &self.parked_pair);
        let run = |c: usize, f: &mut [Vec3], t: &mut [Vec3], w: Option<&mut [Matrix3<f64>]>| {
            let mut w = w;
            for k in 0..f.len() {
                let kk = c * BLOCK + k;
                for &p in &parked[start[kk] as usize..start[kk + 1] as usize] {
                    let p = p as usize;
                    let o = &out[p];
                    f[k] -= o.f;
                    t[k] += o.tj;
                    if let Some(w) = w.as_deref_mut() {
                        let d = ctx.separation(list.i[p] as usize, kk, list.image[p]);
                        w[k] += -0.5 * d * o.f.transpose();
                    }
                }
            }
        };
        let virial: Vec<Option<&mut [Matrix3<f64>]>> = if phase.virial {
            self.virial.chunks_mut(BLOCK).map(Some).collect()
        } else {
            (0..self.force.len().div_ceil(BLOCK))
                .map(|_| None)
                .collect()
        };
        let tasks: Vec<_> = self
            .force
            .chunks_mut(BLOCK)
            .zip(self.torque.chunks_mut(BLOCK))
            .zip(virial)
            .enumerate()
            .collect();
        if phase.parallel {
            tasks
                .into_par_iter()
                .for_each(|(c, ((f, t), w))| run(c, f, t, w));
        } else {
            tasks
                .into_iter()
                .for_each(|(c, ((f, t), w))| run(c, f, t, w));
        }
    }
}
