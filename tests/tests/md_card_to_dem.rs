//! Across the crates that do not know each other: a material card written by md-bridge's own writer
//! is the calibration target of `calibrate`, whose patch tests run in the `dem` engine in nanoscale
//! units, and `validation` draws the result. md-bridge and calibrate share no code, so only this
//! test catches a drift between the card's writer and its reader.

use std::path::PathBuf;

use calibrate::{calibrate, remeasure, CalibrationConfig};
use dem::{Parallelism, UnitSystem};
use md_bridge::card::{MaterialCard, Provenance, SiMaterial};
use validation::figures::calibration::{cost_series, draw, error_rows};

fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("cgdem-e2e-card-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn an_md_card_calibrates_the_dem_model_in_si() {
    let d = dir();
    let card = MaterialCard {
        // A measured card names no eq (10) exponent (MD cannot measure it).
        material: SiMaterial {
            scaling: None,
            ..SiMaterial::table5()
        },
        provenance: Provenance {
            source: "end-to-end test (Table 5 numbers, no MD run)".into(),
            lammps_version: "none".into(),
            potential: "none".into(),
            potential_sha256: "none".into(),
            input_hash: "none".into(),
            seed: 0,
            mpi_ranks: 1,
            cgdem_version: env!("CARGO_PKG_VERSION").into(),
            notes: vec![],
        },
    };
    card.write(&d.join("card.toml")).unwrap();
    // E and nu on an HCP block of 3 nm spheres: the elastic test only, a few seconds.
    let cfg = "targets = [\"young_modulus\", \"poisson_ratio\"]\nunknowns = [\"k_n\", \"k_t\"]\n\
               d0_m = 3e-9\n[material_card]\npath = \"card.toml\"\n\
               [verification]\nskip = true\n\
               [sample]\nkind = \"hcp\"\nd0_over_dc = 1.0\nl_over_d0 = 8.0\nw_over_d0 = 3.0\n";
    std::fs::write(d.join("cal.toml"), cfg).unwrap();
    let cfg = CalibrationConfig::from_file(&d.join("cal.toml")).unwrap();
    let out = d.join("out");
    let o = calibrate(&cfg, &out, Parallelism::Sequential, None).unwrap();

    // The card's targets are the MD card's numbers, converted at input with the named conversions.
    let u = UnitSystem::NANO;
    let t = &o.card.targets;
    let m = &card.material;
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs();
    assert!(close(
        u.stress_to_pa(t.young_modulus.unwrap()),
        m.young_modulus
    ));
    assert_eq!(t.poisson_ratio, Some(m.poisson_ratio));
    let p = &o.card.model.material;
    assert!(close(
        u.stress_to_pa(p.tensile_strength),
        m.tensile_strength
    ));
    assert!(close(
        u.surface_energy_to_si(p.surface_energy),
        m.surface_energy
    ));
    assert!(close(u.density_to_si(p.density), m.density));

    // Re-running the patch tests with the written card meets both targets within 1 %.
    let verified = remeasure(&o.problem, &o.card, Parallelism::Sequential).unwrap();
    let e = verified.young_modulus.unwrap() / t.young_modulus.unwrap() - 1.0;
    let nu = verified.poisson_ratio.unwrap() / m.poisson_ratio - 1.0;
    assert!(e.abs() < 0.01 && nu.abs() < 0.01, "E {e:+.4}, nu {nu:+.4}");

    let rows = error_rows(
        &o.card.targets,
        &o.card.uncalibrated,
        &o.card.calibrated,
        Some(&verified),
        None,
    );
    assert_eq!(rows.len(), 2);
    let png = out.join("e2e.png");
    draw(&png, &rows, &cost_series(&o.checkpoint.history)).unwrap();
    assert_eq!(&std::fs::read(&png).unwrap()[..4], b"\x89PNG");
    let _ = std::fs::remove_dir_all(&d);
}
