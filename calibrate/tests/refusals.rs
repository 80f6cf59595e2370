//! Targets the model cannot reach and bad inputs are refused before any simulation (no files written).

use calibrate::{calibrate, CalibrateError, CalibrationConfig};

fn cfg(law: &str, nu: f64, extra: &str) -> CalibrationConfig {
    CalibrationConfig::from_toml(&format!(
        "law = \"{law}\"\n{extra}\n[material]\nyoung_modulus = 1.0\npoisson_ratio = {nu}\n\
         tensile_strength = 0.2\nshear_strength = 0.1\nsurface_energy = 1.5\nrestitution = 0.95\n\
         density = 1.0\n[sample]\nkind = \"hcp\"\nd0_over_dc = 0.6\nl_over_d0 = 8.0\nw_over_d0 = 3.0\n"
    ))
    .unwrap()
}

fn refused(c: &CalibrationConfig) -> CalibrateError {
    let out = std::env::temp_dir().join(format!("calibrate-refusal-{}", std::process::id()));
    let e = calibrate(c, &out, dem::Parallelism::Sequential, None).unwrap_err();
    assert!(!out.exists(), "nothing may be written for a refused input");
    e
}

#[test]
fn poisson_ratio_above_a_quarter_with_tangential_forces_is_unreachable() {
    let e = refused(&cfg("cohesive", 0.3, ""));
    assert!(matches!(e, CalibrateError::Unreachable(_)), "{e}");
    let msg = e.to_string();
    assert!(
        msg.contains("1/4") && msg.contains("no simulation was run"),
        "{msg}"
    );
}

#[test]
fn normal_only_law_cannot_leave_a_quarter() {
    let e = refused(&cfg("normal_only", 0.15, ""));
    assert!(matches!(e, CalibrateError::Unreachable(_)), "{e}");
    assert!(e.to_string().contains("0.25"), "{e}");
    // At 1/4 it is accepted, but not with tangential unknowns.
    assert!(cfg("normal_only", 0.25, "").prepare().is_ok());
    let e = refused(&cfg("normal_only", 0.25, "unknowns = [\"k_n\", \"k_t\"]"));
    assert!(matches!(e, CalibrateError::InvalidConfig(_)), "{e}");
}

#[test]
fn bad_inputs_are_errors_not_panics() {
    let mut c = cfg("cohesive", 0.15, "");
    c.material_si = Some(dem::material::SiMaterial::table5());
    assert!(matches!(refused(&c), CalibrateError::InvalidConfig(_)));
    let e = refused(&cfg("cohesive", 0.15, "targets = []"));
    assert!(matches!(e, CalibrateError::InvalidConfig(_)), "{e}");
    let twice = "targets = [\"young_modulus\", \"poisson_ratio\", \"young_modulus\"]";
    let e = refused(&cfg("cohesive", 0.15, twice));
    assert!(
        e.to_string().contains("young_modulus is listed twice"),
        "{e}"
    );
    let e = refused(&cfg("cohesive", 0.15, "unknowns = [\"k_n\", \"k_n\"]"));
    assert!(e.to_string().contains("k_n is listed twice"), "{e}");
    let mut c = cfg("cohesive", 0.15, "");
    c.material.as_mut().unwrap().tensile_strength = -1.0;
    assert!(matches!(refused(&c), CalibrateError::Dem(_)));
    let mut c = cfg("cohesive", 0.15, "");
    c.solver.fd_step = 0.0;
    let e = refused(&c);
    assert!(matches!(e, CalibrateError::InvalidConfig(_)), "{e}");
    assert!(CalibrationConfig::from_toml("nonsense = 1").is_err());
}

#[test]
fn si_material_is_converted_once_with_the_nano_unit_system() {
    let c = CalibrationConfig::from_toml(
        "d0_m = 3e-9\n[material_si]\nyoung_modulus = 73e9\npoisson_ratio = 0.17\n\
         tensile_strength = 16e9\nshear_strength = 9e9\nsurface_energy = 1.5\nrestitution = 0.9\n\
         density = 2200.0\n[sample]\nkind = \"amorphous\"\nd0_over_dc = 1.0\nl_over_d0 = 10.0\n\
         w_over_d0 = 3.0\n",
    )
    .unwrap();
    let p = c.prepare().unwrap();
    let m = &p.model.material;
    assert!((m.young_modulus - 73e3).abs() < 1e-9, "MPa");
    assert!((m.surface_energy - 1500.0).abs() < 1e-9, "mJ/m^2");
    assert_eq!(m.scaling, 0.5, "SI default s = 1/2");
    let dc = m.critical_diameter();
    assert!((dc - 1.711).abs() < 1e-3, "d_c = {dc} nm");
    match p.sample {
        dem::sample::SampleSpec::Amorphous { d0_over_dc, .. } => {
            assert!((d0_over_dc * dc - 3.0).abs() < 1e-12)
        }
        _ => panic!("amorphous expected"),
    }
}

#[test]
fn every_shipped_calibration_config_is_accepted() {
    // The configs the docs tell users to run (configs/calibrate-*.toml) must parse, resolve their
    // material and start, and build their problem; a config that rots is found here, not after a
    // user's first relaxation.
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../configs");
    let mut seen = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if !(name.starts_with("calibrate-") && name.ends_with(".toml")) {
            continue;
        }
        let c = CalibrationConfig::from_file(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        calibrate::run::problem(&c, None).unwrap_or_else(|e| panic!("{name}: {e}"));
        seen += 1;
    }
    assert!(
        seen >= 8,
        "found {seen} calibration configs in {}",
        dir.display()
    );
}
