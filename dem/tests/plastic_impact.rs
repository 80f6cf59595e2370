//! Impacts on the plastic-wear surface of paper 001 (sections 4.1, 4.2, 4.4) against eq 16, Hertz
//! theory and the trends of Figs. 5-7 and 12, with their tolerances stated where they are asserted.
//! Every test prints what it measured before it asserts.

use dem::scenario::plastic::{
    run_impact, ContactModulus, ImpactConfig, ImpactFile, ImpactPoint, ImpactResult,
};

fn normal(hardness: f64, speed: f64) -> ImpactConfig {
    toml::from_str(&format!(
        "[model]\nhardness = {hardness:e}\n[projectile]\nradius = 0.01\ndensity = 8000.0\n\
         [impact]\nspeed = {speed}\nangle_deg = 90.0\n"
    ))
    .unwrap()
}

/// Fig. 4: R_p = 1 cm, rho = 8 g/cm^3. Eq 16 (W_V = m V_z^2 / 2H) counts all the kinetic energy as
/// wear; the model keeps some in the Hertzian springs at the flow threshold and returns it at the
/// rebound (COR 0.15-0.45), so it stays below eq 16, the more so the harder the surface: the
/// overlap at the flow force grows as H^(2/3) while the crater depth shrinks as H^(-1/2).
#[test]
fn normal_impact_wear_against_eq16() {
    let mut rows = Vec::new();
    for h in [1e9, 1.7e9, 2e9, 3e9, 4e9, 5e9, 6e9, 7e9] {
        rows.push(("H", h, run_impact(&normal(h, 45.0)).unwrap()));
    }
    for v in [20.0, 30.0, 40.0, 50.0, 60.0] {
        rows.push(("V", v, run_impact(&normal(1.7e9, v)).unwrap()));
    }
    for (what, x, r) in &rows {
        let e = &r.energy;
        println!(
            "{what} = {x:e}: W_V {:.4e} eq16 {:.4e} ratio {:.4} COR {:.4} rebound {:.2} % of E0, \
             wear energy / (H W_V) {:.4}, balance {:.1e}",
            r.wear_volume,
            r.reference_wear_volume,
            r.wear_volume / r.reference_wear_volume,
            r.cor,
            100.0 * e.kinetic / e.initial_kinetic,
            e.wear / (r.hardness * r.wear_volume),
            e.max_balance_error
        );
    }
    for (what, x, r) in &rows {
        let ratio = r.wear_volume / r.reference_wear_volume;
        // The acceptance band of the issue, where the model meets it: every speed at 1.7 GPa and
        // H up to 4 GPa at 45 m/s (measured 0.90-0.94).
        if *what == "V" || *x <= 4e9 {
            assert!(
                (ratio - 1.0).abs() <= 0.15,
                "{what} = {x}: W_V / eq16 = {ratio}"
            );
        }
        // Everywhere, what eq 16 misses is the rebound's energy: with it, the volume is the energy
        // spent over H within 10 % (the rest: flowing spheres on the crater's tilted wall carry a_i H
        // with a_i > a_s, App. A, and friction).
        let spent = r.energy.initial_kinetic - r.energy.kinetic;
        let corrected = r.wear_volume * r.hardness / spent;
        assert!(
            (0.9..=1.0).contains(&corrected),
            "{what} = {x}: W_V H / (E0 - E_rebound) = {corrected}"
        );
        // Eqs 21-22: the wear energy is the work of flowing spheres at (about) a_i H.
        let per_volume = r.energy.wear / (r.hardness * r.wear_volume);
        assert!(
            (1.0..1.1).contains(&per_volume),
            "{what} = {x}: {per_volume}"
        );
        assert!(r.energy.max_balance_error < 1e-4);
        assert!(r.wear_volume_scratch == 0.0 && r.deviation_deg.abs() < 1e-9);
    }
    // The rebound returns the Hertzian energy of the spheres held at the flow threshold under the
    // crater, in closed form with the paper's constants (not the engine's): each flowing sphere
    // carries F = a_s H at the Hertz overlap delta(F) (E* = E / 2(1 - nu^2), R* of a 1 cm and a
    // 0.25 mm sphere) and stores 2/5 F delta; the crater's contact disc pi a^2 = 2 pi R_p h holds
    // pi a^2 / a_s of them, with h from the measured volume (W_V = pi h^2 R_p). So
    // E_el = (4/5) pi R_p h H delta, a_s cancelling but in delta. Measured: the rebound is 1.06-1.20
    // times this (the crater's rim adds spheres loaded below the threshold, eq 16's shape ignores
    // them); asserted within [1.0, 1.3]. At 7 GPa it is 17 % of E0, which alone puts eq 16 out of
    // its 15 % band: no Hertzian surface with these constants meets eq 16 there.
    let (rp, rs): (f64, f64) = (0.01, 0.25e-3);
    let e_star = 200e9 / (2.0 * (1.0 - 0.3f64 * 0.3));
    let r_star = rp * rs / (rp + rs);
    let a_s = 0.0935 * 0.0168 / 5012.0;
    for (what, x, r) in &rows {
        let f = a_s * r.hardness;
        let delta = (f / (4.0 / 3.0 * e_star * r_star.sqrt())).powf(2.0 / 3.0);
        let h = (r.wear_volume / (std::f64::consts::PI * rp)).sqrt();
        let stored = 0.8 * std::f64::consts::PI * rp * h * r.hardness * delta;
        let ratio = r.energy.kinetic / stored;
        println!(
            "{what} = {x:e}: rebound {:.3e} J, Hertz at the threshold {stored:.3e} J ({:.1} % of E0), ratio {ratio:.3}",
            r.energy.kinetic,
            100.0 * stored / r.energy.initial_kinetic
        );
        assert!((1.0..=1.3).contains(&ratio), "{what} = {x}: {ratio}");
    }
    // Harder surface, larger rebound, larger shortfall: the trend the elastic storage explains.
    let by_h: Vec<&ImpactResult> = rows.iter().filter(|r| r.0 == "H").map(|r| &r.2).collect();
    for w in by_h.windows(2) {
        assert!(w[1].cor > w[0].cor);
    }
}

/// The flow threshold is crossed within a step, and a flowing sphere keeps the force of that step
/// (eq 9 moves it with the projectile): the wear volume grows towards its limit as the advance per
/// step shrinks. Measured: +0.9 % from 4 % to 2 % of the flow overlap per step, then +0.3, +0.4,
/// +0.2 % per halving (the lattice makes the approach irregular); the default (1 %) is asserted
/// within 1 % of the finest run (2.5e-3) and the differences are asserted to shrink overall.
#[test]
fn wear_volume_converges_with_the_advance_per_step() {
    let at = |adv: f64| {
        let mut c = normal(1.7e9, 45.0);
        c.run.max_advance = adv;
        run_impact(&c).unwrap()
    };
    let runs: Vec<(f64, ImpactResult)> = [0.04, 0.02, 0.01, 0.005, 0.0025]
        .iter()
        .map(|&a| (a, at(a)))
        .collect();
    for (a, r) in &runs {
        println!(
            "max_advance {a}: dt {:.3e} s, {} steps, W_V {:.6e}, balance {:.2e}",
            r.time_step, r.steps, r.wear_volume, r.energy.max_balance_error
        );
    }
    let w: Vec<f64> = runs.iter().map(|r| r.1.wear_volume).collect();
    for k in 1..w.len() {
        assert!(w[k] > w[k - 1], "monotone approach: {w:?}");
    }
    assert!(w[4] - w[3] < 0.5 * (w[1] - w[0]), "{w:?}");
    assert!((w[4] - w[2]) / w[4] < 0.01, "{w:?}");
    // The ledger closes better with every smaller step.
    for k in 1..runs.len() {
        assert!(runs[k].1.energy.max_balance_error < runs[k - 1].1.energy.max_balance_error);
    }
}

/// With the hardness out of reach the surface is elastic, and a slow normal impact onto one sphere
/// (its neighbours, 0.6 mm away, stay out of reach of the 8-12 um overlap) is a Hertz collision of
/// a sphere with a fixed one: peak overlap delta_m = (5 m V^2 / (4 k_h))^(2/5), contact time
/// 2.9433 delta_m / V (= 2.868 (m^2 / (R* E*^2 V))^(1/5)), and COR 1.
#[test]
fn an_elastic_impact_is_a_hertz_collision() {
    for modulus in ["lammps", "rigid"] {
        let c: ImpactConfig = toml::from_str(&format!(
            "[model]\nhardness = 1e15\ncontact_modulus = \"{modulus}\"\n\
             [projectile]\nradius = 0.003\ndensity = 2500.0\n\
             [impact]\nspeed = 1.0\nangle_deg = 90.0\nstart_gap = 0.0\n\
             [run]\ntime_step = {{ fraction_of_stable = 0.005 }}\n"
        ))
        .unwrap();
        let r = run_impact(&c).unwrap();
        let e = if modulus == "lammps" { 0.5 } else { 1.0 } * 200e9 / (1.0 - 0.09);
        let r_star: f64 = 3e-3 * 0.25e-3 / 3.25e-3;
        let k_h = 4.0 / 3.0 * e * r_star.sqrt();
        let delta_m = (1.25 * r.mass * 1.0 * 1.0 / k_h).powf(0.4);
        let t_c = 2.943_28 * delta_m / 1.0;
        println!(
            "{modulus}: contact {:.6e} s (Hertz {t_c:.6e}), COR {:.6}, wear {:e}, balance {:.1e}",
            r.contact_time, r.cor, r.wear_volume, r.energy.max_balance_error
        );
        assert!((r.contact_time - t_c).abs() / t_c < 5e-3);
        assert!((r.cor - 1.0).abs() < 1e-4);
        assert_eq!(r.wear_volume, 0.0);
        assert!(r.energy.max_balance_error < 1e-5);
    }
    // The rigid-projectile modulus is twice LAMMPS's: the contact lasts 2^(-2/5) as long (checked
    // above against each own formula).
    let _ = ContactModulus::Rigid;
}

fn oblique_sweep() -> Vec<ImpactPoint> {
    let file: ImpactFile = toml::from_str(
        r#"
[model]
hardness = 6.6e9
mu_a = 0.25
[projectile]
radius = 0.003
density = 2500.0
[impact]
speed = 35.0
angle_deg = 45.0
[sweep]
angle_deg = [10.0, 20.0, 25.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0, 90.0]
speed = [30.0, 35.0, 40.0]
mu_a = [0.15, 0.25]
aims = 8
"#,
    )
    .unwrap();
    let runs: Vec<ImpactResult> = file
        .jobs()
        .unwrap()
        .iter()
        .map(|c| run_impact(c).unwrap())
        .collect();
    file.points(&runs)
}

fn curve(points: &[ImpactPoint], speed: f64, mu_a: f64) -> Vec<&ImpactPoint> {
    points
        .iter()
        .filter(|p| p.speed == speed && p.mu_a == mu_a)
        .collect()
}

fn argmax(c: &[&ImpactPoint], f: impl Fn(&ImpactPoint) -> f64) -> (f64, f64) {
    c.iter()
        .map(|p| (p.angle_deg, f(p)))
        .fold(
            (0.0, f64::NEG_INFINITY),
            |m, x| if x.1 > m.1 { x } else { m },
        )
}

/// Figs. 5-7 (3 mm, 2.5 g/cm^3, H = 6.6 GPa), each point the mean over 8 landing points:
/// - Fig. 5: the wear volume peaks strictly between 0 and 90 deg (asserted: 20-70 deg; the paper:
///   ~45 deg) and grows with V (peak and every angle of 30-60 deg: 30 < 35 < 40 m/s); the normal part
///   dominates near 90 deg, the scratch part below 60 deg;
/// - Fig. 6: mu_a = 0.15 wears more than 0.25 at 40-70 deg (by 1.5x at least);
/// - Fig. 7: the COR is smallest within 10 deg of 25 deg, the deviation largest within 20 deg of
///   that angle; near 90 deg the COR is ~1 (>= 0.95) and the deviation ~0 (< 1 deg); the lower
///   mu_a lowers both COR and deviation at 30-60 deg.
#[test]
fn oblique_impacts_follow_figs_5_to_7() {
    let pts = oblique_sweep();
    for p in &pts {
        println!(
            "V {} mu_a {} angle {:>4}: W {:.3e} (normal {:.2e}, scratch {:.2e}, sd {:.1e}) COR {:.4} dev {:.3}",
            p.speed, p.mu_a, p.angle_deg, p.wear_volume, p.wear_volume_normal,
            p.wear_volume_scratch, p.wear_volume_sd, p.cor, p.deviation_deg
        );
    }
    let mut peaks = Vec::new();
    for v in [30.0, 35.0, 40.0] {
        let c = curve(&pts, v, 0.25);
        let (at, w) = argmax(&c, |p| p.wear_volume);
        println!("V {v}: wear peak {w:.3e} at {at} deg");
        assert!((20.0..=70.0).contains(&at), "V {v}: peak at {at}");
        peaks.push(w);
    }
    assert!(peaks[0] < peaks[1] && peaks[1] < peaks[2], "{peaks:?}");
    for a in [30.0, 40.0, 50.0, 60.0] {
        let w: Vec<f64> = [30.0, 35.0, 40.0]
            .iter()
            .map(|&v| {
                curve(&pts, v, 0.25)
                    .iter()
                    .find(|p| p.angle_deg == a)
                    .unwrap()
                    .wear_volume
            })
            .collect();
        assert!(w[0] < w[1] && w[1] < w[2], "angle {a}: {w:?}");
    }
    let c35 = curve(&pts, 35.0, 0.25);
    let at = |c: &[&ImpactPoint], a: f64| (*c.iter().find(|p| p.angle_deg == a).unwrap()).clone();
    let p90 = at(&c35, 90.0);
    assert!(p90.wear_volume_normal > p90.wear_volume_scratch && p90.wear_volume > 0.0);
    for a in [30.0, 40.0, 50.0] {
        let p = at(&c35, a);
        assert!(p.wear_volume_scratch > p.wear_volume_normal, "angle {a}");
    }
    let soft = curve(&pts, 35.0, 0.15);
    for a in [40.0, 50.0, 60.0, 70.0] {
        let (s, h) = (at(&soft, a), at(&c35, a));
        assert!(
            s.wear_volume > 1.5 * h.wear_volume,
            "angle {a}: {} vs {}",
            s.wear_volume,
            h.wear_volume
        );
        if a <= 60.0 {
            assert!(
                s.cor < h.cor && s.deviation_deg < h.deviation_deg,
                "angle {a}"
            );
        }
    }
    for c in [&c35, &soft] {
        let (cor_at, _) = argmax(c, |p| -p.cor);
        let (dev_at, _) = argmax(c, |p| p.deviation_deg);
        println!(
            "mu_a {}: COR min at {cor_at} deg, deviation max at {dev_at} deg",
            c[0].mu_a
        );
        assert!((cor_at - 25.0).abs() <= 10.0, "COR min at {cor_at}");
        assert!((dev_at - cor_at).abs() <= 20.0, "deviation max at {dev_at}");
        let p = at(c, 90.0);
        assert!(p.cor >= 0.95 && p.deviation_deg.abs() < 1.0);
    }
}

/// Fig. 12 (V = 35 m/s at 29, 45 and 90 deg) and Fig. 4's normal impacts: kinetic + strain +
/// friction + wear stays constant within 1 % (measured: a few 1e-5) through the impact, and closer
/// with a smaller step.
#[test]
fn impact_energy_balance() {
    let mut worst = 0.0f64;
    for angle in [29.0, 45.0, 90.0] {
        let base = format!(
            "[model]\nhardness = 6.6e9\n[projectile]\nradius = 0.003\ndensity = 2500.0\n\
             [impact]\nspeed = 35.0\nangle_deg = {angle}\n"
        );
        let coarse: ImpactConfig = toml::from_str(&base).unwrap();
        let fine: ImpactConfig = toml::from_str(&format!(
            "{base}[run]\ntime_step = {{ fraction_of_stable = 0.005 }}\nmax_advance = 0.0025\n"
        ))
        .unwrap();
        let (a, b) = (run_impact(&coarse).unwrap(), run_impact(&fine).unwrap());
        let e = &a.energy;
        println!(
            "{angle} deg: E0 {:.4e} J -> kinetic {:.4e}, friction {:.4e}, wear {:.4e}; balance {:.2e} (finer step {:.2e})",
            e.initial_kinetic, e.kinetic, e.friction, e.wear, e.max_balance_error,
            b.energy.max_balance_error
        );
        assert!(e.max_balance_error < 0.01);
        assert!(b.energy.max_balance_error < e.max_balance_error);
        // The recorded series closes too, sample by sample.
        let s = &a.series;
        for k in 0..s.len() {
            assert!((s.balance(k) - s.balance(0)).abs() < 0.01 * e.initial_kinetic);
        }
        worst = worst.max(e.max_balance_error);
    }
    println!("worst balance error {worst:.2e}");
}

/// Bad input is a clear error naming the problem, never a panic.
#[test]
fn bad_impacts_are_refused() {
    let bad = |edit: &dyn Fn(&mut ImpactConfig)| {
        let mut c = normal(1.7e9, 45.0);
        edit(&mut c);
        run_impact(&c).unwrap_err().to_string()
    };
    let e = bad(&|c| c.model.hardness = 0.0);
    assert!(e.contains("hardness"), "{e}");
    let e = bad(&|c| c.model.hardness = -1.0);
    assert!(e.contains("hardness"), "{e}");
    let e = bad(&|c| c.model.mu_a = 0.6);
    assert!(e.contains("mu_a") && e.contains("(0, mu)"), "{e}");
    let e = bad(&|c| c.model.mu_a = 0.0);
    assert!(e.contains("mu_a"), "{e}");
    let e = bad(&|c| c.impact.angle_deg = 0.0);
    assert!(e.contains("angle_deg") && e.contains("(0, 90]"), "{e}");
    let e = bad(&|c| c.impact.angle_deg = 120.0);
    assert!(e.contains("angle_deg"), "{e}");
    let e = bad(&|c| c.impact.start_gap = -1e-5);
    assert!(e.contains("inside the surface"), "{e}");
    let e = bad(&|c| {
        c.run.time_step = dem::scenario::plastic::PlasticTimeStep::Seconds(1e-3);
    });
    assert!(e.contains("stable step"), "{e}");
    let e = bad(&|c| c.impact.speed = f64::NAN);
    assert!(e.contains("speed"), "{e}");
    let e = bad(&|c| c.impact.aim_offset = [0.05, 0.0]);
    assert!(e.contains("surface"), "{e}");
}
