use super::*;
use md_bridge::loading::Strength;
use wear::dstar::{next_step, Bracket, Probe, SearchSettings, Step};

fn strength(peak: f64) -> Strength {
    Strength {
        peak_stress: peak,
        peak_strain: 0.1,
        peak_reached: true,
        curve: vec![],
    }
}

fn card() -> ModelResult {
    ModelResult {
        n_atoms: 672,
        number_density: 1.0,
        atoms_per_nm2: 8.0,
        c11: 1.0,
        c12: 1.0,
        c66: 1.0,
        young_modulus: 66.0,
        poisson_ratio: 1.0 / 3.0,
        shear_modulus: 24.75,
        tension: strength(2.36),
        shear: strength(3.11),
        surface_energy: 0.306,
        d_min: 1.0,
        d_c: 5.0,
        d_star: 25.0,
        d_star_nm: 8.5,
    }
}

/// The bisection against a sharp threshold at `t`, as both sides run it.
fn probes(t: f64, range: [f64; 2], width: f64) -> Vec<Probe> {
    let s = SearchSettings {
        range,
        limits: [4.0, 200.0],
        relative_width: width,
        widen: 1.5,
        max_rounds: 10,
    };
    let mut p: Vec<Probe> = Vec::new();
    let mut rounds = 0;
    while let Step::Probe(ds) = next_step(&s, &p, rounds).unwrap() {
        for d in ds {
            let o = if d >= t {
                Outcome::WearParticle
            } else {
                Outcome::PlasticSmoothing
            };
            p.push(Probe {
                size: d,
                outcomes: vec![o, o],
            });
        }
        rounds += 1;
    }
    p
}

fn md_of(p: &[Probe]) -> MdSearch {
    let b = Bracket::of(p);
    let runs: Vec<MdRun> = p
        .iter()
        .flat_map(|q| {
            q.outcomes.iter().enumerate().map(|(k, &o)| MdRun {
                diameter: q.size,
                seed: k as u64 + 1,
                lattice_offset: super::super::md::lattice_offset(k as u64 + 1),
                outcome: o,
                turn: 0.0,
                rigidity: 1.0,
                debris_fraction: None,
                force_late_over_peak: None,
                atoms: 100,
                junction_atoms: 10,
                // MD cost grows as D^3 (atoms D^2, steps D).
                wall_seconds: 1e-3 * q.size.powi(3),
                ranks: 1,
                job: String::new(),
            })
        })
        .collect();
    MdSearch {
        bracket: [b.lower, b.upper],
        converged: true,
        reason: String::new(),
        split: vec![],
        non_monotonic: vec![],
        seeds: vec![1, 2],
        rounds: 1,
        cost_seconds: runs.iter().map(|r| r.wall_seconds).sum(),
        runs,
    }
}

fn dem_of(p: &[Probe], d0: f64) -> DemEntry {
    let b = Bracket::of(p);
    let bracket = [b.lower, b.upper];
    DemEntry {
        config: "c.toml".into(),
        out: "o".into(),
        d0,
        bracket,
        relative_width: relative_width(&bracket),
        converged: true,
        reason: String::new(),
        split: vec![],
        non_monotonic: vec![],
        dstar_eq22_measured: Some(30.0),
        measured: Some(Measured {
            young_modulus: 60.0,
            poisson_ratio: 0.3,
            tensile_strength: 2.0,
            shear_strength: 3.0,
            surface_energy: None,
            seed: 1,
            particles: 100,
            seconds: 1.0,
        }),
        runs: p
            .iter()
            .flat_map(|q| {
                q.outcomes.iter().enumerate().map(|(k, &o)| DemRun {
                    diameter: q.size,
                    seed: k as u64 + 1,
                    outcome: o,
                    turn: 0.0,
                    rigidity: 1.0,
                    particles: 10,
                    run_seconds: 1e-4 * q.size.powi(2),
                    relax_seconds: 0.0,
                })
            })
            .collect(),
        cost_seconds: 1.0,
        detachment: None,
    }
}

#[test]
fn brackets_overlap_when_each_lower_bound_is_below_the_other_upper() {
    let s = |l: f64, u: f64| [Some(l), Some(u)];
    assert_eq!(overlap(&s(20.0, 30.0), &s(25.0, 35.0)), Some(true));
    assert_eq!(overlap(&s(25.0, 35.0), &s(20.0, 30.0)), Some(true));
    // (20, 25] and (25, 30] share no size: a bound is exclusive below.
    assert_eq!(overlap(&s(20.0, 25.0), &s(25.0, 30.0)), Some(false));
    assert_eq!(overlap(&s(20.0, 25.0), &s(26.0, 30.0)), Some(false));
    assert_eq!(overlap(&[None, Some(3.0)], &s(1.0, 2.0)), None);
    assert_eq!(centre(&s(20.0, 30.0)), Some(25.0));
    assert_eq!(relative_width(&s(20.0, 30.0)), Some(0.4));
}

#[test]
fn the_same_threshold_on_both_sides_gives_overlapping_brackets_and_centres_near_one() {
    let md = md_of(&probes(27.0, [35.0, 50.0], 0.2));
    let dem = vec![
        dem_of(&probes(27.0, [20.0, 40.0], 0.15), 2.0),
        dem_of(&probes(27.0, [20.0, 40.0], 0.15), 1.0),
    ];
    let r = CompareResult::new(&card(), 3.0, md, None, dem);
    let [l, u] = r.md_bracket;
    assert!(
        l.unwrap() < 27.0 && 27.0 <= u.unwrap(),
        "{:?}",
        r.md_bracket
    );
    assert!(r.md_relative_width.unwrap() <= 0.2);
    assert_eq!(r.md_seeds_at_bounds, [2, 2]);
    for a in &r.agreement {
        assert_eq!(a.overlap, Some(true), "{a:?}");
        let c = a.centre_ratio.unwrap();
        assert!((c - 1.0).abs() < 0.2, "{c}");
        assert_eq!(a.centres_within_25_percent, Some(true));
    }
    assert_eq!(r.dem_brackets_overlap, Some(true));
    // Different thresholds: no overlap, the centre ratio says by how much.
    let md = md_of(&probes(27.0, [35.0, 50.0], 0.2));
    let dem = vec![dem_of(&probes(60.0, [20.0, 40.0], 0.15), 2.0)];
    let r = CompareResult::new(&card(), 3.0, md, None, dem);
    let a = &r.agreement[0];
    assert_eq!(a.overlap, Some(false));
    let c = a.centre_ratio.unwrap();
    assert!((c - 60.0 / 27.0).abs() < 0.3, "{c}");
    assert_eq!(a.centres_within_25_percent, Some(false));
}

#[test]
fn cost_ratios_pair_equal_sizes_and_interpolate_dem_between_its_sizes() {
    let md = md_of(&probes(27.0, [35.0, 50.0], 0.2));
    let dem = dem_of(&probes(27.0, [20.0, 40.0], 0.15), 2.0);
    let c = cost_ratios(&md.runs, &dem);
    assert!(!c.is_empty());
    for r in &c {
        // MD 1e-3 D^3 against DEM 1e-4 D^2: ratio 10 D, exact at equal sizes and for the
        // log-log interpolation of a power law.
        assert!(
            (r.ratio - 10.0 * r.diameter).abs() < 1e-9 * r.ratio,
            "{r:?}"
        );
        assert!(r.how == "same D" || r.how == "DEM interpolated");
    }
    // An MD size outside the DEM sizes gets no ratio rather than an extrapolation.
    let top = dem.runs.iter().map(|r| r.diameter).fold(0.0, f64::max);
    assert!(c.iter().all(|r| r.diameter <= top));
}

#[test]
fn the_json_holds_what_checks_read_and_the_markdown_both_materials() {
    let md = md_of(&probes(27.0, [35.0, 50.0], 0.2));
    let dem = vec![dem_of(&probes(27.0, [20.0, 40.0], 0.15), 2.0)];
    let r = CompareResult::new(&card(), 3.0, md, None, dem);
    let v = serde_json::to_value(&r).unwrap();
    let b = v["md_bracket"].as_array().unwrap();
    assert_eq!(b.len(), 2);
    assert!(b[0].as_f64().unwrap() < b[1].as_f64().unwrap());
    assert_eq!(v["dstar_theory"].as_f64(), Some(25.0));
    let d = v["dem"].as_array().unwrap();
    assert_eq!(d.len(), 1);
    assert_eq!(d[0]["bracket"].as_array().unwrap().len(), 2);
    assert!(v["md"]["runs"][0]["wall_seconds"].as_f64().unwrap() > 0.0);
    assert!(v["cost_ratios"].as_array().is_some());
    // Six properties, the MD card's values and the DEM's measured ones.
    let p = v["properties"].as_array().unwrap();
    assert_eq!(p.len(), 6);
    assert_eq!(p[0]["md"].as_f64(), Some(66.0));
    assert_eq!(p[0]["dem"][0].as_f64(), Some(60.0));
    assert!(p[4]["dem"][0].is_null(), "gamma not measured: null");
    let m = markdown(&r);
    assert!(m.contains("| Young's modulus E | 66.0000 |"), "{m}");
    assert!(m.contains("DEM d0 = 2"));
    assert!(m.contains("| MD | atoms |"));
    // The figure rows: one per seed and side, x in units of d*_theory.
    let rows = figure_rows(&r);
    assert_eq!(rows.len(), 4);
    assert!(rows
        .iter()
        .all(|row| row.points.iter().all(|p| p.0 > 0.1 && p.0 < 4.0)));
}

#[test]
fn d50_ratios_divide_the_fits_and_the_markdown_and_json_carry_them() {
    use super::super::scan::Trial;
    use wear::detachment::FitSettings;
    // Each side's trials: plastic below its threshold, wear above, two split sizes between.
    let trials = |lo: f64, hi: f64| -> Vec<Trial> {
        let mut v = Vec::new();
        for (k, d) in [0.6, 0.8, 0.9, 1.1, 1.2, 1.4].iter().enumerate() {
            for seed in 1..=8u64 {
                // Wear fraction rises 0, 0, 3/8, 5/8, 1, 1 with size.
                let wear = match k {
                    0 | 1 => false,
                    2 => seed <= 3,
                    3 => seed <= 5,
                    _ => true,
                };
                v.push(Trial {
                    diameter: d * (lo + hi) / 2.0,
                    seed,
                    outcome: if wear {
                        Outcome::WearParticle
                    } else {
                        Outcome::PlasticSmoothing
                    },
                    scan: seed > 2,
                    seconds: 1.0,
                });
            }
        }
        v
    };
    let det = |t: Vec<Trial>| Detachment::new(vec![], vec![3], t, &FitSettings::default()).unwrap();
    let md = md_of(&probes(27.0, [35.0, 50.0], 0.2));
    let mut e = dem_of(&probes(54.0, [20.0, 40.0], 0.15), 2.0);
    e.detachment = Some(det(trials(50.0, 58.0)));
    let r = CompareResult::new(&card(), 3.0, md, Some(det(trials(25.0, 29.0))), vec![e]);
    let (m, d) = (
        r.md_detachment.as_ref().unwrap().fit.clone(),
        r.dem[0].detachment.as_ref().unwrap().fit.clone(),
    );
    // Same shape at twice the size: D50 twice, the same slope, ratio 2.
    let q = &r.d50_ratios[0];
    assert!((d.d50.unwrap() / m.d50.unwrap() - 2.0).abs() < 1e-6);
    assert!((q.ratio.unwrap() - 2.0).abs() < 1e-6, "{q:?}");
    assert!((d.slope.unwrap() - m.slope.unwrap()).abs() < 1e-6 * m.slope.unwrap());
    let (lo, hi) = (q.range[0].unwrap(), q.range[1].unwrap());
    assert!(lo < 2.0 && 2.0 < hi, "{lo} {hi}");
    assert_eq!(lo, d.interval[0].unwrap() / m.interval[1].unwrap());
    assert!((q.d50_over_d0.unwrap() - d.d50.unwrap() / 2.0).abs() < 1e-12);
    let v = serde_json::to_value(&r).unwrap();
    assert!(v["md_detachment"]["fit"]["d50"].as_f64().unwrap() > 25.0);
    assert_eq!(v["dem"][0]["detachment"]["fit"]["runs"].as_u64(), Some(48));
    let text = markdown(&r);
    assert!(text.contains("Detachment probability"), "{text}");
    assert!(text.contains("| MD | atoms | 48 (36) |"), "{text}");
    assert!(text.contains("- DEM d0 = 2: "), "{text}");
    // The figure's series: MD first, a curve through D50 on each side.
    let p = probability_series(&r);
    assert_eq!(p.len(), 2);
    assert!(p
        .iter()
        .all(|s| s.curve.is_some() && s.fractions.len() == 6));
    assert!(
        p[0].label.starts_with("MD (LAMMPS): D50 = "),
        "{}",
        p[0].label
    );
    // Without a scan: no ratio, the words say so.
    let md = md_of(&probes(27.0, [35.0, 50.0], 0.2));
    let r = CompareResult::new(
        &card(),
        3.0,
        md,
        None,
        vec![dem_of(&probes(54.0, [20.0, 40.0], 0.15), 2.0)],
    );
    assert!(r.d50_ratios.is_empty());
    assert_eq!(d50_words(None), "no scan");
    assert!(!markdown(&r).contains("Detachment probability"));
}
