//! The cohesive pair force of Pham-Ba & Molinari (paper 000, section 2.1).
//!
//! Force on particle i from j, with n the unit vector from i to j and delta_N = |x_j - x_i| - r_i - r_j:
//!
//! F_i = (F_N + c_N v_N) n - (F_T + c_T v_T)                                 (eq 2)
//!
//! - F_N(delta_N) is the piecewise-linear law of eq (3): Hookean up to delta_e, linear softening to zero
//!   at delta_f, zero beyond; positive F_N pulls i towards j (cohesion), negative pushes it away.
//! - v_N = d(delta_N)/dt = (v_j - v_i) . n, so the damping resists opening and closing alike.
//! - The tangential spring acts on the sliding displacement delta_T, a vector in the tangent plane that
//!   accumulates the relative velocity of i with respect to j at the contact point (translation and
//!   rotation); its elastic part k_T delta_T is capped at F'_mT (eqs 4-5), and when the cap is reached
//!   delta_T is rescaled so that k_T |delta_T| = F'_mT (sliding).
//! - The contact point sits in the middle of the gap: lever arms a_i = r_i + delta_N / 2 and
//!   a_j = r_j + delta_N / 2 add up to the centre distance, which makes the total angular momentum
//!   (orbital + spin) exactly conserved by every pair.
//!
//! Decision (time discretisation of the history): the slip increment of a step is computed in the
//! geometry of the step's midpoint: normal n_mid = (n_{k-1} + n_k)/|...| and lever arms
//! r + delta_N,mid / 2, with the previous configuration recovered exactly as d_{k-1} = d_k + (v_i - v_j) dt
//! (symplectic Euler moved the particles by v dt). The torques keep the current arms a_i + a_j = d, so
//! angular momentum stays exact. Why: the continuous model is conservative (the tangential power
//! F_T . v_T equals the rate of 1/2 k_T |delta_T|^2), but with end-of-step geometry the lever arms
//! oscillate with the normal vibration and the first-order update pumps energy into the
//! spin-tangential modes (an HCP crystal at 0.1 dt_c gained ~100 % of its kinetic energy in 1e5
//! steps); with midpoint geometry the energy error stays bounded
//! (`tests/conservation.rs::total_energy_has_no_secular_drift_over_1e5_steps`).
//!
//! Decision: the damping force c_T v_T is added outside the cap (the paper caps F_T only, eq 4), as in
//! LAMMPS's granular models, and v_T is the same midpoint tangential velocity that advances delta_T
//! (one tangential velocity per step for both, as LAMMPS uses one `vtr` for the shear increment and
//! the damping). The end-of-step velocity would differ from it by O(dt) and cost a second evaluation of
//! the rotational terms. The normal damping uses v_N = (v_j - v_i) . n exactly: spins add nothing
//! along n.

use super::pair_consts::{ConstWindow, Lane, LaneConsts, LANES};
use crate::material::PairParams;
use crate::Vec3;

/// Normal force F_N(delta_N) of eq (3); positive is cohesive (attractive).
#[inline]
pub fn normal_force(p: &PairParams, dn: f64) -> f64 {
    if dn <= p.delta_e {
        p.k_n * dn
    } else if dn <= p.delta_f {
        // Reached only when delta_f > delta_e, so the slope is finite.
        softening_slope(p) * (p.delta_f - dn)
    } else {
        0.0
    }
}

/// The slope k_N delta_e / (delta_f - delta_e) of eq (3)'s softening branch (0 when there is none).
#[inline]
pub(crate) fn softening_slope(p: &PairParams) -> f64 {
    if p.delta_f > p.delta_e {
        p.k_n * p.delta_e / (p.delta_f - p.delta_e)
    } else {
        0.0
    }
}

/// Potential energy of the normal force, zero for separated particles: U' = F_N, U(delta_f) = 0, so
/// a bonded pair at rest (delta_N = 0) holds -1/2 k_N delta_e delta_f, the bond energy.
#[inline]
pub fn normal_energy(p: &PairParams, dn: f64) -> f64 {
    let w = p.bond_energy();
    if dn <= p.delta_e {
        0.5 * p.k_n * dn * dn - w
    } else if dn <= p.delta_f {
        let (de, df) = (p.delta_e, p.delta_f);
        0.5 * p.k_n * de * de
            + p.k_n * de / (df - de) * ((dn - de) * df - 0.5 * (dn * dn - de * de))
            - w
    } else {
        0.0
    }
}

/// Cap of the tangential force F'_mT of eq (5).
#[inline]
pub fn tangential_cap(p: &PairParams, dn: f64) -> f64 {
    if dn <= 0.0 {
        p.f_mt
    } else {
        p.f_mt * ((p.delta_f - dn) / p.delta_f).clamp(0.0, 1.0)
    }
}

/// Rotates `h` (in the plane normal to `a`) by the smallest rotation that takes unit `a` to unit `b`
/// (Rodrigues, with k = a x b, c = a . b and `inv_1pc` = 1 / (1 + c)): the spring turns with the pair
/// and keeps its length.
#[inline(always)]
fn rotate_between(h: Vec3, a: &Vec3, b: &Vec3, inv_1pc: f64) -> Vec3 {
    let k = a.cross(b);
    h * a.dot(b) + k.cross(&h) + k * (k.dot(&h) * inv_1pc)
}

/// Structure-of-arrays inputs and outputs of `LANES` consecutive pairs (scratch, reused).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Batch {
    /// Separation x_j(image) - x_i.
    pub d: [Lane; 3],
    /// v_i - v_j.
    pub dv: [Lane; 3],
    pub wi: [Lane; 3],
    pub wj: [Lane; 3],
    /// This batch's pair constants, copied from a [`ConstWindow`] (whole-array copies: cheap, and the
    /// kernel then reads memory the compiler knows is not aliased by its outputs, so it vectorises).
    k: LaneConsts,
    /// Tangential history in, advanced history out.
    pub h: [Lane; 3],
    /// Force on i (the force on j is its opposite).
    pub f: [Lane; 3],
    /// Torques on i and on j.
    pub ti: [Lane; 3],
    pub tj: [Lane; 3],
    /// Energy terms (filled when requested): normal potential, tangential spring, damping power,
    /// spring energy released by sliding this step.
    pub e_normal: Lane,
    pub e_tangential: Lane,
    pub damping_power: Lane,
    pub slid: Lane,
    s: SlideScratch,
    g: StageScratch,
}

impl Batch {
    /// Evaluates every lane (constants `c`) and advances its history; lanes out of range get zero
    /// force and history. `TANGENTIAL` compiles the tangential part in or out, `ENERGY` the energy
    /// terms. Lanes beyond the last pair hold stale inputs whose outputs the caller ignores. (The
    /// force loop calls the two halves itself, to load a shared window once.)
    #[cfg(test)]
    pub fn evaluate<const TANGENTIAL: bool, const ENERGY: bool>(
        &mut self,
        c: &ConstWindow,
        dt: f64,
    ) {
        self.load_consts(c);
        self.evaluate_loaded::<TANGENTIAL, ENERGY>(dt);
    }

    /// Takes the constants of the next lanes (kept until the next call: a system whose pairs all
    /// share one window loads it once).
    #[inline(always)]
    pub fn load_consts(&mut self, c: &ConstWindow) {
        self.k.load(c);
    }

    /// [`Batch::evaluate`] with the constants already loaded.
    ///
    /// Decision (speed): the kernel runs in three stages, each over every lane, instead of one lane
    /// function from inputs to outputs. One lane's chain of dependent operations (a square root, the
    /// division, the normals, the midpoint velocity, the history, the force, the torques) is about
    /// 150 cycles long, and with the whole kernel in one loop body (~290 instructions per vector of
    /// lanes) the processor's reorder window held one vector's chain at a time: the kernel ran at
    /// ~1.5 instructions per cycle, bound by latency. A stage's body is short enough that the window
    /// holds the chains of every vector of lanes at once. Each lane computes the same expressions in
    /// the same order as before, so the results are the same bits (docs/performance.md, "The kernel
    /// in stages").
    #[inline(always)]
    pub fn evaluate_loaded<const TANGENTIAL: bool, const ENERGY: bool>(&mut self, dt: f64) {
        for l in 0..LANES {
            self.geometry::<TANGENTIAL>(l, dt);
        }
        for l in 0..LANES {
            self.normal::<TANGENTIAL, ENERGY>(l);
        }
        for l in 0..LANES {
            self.tangential::<TANGENTIAL, ENERGY>(l, dt);
        }
        if TANGENTIAL {
            let s = &self.s;
            let any = (0..LANES).fold(false, |a, l| a | (s.spring2[l] > s.cap[l] * s.cap[l]));
            if any {
                for l in 0..LANES {
                    self.slide::<ENERGY>(l);
                }
            }
        }
    }

    /// Stage 1: the distance and the unit normal, now and (with the history on) one step earlier.
    #[inline(always)]
    fn geometry<const TANGENTIAL: bool>(&mut self, l: usize, dt: f64) {
        let v3 = |a: &[Lane; 3]| Vec3::new(a[0][l], a[1][l], a[2][l]);
        let (d, dv) = (v3(&self.d), v3(&self.dv));
        let dist2 = d.norm_squared();
        let dist = dist2.sqrt();
        // With the history on, the separation one step earlier is needed too (exactly d + dv dt in
        // symplectic Euler), and n and n_prev share one division (1 / (|d| |d_prev|)), the slowest
        // vector instruction here.
        let (n, n_prev, dist_prev) = if TANGENTIAL {
            let d_prev = d + dv * dt;
            let dist_prev = d_prev.norm();
            let inv = 1.0 / (dist * dist_prev);
            (d * (dist_prev * inv), d_prev * (dist * inv), dist_prev)
        } else {
            (d * (1.0 / dist), Vec3::zeros(), 0.0)
        };
        let g = &mut self.g;
        for a in 0..3 {
            self.s.n[a][l] = n[a];
            g.n_prev[a][l] = n_prev[a];
        }
        (g.dist2[l], g.dist[l], g.dist_prev[l]) = (dist2, dist, dist_prev);
    }

    /// Stage 2: the normal force of eq (3) with its damping, its energy, and (with the history on)
    /// the tangential velocity at the contact in the step's midpoint geometry.
    #[inline(always)]
    fn normal<const TANGENTIAL: bool, const ENERGY: bool>(&mut self, l: usize) {
        let v3 = |a: &[Lane; 3]| Vec3::new(a[0][l], a[1][l], a[2][l]);
        let (dv, n) = (v3(&self.dv), v3(&self.s.n));
        let (ri, rj) = (self.k.ri[l], self.k.rj[l]);
        let (k_n, de, df, c_n) = (
            self.k.k_n[l],
            self.k.delta_e[l],
            self.k.delta_f[l],
            self.k.c_n[l],
        );
        let (dist, dist_prev) = (self.g.dist[l], self.g.dist_prev[l]);
        let inside = self.g.dist2[l] < self.k.reach2[l];
        let dn = dist - ri - rj;
        // Normal velocity of i relative to j: the spins add nothing along n ((a w) x n is normal to n).
        let vn = -dv.dot(&n);
        // Eq (3), every branch evaluated and one selected.
        let soft = self.k.slope[l] * (df - dn);
        let fn_ = if dn <= de {
            k_n * dn
        } else if dn <= df {
            soft
        } else {
            0.0
        };
        let f = (fn_ + c_n * vn) * n;
        for a in 0..3 {
            self.f[a][l] = f[a];
        }
        self.g.dn[l] = dn;
        if TANGENTIAL {
            // Slip over the step that just moved the particles by v dt, in the midpoint geometry (see
            // the module docs). The normal turns by a tiny angle theta per step; with
            // e = 1 - cos(theta) ~ theta^2 / 2, the midpoint normal's 1/|n + n_prev| =
            // (1/2)(1 - e/2)^(-1/2) and 1/(1 + cos) = 1/(2 - e) are taken as series (remainder O(e^3),
            // below 1e-9 even for a 0.05 rad step).
            let (wi, wj, n_prev) = (v3(&self.wi), v3(&self.wj), v3(&self.g.n_prev));
            let cos = n.dot(&n_prev);
            let e = 1.0 - cos;
            let m = (n + n_prev) * (0.5 * (1.0 + e * (0.25 + 0.09375 * e)));
            let half_gap_mid = 0.25 * (dist + dist_prev - 2.0 * (ri + rj));
            let v_rel_mid = dv + ((ri + half_gap_mid) * wi + (rj + half_gap_mid) * wj).cross(&m);
            let v_mid = v_rel_mid - m * v_rel_mid.dot(&m);
            for a in 0..3 {
                self.g.v_mid[a][l] = v_mid[a];
            }
            self.g.e[l] = e;
        }
        if ENERGY {
            self.damping_power[l] = c_n * vn * vn;
            let normal = if dn <= de {
                0.5 * k_n * dn * dn - 0.5 * k_n * de * df
            } else if dn <= df {
                // Remaining area under the softening line from delta_N to delta_f, negated.
                -0.5 * soft * (df - dn)
            } else {
                0.0
            };
            self.e_normal[l] = if inside { normal } else { 0.0 };
        }
    }

    /// Stage 3: the tangential spring (turned with the pair, advanced by the slip, capped by eq 5),
    /// its force and damping, the range cut, and the torques.
    #[inline(always)]
    fn tangential<const TANGENTIAL: bool, const ENERGY: bool>(&mut self, l: usize, dt: f64) {
        let v3 = |a: &[Lane; 3]| Vec3::new(a[0][l], a[1][l], a[2][l]);
        let (n, mut f) = (v3(&self.s.n), v3(&self.f));
        let (ri, rj) = (self.k.ri[l], self.k.rj[l]);
        let (df, c_t, k_t) = (self.k.delta_f[l], self.k.c_t[l], self.k.k_t[l]);
        let inside = self.g.dist2[l] < self.k.reach2[l];
        let dn = self.g.dn[l];
        let ai = ri + 0.5 * dn;
        let aj = rj + 0.5 * dn;
        let mut h = Vec3::zeros();
        let mut e_t = 0.0;
        let mut damping_power = if ENERGY { self.damping_power[l] } else { 0.0 };
        if TANGENTIAL {
            let (n_prev, v_mid, e) = (v3(&self.g.n_prev), v3(&self.g.v_mid), self.g.e[l]);
            // Rodrigues: the smallest rotation taking n_prev to n turns the spring with the pair and
            // keeps its length (k = n_prev x n, c = n_prev . n, 1/(1 + c) as a series).
            let h_old = v3(&self.h);
            let inv_1pc = 0.5 * (1.0 + e * (0.5 + 0.25 * e));
            h = rotate_between(h_old, &n_prev, &n, inv_1pc);
            h += v_mid * dt;
            h -= h.dot(&n) * n;
            // Eq (5): the cap shrinks linearly to zero at delta_f; eq (4): slide at the cap.
            let f_mt = self.k.f_mt[l];
            let capped = (self.k.fmt_per_df[l] * (df - dn)).max(0.0).min(f_mt);
            let cap = if dn <= 0.0 { f_mt } else { capped };
            // Sliding (the spring beyond its cap) is rescaled in `slide`, run only for the rare
            // batches that need it: the square root and division it takes are the costliest vector
            // instructions of the kernel.
            let h2 = h.norm_squared();
            self.s.spring2[l] = if inside { k_t * k_t * h2 } else { 0.0 };
            self.s.cap[l] = cap;
            if ENERGY {
                e_t = 0.5 * k_t * h2;
            }
            // The tangential damping acts on the same tangential velocity as the slip increment (one
            // velocity per step for both, as LAMMPS's granular pair styles do).
            let ft = k_t * h + c_t * v_mid;
            f -= ft;
            damping_power += c_t * v_mid.norm_squared();
        }
        if !inside {
            f = Vec3::zeros();
            h = Vec3::zeros();
        }
        let nxf = n.cross(&f);
        let (ti, tj) = (ai * nxf, aj * nxf);
        if TANGENTIAL {
            (self.s.ai[l], self.s.aj[l]) = (ai, aj);
        }
        for a in 0..3 {
            self.f[a][l] = f[a];
            self.ti[a][l] = ti[a];
            self.tj[a][l] = tj[a];
            self.h[a][l] = h[a];
        }
        if ENERGY {
            self.e_tangential[l] = if inside { e_t } else { 0.0 };
            self.damping_power[l] = if inside { damping_power } else { 0.0 };
            // Energy released by sliding: set by `slide` for the lanes that slide.
            self.slid[l] = 0.0;
        }
    }

    /// Eq (4) for the lanes whose spring exceeds its cap: rescales delta_T so that k_T |delta_T| =
    /// F'_mT, and moves force, torques and energies by the spring force removed.
    #[inline(always)]
    fn slide<const ENERGY: bool>(&mut self, l: usize) {
        let (spring2, cap) = (self.s.spring2[l], self.s.cap[l]);
        if spring2 <= cap * cap {
            return;
        }
        let v3 = |a: &[Lane; 3]| Vec3::new(a[0][l], a[1][l], a[2][l]);
        let scale = cap / spring2.sqrt();
        let (h, n) = (v3(&self.h), v3(&self.s.n));
        // The spring force was -k_T h; it becomes -k_T h scale.
        let df = self.k.k_t[l] * (1.0 - scale) * h;
        let nxdf = n.cross(&df);
        let (ai, aj) = (self.s.ai[l], self.s.aj[l]);
        for a in 0..3 {
            self.h[a][l] = h[a] * scale;
            self.f[a][l] += df[a];
            self.ti[a][l] += ai * nxdf[a];
            self.tj[a][l] += aj * nxdf[a];
        }
        if ENERGY {
            let e_t = self.e_tangential[l] * scale * scale;
            self.slid[l] = self.e_tangential[l] - e_t;
            self.e_tangential[l] = e_t;
        }
    }
}

/// What the kernel's stages pass on to the next (see [`Batch::evaluate_loaded`]).
#[derive(Debug, Clone, Copy, Default)]
struct StageScratch {
    /// |d|^2, |d|, |d_prev| and delta_N.
    dist2: Lane,
    dist: Lane,
    dist_prev: Lane,
    dn: Lane,
    n_prev: [Lane; 3],
    /// The midpoint tangential velocity and e = 1 - n . n_prev.
    v_mid: [Lane; 3],
    e: Lane,
}

/// What [`Batch::slide`] needs from the main pass.
#[derive(Debug, Clone, Copy, Default)]
struct SlideScratch {
    /// k_T^2 |delta_T|^2 before the cap (0 for pairs out of range) and the cap F'_mT.
    spring2: Lane,
    cap: Lane,
    n: [Lane; 3],
    ai: Lane,
    aj: Lane,
}

#[cfg(test)]
mod tests {
    use super::super::pair_consts::{PairConst, PairConstArrays};
    use super::*;
    use crate::material::{Material, PairCoefficients, PairModel};

    fn params() -> PairParams {
        PairModel::cohesive(Material::table4(0.15)).params(45.0, 45.0, 1.0, 1.0)
    }

    /// A batch of head-on pairs at rest (radii 45) with normal gaps `gaps`, and their constants.
    fn head_on(gaps: &[f64]) -> (Batch, PairConstArrays) {
        let coef = PairCoefficients::new(&PairModel::cohesive(Material::table4(0.15)));
        let mut consts = PairConstArrays::default();
        consts.fill(&coef, gaps.len(), |_| {
            PairConst::new(&coef, 45.0, 45.0, 1.0, 1.0)
        });
        let mut b = Batch::default();
        for (l, g) in gaps.iter().enumerate() {
            b.d[0][l] = 90.0 + g;
        }
        (b, consts)
    }

    #[test]
    fn lanes_reproduce_eq3_and_its_energy_in_every_branch() {
        let p = params();
        let gaps = [
            -2.0,
            0.0,
            0.5 * p.delta_e,
            p.delta_e,
            0.5 * (p.delta_e + p.delta_f),
            0.999 * p.delta_f,
            1.5 * p.delta_f,
        ];
        let (mut b, consts) = head_on(&gaps);
        b.evaluate::<true, true>(&consts.window(0), 1e-3);
        for (l, &g) in gaps.iter().enumerate() {
            // Force on i along +x is cohesive (towards j).
            let f = b.f[0][l];
            let want = normal_force(&p, g);
            assert!(
                (f - want).abs() <= 1e-12 * p.k_n * p.delta_e,
                "gap {g}: {f} vs {want}"
            );
            let e = b.e_normal[l];
            let want = normal_energy(&p, g);
            assert!(
                (e - want).abs() <= 1e-12 * p.bond_energy(),
                "gap {g}: {e} vs {want}"
            );
            assert_eq!((b.f[1][l], b.f[2][l]), (0.0, 0.0));
        }
    }

    #[test]
    fn lanes_out_of_range_drop_force_and_history() {
        let p = params();
        let (mut b, consts) = head_on(&[0.0, 1.01 * p.delta_f]);
        b.h[1] = [1e-3; LANES];
        b.evaluate::<true, false>(&consts.window(0), 1e-3);
        assert_eq!(b.h[1][1], 0.0);
        assert_eq!(b.f[0][1], 0.0);
        assert!(b.h[1][0] != 0.0, "the pair in range keeps its spring");
    }

    #[test]
    fn lanes_saturate_the_tangential_spring_at_the_cap() {
        let p = params();
        let dn = 0.3 * p.delta_f;
        let (mut b, consts) = head_on(&[dn]);
        // A slip far beyond the cap: the history is rescaled so that k_T |delta_T| = F'_mT.
        b.h[1][0] = 10.0 * p.f_mt / p.k_t;
        b.evaluate::<true, true>(&consts.window(0), 1e-6);
        let cap = tangential_cap(&p, dn);
        assert!((p.k_t * b.h[1][0] - cap).abs() < 1e-12 * cap);
        assert!(
            (b.f[1][0] + cap).abs() < 1e-9 * cap,
            "spring force opposes the slip"
        );
        let released = 0.5 / p.k_t * (100.0 * p.f_mt * p.f_mt - cap * cap);
        assert!(b.slid[0] > 0.0 && (b.slid[0] - released).abs() < 1e-9 * released);
    }

    #[test]
    fn normal_force_is_eq3() {
        let p = params();
        assert_eq!(normal_force(&p, -2.0), -2.0 * p.k_n);
        assert!((normal_force(&p, p.delta_e) - p.k_n * p.delta_e).abs() < 1e-12);
        let mid = 0.5 * (p.delta_e + p.delta_f);
        assert!((normal_force(&p, mid) - 0.5 * p.k_n * p.delta_e).abs() < 1e-12);
        assert_eq!(normal_force(&p, p.delta_f + 1e-9), 0.0);
    }

    #[test]
    fn energy_is_the_integral_of_the_force() {
        let p = params();
        let n = 200_000;
        let (a, b) = (-5.0, p.delta_f + 3.0);
        let h = (b - a) / n as f64;
        let mut acc = 0.0;
        for k in 0..n {
            let x = a + (k as f64 + 0.5) * h;
            acc += normal_force(&p, x) * h;
        }
        let exact = normal_energy(&p, b) - normal_energy(&p, a);
        assert!(
            (acc - exact).abs() < 1e-6 * p.bond_energy(),
            "{acc} vs {exact}"
        );
    }

    #[test]
    fn rotation_between_normals_is_exact_and_keeps_length() {
        let a = Vec3::new(0.3, -0.5, 0.8).normalize();
        let b = Vec3::new(0.31, -0.49, 0.81).normalize();
        let h = Vec3::new(1.0, 2.0, 0.0);
        let h = h - h.dot(&a) * a;
        let e = 1.0 - a.dot(&b);
        let series = 0.5 * (1.0 + e * (0.5 + 0.25 * e));
        assert!((series - 1.0 / (1.0 + a.dot(&b))).abs() < 1e-12);
        let r = rotate_between(h, &a, &b, series);
        assert!((r.norm() - h.norm()).abs() < 1e-12 * h.norm());
        assert!(
            r.dot(&b).abs() < 1e-12 * h.norm(),
            "lands in the new tangent plane"
        );
    }

    #[test]
    fn cap_shrinks_linearly() {
        let p = params();
        assert_eq!(tangential_cap(&p, -1.0), p.f_mt);
        assert!((tangential_cap(&p, 0.25 * p.delta_f) - 0.75 * p.f_mt).abs() < 1e-12);
        assert_eq!(tangential_cap(&p, p.delta_f), 0.0);
    }

    #[test]
    fn repulsive_only_has_no_range_beyond_contact() {
        let mut model = PairModel::cohesive(Material::table4(0.15));
        model.interactions = crate::material::Interactions::REPULSIVE;
        let p = model.params(1.0, 1.0, 1.0, 1.0);
        assert_eq!(normal_force(&p, 1e-9), 0.0);
        assert!(normal_force(&p, -1e-3) < 0.0);
        assert_eq!(normal_energy(&p, 0.0), 0.0);
    }
}
