//! The force phase. Particles are cut into fixed blocks; each block walks its rows and adds every pair
//! that stays inside the block straight into both particles' sums, parking only the pairs that reach
//! into a later block, which are added afterwards per particle in pair order. Blocks are the same for
//! any thread count and every sum happens in the same order, so one thread and many give bit-identical
//! results, while almost all pairs avoid the per-pair buffer. Energies are summed block by block in
//! block order.

use nalgebra::Matrix3;
use rayon::prelude::*;

use super::cohesive::{pair, PairEnergy, PairInput, PairOut};
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
    pub out: Vec<PairOut>,
    pub force: Vec<Vec3>,
    pub torque: Vec<Vec3>,
    /// Per-particle virial sum_j 1/2 (x_i - x_j) (x) F_ij (filled when requested).
    pub virial: Vec<Matrix3<f64>>,
    kin: Vec<Kin>,
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
    fn add(&mut self, e: &PairEnergy) {
        self.normal += e.normal;
        self.tangential += e.tangential;
        self.damping_power += e.damping_power;
        self.slid += e.slid;
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
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Kin {
    x: Vec3,
    v: Vec3,
    w: Vec3,
    r: f64,
    m: f64,
}

/// One block's share of the mutable arrays: its pairs' history and parked outputs, its particles' sums.
struct BlockTask<'a> {
    b: usize,
    hist: &'a mut [Vec3],
    out: &'a mut [PairOut],
    f: &'a mut [Vec3],
    t: &'a mut [Vec3],
    w: Option<&'a mut [Matrix3<f64>]>,
}

/// Read-only inputs of the pair loop.
struct Ctx<'a> {
    coef: &'a PairCoefficients,
    kin: &'a [Kin],
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

    #[inline(always)]
    fn eval<const T: bool>(
        &self,
        ki: &Kin,
        kj: &Kin,
        d: Vec3,
        hist: &mut Vec3,
    ) -> (PairOut, PairEnergy) {
        let inp = PairInput {
            d,
            dv: ki.v - kj.v,
            wi: ki.w,
            wj: kj.w,
            ri: ki.r,
            rj: kj.r,
            mi: ki.m,
            mj: kj.m,
        };
        pair::<T>(self.coef, &inp, hist, self.dt)
    }
}

impl ForceBuffers {
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
        let mut kin = std::mem::take(&mut self.kin);
        kin.resize(n, Kin::default());
        for (i, k) in kin.iter_mut().enumerate() {
            *k = Kin {
                x: parts.pos[i],
                v: parts.vel[i],
                w: parts.omega[i],
                r: parts.radius[i],
                m: parts.mass[i],
            };
        }
        let ctx = Ctx {
            coef,
            kin: &kin,
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
        self.out.resize(list.len(), PairOut::default());
        self.force.iter_mut().for_each(|f| *f = Vec3::zeros());
        self.torque.iter_mut().for_each(|t| *t = Vec3::zeros());
        if phase.virial {
            self.virial.iter_mut().for_each(|w| *w = Matrix3::zeros());
        } else {
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
        let (lj, limg, rows) = (&list.j, &list.image, &list.row_start);
        let run = |BlockTask {
                       b,
                       hist,
                       out,
                       f,
                       t,
                       mut w,
                   }: BlockTask<'_>| {
            let (k0, k1) = (b * BLOCK, ((b + 1) * BLOCK).min(n));
            let p0 = rows[k0] as usize;
            let mut totals = PairEnergyTotals::default();
            for i in k0..k1 {
                let ki = ctx.kin[i];
                let (mut fi, mut ti) = (f[i - k0], t[i - k0]);
                for p in rows[i] as usize..rows[i + 1] as usize {
                    let j = lj[p] as usize;
                    let d = ctx.separation(i, j, limg[p]);
                    let (o, e) = ctx.eval::<T>(&ki, &ctx.kin[j], d, &mut hist[p - p0]);
                    fi += o.f;
                    ti += o.ai * o.nxf;
                    if j == i {
                        fi -= o.f;
                        ti += o.aj * o.nxf;
                    } else if j < k1 {
                        f[j - k0] -= o.f;
                        t[j - k0] += o.aj * o.nxf;
                    } else {
                        out[p - p0] = o;
                    }
                    if let Some(w) = w.as_deref_mut() {
                        let wp = -0.5 * d * o.f.transpose();
                        w[i - k0] += wp;
                        if j < k1 {
                            w[j - k0] += wp;
                        }
                    }
                    if E {
                        totals.add(&e);
                    }
                }
                f[i - k0] = fi;
                t[i - k0] = ti;
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
        let out = &self.out;
        let parked = |k: usize| {
            let k0 = (k / BLOCK) * BLOCK;
            list.rev_pair[list.rev_start[k] as usize..list.rev_start[k + 1] as usize]
                .iter()
                .map(|&p| p as usize)
                .filter(move |&p| (list.i[p] as usize) < k0)
        };
        let run = |c: usize, f: &mut [Vec3], t: &mut [Vec3], w: Option<&mut [Matrix3<f64>]>| {
            let mut w = w;
            for k in 0..f.len() {
                let kk = c * BLOCK + k;
                for p in parked(kk) {
                    let o = &out[p];
                    f[k] -= o.f;
                    t[k] += o.aj * o.nxf;
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
