//! Per-pair constants of the cohesive force (paper 000 eqs 7-13 with the s-scaling of eq 10): they
//! depend only on the two radii, the two masses and the model, so they are evaluated once per
//! neighbour-list build (and after any change of particles or model) instead of at every step, which
//! takes the divisions, square roots and powers out of the pair loop. Stored as structure of arrays so
//! that a batch of `LANES` consecutive pairs loads each constant with whole-array copies.
//!
//! Only what costs a division, a square root or a power is stored: the radii, r_eff^2 / (r_i + r_j),
//! delta_f, c_N, the softening slope and F_mT / delta_f (7 numbers per pair). k_N, k_T, delta_e, F_mT,
//! c_T and the squared reach follow from them and the material's coefficients ([`Shared`]) by the
//! very expressions of `PairCoefficients::params_in_range`, so they carry the same bits; they are
//! derived in the batch (a few vector multiplications) instead of being streamed from memory (5 more
//! numbers, 40 bytes, per pair and step on a wide size distribution, where every pair differs).

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
    /// r_eff^2 / (r_i + r_j), the factor of k_N and k_T (eqs 7-8, 15-16).
    pub r2_over_d: f64,
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
        let reff = ri.min(rj);
        PairConst {
            p,
            ri,
            rj,
            r2_over_d: reff * reff / d_sum,
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

/// The material-level coefficients a batch derives its remaining constants with (copied from
/// `PairCoefficients` at each fill).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct Shared {
    kn_coef: f64,
    kt_coef: f64,
    fmt_coef: f64,
    strain_e: f64,
    scale_de: f64,
    ct_over_cn: f64,
    cohesion: bool,
}

impl Shared {
    fn new(c: &PairCoefficients) -> Self {
        Shared {
            kn_coef: c.kn_coef,
            kt_coef: c.kt_coef,
            fmt_coef: c.fmt_coef,
            strain_e: c.strain_e,
            scale_de: c.scale_de,
            ct_over_cn: c.ct_over_cn,
            cohesion: c.cohesion,
        }
    }
}

/// Per-pair constants of a whole neighbour list as structure of arrays, padded by `LANES` zeros so
/// that a window of `LANES` pairs starting at any pair is in bounds.
#[derive(Debug, Clone, Default)]
pub(crate) struct PairConstArrays {
    /// All pairs share the constants of window 0.
    uniform: bool,
    /// Pairs held.
    len: usize,
    shared: Shared,
    ri: Vec<f64>,
    rj: Vec<f64>,
    r2_over_d: Vec<f64>,
    delta_f: Vec<f64>,
    slope: Vec<f64>,
    fmt_per_df: Vec<f64>,
    c_n: Vec<f64>,
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

/// `LANES` consecutive pairs' stored constants, and the coefficients that derive the rest.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ConstWindow<'a> {
    shared: &'a Shared,
    ri: &'a Lane,
    rj: &'a Lane,
    r2_over_d: &'a Lane,
    delta_f: &'a Lane,
    slope: &'a Lane,
    fmt_per_df: &'a Lane,
    c_n: &'a Lane,
}

impl PairConstArrays {
    /// Refills the arrays for `len` pairs, pair `k` getting `at(k)` (made with `coef`). When every
    /// pair has the same constants (equal spheres of equal mass: lattices, the benchmark), one window
    /// is stored and reused for every batch, so the force loop streams no constants at all.
    pub fn fill(&mut self, coef: &PairCoefficients, len: usize, at: impl Fn(usize) -> PairConst) {
        let first = if len > 0 { at(0) } else { PairConst::default() };
        self.uniform = (1..len).all(|k| at(k) == first);
        self.shared = Shared::new(coef);
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
            self.r2_over_d[k] = c.r2_over_d;
            self.delta_f[k] = c.p.delta_f;
            self.slope[k] = c.slope;
            self.fmt_per_df[k] = c.fmt_per_df;
            self.c_n[k] = c.p.c_n;
        }
        self.len = len;
    }

    fn columns_mut(&mut self) -> [&mut Vec<f64>; 7] {
        [
            &mut self.ri,
            &mut self.rj,
            &mut self.r2_over_d,
            &mut self.delta_f,
            &mut self.slope,
            &mut self.fmt_per_df,
            &mut self.c_n,
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
            shared: &self.shared,
            ri: w(&self.ri, p),
            rj: w(&self.rj, p),
            r2_over_d: w(&self.r2_over_d, p),
            delta_f: w(&self.delta_f, p),
            slope: w(&self.slope, p),
            fmt_per_df: w(&self.fmt_per_df, p),
            c_n: w(&self.c_n, p),
        }
    }
}

impl LaneConsts {
    /// Copies a window in, field by field (64-byte moves the compiler keeps inline, where one
    /// struct-sized assignment became a call to memcpy), and derives the other constants lane by lane
    /// with the expressions of `PairCoefficients::params_in_range` (the same bits).
    #[inline(always)]
    pub fn load(&mut self, c: &ConstWindow<'_>) {
        let g = c.shared;
        self.ri = *c.ri;
        self.rj = *c.rj;
        self.delta_f = *c.delta_f;
        self.slope = *c.slope;
        self.fmt_per_df = *c.fmt_per_df;
        self.c_n = *c.c_n;
        for l in 0..LANES {
            let (ri, rj, df) = (c.ri[l], c.rj[l], c.delta_f[l]);
            let d = ri + rj;
            let reff = ri.min(rj);
            let reach = d + df;
            self.reach2[l] = reach * reach;
            self.k_n[l] = g.kn_coef * c.r2_over_d[l];
            self.k_t[l] = g.kt_coef * c.r2_over_d[l];
            let de = (d * g.strain_e * g.scale_de).min(df);
            self.delta_e[l] = if g.cohesion { de } else { 0.0 };
            self.f_mt[l] = g.fmt_coef * (reff * reff);
            self.c_t[l] = c.c_n[l] * g.ct_over_cn;
        }
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
        a.fill(&c, radii.len(), at);
        assert_eq!(a.len(), radii.len());
        for p in 0..radii.len() {
            let w = a.window(p);
            let want = at(p);
            assert_eq!((w.ri[0], w.c_n[0]), (want.ri, want.p.c_n));
        }
    }

    #[test]
    fn equal_pairs_share_one_window() {
        let c = coef();
        let at = |_| PairConst::new(&c, 45.0, 45.0, 1.0, 1.0);
        let mut a = PairConstArrays::default();
        a.fill(&c, 1000, at);
        assert_eq!(a.len(), 1000);
        assert_eq!(a.c_n.len(), LANES, "one window stored");
        let mut lanes = LaneConsts::default();
        lanes.load(&a.window(993));
        assert!(lanes.k_n.iter().all(|&k| k == at(0).p.k_n));
    }

    #[test]
    fn derived_constants_carry_the_bits_of_the_pair_parameters() {
        // Every model variant the kernel meets: silica's s = 1/2 with pairs on both sides of d_c,
        // calibration multipliers, the relaxation's switches and the exact damping model.
        let silica = Material::from_si(
            &crate::material::SiMaterial::table5(),
            crate::UnitSystem::NANO,
        );
        let mut models = vec![
            PairModel::cohesive(Material::table4(0.15)),
            PairModel::cohesive(silica.clone()),
            PairModel::normal_only(Material::table4(0.25)),
        ];
        let mut scaled = PairModel::cohesive(silica.clone());
        scaled.scale = crate::material::ParamScale {
            k_n: 1.3,
            k_t: 0.7,
            delta_e: 1.38,
            delta_f: 0.9,
            f_mt: 1.1,
        };
        scaled.damping = crate::material::DampingModel::Exact;
        models.push(scaled);
        for switches in [
            crate::material::Interactions::REPULSIVE,
            crate::material::Interactions::NORMAL,
        ] {
            let mut m = PairModel::cohesive(silica.clone());
            m.interactions = switches;
            models.push(m);
        }
        for model in &models {
            let c = PairCoefficients::new(model);
            let d_c = model.material.critical_diameter();
            // Radii from 0.2 d_c to 3 d_c, unequal pairs, unequal masses.
            let r = |k: usize| d_c * (0.2 + 0.37 * (k % 8) as f64);
            let at = |k: usize| PairConst::new(&c, r(k), r(k / 3 + 1), 1.0 + k as f64, 2.5);
            let n = 29;
            let mut a = PairConstArrays::default();
            a.fill(&c, n, at);
            assert!(!a.is_uniform());
            let mut lanes = LaneConsts::default();
            for k in 0..n {
                lanes.load(&a.window(k));
                let (want, bits) = (at(k), |x: f64| x.to_bits());
                let got = [
                    lanes.k_n[0],
                    lanes.k_t[0],
                    lanes.delta_e[0],
                    lanes.delta_f[0],
                    lanes.f_mt[0],
                    lanes.c_n[0],
                    lanes.c_t[0],
                    lanes.reach2[0],
                    lanes.slope[0],
                    lanes.fmt_per_df[0],
                ];
                let p = want.p;
                let expected = [
                    p.k_n,
                    p.k_t,
                    p.delta_e,
                    p.delta_f,
                    p.f_mt,
                    p.c_n,
                    p.c_t,
                    want.reach2,
                    want.slope,
                    want.fmt_per_df,
                ];
                assert_eq!(got.map(bits), expected.map(bits), "{model:?} pair {k}");
            }
        }
    }
}
