//! `cgdem md silica` end to end through the real binary and a real (small, fast) LAMMPS run: the
//! material card has exactly the agreed keys in SI units, plausible values for this potential,
//! provenance, the Table 5 comparison with d_min/d_c/d*, and a second identical request is cached.

mod common;

use std::process::Command;

// Default elastic constants (thermal average at 300 K, +-0.01 strain) with a short stress average.
const TINY: &str = "formula_units = 64
melt_ps = 2.0
anneal_ps = 1.0
elastic_md_ps = 0.5
surface_anneal_ps = 0.5
";

#[test]
fn silica_card_from_worker_has_agreed_keys_plausible_values_and_is_cached() {
    common::venv_or_fail();
    let d = common::scratch("md-silica-test");
    std::fs::write(d.join("tiny.toml"), TINY).unwrap();
    let (cfg, out_dir, cache) = (d.join("tiny.toml"), d.join("out"), d.join("cache"));
    let args = [
        "md",
        "silica",
        "--config",
        cfg.to_str().unwrap(),
        "--out",
        out_dir.to_str().unwrap(),
        "--cache",
        cache.to_str().unwrap(),
    ];
    let run = || {
        Command::new(env!("CARGO_BIN_EXE_cgdem"))
            .args(args)
            .output()
            .unwrap()
    };
    let out = run();
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(out.status.success(), "stdout {stdout}\nstderr {stderr}");
    for row in [
        "d_min (nm, eq 19)",
        "d_c (nm, eq 18)",
        "d* (nm, eq 22)",
        "Table 5",
    ] {
        assert!(stdout.contains(row), "missing `{row}` in:\n{stdout}");
    }
    let card: toml::Table = std::fs::read_to_string(d.join("out/card.toml"))
        .unwrap()
        .parse()
        .unwrap();
    let m = card["material"].as_table().unwrap();
    let mut keys: Vec<&str> = m.keys().map(String::as_str).collect();
    keys.sort();
    assert_eq!(
        keys,
        [
            "density",
            "name",
            "poisson_ratio",
            "restitution",
            "shear_strength",
            "surface_energy",
            "tensile_strength",
            "young_modulus"
        ]
    );
    let f = |k: &str| m[k].as_float().unwrap();
    eprintln!("{m:#?}");
    // Bands for a 192-atom fast-quenched Vashishta glass (SI units: Pa, J/m^2, kg/m^3).
    assert!(
        (2200.0..2700.0).contains(&f("density")),
        "density {}",
        f("density")
    );
    assert!(
        (60e9..160e9).contains(&f("young_modulus")),
        "E {}",
        f("young_modulus")
    );
    assert!(
        (0.1..0.32).contains(&f("poisson_ratio")),
        "nu {}",
        f("poisson_ratio")
    );
    assert!(
        (5e9..30e9).contains(&f("tensile_strength")),
        "sigma_N {}",
        f("tensile_strength")
    );
    assert!(
        (2e9..20e9).contains(&f("shear_strength")),
        "sigma_T {}",
        f("shear_strength")
    );
    assert!(
        (0.5..3.0).contains(&f("surface_energy")),
        "gamma {}",
        f("surface_energy")
    );
    // gamma is the mean of the default three cleave planes, each recorded with the job.
    let rec: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("out/silica.json")).unwrap()).unwrap();
    let planes = rec["output"]["silica"]["surface_cleaves"]
        .as_array()
        .unwrap();
    assert_eq!(planes.len(), 3, "{planes:?}");
    let annealed: Vec<f64> = planes.iter().map(|p| p[1].as_f64().unwrap()).collect();
    let mean = annealed.iter().sum::<f64>() / 3.0;
    assert!(
        (mean / f("surface_energy") - 1.0).abs() < 1e-12,
        "{annealed:?}"
    );
    assert!(
        annealed.windows(2).all(|w| w[0] != w[1]),
        "three planes, three different surfaces: {annealed:?}"
    );
    assert_eq!(f("restitution"), 0.9);
    // The loading curves are drawn beside the record.
    let png = std::fs::read(d.join("out/silica.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let p = card["provenance"].as_table().unwrap();
    assert_eq!(p["potential"].as_str(), Some("SiO.1990.vashishta"));
    assert_eq!(p["potential_sha256"].as_str().unwrap().len(), 64);
    assert!(p["lammps_version"].as_str().unwrap().contains("20250722"));
    assert!(p["notes"]
        .as_array()
        .unwrap()
        .iter()
        .any(|n| n.as_str().unwrap().contains("restitution")));
    // The default card: E, nu thermally averaged at 300 K like the density, strengths ideal
    // (nearly athermal, 10 K), after the default fast quench.
    let notes: Vec<&str> = p["notes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n.as_str().unwrap())
        .collect();
    for want in [
        "quench 2000 K/ps to 300 K",
        "at 300 K (stress averaged",
        "peak stress at 10 K",
    ] {
        assert!(
            notes.iter().any(|n| n.contains(want)),
            "no note with `{want}` in {notes:#?}"
        );
    }
    assert!(
        stdout.contains("thermal average at 300 K"),
        "summary does not say where E was measured:\n{stdout}"
    );

    let again = run();
    assert!(again.status.success());
    assert!(String::from_utf8_lossy(&again.stderr).contains("cached job"));
    assert_eq!(
        String::from_utf8_lossy(&again.stdout),
        stdout,
        "a cache hit reproduces the card"
    );
    let _ = std::fs::remove_dir_all(&d);
}
