//! Hertzian contact with Coulomb friction and a tangential history, the contact law of the
//! plastic-wear model (paper 001, Capozza & Hanley 2022, section 3): a rigid sphere against elastic
//! surface spheres. Pure functions; the contact loop that uses them is
//! [`crate::scenario::plastic`]. It stays out of the cohesive kernel (DESIGN.md section 7).
//!
//! Normal force (Hertz), with delta the overlap, R* = R_1 R_2 / (R_1 + R_2) and E* the contact
//! modulus:
//!
//! F_n = k_h delta^(3/2),  k_h = 4/3 E* sqrt(R*),  U_n = 2/5 k_h delta^(5/2),
//! dF_n/d delta = 3/2 k_h delta^(1/2).
//!
//! 1/E* = (1 - nu_1^2)/E_1 + (1 - nu_2^2)/E_2. Paper 001 gives E = 200 GPa and nu = 0.3 as "the
//! elastic properties of the surface spheres, as the particle is assumed rigid", which reads
//! E* = E / (1 - nu^2) ([`contact_modulus_rigid`]). Its simulations ran LAMMPS's `hertz/material`,
//! which mixes the moduli of the two particles: a pair given one E and nu gets E / (2 (1 - nu^2)).
//! Decision: the plastic-wear model defaults to the latter (`scenario::plastic::ContactModulus`),
//! because only it reproduces what section 4.2 reports: with it a 3 mm projectile at 35 m/s on
//! H = 6.6 GPa rebounds from a normal impact with COR 0.995 ("close to 90 deg the COR ~ 1") and wears
//! most near 40-45 deg; with the rigid-projectile modulus the COR at 90 deg is 0.82-0.89 and the wear
//! is largest at 90 deg (docs/plastic-wear.md). The rigid case stays available.
//!
//! Tangential force: a spring of stiffness k_t on the accumulated tangential displacement xi of the
//! contact, capped by Coulomb's mu F_n. Each step the history is turned into the current tangent
//! plane keeping its length (LAMMPS's `rotate_rescale_vec`), the step's tangential displacement is
//! added, and when k_t |xi| exceeds mu F_n the spring is cut back to the cap (sliding). The mean force
//! times the slip is the friction dissipation of paper 001 section 4.4 ([`tangential_step`] says which
//! mean); the spring keeps U_t = 1/2 k_t |xi|^2.
//!
//! Decision: k_t is a constant (LAMMPS's `tangential linear_history`), not Mindlin's 8 G* a, whose
//! stiffness changes with the overlap: then 1/2 k_t |xi|^2 is not a potential, the strain energy must
//! be summed incrementally and a residual is left when a contact opens (paper 001 cites that
//! incremental scheme, ref. 60). With a constant k_t the ledger closes to the integrator's accuracy.
//! Its default is Mindlin's stiffness at the overlap where a surface sphere starts to flow
//! ([`mindlin_stiffness`] at [`HertzLaw::overlap_at`] of a_s H, chosen by the scenario), the overlap
//! around which wear contacts live.

use crate::Vec3;

/// Contact modulus E* of an elastic body (E, nu) against a rigid one: E / (1 - nu^2).
pub fn contact_modulus_rigid(young: f64, poisson: f64) -> f64 {
    young / (1.0 - poisson * poisson)
}

/// Contact shear modulus G* of an elastic body against a rigid one (Mindlin): G / (2 - nu), with
/// G = E / (2 (1 + nu)).
pub fn contact_shear_modulus_rigid(young: f64, poisson: f64) -> f64 {
    young / (2.0 * (1.0 + poisson)) / (2.0 - poisson)
}

/// Effective radius R* = R_1 R_2 / (R_1 + R_2).
pub fn effective_radius(r1: f64, r2: f64) -> f64 {
    r1 * r2 / (r1 + r2)
}

/// Mindlin's tangential stiffness 8 G* a at overlap delta, with contact radius a = sqrt(R* delta).
pub fn mindlin_stiffness(shear_modulus: f64, r_star: f64, delta: f64) -> f64 {
    8.0 * shear_modulus * (r_star * delta.max(0.0)).sqrt()
}

/// The Hertz normal law of one contact: F_n = k_h delta^(3/2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzLaw {
    /// k_h = 4/3 E* sqrt(R*).
    pub k_h: f64,
}

impl HertzLaw {
    /// The law for contact modulus `e_star` and effective radius `r_star`.
    pub fn new(e_star: f64, r_star: f64) -> Self {
        HertzLaw {
            k_h: 4.0 / 3.0 * e_star * r_star.sqrt(),
        }
    }
    /// Normal force magnitude at overlap `delta` (zero when apart).
    #[inline]
    pub fn force(&self, delta: f64) -> f64 {
        if delta > 0.0 {
            self.k_h * delta * delta.sqrt()
        } else {
            0.0
        }
    }
    /// Elastic energy 2/5 k_h delta^(5/2): its derivative is the force.
    #[inline]
    pub fn energy(&self, delta: f64) -> f64 {
        if delta > 0.0 {
            0.4 * self.k_h * delta * delta * delta.sqrt()
        } else {
            0.0
        }
    }
    /// Tangent stiffness dF_n/d delta = 3/2 k_h delta^(1/2).
    #[inline]
    pub fn stiffness(&self, delta: f64) -> f64 {
        1.5 * self.k_h * delta.max(0.0).sqrt()
    }
    /// The overlap at which the normal force reaches `force`: (F / k_h)^(2/3).
    pub fn overlap_at(&self, force: f64) -> f64 {
        (force.max(0.0) / self.k_h).powf(2.0 / 3.0)
    }
}

/// What one tangential update gives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tangential {
    /// The history after the step (in the current tangent plane, within the cap).
    pub xi: Vec3,
    /// Tangential force on the body whose motion `slip` describes: -k_t xi.
    pub force: Vec3,
    /// Spring energy released by sliding this step (>= 0): the friction dissipation.
    pub dissipated: f64,
}

/// One step of the tangential spring of a contact with unit normal `n`: turn `xi` into the plane
/// normal to `n` keeping its length, add the tangential part of `slip` (the relative displacement of
/// the step), and cap k_t |xi| at `mu` times the normal force `f_n`.
///
/// The dissipation booked is the mean of the spring forces at the start and at the end of the step
/// times the slip, k_t (xi_0 + xi_1) / 2 . (du - (xi_1 - xi_0)): the work of those forces over the
/// step's displacement du (the trapezoid the integrator's kinetic energy follows, see
/// `scenario::plastic::ledger`) minus the change of the stored 1/2 k_t |xi|^2. It is zero while the
/// contact sticks and mu F_n |du| in steady sliding; booking the spring energy cut at the cap
/// instead, 1/2 k_t (|xi_0 + du|^2 - |xi_1|^2), counts 1/2 k_t |du|^2 too much per sliding step, a
/// 3 % error in the balance of a grazing impact at a few per cent of the stable step.
#[inline]
pub fn tangential_step(xi: Vec3, n: &Vec3, slip: &Vec3, k_t: f64, mu: f64, f_n: f64) -> Tangential {
    let len = xi.norm();
    let mut h0 = xi - n * xi.dot(n);
    let projected = h0.norm();
    if projected > 0.0 {
        h0 *= len / projected;
    }
    let du = slip - n * slip.dot(n);
    let mut h = h0 + du;
    let cap = mu * f_n.max(0.0);
    let trial = h.norm();
    let mut dissipated = 0.0;
    if k_t * trial > cap {
        h *= if trial > 0.0 {
            cap / (k_t * trial)
        } else {
            0.0
        };
        dissipated = 0.5 * k_t * ((h0 + h).dot(&du) - (h.norm_squared() - h0.norm_squared()));
    }
    Tangential {
        xi: h,
        force: -k_t * h,
        dissipated,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, tol: f64) -> bool {
        ((a - b) / b).abs() < tol
    }

    #[test]
    fn hertz_force_of_a_steel_sphere_on_a_rigid_flat() {
        // E = 200 GPa, nu = 0.3, R = 1 mm, delta = 1 um: F = 4/3 * 200e9/0.91 * sqrt(1e-3) * 1e-9.
        let e_star = contact_modulus_rigid(200e9, 0.3);
        assert!(close(e_star, 2.197_802e11, 1e-6));
        let law = HertzLaw::new(e_star, 1e-3);
        let f = law.force(1e-6);
        assert!(close(
            f,
            4.0 / 3.0 * 2.197_802e11 * 1e-3f64.sqrt() * 1e-9,
            1e-6
        ));
        assert!(close(f, 9.2669, 1e-4), "{f}");
        assert_eq!(law.force(-1e-6), 0.0);
        assert_eq!(law.energy(0.0), 0.0);
        // The overlap that carries a force is the inverse of the force law.
        assert!(close(law.overlap_at(f), 1e-6, 1e-12));
    }

    #[test]
    fn energy_derivative_is_the_force_and_force_derivative_the_stiffness() {
        let law = HertzLaw::new(2.2e5, 0.24);
        for &d in &[1e-4, 3e-3, 2.4e-2] {
            let h = d * 1e-5;
            let de = (law.energy(d + h) - law.energy(d - h)) / (2.0 * h);
            assert!(close(de, law.force(d), 1e-8), "dU/d delta at {d}");
            let df = (law.force(d + h) - law.force(d - h)) / (2.0 * h);
            assert!(close(df, law.stiffness(d), 1e-8), "dF/d delta at {d}");
        }
    }

    #[test]
    fn radii_and_moduli_combine_as_in_hertz_and_mindlin() {
        assert!(close(effective_radius(10.0, 0.25), 2.5 / 10.25, 1e-15));
        // G = E / (2 (1 + nu)) = 76.9 GPa, G* = G / (2 - nu) = 45.25 GPa.
        let g = contact_shear_modulus_rigid(200e9, 0.3);
        assert!(close(g, 200e9 / 2.6 / 1.7, 1e-15));
        let k = mindlin_stiffness(g, 1e-3, 1e-6);
        assert!(close(k, 8.0 * g * 1e-9f64.sqrt(), 1e-15));
        assert_eq!(mindlin_stiffness(g, 1e-3, -1.0), 0.0);
    }

    #[test]
    fn sticking_spring_follows_the_slip_and_stays_tangent() {
        let n = Vec3::new(0.0, 0.0, 1.0);
        let t = tangential_step(
            Vec3::zeros(),
            &n,
            &Vec3::new(1e-3, 0.0, 5.0),
            100.0,
            0.5,
            10.0,
        );
        // Only the tangential part of the slip loads the spring.
        assert_eq!(t.xi, Vec3::new(1e-3, 0.0, 0.0));
        assert_eq!(t.force, Vec3::new(-0.1, 0.0, 0.0));
        assert_eq!(t.dissipated, 0.0);
        // A new normal: the old spring is turned into the new plane with its length kept.
        let n2 = Vec3::new(1.0, 0.0, 1.0).normalize();
        let t2 = tangential_step(t.xi, &n2, &Vec3::zeros(), 100.0, 0.5, 10.0);
        assert!(t2.xi.dot(&n2).abs() < 1e-18);
        assert!(close(t2.xi.norm(), 1e-3, 1e-12));
    }

    #[test]
    fn sliding_caps_the_force_and_dissipates_mean_force_times_slip() {
        let n = Vec3::new(0.0, 1.0, 0.0);
        let (k, mu, f_n) = (100.0, 0.5, 2.0);
        let xi0 = Vec3::new(0.009, 0.0, 0.0);
        let du = Vec3::new(0.003, 0.0, 0.004);
        let t = tangential_step(xi0, &n, &du, k, mu, f_n);
        // Trial spring (0.012, 0, 0.004): |k xi| = 1.265 > mu F_n = 1: cut back to the cap.
        assert!(close(t.force.norm(), 1.0, 1e-12));
        let trial = Vec3::new(0.012, 0.0, 0.004);
        assert!(close(
            t.xi.dot(&trial) / (t.xi.norm() * trial.norm()),
            1.0,
            1e-12
        ));
        // Mean force times slip, slip = du - (xi_1 - xi_0).
        let mean_force = 0.5 * k * (xi0 + t.xi);
        let slip = du - (t.xi - xi0);
        assert!(close(t.dissipated, mean_force.dot(&slip), 1e-12));
        // Energy: stored before + trapezoid work over du = stored after + dissipated.
        let work = mean_force.dot(&du);
        assert!(close(
            0.5 * k * xi0.norm_squared() + work,
            0.5 * k * t.xi.norm_squared() + t.dissipated,
            1e-12
        ));
        // Steady sliding (spring at the cap along the slip): mu F_n |du| exactly.
        let at_cap = Vec3::new(mu * f_n / k, 0.0, 0.0);
        let s = tangential_step(at_cap, &n, &Vec3::new(1e-3, 0.0, 0.0), k, mu, f_n);
        assert!(close(s.dissipated, mu * f_n * 1e-3, 1e-12));
        assert!(close(s.xi.x, at_cap.x, 1e-12));
        // No normal force (the contact opens): the spring goes to zero.
        let open = tangential_step(xi0, &n, &Vec3::zeros(), k, mu, 0.0);
        assert_eq!(open.xi, Vec3::zeros());
        assert!(close(open.dissipated, 0.5 * k * xi0.norm_squared(), 1e-12));
    }
}
