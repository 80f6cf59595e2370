//! An MD material card (the TOML `cgdem md silica` writes, SI units with provenance) is accepted as the
//! calibration target directly, by path, and converted like `[material_si]`.

use std::path::PathBuf;

use calibrate::{CalibrateError, CalibrationConfig};
use dem::material::SiMaterial;

/// A card in the layout md-bridge writes (`md-bridge/src/card.rs`), provenance included.
const CARD: &str = r#"[material]
name = "amorphous silica (LAMMPS SiO.1990.vashishta)"
young_modulus = 121045044230.5898
poisson_ratio = 0.21
tensile_strength = 14243390991.403591
shear_strength = 10017126652.566345
surface_energy = 1.486966960671157
restitution = 0.9
density = 2536.6116298195216

[provenance]
source = "cgdem md silica (md-bridge, LAMMPS via PyO3, worker process)"
lammps_version = "2025.7.22.4.0 (LAMMPS 20250722)"
potential = "SiO.1990.vashishta"
seed = 12345
notes = ["192 atoms"]
"#;

/// Top-level keys come first in TOML, so the configs below start with `d0_m`.
const SAMPLE: &str = r#"
[sample]
kind = "amorphous"
d0_over_dc = 1.0
l_over_d0 = 10.0
w_over_d0 = 3.0
ds_over_d0 = 0.75
dl_over_d0 = 2.5
seed = 1
"#;

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("calibrate-card-{name}-{}", std::process::id()));
    std::fs::create_dir_all(d.join("md")).unwrap();
    d
}

#[test]
fn a_card_is_read_relative_to_the_config_and_equals_material_si() {
    let d = dir("ok");
    std::fs::write(d.join("md/card.toml"), CARD).unwrap();
    let with_card =
        format!("d0_m = 3e-9\n[material_card]\npath = \"md/card.toml\"\nscaling = 0.5\n{SAMPLE}");
    std::fs::write(d.join("cal.toml"), with_card).unwrap();
    let cfg = CalibrationConfig::from_file(&d.join("cal.toml")).unwrap();
    let si = cfg
        .material_si
        .clone()
        .expect("card loaded into material_si");
    let want = SiMaterial {
        name: Some("amorphous silica (LAMMPS SiO.1990.vashishta)".into()),
        young_modulus: 121045044230.5898,
        poisson_ratio: 0.21,
        tensile_strength: 14243390991.403591,
        shear_strength: 10017126652.566345,
        surface_energy: 1.486966960671157,
        restitution: 0.9,
        density: 2536.6116298195216,
        scaling: Some(0.5),
    };
    assert_eq!(si, want);
    // The same target as writing the numbers into [material_si] by hand.
    let by_hand = CalibrationConfig {
        material_card: None,
        material_si: Some(want),
        ..cfg.clone()
    };
    assert_eq!(
        cfg.prepare().unwrap().target,
        by_hand.prepare().unwrap().target
    );
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn missing_or_conflicting_cards_are_clear_errors() {
    let d = dir("bad");
    let missing = format!("d0_m = 3e-9\n[material_card]\npath = \"nowhere.toml\"\n{SAMPLE}");
    std::fs::write(d.join("missing.toml"), missing).unwrap();
    let e = CalibrationConfig::from_file(&d.join("missing.toml")).unwrap_err();
    assert!(
        matches!(&e, CalibrateError::Io { path, .. } if path.ends_with("nowhere.toml")),
        "{e}"
    );
    std::fs::write(d.join("md/card.toml"), CARD).unwrap();
    let both = format!(
        "d0_m = 3e-9\n[material_card]\npath = \"md/card.toml\"\n\n[material_si]\nyoung_modulus = 1e9\n\
         poisson_ratio = 0.2\ntensile_strength = 1e8\nshear_strength = 1e8\nsurface_energy = 1.0\n\
         restitution = 0.9\ndensity = 2000.0\n{SAMPLE}"
    );
    std::fs::write(d.join("both.toml"), both).unwrap();
    let e = CalibrationConfig::from_file(&d.join("both.toml")).unwrap_err();
    assert!(e.to_string().contains("exactly one"), "{e}");
    std::fs::write(
        d.join("md/broken.toml"),
        "[material]\nyoung_modulus = \"stiff\"\n",
    )
    .unwrap();
    let broken = format!("d0_m = 3e-9\n[material_card]\npath = \"md/broken.toml\"\n{SAMPLE}");
    std::fs::write(d.join("broken.toml"), broken).unwrap();
    let e = CalibrationConfig::from_file(&d.join("broken.toml")).unwrap_err();
    assert!(matches!(e, CalibrateError::Format { .. }), "{e}");
    std::fs::remove_dir_all(&d).ok();
}
