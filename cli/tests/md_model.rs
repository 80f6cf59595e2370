//! `cgdem md model` through the real binary and real LAMMPS, checked against lattice sums: at 0 K
//! the 2D hexagonal Lennard-Jones crystal (cut-off 2.5 sigma, energy shifted) has a lattice constant,
//! elastic constants and an unrelaxed surface energy that follow from sums over its neighbours, with
//! no fitted number. A missing venv fails the test with the fix command.

mod common;

use std::process::Command;

const CUTOFF: f64 = 2.5;

fn lj(r: f64) -> f64 {
    4.0 * (r.powi(-12) - r.powi(-6))
}

fn lj_d1(r: f64) -> f64 {
    -48.0 * r.powi(-13) + 24.0 * r.powi(-7)
}

fn lj_d2(r: f64) -> f64 {
    624.0 * r.powi(-14) - 168.0 * r.powi(-8)
}

/// Every lattice vector (x, y) of the hexagonal lattice of spacing `a` shorter than the cut-off.
fn neighbours(a: f64) -> Vec<(f64, f64)> {
    let mut v = Vec::new();
    for i in -6i32..=6 {
        for j in -6i32..=6 {
            let (x, y) = (
                a * (i as f64 + 0.5 * j as f64),
                a * 0.75f64.sqrt() * j as f64,
            );
            let r = x.hypot(y);
            if r > 0.0 && r < CUTOFF {
                v.push((x, y));
            }
        }
    }
    v
}

/// The spacing at zero pressure: sum over neighbours of r phi'(r) = 0 (bisection).
fn zero_pressure_spacing() -> f64 {
    let virial = |a: f64| -> f64 {
        neighbours(a)
            .iter()
            .map(|&(x, y)| x.hypot(y) * lj_d1(x.hypot(y)))
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
    0.5 * (lo + hi)
}

/// Born elastic constants (C11, C12) at zero stress: (1 / 2 A0) sum (phi'' - phi'/r) x_a x_b x_c x_d / r^2.
/// Every atom of the hexagonal lattice is a centre of inversion, so there is no internal relaxation.
fn born_constants(a: f64) -> (f64, f64) {
    let area = 0.75f64.sqrt() * a * a;
    let (mut c11, mut c12) = (0.0, 0.0);
    for (x, y) in neighbours(a) {
        let r = x.hypot(y);
        let b = (lj_d2(r) - lj_d1(r) / r) / (r * r);
        c11 += b * x.powi(4);
        c12 += b * x * x * y * y;
    }
    (c11 / (2.0 * area), c12 / (2.0 * area))
}

/// Energy per unit length to cut the crystal between two close-packed rows, halved (two surfaces),
/// with the shifted potential: the unrelaxed surface energy.
fn unrelaxed_surface_energy(a: f64) -> f64 {
    let h = 0.75f64.sqrt() * a;
    let mut cut = 0.0;
    for row in 0..5 {
        let (x0, y0) = (-0.5 * a * row as f64, -h * row as f64);
        for j in 1..6 {
            for i in -10..=10 {
                let (x, y) = (a * (i as f64 + 0.5 * j as f64), h * j as f64);
                let r = (x - x0).hypot(y - y0);
                if r < CUTOFF {
                    cut += lj(r) - lj(CUTOFF);
                }
            }
        }
    }
    -cut / (2.0 * a)
}

#[test]
fn model_material_matches_lattice_sums_and_fails_in_tension_and_shear() {
    common::venv_or_fail();
    let dir = common::scratch("md-model");
    let out = Command::new(env!("CARGO_BIN_EXE_cgdem"))
        .args(["md", "model", "--no-cache", "--cache"])
        .arg(dir.join("cache"))
        .arg("--out")
        .arg(dir.join("out"))
        .output()
        .expect("cannot start cgdem");
    assert!(
        out.status.success(),
        "cgdem md model failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(dir.join("out/model.json")).unwrap();
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let m = &json["output"]["model"];
    let f = |k: &str| {
        m[k].as_f64()
            .unwrap_or_else(|| panic!("{k} missing in {text}"))
    };

    let a = zero_pressure_spacing();
    let density = 2.0 / (3.0f64.sqrt() * a * a);
    let rel = |got: f64, want: f64| (got / want - 1.0).abs();
    assert!(
        rel(f("number_density"), density) < 1e-6,
        "density {} vs lattice sum {density}",
        f("number_density")
    );
    // Finite strains of 1e-3 and the minimiser's tolerance leave ~1e-4 on the constants.
    let (c11, c12) = born_constants(a);
    for (k, want) in [("c11", c11), ("c12", c12), ("c66", c12)] {
        assert!(rel(f(k), want) < 1e-3, "{k} {} vs lattice sum {want}", f(k));
    }
    // Isotropy and the Cauchy relation of central forces: nu = 1/3 in 2D.
    assert!((f("poisson_ratio") - 1.0 / 3.0).abs() < 1e-3);
    // Relaxation can only lower the cleaved energy, and only a little for a close-packed row.
    let gamma0 = unrelaxed_surface_energy(a);
    let gamma = f("surface_energy");
    assert!(
        gamma <= gamma0 * (1.0 + 1e-6) && gamma > 0.98 * gamma0,
        "surface energy {gamma} vs unrelaxed lattice sum {gamma0}"
    );
    // Both loadings pass a stress peak inside their strain windows.
    for load in ["tension", "shear"] {
        let s = &m[load];
        assert_eq!(s["peak_reached"], true, "{load}: {s}");
        let peak = s["peak_stress"].as_f64().unwrap();
        assert!(
            peak > 0.01 * c11 && peak < 0.2 * c11,
            "{load} peak {peak} vs C11 {c11}"
        );
    }
    assert!(f("d_min") < f("d_c") && f("d_c") < f("d_star"));
    let _ = std::fs::remove_dir_all(&dir);
}
