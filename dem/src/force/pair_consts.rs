//! Per-pair constants of the cohesive force (paper 000 eqs 7-13 with the s-scaling of eq 10): they
//! depend only on the two radii, the two masses and the model, so they are evaluated once per
//! neighbour-list build (and after any change of particles or model) instead of at every step, which
//! takes the divisions, square roots and powers out of the pair loop. Stored as structure of arrays so
//! that a batch of `LANES` consecutive pairs loads each constant with whole-array copies.

use super::cohesive::softening_slope;
use crate::material::{PairCoefficients, PairParams};

/// Everything the kernel needs about one pair that depends only on the two radii, the two masses and
/// the model: evaluated once per neighbour-list build (and after any change of particles or model)
/// instead of at every step, which takes the divisions and square roots of eqs (7)-(13) out of the
/// pair loop.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct PairConst {
    pub p: PairParams,
    /// The two radii (constant between builds, so read from here rather than gathered per step).
    pub ri: f64,
    pub rj: f64,
    /// Square of the interaction reach r_i + r_j + delta_f.
    pub reach2: f64,
    /// k_N delta_e / (delta_f - delta_e).
    pub slope: f64,
    /// F_mT / delta_f.
    pub fmt_per_df: f64,
}

impl PairConst {
    pub fn new(coef: &PairCoefficients, ri: f64, rj: f64, mi: f64, mj: f64) -> Self {
        let (d_sum, delta_f) = coef.range(ri, rj);
        let p = coef.params_in_range(ri, rj, d_sum, delta_f, mi, mj);
        let reach = d_sum + delta_f;
        PairConst {
            p,
            ri,
            rj,
            reach2: reach * reach,
            slope: softening_slope(&p),
            fmt_per_df: if p.delta_f > 0.0 {
                p.f_mt / p.delta_f
            } else {
                0.0
            },
        }
    }
}

/// Pairs evaluated together: the kernel below is written per lane over fixed-size arrays, so that the
/// compiler turns each statement into one vector instruction over `LANES` pairs (no branches: every
/// case of eqs 3-5 is computed and selected).
pub(crate) const LANES: usize = 8;
pub(crate) type Lane = [f64; LANES];

/// Per-pair constants of a whole neighbour list as structure of arrays, padded by `LANES` zeros so
/// that a window of `LANES` pairs starting at any pair is in bounds.
#[derive(Debug, Clone, Default)]
pub(crate) struct PairConstArrays {
    /// All pairs share the constants of window 0.
    uniform: bool,
    /// Pairs held.
    len: usize,
    ri: Vec<f64>,
    rj: Vec<f64>,
    reach2: Vec<f64>,
    k_n: Vec<f64>,
    slope: Vec<f64>,
    delta_e: Vec<f64>,
    delta_f: Vec<f64>,
    k_t: Vec<f64>,
    f_mt: Vec<f64>,
    fmt_per_df: Vec<f64>,
    c_n: Vec<f64>,
    c_t: Vec<f64>,
}

/// The pair constants of one batch.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct LaneConsts {
    pub ri: Lane,
    pub rj: Lane,
    pub reach2: Lane,
    pub k_n: Lane,
    pub slope: Lane,
    pub delta_e: Lane,
    pub delta_f: Lane,
    pub k_t: Lane,
    pub f_mt: Lane,
    pub fmt_per_df: Lane,
    pub c_n: Lane,
    pub c_t: Lane,
}

/// `LANES` consecutive pairs' constants.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ConstWindow<'a> {
    ri: &'a Lane,
    rj: &'a Lane,
    reach2: &'a Lane,
    k_n: &'a Lane,
    slope: &'a Lane,
    delta_e: &'a Lane,
    delta_f: &'a Lane,
    k_t: &'a Lane,
    f_mt: &'a Lane,
    fmt_per_df: &'a Lane,
    c_n: &'a Lane,
    c_t: &'a Lane,
}

impl PairConstArrays {
    /// Refills the arrays for `len` pairs, pair `k` getting `at(k)`. When every pair has the same
    /// constants (equal spheres of equal mass: lattices, the benchmark), one window is stored and
    /// reused for every batch, so the force loop streams no constants at all.
    pub fn fill(&mut self, len: usize, at: impl Fn(usize) -> PairConst) {
        let first = if len > 0 { at(0) } else { PairConst::default() };
        self.uniform = (1..len).all(|k| at(k) == first);
        let stored = if self.uniform { 0 } else { len };
        for v in self.columns_mut() {
            v.clear();
            v.resize(stored + LANES, 0.0);
        }
        let slots = if self.uniform { LANES } else { len };
        for k in 0..slots {
            let c = if self.uniform { first } else { at(k) };
            self.ri[k] = c.ri;
            self.rj[k] = c.rj;
            self.reach2[k] = c.reach2;
            self.k_n[k] = c.p.k_n;
            self.slope[k] = c.slope;
            self.delta_e[k] = c.p.delta_e;
            self.delta_f[k] = c.p.delta_f;
            self.k_t[k] = c.p.k_t;
            self.f_mt[k] = c.p.f_mt;
            self.fmt_per_df[k] = c.fmt_per_df;
            self.c_n[k] = c.p.c_n;
            self.c_t[k] = c.p.c_t;
        }
        self.len = len;
    }

    fn columns_mut(&mut self) -> [&mut Vec<f64>; 12] {
        [
            &mut self.ri,
            &mut self.rj,
            &mut self.reach2,
            &mut self.k_n,
            &mut self.slope,
            &mut self.delta_e,
            &mut self.delta_f,
            &mut self.k_t,
            &mut self.f_mt,
            &mut self.fmt_per_df,
            &mut self.c_n,
            &mut self.c_t,
        ]
    }

    /// Whether every pair shares one window.
    pub fn is_uniform(&self) -> bool {
        self.uniform
    }

    /// Number of pairs held.
    pub fn len(&self) -> usize {
        self.len
    }

    /// The constants of pairs `p..p + LANES` (`p` at most `len()`).
    #[inline(always)]
    pub fn window(&self, p: usize) -> ConstWindow<'_> {
        let p = if self.uniform { 0 } else { p };
        fn w(v: &[f64], p: usize) -> &Lane {
            v[p..p + LANES]
                .try_into()
                .expect("window within the padded arrays")
        }
        ConstWindow {
            ri: w(&self.ri, p),
            rj: w(&self.rj, p),
            reach2: w(&self.reach2, p),
            k_n: w(&self.k_n, p),
            slope: w(&self.slope, p),
            delta_e: w(&self.delta_e, p),
            delta_f: w(&self.delta_f, p),
            k_t: w(&self.k_t, p),
            f_mt: w(&self.f_mt, p),
            fmt_per_df: w(&self.fmt_per_df, p),
            c_n: w(&self.c_n, p),
            c_t: w(&self.c_t, p),
        }
    }
}

impl LaneConsts {
    /// Copies a window in, field by field (64-byte moves the compiler keeps inline, where one
    /// struct-sized assignment became a call to memcpy).
    #[inline(always)]
    pub fn load(&mut self, c: &ConstWindow<'_>) {
        self.ri = *c.ri;
        self.rj = *c.rj;
        self.reach2 = *c.reach2;
        self.k_n = *c.k_n;
        self.slope = *c.slope;
        self.delta_e = *c.delta_e;
        self.delta_f = *c.delta_f;
        self.k_t = *c.k_t;
        self.f_mt = *c.f_mt;
        self.fmt_per_df = *c.fmt_per_df;
        self.c_n = *c.c_n;
        self.c_t = *c.c_t;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{Material, PairModel};

    fn coef() -> PairCoefficients {
        PairCoefficients::new(&PairModel::cohesive(Material::table4(0.15)))
    }

    #[test]
    fn windows_hold_each_pairs_constants() {
        let c = coef();
        let radii = [
            40.0, 45.0, 50.0, 41.0, 44.0, 47.0, 49.0, 43.0, 46.0, 48.0, 42.0,
        ];
        let at = |k: usize| PairConst::new(&c, radii[k], 45.0, 1.0 + k as f64, 2.0);
        let mut a = PairConstArrays::default();
        a.fill(radii.len(), at);
        assert_eq!(a.len(), radii.len());
        for p in 0..radii.len() {
            let w = a.window(p);
            let want = at(p);
            assert_eq!(
                (w.ri[0], w.k_n[0], w.c_n[0]),
                (want.ri, want.p.k_n, want.p.c_n)
            );
        }
    }

    #[test]
    fn equal_pairs_share_one_window() {
        let c = coef();
        let at = |_| PairConst::new(&c, 45.0, 45.0, 1.0, 1.0);
        let mut a = PairConstArrays::default();
        a.fill(1000, at);
        assert_eq!(a.len(), 1000);
        assert_eq!(a.k_n.len(), LANES, "one window stored");
        let w = a.window(993);
        assert!(w.k_n.iter().all(|&k| k == at(0).p.k_n));
    }
}
