//! Patch tests on relaxed amorphous samples (paper 000 section 3.2-3.3, Figs. 7-8, A.6-A.9).
//!
//! CI runs L = 10 d0 (~410 particles, ~25 s); docs/patch-tests.md records L = 20 d0 and the larger
//! reproductions. The d_l-fixed discretisation study (section 3.3) takes ~3 minutes and is ignored in
//! CI: `cargo test --release -p dem --test patch_amorphous -- --ignored --nocapture`.

use dem::sample::insert::InsertionConfig;
use dem::sample::{amorphous, RelaxConfig, Sample, SizeDistribution};
use dem::scenario::patch::{elastic, strength, ElasticConfig, StrengthConfig, StrengthMode};
use dem::{Material, PairModel, Parallelism, Vec3};

fn relaxed(mat: &Material, d0: f64, l: f64, d_l: f64, seed: u64) -> Sample {
    let ins = InsertionConfig {
        lengths: Vec3::new(l, l, 3.0 * d0),
        sizes: SizeDistribution::paper000(d0, 0.75 * d0, d_l),
        volume_fraction: 0.75,
        density: mat.density,
        seed,
    };
    let s = amorphous(
        &ins,
        &PairModel::cohesive(mat.clone()),
        &RelaxConfig::default(),
        Parallelism::Sequential,
    )
    .unwrap();
    assert!(s.relaxation.as_ref().unwrap().converged);
    s
}

#[test]
fn amorphous_poisson_ratio_and_strengths_at_l_10() {
    let mat = Material::table4(0.15);
    let d0 = 0.6 * mat.critical_diameter();
    let sample = relaxed(&mat, d0, 10.0 * d0, 1.25 * d0, 1);
    let model = PairModel::cohesive(mat);
    let par = Parallelism::Sequential;
    let e = elastic(&sample, &model, &ElasticConfig::default(), par).unwrap();
    let t = strength(
        &sample,
        &model,
        &StrengthConfig::paper(StrengthMode::Tensile),
        par,
    )
    .unwrap();
    let s = strength(
        &sample,
        &model,
        &StrengthConfig::paper(StrengthMode::Shear),
        par,
    )
    .unwrap();
    // The cohesive law has a target in both modes.
    let (tr, sr) = (t.ratio.unwrap(), s.ratio.unwrap());
    println!(
        "E {:.4} nu {:.4} tensile {:.4} ({tr:.3}) shear {:.4} ({sr:.3}) fracture {:?}",
        e.young_modulus, e.poisson_ratio, t.strength, s.strength, t.fracture
    );
    // Paper: nu ~ 0.20 for a target of 0.15, strengths at 50 % / 56 % of target. Measured here (L = 10
    // and 20 d0 alike): nu 0.156, tensile 69 % / 64 %, shear 87 % / 85 % (docs/patch-tests.md discusses
    // the gap). Asserted: what the paper's explanation predicts (strengths below target, tensile more
    // reduced than shear, nu at or above target) with bands that pin the measured values.
    assert!(
        e.converged && e.poisson_ratio > 0.14 && e.poisson_ratio < 0.21,
        "{e:?}"
    );
    assert!(e.young_modulus > 0.9 && e.young_modulus < 1.35, "{e:?}");
    assert!(tr > 0.5 && tr < 0.8, "{t:?}");
    assert!(sr > 0.6 && sr < 0.95, "{s:?}");
    assert!(tr < sr);
}

/// Section 3.3 / A.4 (Fig. A.9): at one L, a finer discretisation keeps the coarse sample's strength when
/// d_l stays fixed, and is stronger when d_l = 1.25 d0 follows d0. s = 1/2, L = 48 d_c, d0 = L/10 and
/// L/20, d_l = 0.125 L (= 1.25 x the coarse d0) or 1.25 d0.
#[test]
#[ignore = "about 3 minutes; run with --ignored (docs/patch-tests.md)"]
fn fixed_largest_diameter_harmonises_tensile_strength() {
    let mut mat = Material::table4(0.15);
    mat.scaling = 0.5;
    let l = 48.0 * mat.critical_diameter();
    let model = PairModel::cohesive(mat.clone());
    let cfg = StrengthConfig::paper(StrengthMode::Tensile);
    let run = |d0: f64, d_l: f64| {
        let s = relaxed(&mat, d0, l, d_l, 1);
        let r = strength(&s, &model, &cfg, Parallelism::Threads(2)).unwrap();
        println!(
            "d0 {:.2} d_c, d_l {:.2} d_c: n {} tensile {:.4}",
            d0 / 150.0,
            d_l / 150.0,
            s.particles.len(),
            r.strength
        );
        r.strength
    };
    let coarse = run(l / 10.0, 0.125 * l);
    let fine_free = run(l / 20.0, 1.25 * l / 20.0);
    let fine_fixed = run(l / 20.0, 0.125 * l);
    assert!(
        (fine_fixed - coarse).abs() < (fine_free - coarse).abs(),
        "{coarse} {fine_free} {fine_fixed}"
    );
}
