//! The force phase: pairs in parallel into a per-pair buffer, then a per-particle gather in fixed order.

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

/// Scratch reused from step to step (sized once per neighbour-list build, never in the force loop).
#[derive(Debug, Clone, Default)]
pub(crate) struct ForceBuffers {
    pub out: Vec<PairOut>,
    pub energy: Vec<PairEnergy>,
    pub force: Vec<Vec3>,
    pub torque: Vec<Vec3>,
    /// Per-particle virial sum_j 1/2 (x_i - x_j) (x) F_ij (filled when requested).
    pub virial: Vec<Matrix3<f64>>,
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

impl ForceBuffers {
    /// Evaluates all pairs and gathers forces, torques (and optionally energies and virials).
    pub fn compute(
        &mut self,
        phase: ForcePhase,
        coef: &PairCoefficients,
        parts: &Particles,
        bx: &SimBox,
        list: &mut NeighborList,
        dt: f64,
    ) -> PairEnergyTotals {
        let np = list.len();
        let n = parts.len();
        self.out.resize(np, PairOut::default());
        self.force.resize(n, Vec3::zeros());
        self.torque.resize(n, Vec3::zeros());
        if phase.energy {
            self.energy.resize(np, PairEnergy::default());
        }
        {
            let _s = tracing::trace_span!("pairs", np).entered();
            match (coef.tangential, phase.energy) {
                (true, true) => self.pairs::<true, true>(phase.parallel, coef, parts, bx, list, dt),
                (true, false) => {
                    self.pairs::<true, false>(phase.parallel, coef, parts, bx, list, dt)
                }
                (false, true) => {
                    self.pairs::<false, true>(phase.parallel, coef, parts, bx, list, dt)
                }
                (false, false) => {
                    self.pairs::<false, false>(phase.parallel, coef, parts, bx, list, dt)
                }
            }
        }
        {
            let _s = tracing::trace_span!("gather", n).entered();
            self.gather(phase.parallel, list);
            if phase.virial {
                self.gather_virial(phase.parallel, parts, bx, list);
            }
        }
        if phase.energy {
            self.energy_totals()
        } else {
            PairEnergyTotals::default()
        }
    }

    fn pairs<const T: bool, const E: bool>(
        &mut self,
        parallel: bool,
        coef: &PairCoefficients,
        parts: &Particles,
        bx: &SimBox,
        list: &mut NeighborList,
        dt: f64,
    ) {
        let (li, lj, limg) = (&list.i, &list.j, &list.image);
        let run = |start: usize, out: &mut [PairOut], hist: &mut [Vec3], en: &mut [PairEnergy]| {
            for k in 0..out.len() {
                let p = start + k;
                let (i, j) = (li[p] as usize, lj[p] as usize);
                let inp = PairInput {
                    d: parts.pos[j] + bx.shift(limg[p]) - parts.pos[i],
                    dv: parts.vel[i] - parts.vel[j],
                    wi: parts.omega[i],
                    wj: parts.omega[j],
                    ri: parts.radius[i],
                    rj: parts.radius[j],
                    mi: parts.mass[i],
                    mj: parts.mass[j],
                };
                let (o, e) = pair::<T>(coef, &inp, &mut hist[k], dt);
                out[k] = o;
                if E {
                    en[k] = e;
                }
            }
        };
        let en: &mut [PairEnergy] = if E { &mut self.energy } else { &mut [] };
        if parallel {
            if E {
                self.out
                    .par_chunks_mut(PAIR_CHUNK)
                    .zip(list.hist.par_chunks_mut(PAIR_CHUNK))
                    .zip(en.par_chunks_mut(PAIR_CHUNK))
                    .enumerate()
                    .for_each(|(c, ((o, h), e))| run(c * PAIR_CHUNK, o, h, e));
            } else {
                self.out
                    .par_chunks_mut(PAIR_CHUNK)
                    .zip(list.hist.par_chunks_mut(PAIR_CHUNK))
                    .enumerate()
                    .for_each(|(c, (o, h))| run(c * PAIR_CHUNK, o, h, &mut []));
            }
        } else {
            run(0, &mut self.out, &mut list.hist, en);
        }
    }

    fn gather(&mut self, parallel: bool, list: &NeighborList) {
        let out = &self.out;
        let run = |start: usize, f: &mut [Vec3], t: &mut [Vec3]| {
            for k in 0..f.len() {
                let i = start + k;
                let mut fi = Vec3::zeros();
                let mut ti = Vec3::zeros();
                for o in &out[list.row_start[i] as usize..list.row_start[i + 1] as usize] {
                    fi += o.f;
                    ti += o.ai * o.nxf;
                }
                for &p in &list.rev_pair[list.rev_start[i] as usize..list.rev_start[i + 1] as usize]
                {
                    let o = &out[p as usize];
                    fi -= o.f;
                    ti += o.aj * o.nxf;
                }
                f[k] = fi;
                t[k] = ti;
            }
        };
        if parallel {
            self.force
                .par_chunks_mut(PARTICLE_CHUNK)
                .zip(self.torque.par_chunks_mut(PARTICLE_CHUNK))
                .enumerate()
                .for_each(|(c, (f, t))| run(c * PARTICLE_CHUNK, f, t));
        } else {
            run(0, &mut self.force, &mut self.torque);
        }
    }

    fn gather_virial(
        &mut self,
        parallel: bool,
        parts: &Particles,
        bx: &SimBox,
        list: &NeighborList,
    ) {
        let n = parts.len();
        self.virial.resize(n, Matrix3::zeros());
        let out = &self.out;
        // Half of the pair virial (x_i - x_j) (x) F_i = -d (x) f to each partner.
        let half_pair = |p: usize| -> Matrix3<f64> {
            let (i, j) = (list.i[p] as usize, list.j[p] as usize);
            let d = parts.pos[j] + bx.shift(list.image[p]) - parts.pos[i];
            -0.5 * d * out[p].f.transpose()
        };
        let run = |start: usize, w: &mut [Matrix3<f64>]| {
            for k in 0..w.len() {
                let i = start + k;
                let mut acc = Matrix3::zeros();
                for p in list.row_start[i] as usize..list.row_start[i + 1] as usize {
                    acc += half_pair(p);
                }
                for &p in &list.rev_pair[list.rev_start[i] as usize..list.rev_start[i + 1] as usize]
                {
                    acc += half_pair(p as usize);
                }
                w[k] = acc;
            }
        };
        if parallel {
            self.virial
                .par_chunks_mut(PARTICLE_CHUNK)
                .enumerate()
                .for_each(|(c, w)| run(c * PARTICLE_CHUNK, w));
        } else {
            run(0, &mut self.virial);
        }
    }

    /// Deterministic sum: fixed chunks summed in order, whatever the thread count.
    fn energy_totals(&self) -> PairEnergyTotals {
        let mut t = PairEnergyTotals::default();
        for e in &self.energy {
            t.normal += e.normal;
            t.tangential += e.tangential;
            t.damping_power += e.damping_power;
            t.slid += e.slid;
        }
        t
    }
}
