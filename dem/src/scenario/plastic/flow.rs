//! The flow rules of paper 001 (section 2, section 3 eqs 7-9, appendices A and B) as pure functions.
//!
//! - Effective area (App. A, eq A.1): a_i = a_s r / (r - h_i), with r = R_p + r_s and h_i the depth of
//!   the effective sphere (radius r, centre at the projectile's) below the centre of sphere i:
//!   h_i = z_i - (Z - r), so r - h_i = Z - z_i is the vertical distance between the two centres and
//!   a_i = a_s / cos phi_i, the flat area a_s seen on the tilted crater wall.
//! - Flow indexes (eqs 7-8): i_V = 1 if F_z,i > a_i H; i_L = 1 if F_x,i > a_i H_l, H_l = mu_a H.
//! - Vertical flow (eqs 3-4): a flowing sphere follows the projectile down by its vertical
//!   displacement of the step, dz.
//! - Lateral flow (eq 5, App. B): when the projectile advances dx, sphere i goes down by
//!   dz_x,i = sqrt((r - h_i)^2 + 2 a dx) - (r - h_i), a = sqrt(2 r h_i - h_i^2), which puts it back
//!   on the translated effective sphere (dx^2 neglected).
//! - Wear volume of a normal impact (eq 16): W_V = m V_z^2 / (2 H).
//!
//! Decision (eq 5 in three dimensions): App. B derives dz_x,i in the plane of motion (Fig. 15), where
//! the horizontal offset of sphere i from the projectile's centre is a = sqrt(2 r h_i - h_i^2), and
//! the paper applies it to every sphere with i_L = 1, wherever it lies. The default,
//! [`LateralOffset::Paper`], does the same: it is the model whose figures we reproduce. In it a sphere
//! that friction drags past the flow threshold (mu F_n > a_i H_l, the scratching-without-indentation
//! of section 3.1) is lowered even when it lies beside or behind the projectile's centre, which the
//! geometry of Fig. 15 does not ask for. [`LateralOffset::AlongMotion`] is the geometric variant: a
//! replaced by the offset along the motion, a_par = (x_i - X) . e, so that the displacement keeps the
//! distance between the centres, hence the contact force, unchanged to first order for every sphere
//! (equal to eq 5 in the plane), and spheres behind the centre (a_par <= 0), which the projectile
//! moves away from, are not lowered. docs/plastic-wear.md compares the two.

use serde::{Deserialize, Serialize};

/// Which horizontal offset enters eq (5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LateralOffset {
    /// Eq (5) as printed: a = sqrt(2 r h_i - h_i^2), as if every sphere lay in the plane of motion
    /// ahead of the centre.
    #[default]
    Paper,
    /// The sphere's offset from the projectile's centre along the direction of motion.
    AlongMotion,
}

/// Effective area of sphere i, eq (A.1): a_s r / (r - h_i), with `r_minus_h` = r - h_i = Z - z_i.
/// Infinite (no flow) when sphere i is level with or above the projectile's centre.
#[inline]
pub fn effective_area(a_s: f64, r: f64, r_minus_h: f64) -> f64 {
    if r_minus_h > 0.0 {
        a_s * r / r_minus_h
    } else {
        f64::INFINITY
    }
}

/// Vertical flow index, eq (7): the vertical force on the sphere exceeds a_i H.
#[inline]
pub fn flows_vertically(f_z: f64, a_i: f64, hardness: f64) -> bool {
    f_z > a_i * hardness
}

/// Lateral flow index, eq (8): the force along the motion exceeds a_i H_l.
#[inline]
pub fn flows_laterally(f_par: f64, a_i: f64, shear_hardness: f64) -> bool {
    f_par > a_i * shear_hardness
}

/// Eq (5) as printed, in terms of the effective radius r, the sphere's depth h_i and the advance dx.
pub fn eq5(r: f64, h: f64, dx: f64) -> f64 {
    let a = (2.0 * r * h - h * h).max(0.0).sqrt();
    lateral_displacement(r - h, a, dx)
}

/// Downward displacement that keeps a sphere at vertical distance `v` = r - h_i below the
/// projectile's centre and horizontal offset `along` (> 0: ahead) on its sphere when the projectile
/// advances `dx`: sqrt(v^2 + 2 along dx) - v; zero unless both `along` and `dx` are positive.
#[inline]
pub fn lateral_displacement(v: f64, along: f64, dx: f64) -> f64 {
    if along > 0.0 && dx > 0.0 && v > 0.0 {
        let q = 2.0 * along * dx;
        // sqrt(v^2 + q) - v without the cancellation of two close numbers.
        q / ((v * v + q).sqrt() + v)
    } else {
        0.0
    }
}

/// Wear volume of a normal impact, eq (16): m V_z^2 / (2 H).
pub fn normal_impact_wear(mass: f64, v_z: f64, hardness: f64) -> f64 {
    mass * v_z * v_z / (2.0 * hardness)
}

/// Deepest indentation of a normal impact (section 4.1): h_max = V_z / alpha,
/// alpha = sqrt(2 pi R_p H / m).
pub fn normal_impact_depth(mass: f64, radius: f64, v_z: f64, hardness: f64) -> f64 {
    v_z / (2.0 * std::f64::consts::PI * radius * hardness / mass).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn effective_area_is_the_tilted_cell() {
        // A sphere on the effective sphere at angle phi from the vertical: r - h = r cos phi.
        let (a_s, r) = (0.31, 10.25);
        for phi in [0.0f64, 0.2, 0.7] {
            let a = effective_area(a_s, r, r * phi.cos());
            assert!((a - a_s / phi.cos()).abs() < 1e-12);
        }
        assert_eq!(effective_area(a_s, r, 0.0), f64::INFINITY);
        assert!(!flows_vertically(1e9, f64::INFINITY, 1.0));
    }

    #[test]
    fn flow_indexes_compare_force_with_area_times_hardness() {
        assert!(flows_vertically(5.28, 0.31, 17.0));
        assert!(!flows_vertically(5.27, 0.31, 17.0));
        assert!(flows_laterally(1.33, 0.31, 0.25 * 17.0));
        assert!(!flows_laterally(-3.0, 0.31, 0.25 * 17.0));
    }

    #[test]
    fn eq5_puts_the_sphere_back_on_the_translated_sphere() {
        // App. B: a sphere on the effective sphere (offset a, depth below the centre r - h), moved
        // down by dz_x, lies on the sphere translated by dx, up to the dx^2 eq 5 neglects.
        let (r, h) = (10.25f64, 0.4f64);
        let a = (2.0 * r * h - h * h).sqrt();
        for dx in [1e-6, 1e-4] {
            let dz = eq5(r, h, dx);
            let dist = ((a - dx).powi(2) + (r - h + dz).powi(2)).sqrt();
            assert!(
                (dist - r).abs() < 2.0 * dx * dx / r + 1e-12,
                "dx {dx}: {dist}"
            );
        }
        // No advance, or no depth: no displacement (App. B's checks).
        assert_eq!(eq5(r, h, 0.0), 0.0);
        assert!(eq5(r, 1e-12, 1e-4) < 1e-9);
        // Printed form: h - r + sqrt((r - h)^2 + 2 sqrt(2 r h - h^2) dx).
        let dx = 1e-3;
        let printed = h - r + ((r - h).powi(2) + 2.0 * a * dx).sqrt();
        assert!((eq5(r, h, dx) - printed).abs() < 1e-12);
    }

    #[test]
    fn offset_along_the_motion_keeps_off_plane_spheres_in_contact() {
        // A sphere at azimuth psi: horizontal offset a (cos psi, sin psi), vertical distance v.
        let (r, h, dx) = (10.25f64, 0.4f64, 1e-5f64);
        let v = r - h;
        let a = (r * r - v * v).sqrt();
        for psi in [0.0f64, 0.5, 1.2] {
            let (ax, ay) = (a * psi.cos(), a * psi.sin());
            let dz = lateral_displacement(v, ax, dx);
            let dist = ((ax - dx).powi(2) + ay * ay + (v + dz).powi(2)).sqrt();
            assert!((dist - r).abs() < 2.0 * dx * dx / r + 1e-12, "psi {psi}");
            // The printed eq 5 (offset a) sinks the off-plane sphere below the translated sphere.
            if psi > 0.0 {
                assert!(eq5(r, h, dx) > dz);
            }
        }
        assert_eq!(lateral_displacement(v, -1.0, dx), 0.0, "behind the centre");
        assert_eq!(lateral_displacement(v, 1.0, -dx), 0.0, "moving back");
    }

    #[test]
    fn normal_impact_reference() {
        // R_p = 1 cm, rho = 8 g/cm^3, V_z = 45 m/s, H = 1.7 GPa (Fig. 4): W_V ~ 20 mm^3, h ~ 0.8 mm.
        let m = 8000.0 * 4.0 / 3.0 * std::f64::consts::PI * 1e-6;
        let w = normal_impact_wear(m, 45.0, 1.7e9);
        assert!((w - 1.996e-8).abs() < 1e-10, "{w}");
        let h = normal_impact_depth(m, 0.01, 45.0, 1.7e9);
        // Eq 16 is pi h_max^2 R_p.
        assert!((std::f64::consts::PI * h * h * 0.01 - w).abs() / w < 1e-12);
    }
}
