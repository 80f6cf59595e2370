//! The silica junction cluster job, built small and checked for real: a tiny melt-quenched glass
//! block is written as a data file, the junction input is generated from it exactly as for the
//! millions-of-atom paper geometry (only the box and D are smaller), and LAMMPS runs a few steps of
//! every stage of that input file (carving, minimisation, thermostatted relaxation, driven shear).

mod common;

use md_bridge::silica::junction::{
    mpirun_command, write_glass, write_job, SilicaJunctionConfig, INPUT_FILE,
};
use md_bridge::silica::{self, SilicaConfig};

#[test]
fn small_silica_junction_input_runs_in_lammps() {
    let v = common::venv();
    let pot = v.potential(silica::POTENTIAL).unwrap();
    let dir = std::env::temp_dir().join(format!("cgdem-silica-junction-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();

    // A 96-atom block, quenched absurdly fast: this checks the input, not the glass.
    let glass_cfg = SilicaConfig {
        formula_units: 32,
        melt_ps: 0.3,
        quench_rate: 20000.0,
        anneal_ps: 0.2,
        measure_strength: false,
        measure_surface: false,
        ..SilicaConfig::default()
    };
    let glass_path = dir.join("block.data");
    let rho = write_glass(&common::lammps(), &pot, &glass_cfg, &glass_path).unwrap();
    assert!((1800.0..3000.0).contains(&rho), "block density {rho}");
    let glass = std::fs::read_to_string(&glass_path).unwrap();

    let cfg = SilicaJunctionConfig {
        diameter_nm: 2.0,
        box_nm: [5.0, 4.0, 4.0],
        wall_nm: 0.4,
        bath_nm: 0.4,
        min_iterations: 20,
        relax_ps: 0.01,
        dump_every_ps: 0.0,
        ..SilicaJunctionConfig::default()
    };
    let out = dir.join("job");
    let plan = write_job(&cfg, &glass, &pot, &out).unwrap();
    eprintln!("{:#?}", (&plan.replicas, plan.box_nm, plan.atoms_estimate));
    for f in [INPUT_FILE, "glass.data", silica::POTENTIAL, "junction.toml"] {
        assert!(out.join(f).is_file(), "{f} not written");
    }
    assert_eq!(mpirun_command(64), "mpirun -np 64 lmp -in in.junction");

    // Run the written file itself, shortened through its index variables.
    let shear_steps = 30;
    let l = common::lammps();
    l.commands(&format!(
        "variable dir index {}\nvariable shear_steps index {shear_steps}",
        out.display()
    ))
    .unwrap();
    l.file(&out.join(INPUT_FILE)).unwrap();

    let n = l.natoms().unwrap() as f64;
    let est = plan.atoms_estimate as f64;
    assert!((n / est - 1.0).abs() < 0.1, "{n} atoms vs estimate {est}");
    assert!(n < plan.atoms_replicated as f64, "nothing was carved");
    let count = |v: &str| l.variable(v).unwrap();
    let (bot, top, junction) = (count("n_bot"), count("n_top"), count("n_junction"));
    eprintln!("atoms {n}: bottom wall {bot}, top wall {top}, junction {junction}");
    assert!(bot > 50.0 && top > 50.0, "walls {bot} / {top}");
    // The cylinder holds about its volume's worth of atoms.
    let vol_ratio = (std::f64::consts::PI * 1.0 * plan.height_nm)
        / (plan.box_nm[0] * plan.box_nm[1] * 2.0 * plan.slab_nm
            + std::f64::consts::PI * plan.height_nm);
    assert!(
        (junction / n / vol_ratio - 1.0).abs() < 0.25,
        "junction holds {junction} of {n} atoms, expected fraction {vol_ratio}"
    );
    // The top wall slid at 10 m/s = 0.1 A/ps for shear_steps fs.
    let slide = count("slide");
    let expected = 0.1 * shear_steps as f64 * 1e-3;
    assert!(
        (slide - expected).abs() < 1e-6,
        "slide {slide} A, expected {expected}"
    );
    let (t, pe) = (l.thermo("temp").unwrap(), l.thermo("pe").unwrap());
    assert!(
        t.is_finite() && t > 0.0 && pe.is_finite() && pe < 0.0,
        "T {t} pe {pe}"
    );
    assert!(out.join("junction.restart").is_file());
    let _ = std::fs::remove_dir_all(&dir);
}
