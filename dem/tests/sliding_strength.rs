//! The sliding material's strengths from the patch-test rig (paper 004 section 3: tau_m ~ 0.22
//! sigma_m).
//!
//! Why tau_m is not linear in sigma_m at fixed d*: the normal-only law's force is k delta with
//! k = A_eff E / d, independent of sigma_m; sigma_m sets only where a pair breaks, delta_e =
//! d sigma_m / E (pairs above d_c = d*/8, all of them here). A pair attracts over a range that grows
//! with sigma_m, so the relaxed box of a stronger material holds more interacting partners (measured
//! at L = 10 d0: 7.3, 7.8, 9.4, 10.5, 12.2 at sigma_m = 0.01, 0.02, 0.05, 0.1, 0.2 E), and its
//! strengths grow faster than sigma_m: tau_m / sigma_m = 0.14, 0.20, 0.24, 0.29, 0.36 and
//! sigma_t / sigma_m = 0.17, 0.20, 0.31, 0.49, 0.65 (docs/sliding.md). The test asserts that trend and
//! its cause, and tau_m near the paper's 0.22 sigma_m at the paper's sigma_m = 0.1 E.

use dem::sample::{make_sample, RelaxConfig, Sample};
use dem::scenario::sliding::{
    measure_strength, MaterialStrength, SlidingConfig, SlidingMaterial, StrengthTests,
};
use dem::Parallelism;

/// L = 10 d0 (d0 = 0.1 L), d* = 0.3 L (d_m = 0.375 d0, below every pair).
fn cfg(sigma_m: f64) -> SlidingConfig {
    SlidingConfig {
        d0_over_l: 0.1,
        material: SlidingMaterial {
            strength: sigma_m,
            surface_energy: None,
            d_star: Some(0.3),
        },
        ..SlidingConfig::default()
    }
}

fn sample(c: &SlidingConfig) -> Sample {
    make_sample(
        &c.recipe().unwrap(),
        &c.model().unwrap(),
        &RelaxConfig::default(),
        Parallelism::Sequential,
    )
    .unwrap()
}

/// The strengths and the mean number of interacting partners of the relaxed box.
fn measure(sigma_m: f64) -> (MaterialStrength, f64) {
    let c = cfg(sigma_m);
    let relaxed = sample(&c);
    let partners = dem::sample::stats::coordination(
        &relaxed.particles,
        &relaxed.sim_box,
        &c.model().unwrap(),
        1e-3,
    )
    .unwrap()
    .interacting;
    let s = measure_strength(
        &relaxed,
        &c,
        &StrengthTests::default(),
        Parallelism::Sequential,
        None,
    )
    .unwrap();
    eprintln!(
        "sigma_m = {sigma_m}: tau_m = {:.5} ({:.3} sigma_m, peak at {:.3}, {} steps), tau_flow = \
         {:?}, sigma_t = {:.5} ({:.3} sigma_m, peak at {:.3}, {} steps), {} particles",
        s.tau_m,
        s.tau_over_sigma_m(),
        s.shear.strain_at_peak,
        s.shear.steps,
        s.tau_flow,
        s.sigma_t,
        s.sigma_t / sigma_m,
        s.tensile.strain_at_peak,
        s.tensile.steps,
        s.particles
    );
    (s, partners)
}

#[test]
fn strengths_grow_faster_than_sigma_m_and_tau_m_is_near_the_papers() {
    let (a, za) = measure(0.1);
    let (b, zb) = measure(0.2);
    for s in [&a, &b] {
        // Each test went past its peak and reports the largest stress it recorded.
        for p in [&s.shear, &s.tensile] {
            let last = p.curve.last().unwrap().0;
            assert!(
                last > p.strain_at_peak + 0.01,
                "{last} vs {}",
                p.strain_at_peak
            );
            let max = p.curve.iter().map(|c| c.1).fold(f64::MIN, f64::max);
            assert_eq!(max, p.peak);
        }
        // Without tangential forces the box is weaker in shear than in tension.
        assert!(s.tau_m < s.sigma_t, "{} vs {}", s.tau_m, s.sigma_t);
        // The default shear test runs on past the peak: the box flows below its peak (stick-slip,
        // measured 0.70 of the peak at L = 20 d0), but the sheared material still carries stress.
        let f = s
            .tau_flow
            .expect("the default shear test measures the flow stress");
        assert_eq!(f.from, s.shear.strain_at_peak + 0.15);
        assert!(
            f.to - f.from >= dem::scenario::sliding::MIN_FLOW_WINDOW,
            "{f:?}"
        );
        assert!(
            f.min <= f.mean && f.mean <= f.max && f.max <= s.tau_m,
            "{f:?}"
        );
        assert!(
            f.mean > 0.4 * s.tau_m && f.mean < 0.95 * s.tau_m,
            "flow {} vs peak {}",
            f.mean,
            s.tau_m
        );
    }
    // The cause: more interacting partners at the larger sigma_m (longer attraction range) ...
    assert!(zb > za + 1.0, "partners {za} at 0.1 E, {zb} at 0.2 E");
    // ... and the effect: both strengths more than double when sigma_m doubles (measured 2.4, 2.6).
    let (shear, tension) = (b.tau_m / a.tau_m, b.sigma_t / a.sigma_t);
    assert!(shear > 2.1, "tau_m(0.2) / tau_m(0.1) = {shear}");
    assert!(tension > 2.1, "sigma_t(0.2) / sigma_t(0.1) = {tension}");
    // Paper 004: tau_m "roughly" 0.22 sigma_m (method and sample not given; at sigma_m = 0.1 E);
    // within 40 % at this small box (measured 0.29 here, 0.27 at L = 20 d0).
    let r = a.tau_over_sigma_m();
    assert!((r - 0.22).abs() < 0.4 * 0.22, "tau_m = {r} sigma_m");
}

#[test]
fn tests_with_the_wrong_mode_are_refused() {
    let c = cfg(0.1);
    let mut t = StrengthTests::default();
    t.shear.mode = dem::scenario::patch::StrengthMode::Tensile;
    let bx = dem::domain::SimBox::new(dem::Vec3::zeros(), dem::Vec3::new(1.0, 1.0, 0.3), [true; 3])
        .unwrap();
    let empty = Sample::new(dem::state::Particles::default(), bx, 0.1, "empty");
    let e = measure_strength(&empty, &c, &t, Parallelism::Sequential, None).unwrap_err();
    assert!(e.to_string().contains("mode"), "{e}");
}

/// A finished shear test of the normal-only law (no shear target: its ratio to one is undefined)
/// keeps its result in its progress file: a second call takes it from there, to the bit and with
/// the first call's wall time, instead of running the test again (a paper-size box spends half an
/// hour in it, and a sliding run killed during the tensile test that follows resumes this way).
#[test]
fn a_finished_normal_only_shear_test_is_taken_from_its_progress_file() {
    let c = cfg(0.1);
    let relaxed = sample(&c);
    let mut shear = StrengthTests::default().shear;
    (shear.post_peak_strain, shear.max_strain) = (0.05, 0.3);
    let dir = std::env::temp_dir().join(format!("cgdem_normal_only_shear_{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    let file = dem::scenario::patch::ProgressFile::new(dir.join("shear.progress.json"));
    let model = c.model().unwrap();
    let run = || {
        dem::scenario::patch::strength_resumable(
            &relaxed,
            &model,
            &shear,
            Parallelism::Sequential,
            Some(&file),
        )
        .unwrap()
    };
    let first = run();
    assert_eq!(
        first.target_strength, 0.0,
        "the normal-only law has no shear target"
    );
    assert_eq!(first.ratio, None, "no target, no ratio to it");
    let again = run();
    // The first call's wall time comes back only from the file (a rerun measures its own).
    assert_eq!(first.wall_seconds, again.wall_seconds, "the test ran again");
    assert_eq!(
        (first.strength, first.steps, first.curve.points.len()),
        (again.strength, again.steps, again.curve.points.len())
    );
    std::fs::remove_dir_all(&dir).ok();
}
