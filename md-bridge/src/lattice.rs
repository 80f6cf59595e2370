//! The 0 K 2D hexagonal Lennard-Jones crystal from sums over its neighbours, no fitted number: the
//! zero-pressure spacing (sum_j r phi'(r) = 0), the Born elastic constants at zero stress,
//! C_ab = (1 / 2 A0) sum_j (phi'' - phi'/r) x_a x_b x_c x_d / r^2 (every atom is a centre of inversion,
//! so no internal relaxation; central forces give the Cauchy relation C12 = C66 = C11 / 3, nu = 1/3),
//! and the unrelaxed surface energy of a close-packed row. The oracle `cgdem md model` (LAMMPS) is
//! checked against, in the report and in `cli/tests/md_model.rs`. Reduced units (epsilon, sigma), the
//! potential energy-shifted at the cut-off.

/// The 0 K 2D hexagonal Lennard-Jones crystal (energy-shifted at `cutoff`) from sums over its
/// neighbours: zero-pressure spacing, number density, Born C11 and C12 (= C66), unrelaxed surface
/// energy of a close-packed row. Reduced units (epsilon, sigma).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LatticeSums {
    pub spacing: f64,
    pub number_density: f64,
    pub c11: f64,
    pub c12: f64,
    pub surface_energy: f64,
}

pub fn lattice_sums(cutoff: f64) -> LatticeSums {
    let lj = |r: f64| 4.0 * (r.powi(-12) - r.powi(-6));
    let d1 = |r: f64| -48.0 * r.powi(-13) + 24.0 * r.powi(-7);
    let d2 = |r: f64| 624.0 * r.powi(-14) - 168.0 * r.powi(-8);
    let neighbours = |a: f64| {
        let mut v = Vec::new();
        for i in -8i32..=8 {
            for j in -8i32..=8 {
                let (x, y) = (
                    a * (i as f64 + 0.5 * j as f64),
                    a * 0.75f64.sqrt() * j as f64,
                );
                let r = x.hypot(y);
                if r > 0.0 && r < cutoff {
                    v.push((x, y));
                }
            }
        }
        v
    };
    // Zero pressure: sum over neighbours of r phi'(r) = 0 (bisection).
    let virial = |a: f64| -> f64 {
        neighbours(a)
            .iter()
            .map(|&(x, y)| x.hypot(y) * d1(x.hypot(y)))
            .sum()
    };
    let (mut lo, mut hi) = (1.0, 1.2);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if virial(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let a = 0.5 * (lo + hi);
    let area = 0.75f64.sqrt() * a * a;
    // Born constants at zero stress; every atom is a centre of inversion: no internal relaxation.
    let (mut c11, mut c12) = (0.0, 0.0);
    for (x, y) in neighbours(a) {
        let r = x.hypot(y);
        let b = (d2(r) - d1(r) / r) / (r * r);
        c11 += b * x.powi(4);
        c12 += b * x * x * y * y;
    }
    // Energy per length to cut between two close-packed rows, halved (two surfaces).
    let h = 0.75f64.sqrt() * a;
    let mut cut = 0.0;
    for row in 0..8 {
        let (x0, y0) = (-0.5 * a * row as f64, -h * row as f64);
        for j in 1..8 {
            for i in -12..=12 {
                let (x, y) = (a * (i as f64 + 0.5 * j as f64), h * j as f64);
                let r = (x - x0).hypot(y - y0);
                if r < cutoff {
                    cut += lj(r) - lj(cutoff);
                }
            }
        }
    }
    LatticeSums {
        spacing: a,
        number_density: 1.0 / area,
        c11: c11 / (2.0 * area),
        c12: c12 / (2.0 * area),
        surface_energy: -cut / (2.0 * a),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// With a cut-off between the first and second shells (1.3 sigma) every sum has one shell: six
    /// springs of stiffness k = phi''(a) at a = 2^(1/6) sigma give C11 = 3 sqrt(3) k / 4, C12 = C11 / 3,
    /// and cutting between rows breaks two bonds per spacing a: gamma = (phi(r_c) - phi(a)) / a.
    #[test]
    fn first_shell_sums_are_the_closed_forms() {
        let s = lattice_sums(1.3);
        let a = 2f64.powf(1.0 / 6.0);
        assert!((s.spacing - a).abs() < 1e-12, "{s:?}");
        let k = 624.0 * a.powi(-14) - 168.0 * a.powi(-8);
        let c11 = 3.0 * 3f64.sqrt() * k / 4.0;
        assert!((s.c11 / c11 - 1.0).abs() < 1e-9, "{s:?} vs {c11}");
        assert!((s.c12 / (c11 / 3.0) - 1.0).abs() < 1e-9, "{s:?}");
        let phi = |r: f64| 4.0 * (r.powi(-12) - r.powi(-6));
        let gamma = (phi(1.3) - phi(a)) / a;
        assert!(
            (s.surface_energy / gamma - 1.0).abs() < 1e-9,
            "{s:?} vs {gamma}"
        );
        assert!((s.number_density - 2.0 / (3f64.sqrt() * a * a)).abs() < 1e-12);
    }

    /// More shells pull the crystal together (the second shell attracts) and keep the Cauchy relation.
    #[test]
    fn longer_cut_offs_keep_cauchy_and_shrink_the_spacing() {
        let (short, long) = (lattice_sums(1.3), lattice_sums(2.5));
        assert!(long.spacing < short.spacing, "{long:?}");
        assert!((long.c12 / long.c11 - 1.0 / 3.0).abs() < 1e-9, "{long:?}");
        assert!(long.surface_energy > short.surface_energy, "{long:?}");
    }
}
