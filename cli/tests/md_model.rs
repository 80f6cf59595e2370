//! `cgdem md model` through the real binary and real LAMMPS, checked against lattice sums: at 0 K
//! the 2D hexagonal Lennard-Jones crystal (cut-off 2.5 sigma, energy shifted) has a lattice constant,
//! elastic constants and an unrelaxed surface energy that follow from sums over its neighbours, with
//! no fitted number. A missing venv fails the test with the fix command.

mod common;

use std::process::Command;

use md_bridge::lattice::lattice_sums;

const CUTOFF: f64 = 2.5;

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

    let sums = lattice_sums(CUTOFF);
    let density = sums.number_density;
    let rel = |got: f64, want: f64| (got / want - 1.0).abs();
    assert!(
        rel(f("number_density"), density) < 1e-6,
        "density {} vs lattice sum {density}",
        f("number_density")
    );
    // Finite strains of 1e-3 and the minimiser's tolerance leave ~1e-4 on the constants.
    let (c11, c12) = (sums.c11, sums.c12);
    for (k, want) in [("c11", c11), ("c12", c12), ("c66", c12)] {
        assert!(rel(f(k), want) < 1e-3, "{k} {} vs lattice sum {want}", f(k));
    }
    // Isotropy and the Cauchy relation of central forces: nu = 1/3 in 2D.
    assert!((f("poisson_ratio") - 1.0 / 3.0).abs() < 1e-3);
    // Relaxation can only lower the cleaved energy, and only a little for a close-packed row.
    let gamma0 = sums.surface_energy;
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
