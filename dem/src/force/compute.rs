//! The force phase, in two interchangeable forms that produce bit-identical results:
//! - one thread: each pair is evaluated and added straight into the per-particle sums (no buffer);
//! - several threads: pairs are evaluated in parallel into a per-pair buffer, then each particle gathers
//!   its contributions in exactly the order the one-thread loop added them (increasing pair index: the
//!   pairs where it is the second particle, then its own row), so the floating-point sums are the same.
//!
//! Energies are summed in pair order in both forms.

use nalgebra::Matrix3;
use rayon::prelude::*;

use super::cohesive::{pair, PairEnergy, PairInput, PairOut};
use crate::domain::SimBox;
use crate::material::PairCoefficients;
use crate::neighbor::NeighborList;
use crate::state::Particles;
use crate::Vec3;

/// Pairs per parallel task: large enough to amortise scheduling, small enough to balance two cores.
const PAIR_CHUNK: usize = 2048;
/// Particles per parallel task in the gather.
const PARTICLE_CHUNK: usize = 1024;

/// Scratch reused from step to step (resized only when the neighbour list changes size).
#[derive(Debug, Clone, Default)]
pub(crate) struct ForceBuffers {
    pub out: Vec<PairOut>,
    pub energy: Vec<PairEnergy>,
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
            let _s =
                tracing::trace_span!("pairs", np = list.len(), parallel = phase.parallel).entered();
            match (coef.tangential, phase.parallel, phase.energy) {
                (true, false, true) => self.direct::<true, true>(&ctx, list, phase),
                (true, false, false) => self.direct::<true, false>(&ctx, list, phase),
                (false, false, true) => self.direct::<false, true>(&ctx, list, phase),
                (false, false, false) => self.direct::<false, false>(&ctx, list, phase),
                (true, true, _) => self.buffered::<true>(&ctx, list, phase),
                (false, true, _) => self.buffered::<false>(&ctx, list, phase),
            }
        };
        self.kin = kin;
        totals
    }

    /// One thread: evaluate and accumulate in pair order. Rows are walked particle by particle: the first
    /// particle's sums stay in registers for its row, which adds in the same order as pair by pair.
    fn direct<const T: bool, const E: bool>(
        &mut self,
        ctx: &Ctx,
        list: &mut NeighborList,
        phase: ForcePhase,
    ) -> PairEnergyTotals {
        self.force.iter_mut().for_each(|f| *f = Vec3::zeros());
        self.torque.iter_mut().for_each(|t| *t = Vec3::zeros());
        if phase.virial {
            self.virial.iter_mut().for_each(|w| *w = Matrix3::zeros());
        }
        let mut totals = PairEnergyTotals::default();
        let (force, torque, virial) = (&mut self.force, &mut self.torque, &mut self.virial);
        for i in 0..ctx.kin.len() {
            let (rs, re) = (list.row_start[i] as usize, list.row_start[i + 1] as usize);
            if rs == re {
                continue;
            }
            let ki = ctx.kin[i];
            let (mut fi, mut ti) = (force[i], torque[i]);
            for p in rs..re {
                let j = list.j[p] as usize;
                let d = ctx.separation(i, j, list.image[p]);
                let (o, e) = ctx.eval::<T>(&ki, &ctx.kin[j], d, &mut list.hist[p]);
                fi += o.f;
                ti += o.ai * o.nxf;
                if j == i {
                    fi -= o.f;
                    ti += o.aj * o.nxf;
                } else {
                    force[j] -= o.f;
                    torque[j] += o.aj * o.nxf;
                }
                if phase.virial {
                    let w = -0.5 * d * o.f.transpose();
                    virial[i] += w;
                    virial[j] += w;
                }
                if E {
                    totals.add(&e);
                }
            }
            force[i] = fi;
            torque[i] = ti;
        }
        totals
    }

    /// Several threads: pairs into the buffer in parallel, then the ordered gather.
    fn buffered<const T: bool>(
        &mut self,
        ctx: &Ctx,
        list: &mut NeighborList,
        phase: ForcePhase,
    ) -> PairEnergyTotals {
        let np = list.len();
        self.out.resize(np, PairOut::default());
        if phase.energy {
            self.energy.resize(np, PairEnergy::default());
        }
        {
            let (li, lj, limg) = (&list.i, &list.j, &list.image);
            let run =
                |start: usize, out: &mut [PairOut], hist: &mut [Vec3], en: &mut [PairEnergy]| {
                    for k in 0..out.len() {
                        let p = start + k;
                        let (i, j) = (li[p] as usize, lj[p] as usize);
                        let d = ctx.separation(i, j, limg[p]);
                        let (o, e) = ctx.eval::<T>(&ctx.kin[i], &ctx.kin[j], d, &mut hist[k]);
                        out[k] = o;
                        if !en.is_empty() {
                            en[k] = e;
                        }
                    }
                };
            if phase.energy {
                self.out
                    .par_chunks_mut(PAIR_CHUNK)
                    .zip(list.hist.par_chunks_mut(PAIR_CHUNK))
                    .zip(self.energy.par_chunks_mut(PAIR_CHUNK))
                    .enumerate()
                    .for_each(|(c, ((o, h), e))| run(c * PAIR_CHUNK, o, h, e));
            } else {
                self.out
                    .par_chunks_mut(PAIR_CHUNK)
                    .zip(list.hist.par_chunks_mut(PAIR_CHUNK))
                    .enumerate()
                    .for_each(|(c, (o, h))| run(c * PAIR_CHUNK, o, h, &mut []));
            }
        }
        let _g = tracing::trace_span!("gather").entered();
        self.gather(list);
        if phase.virial {
            self.gather_virial(ctx, list);
        }
        let mut totals = PairEnergyTotals::default();
        if phase.energy {
            self.energy.iter().for_each(|e| totals.add(e));
        }
        totals
    }

    /// Calls `f(pair, sign)` for every contribution to particle `k` in increasing pair order:
    /// sign -1 where `k` is the second particle, +1 where it is the first (both for a self-image pair).
    #[inline(always)]
    fn for_each_contribution(list: &NeighborList, k: usize, mut f: impl FnMut(usize, f64)) {
        let (row_s, row_e) = (list.row_start[k] as usize, list.row_start[k + 1] as usize);
        for &p in &list.rev_pair[list.rev_start[k] as usize..list.rev_start[k + 1] as usize] {
            if (p as usize) < row_s {
                f(p as usize, -1.0);
            }
        }
        for p in row_s..row_e {
            f(p, 1.0);
            if list.j[p] as usize == k {
                f(p, -1.0);
            }
        }
    }

    fn gather(&mut self, list: &NeighborList) {
        let out = &self.out;
        self.force
            .par_chunks_mut(PARTICLE_CHUNK)
            .zip(self.torque.par_chunks_mut(PARTICLE_CHUNK))
            .enumerate()
            .for_each(|(c, (f, t))| {
                for k in 0..f.len() {
                    let (mut fk, mut tk) = (Vec3::zeros(), Vec3::zeros());
                    Self::for_each_contribution(list, c * PARTICLE_CHUNK + k, |p, sign| {
                        let o = &out[p];
                        if sign > 0.0 {
                            fk += o.f;
                            tk += o.ai * o.nxf;
                        } else {
                            fk -= o.f;
                            tk += o.aj * o.nxf;
                        }
                    });
                    f[k] = fk;
                    t[k] = tk;
                }
            });
    }

    fn gather_virial(&mut self, ctx: &Ctx, list: &NeighborList) {
        let out = &self.out;
        self.virial
            .par_chunks_mut(PARTICLE_CHUNK)
            .enumerate()
            .for_each(|(c, w)| {
                for k in 0..w.len() {
                    let mut acc = Matrix3::zeros();
                    Self::for_each_contribution(list, c * PARTICLE_CHUNK + k, |p, _| {
                        let d =
                            ctx.separation(list.i[p] as usize, list.j[p] as usize, list.image[p]);
                        acc += -0.5 * d * out[p].f.transpose();
                    });
                    w[k] = acc;
                }
            });
    }
}
