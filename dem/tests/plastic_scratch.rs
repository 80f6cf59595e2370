//! Scratching on the plastic-wear surface of paper 001 (sections 3.1, 4.3, 4.4) against Figs. 3,
//! 9-10 and 13, on a shortened slide: 3.2 cm instead of 8 cm (the wear rate is steady after 1.6 cm
//! up to 10 kN, docs/plastic-wear.md) and a faster indentation (the indentation is rate-independent,
//! tested here). Every test prints what it measured before it asserts.

use dem::scenario::plastic::{run_scratch_load, ScratchConfig, ScratchResult, ScratchRun};

fn config(mu_a: f64, loads: &[f64], indent_speed: f64) -> ScratchConfig {
    toml::from_str(&format!(
        "[model]\nhardness = 1.7e9\nmu_a = {mu_a}\n[indent]\nspeed = {indent_speed}\nloads = {loads:?}\n\
         [slide]\nspeed = 0.2\nduration = 0.16\n"
    ))
    .unwrap()
}

fn run(cfg: &ScratchConfig) -> ScratchResult {
    let runs: Vec<ScratchRun> = cfg
        .indent
        .loads
        .iter()
        .map(|&f| run_scratch_load(cfg, f, None).unwrap())
        .collect();
    ScratchResult::collect(runs)
}

/// Fig. 10, Fig. 3 and Fig. 13 at mu = 0.5, mu_a = 0.25, H = 1.7 GPa, R_p = 1 cm:
/// - wear starts near 1 kN (the paper: "above the threshold F_z ~ 1000 N"): asserted, the Archard
///   line's onset within 0.5-2 kN, a wear coefficient below 0.005 at 500 N;
/// - Archard's law holds at small loads: R^2 >= 0.97 of the line from the threshold to three times it
///   (measured 0.99);
/// - and not above: at 10 kN the wear rate is at least 1.5 times the line's (measured 1.9);
/// - the shear hardness dF_x/dA_z at the threshold and the four loads above is within 20 % of
///   mu_a H (the paper: 0.37 GPa against 0.425; measured here 0.39);
/// - every slide is steady (the two halves of the measured window within 3 %) and its ledger equals
///   the external work within 1 % (measured: a few 1e-5).
#[test]
fn scratch_follows_archard_at_small_loads_and_the_shear_hardness() {
    let loads = [
        500.0, 1000.0, 1500.0, 2000.0, 3000.0, 4000.0, 6000.0, 8000.0, 10000.0,
    ];
    let res = run(&config(0.25, &loads, 0.02));
    for r in &res.runs {
        println!(
            "{:>7.1} N: wear/d {:.4e} (halves {:.4e} {:.4e}) K {:.4} F_x {:.1} A_z {:.4e} depth {:.4e} \
             balance {:.1e} ({} steps)",
            r.load,
            r.wear_per_distance,
            r.wear_per_distance_halves[0],
            r.wear_per_distance_halves[1],
            r.wear_coefficient(),
            r.lateral_force,
            r.contact_area,
            r.depth,
            r.energy.max_balance_error,
            r.steps
        );
    }
    let fit = res.archard.clone().unwrap();
    let h = res.shear_hardness.clone().unwrap();
    println!("{fit:?}\n{h:?}");
    assert!(res.runs[0].wear_coefficient() < 0.005);
    assert!(
        (500.0..=2000.0).contains(&fit.onset_load),
        "{}",
        fit.onset_load
    );
    assert!(fit.points >= 3 && fit.r2 >= 0.97, "{fit:?}");
    assert!(fit.excess_at_largest >= 1.5, "{fit:?}");
    let ratio = h.slope / h.reference;
    assert!((ratio - 1.0).abs() <= 0.2, "H_l / mu_a H = {ratio}");
    for r in &res.runs {
        if r.wear_coefficient() > 0.02 {
            let [a, b] = r.wear_per_distance_halves;
            assert!((a - b).abs() / b < 0.03, "{} N not steady: {a} {b}", r.load);
        }
        assert!(r.energy.max_balance_error < 0.01, "{} N", r.load);
        // The sum of the terms is the external work (eq 23) sample by sample.
        let e = &r.series.energy;
        let last = e.len() - 1;
        let gained = e.balance(last) - e.balance(0);
        assert!(gained.abs() < 0.01 * e.external_work[last]);
        // Friction and wear take most of the work (Fig. 13).
        assert!(r.energy.friction + r.energy.wear > 0.9 * r.energy.external_work);
    }
}

/// Fig. 9a: a higher shear hardness (mu_a = 0.4 against 0.25) makes the scratch shallower and wear
/// less at the same load; the load-bearing area moves from vertical to lateral flow as the slide
/// begins (Fig. 9b: A_LB^V falls from the indented area to nothing, A_LB^L rises to a sizeable
/// share of it: measured 110 % at mu_a = 0.25, 44 % at 0.4).
#[test]
fn shear_hardness_sets_the_resistance_to_scratching() {
    let soft = run_scratch_load(&config(0.25, &[8000.0], 0.02), 8000.0, None).unwrap();
    let hard = run_scratch_load(&config(0.4, &[8000.0], 0.02), 8000.0, None).unwrap();
    for r in [&soft, &hard] {
        println!(
            "mu_a {}: depth {:.4e} (indent {:.4e}) wear/d {:.4e} A_LB^V {:.3e} A_LB^L {:.3e}",
            r.mu_a, r.depth, r.depth_indent, r.wear_per_distance, r.area_vertical, r.area_lateral
        );
    }
    assert!(hard.depth < soft.depth && hard.wear_per_distance < soft.wear_per_distance);
    for r in [&soft, &hard] {
        assert!(
            r.depth > r.depth_indent,
            "the indenter sinks as it starts to slide"
        );
        let a_v0 = *r.indentation.area_indented.last().unwrap();
        assert!(a_v0 > 0.0 && r.area_vertical < 0.1 * a_v0);
        assert!(r.area_lateral > 0.25 * a_v0);
    }
}

/// The indentation is kinematic and the surface has no rate: indenting to 5 kN at 2 cm/s or at
/// 5 mm/s gives the same depth and indented area (within 0.5 %: the step's advance differs).
#[test]
fn indentation_is_rate_independent() {
    let mut cfg_fast = config(0.25, &[5000.0], 0.02);
    cfg_fast.slide.duration = 0.005;
    let mut cfg_slow = cfg_fast.clone();
    cfg_slow.indent.speed = 0.005;
    let (a, b) = (
        run_scratch_load(&cfg_fast, 5000.0, None).unwrap(),
        run_scratch_load(&cfg_slow, 5000.0, None).unwrap(),
    );
    let (ia, ib) = (&a.indentation, &b.indentation);
    println!(
        "depth {:.6e} / {:.6e}, area {:.6e} / {:.6e}, wear {:.6e} / {:.6e}",
        a.depth_indent,
        b.depth_indent,
        ia.area_indented.last().unwrap(),
        ib.area_indented.last().unwrap(),
        a.wear_volume_indent,
        b.wear_volume_indent
    );
    assert!((a.depth_indent - b.depth_indent).abs() / b.depth_indent < 5e-3);
    let (aa, ab) = (
        ia.area_indented.last().unwrap(),
        ib.area_indented.last().unwrap(),
    );
    assert!((aa - ab).abs() / ab < 5e-3);
    assert!((a.wear_volume_indent - b.wear_volume_indent).abs() / b.wear_volume_indent < 5e-3);
}

/// Bad input is a clear error naming the problem, never a panic.
#[test]
fn bad_scratches_are_refused() {
    let ok = config(0.25, &[1000.0], 0.02);
    let mut c = ok.clone();
    c.slide.duration = 1.0;
    let e = run_scratch_load(&c, 1000.0, None).unwrap_err().to_string();
    assert!(e.contains("does not fit"), "{e}");
    let mut c = ok.clone();
    c.model.mu_a = 0.7;
    let e = run_scratch_load(&c, 1000.0, None).unwrap_err().to_string();
    assert!(e.contains("mu_a"), "{e}");
    let mut c = ok.clone();
    c.model.hardness = -1.0;
    let e = run_scratch_load(&c, 1000.0, None).unwrap_err().to_string();
    assert!(e.contains("hardness"), "{e}");
    let mut c = ok;
    c.run.time_step = dem::scenario::plastic::PlasticTimeStep::Seconds(1e-4);
    let e = run_scratch_load(&c, 1000.0, None).unwrap_err().to_string();
    assert!(e.contains("stable step"), "{e}");
}
