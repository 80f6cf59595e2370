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
//! LAMMPS's granular models.

use crate::material::{PairCoefficients, PairParams};
use crate::Vec3;

/// Normal force F_N(delta_N) of eq (3); positive is cohesive (attractive).
#[inline(always)]
pub fn normal_force(p: &PairParams, dn: f64) -> f64 {
    if dn <= p.delta_e {
        p.k_n * dn
    } else if dn <= p.delta_f {
        // delta_f > delta_e strictly here, so no division by zero.
        -p.k_n * p.delta_e / (p.delta_f - p.delta_e) * (dn - p.delta_f)
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
#[inline(always)]
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

/// What one pair contributes, kept per pair and gathered per particle afterwards.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PairOut {
    /// Force on i (the force on j is its opposite).
    pub f: Vec3,
    /// n x F: the torque on i is a_i (n x F), on j a_j (n x F).
    pub nxf: Vec3,
    /// Lever arm of i.
    pub ai: f64,
    /// Lever arm of j.
    pub aj: f64,
}

/// Energy bookkeeping of one pair for one step.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PairEnergy {
    /// Normal potential energy (zero when separated).
    pub normal: f64,
    /// Elastic energy of the tangential spring, 1/2 k_T |delta_T|^2.
    pub tangential: f64,
    /// Power dissipated by the pair dampers, c_N v_N^2 + c_T |v_T|^2.
    pub damping_power: f64,
    /// Tangential spring energy released by sliding or by the shrinking cap this step.
    pub slid: f64,
}

/// Inputs of one pair.
#[derive(Debug, Clone, Copy)]
pub struct PairInput {
    /// Separation x_j(image) - x_i.
    pub d: Vec3,
    /// v_i - v_j.
    pub dv: Vec3,
    pub wi: Vec3,
    pub wj: Vec3,
    pub ri: f64,
    pub rj: f64,
    pub mi: f64,
    pub mj: f64,
}

/// Evaluates one pair and advances its history. `TANGENTIAL` compiles the tangential part in or out.
#[inline(always)]
pub(crate) fn pair<const TANGENTIAL: bool>(
    coef: &PairCoefficients,
    inp: &PairInput,
    hist: &mut Vec3,
    dt: f64,
) -> (PairOut, PairEnergy) {
    let dist2 = inp.d.norm_squared();
    let (d_sum, delta_f) = coef.range(inp.ri, inp.rj);
    let reach = d_sum + delta_f;
    if dist2 >= reach * reach {
        *hist = Vec3::zeros();
        return (PairOut::default(), PairEnergy::default());
    }
    let dist = dist2.sqrt();
    let n = inp.d * (1.0 / dist);
    let dn = dist - inp.ri - inp.rj;
    let p = coef.params_in_range(inp.ri, inp.rj, d_sum, delta_f, inp.mi, inp.mj);
    let ai = inp.ri + 0.5 * dn;
    let aj = inp.rj + 0.5 * dn;
    // Velocity of i relative to j at the contact point.
    let v_rel = inp.dv + (ai * inp.wi + aj * inp.wj).cross(&n);
    let vn = -v_rel.dot(&n);
    let fn_ = normal_force(&p, dn);
    let mut f = (fn_ + p.c_n * vn) * n;
    let mut en = PairEnergy {
        normal: normal_energy(&p, dn),
        damping_power: p.c_n * vn * vn,
        ..Default::default()
    };
    let mut nxf = Vec3::zeros();
    if TANGENTIAL {
        let vt = v_rel + vn * n;
        // Slip increment over the step that just moved the particles by v dt, in the midpoint geometry
        // (see the module docs): the previous separation is exactly d + dv dt in symplectic Euler.
        let d_prev = inp.d + inp.dv * dt;
        let dist_prev = d_prev.norm();
        let n_prev = d_prev * (1.0 / dist_prev);
        // The normal turns by a tiny angle theta per step; with e = 1 - cos(theta) ~ theta^2 / 2, the
        // midpoint normal's 1/|n + n_prev| = (1/2)(1 - e/2)^(-1/2) and 1/(1 + cos) = 1/(2 - e) are taken
        // as series (remainder O(e^3), below 1e-9 even for a 0.05 rad step): no square root, no division.
        let e = 1.0 - n.dot(&n_prev);
        let m = (n + n_prev) * (0.5 * (1.0 + e * (0.25 + 0.09375 * e)));
        let half_gap_mid = 0.25 * (dist + dist_prev - 2.0 * (inp.ri + inp.rj));
        let v_rel_mid = inp.dv
            + ((inp.ri + half_gap_mid) * inp.wi + (inp.rj + half_gap_mid) * inp.wj).cross(&m);
        let v_mid = v_rel_mid - m * v_rel_mid.dot(&m);
        let h_old = *hist;
        let inv_1pc = 0.5 * (1.0 + e * (0.5 + 0.25 * e));
        let mut h = if h_old == Vec3::zeros() {
            h_old
        } else {
            rotate_between(h_old, &n_prev, &n, inv_1pc)
        };
        h += v_mid * dt;
        h -= h.dot(&n) * n;
        let cap = tangential_cap(&p, dn);
        let spring2 = p.k_t * p.k_t * h.norm_squared();
        if spring2 > cap * cap {
            let before = 0.5 * p.k_t * h.norm_squared();
            h *= cap / spring2.sqrt();
            en.slid = before - 0.5 * p.k_t * h.norm_squared();
        }
        *hist = h;
        let ft = p.k_t * h + p.c_t * vt;
        f -= ft;
        nxf = n.cross(&f);
        en.tangential = 0.5 * p.k_t * h.norm_squared();
        en.damping_power += p.c_t * vt.norm_squared();
    }
    (PairOut { f, nxf, ai, aj }, en)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{Material, PairModel};

    fn params() -> PairParams {
        PairModel::cohesive(Material::table4(0.15)).params(45.0, 45.0, 1.0, 1.0)
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
