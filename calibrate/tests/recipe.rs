//! Recipe-level calibration (issue 16) on a tiny amorphous recipe (Table 4, d0 = 0.6 d_c, 6 x 6 x 3
//! d0, ~150 particles, two seeds; E and nu by k_N and k_T), cheap enough for CI: every evaluation
//! relaxes its samples with the trial parameters and reports their spread, relaxed samples are shared
//! through the cache, the result does not depend on the thread count, a calibration stopped midway
//! resumes to the same card bit for bit, the card carries its `[verification]` on fresh samples
//! (sheared under load too, and refused by the scenarios when they compact), and a trial under which
//! the packing collapses (in its relaxation or under shear) is a failed evaluation with the reason. The acceptance
//! runs at the sizes of issue 16 are `#[ignore]` (`issue16_acceptance`; figures in docs/calibration.md).

use std::path::{Path, PathBuf};

use calibrate::{calibrate, CalibratedCard, CalibrationConfig, Problem, Status};
use dem::Parallelism;

const TINY: &str = r#"
targets = ["young_modulus", "poisson_ratio"]
unknowns = ["k_n", "k_t"]
[material]
young_modulus = 1.0
poisson_ratio = 0.15
tensile_strength = 0.2
shear_strength = 0.1
surface_energy = 1.5
restitution = 0.95
density = 1.0
[sample]
kind = "amorphous"
d0_over_dc = 0.6
l_over_d0 = 6.0
w_over_d0 = 3.0
seed = 1
[recipe]
seeds = [1, 2]
[verification]
samples = [{ seed = 11 }, { seed = 12, width = 2.0 }]
[solver]
method = "trust_region"
tolerance = 0.01
max_iterations = 20
"#;

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("calibrate-recipe-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn card_without_provenance(out: &Path) -> toml::Value {
    let mut v: toml::Value = std::fs::read_to_string(out.join("card.toml"))
        .unwrap()
        .parse()
        .unwrap();
    v.as_table_mut().unwrap().remove("provenance");
    v
}

fn files(dir: &Path) -> usize {
    std::fs::read_dir(dir).map_or(0, |d| d.count())
}

#[test]
fn recipe_level_calibration_is_cached_thread_independent_resumable_and_verified() {
    let cfg = CalibrationConfig::from_toml(TINY).unwrap();
    let (a, b, c) = (tmp("whole"), tmp("stopped"), tmp("serial"));
    let whole = calibrate(&cfg, &a, Parallelism::Threads(2), None).unwrap();
    let cp = &whole.checkpoint;
    assert_eq!(
        cp.state.status,
        Status::Converged,
        "{:?}",
        cp.history.last()
    );
    assert!(
        cp.state.r.iter().all(|r| r.abs() <= 0.01),
        "{:?}",
        cp.state.r
    );
    // The closed form misses E by ~20 % on these samples.
    assert!(cp.r0[0].abs() > 0.1, "{:?}", cp.r0);
    // Every evaluation reports the spread of its two samples (a standard error per residual).
    assert_eq!(cp.noise0.len(), 2);
    assert!(cp.noise0.iter().all(|v| *v > 0.0), "{:?}", cp.noise0);
    for rec in cp.history.iter().filter(|r| r.r_trial.is_some()) {
        assert_eq!(rec.noise_trial.len(), 2, "{rec:?}");
    }
    // Trial points that differ only in k_T share their samples: fewer relaxations than
    // evaluations times seeds (the sample cache also holds the verification's samples).
    let verified = whole
        .card
        .verification
        .as_ref()
        .map_or(0, |v| v.samples.len());
    let relaxed = files(&a.join("samples")) - verified;
    assert!(
        relaxed < 2 * cp.state.evaluations,
        "{relaxed} relaxations for {} evaluations",
        cp.state.evaluations
    );

    // The card records its recipe, its seeds and its verification on samples it never saw.
    let card = CalibratedCard::read(&a.join("card.toml")).unwrap();
    assert_eq!(card, whole.card);
    assert_eq!(card.seeds, vec![1, 2]);
    let v = card.verification.as_ref().expect("[verification]");
    assert_eq!(v.seeds, vec![11, 12]);
    assert_eq!(v.samples.len(), 2);
    assert!(v.samples[1].particles > v.samples[0].particles);
    // Each records how interpenetrated its relaxed packing is (a sound one: almost no pair overlaps
    // by half the smaller radius).
    for s in &v.samples {
        let deep = s.deep_overlaps.expect("deep overlaps recorded");
        assert!((0.0..0.1).contains(&deep), "{deep}");
    }
    for check in [&v.young_modulus, &v.poisson_ratio] {
        assert_eq!(check.values.len(), 2);
        let worst = check
            .values
            .iter()
            .map(|x| (x - check.target).abs() / check.target)
            .fold(0.0, f64::max);
        assert_eq!(check.spread, worst);
    }
    // Every property is measured, the surface energy from the tensile test run to separation, and
    // d* of eq 22 follows from the means.
    let g = v.surface_energy.mean;
    let (e, nu, st) = (
        v.young_modulus.mean,
        v.poisson_ratio.mean,
        v.shear_strength.mean,
    );
    assert!(g > 0.0 && v.surface_energy.target == 1.5);
    let dstar = 32.0 * g * e / (2.0 * (1.0 + nu)) / (st * st);
    assert!((v.dstar - dstar).abs() <= 1e-12 * dstar);
    // Each sample was sheared under load. Table 4's strengths (0.1-0.2 E) pull this recipe's
    // packings into themselves when they flow (measured 7.1 % at most on the two samples; the
    // closed-form Table 4 recipe at 10 x 10 x 6 d0 compacts by 25 % at shear strain 1,
    // docs/calibration.md "Shear under load"), so the card is marked as collapsing ...
    let sheared = v.compaction.as_ref().expect("compaction check");
    assert_eq!(sheared.values.len(), 2);
    assert_eq!(
        sheared.collapsed,
        sheared
            .values
            .iter()
            .filter(|&&x| x > sheared.limit)
            .count()
    );
    assert!(sheared.collapsed > 0 && !sheared.holds(), "{sheared:?}");
    for (s, x) in v.samples.iter().zip(&sheared.values) {
        assert_eq!(s.compaction, Some(*x));
    }
    // ... and a scenario refuses it before running anything, saying why.
    let source = calibrate::MaterialSource {
        card: Some(a.join("card.toml")),
        ..Default::default()
    };
    match source.resolve(&a, calibrate::Units::Reduced, card.model.law) {
        Err(calibrate::CalibrateError::CardCollapses { detail, .. }) => {
            assert!(detail.contains("collapsing"), "{detail}")
        }
        other => panic!("{other:?}"),
    }
    // A card verified before the test existed (no compaction table) is taken, and the scenario
    // states its verified figures and that it was not verified under shear.
    let old = a.join("old-card.toml");
    let mut table = toml::Value::try_from(&card).unwrap();
    table["verification"]
        .as_table_mut()
        .unwrap()
        .remove("compaction");
    std::fs::write(&old, toml::to_string(&table).unwrap()).unwrap();
    let source = calibrate::MaterialSource {
        card: Some(old.clone()),
        ..Default::default()
    };
    let resolved = source
        .resolve(&a, calibrate::Units::Reduced, card.model.law)
        .unwrap();
    std::fs::remove_file(&old).unwrap();
    assert_eq!(resolved.model, card.pair_model().unwrap());
    assert!(
        resolved.description.contains("verified on seeds [11, 12]")
            && resolved.description.contains("d* (eq 22)")
            && resolved.description.contains("not verified under shear"),
        "{}",
        resolved.description
    );

    // Stopped after two iterations (what a kill leaves) and resumed on one thread: the same
    // trajectory and the same card, bit for bit.
    let part = calibrate(&cfg, &b, Parallelism::Sequential, Some(2)).unwrap();
    assert_eq!(part.checkpoint.state.status, Status::Running);
    assert!(!b.join("card.toml").exists());
    let resumed = calibrate(&cfg, &b, Parallelism::Sequential, None).unwrap();
    assert_eq!(
        resumed.checkpoint.clone().without_times(),
        whole.checkpoint.clone().without_times()
    );
    assert_eq!(card_without_provenance(&b), card_without_provenance(&a));

    // A rerun of the finished calibration relaxes and tests nothing: every sample and evaluation
    // is cached (the sample directory does not grow, the card is the same).
    let before = files(&a.join("samples"));
    let again = calibrate(&cfg, &a, Parallelism::Sequential, None).unwrap();
    assert_eq!(files(&a.join("samples")), before);
    assert_eq!(again.card.model, whole.card.model);
    assert_eq!(card_without_provenance(&a), card_without_provenance(&b));

    // One thread from the start: the same bits as two.
    let serial = calibrate(&cfg, &c, Parallelism::Sequential, None).unwrap();
    assert_eq!(
        serial.checkpoint.without_times(),
        whole.checkpoint.clone().without_times()
    );
    for d in [a, b, c] {
        let _ = std::fs::remove_dir_all(d);
    }
}

/// The stage-3 multipliers of the fixed-sample calibration (docs/calibration.md): relaxed with them,
/// the packing collapses. The evaluation fails early, names the sample and the reason, and the
/// failure is cached like a result.
#[test]
fn a_trial_under_which_the_packing_collapses_is_a_failed_evaluation_with_its_reason() {
    let text = TINY.replace(
        "unknowns = [\"k_n\", \"k_t\"]",
        "unknowns = [\"k_n\", \"k_t\", \"delta_e\", \"delta_f\", \"f_mt\"]",
    );
    let cfg = CalibrationConfig::from_toml(&text).unwrap();
    let out = tmp("collapse");
    std::fs::create_dir_all(&out).unwrap();
    let prob = calibrate::run::problem(&cfg, Some(&out)).unwrap();
    let x: Vec<f64> = [0.8079f64, 0.8604, 2.0454, 0.961, 0.75]
        .iter()
        .map(|v| v.ln())
        .collect();
    let e = prob.evaluate(&x).unwrap_err();
    assert!(
        e.0.contains("sample seed") && e.0.contains("collapses"),
        "{e}"
    );
    // The failed relaxation is cached with its reason: a new problem on the same directory gives
    // the same failure from the file.
    let failed = std::fs::read_dir(out.join("samples"))
        .unwrap()
        .filter(|f| {
            f.as_ref()
                .unwrap()
                .path()
                .to_string_lossy()
                .ends_with(".failed.json")
        })
        .count();
    assert!(failed >= 1);
    let again = calibrate::run::problem(&cfg, Some(&out))
        .unwrap()
        .evaluate(&x)
        .unwrap_err();
    assert_eq!(again, e);
    let _ = std::fs::remove_dir_all(&out);
}

/// `[tests.compaction]`: every evaluation also shears its samples under load, and a trial under which
/// one compacts is a failed evaluation naming the sample and the compaction. The tiny Table 4 recipe
/// at its closed form compacts (as the verification of the test above measures); without the table
/// the same point is a measurement.
#[test]
fn with_tests_compaction_a_packing_that_compacts_under_shear_is_a_failed_evaluation() {
    let text = TINY.replace("[verification]", "[tests.compaction]\n[verification]");
    let cfg = CalibrationConfig::from_toml(&text).unwrap();
    let e = calibrate::run::problem(&cfg, None)
        .unwrap()
        .evaluate(&[0.0, 0.0])
        .unwrap_err();
    assert!(
        e.0.contains("sample seed") && e.0.contains("compaction test: the packing compacted by"),
        "{e}"
    );
    let plain = CalibrationConfig::from_toml(TINY).unwrap();
    let m = calibrate::run::problem(&plain, None)
        .unwrap()
        .evaluate(&[0.0, 0.0])
        .unwrap();
    assert!(m.r.iter().all(|r| r.is_finite()));
}

#[test]
fn continuation_relaxes_a_trial_from_the_closed_form_sample() {
    // `[relax] continuation = true`: the closed-form point relaxes from the insertion as the paper
    // does (the same residuals as without the option); a trial point runs phase 2 only, with the trial
    // model, from that closed-form sample of the same seed: another sample, another response.
    let plain = CalibrationConfig::from_toml(TINY).unwrap();
    let cont = CalibrationConfig::from_toml(&TINY.replace(
        "seeds = [1, 2]",
        "seeds = [1, 2]\n[relax]\ncontinuation = true",
    ))
    .unwrap();
    let (out_p, out_c) = (tmp("plain"), tmp("continued"));
    for o in [&out_p, &out_c] {
        std::fs::create_dir_all(o.join("samples")).unwrap();
    }
    let pp = calibrate::run::problem(&plain, Some(&out_p)).unwrap();
    let pc = calibrate::run::problem(&cont, Some(&out_c)).unwrap();
    assert_eq!(
        pp.evaluate(&[0.0, 0.0]).unwrap().r,
        pc.evaluate(&[0.0, 0.0]).unwrap().r
    );
    let x = [0.15, 0.0];
    let (tp, tc) = (pp.evaluate(&x).unwrap(), pc.evaluate(&x).unwrap());
    assert_ne!(tp.r, tc.r, "a continued sample is another sample");
    let samples: Vec<dem::sample::Sample> = std::fs::read_dir(out_c.join("samples"))
        .unwrap()
        .map(|f| dem::sample::Sample::load(&f.unwrap().path()).unwrap())
        .collect();
    assert_eq!(
        samples.len(),
        4,
        "two closed-form samples and two continued ones"
    );
    let report = |s: &dem::sample::Sample| s.relaxation.clone().unwrap();
    let continued: Vec<_> = samples
        .iter()
        .filter(|s| report(s).phase1_steps == 0)
        .collect();
    assert_eq!(continued.len(), 2);
    for s in continued {
        let r = report(s);
        assert!(r.converged && r.phase2_steps > 0, "{r:?}");
    }
    // The card says how its samples are made, so that a scenario relaxing a new sample with it
    // (`ResolvedMaterial::relax_for`, the patch file) continues from the closed form too.
    let one = CalibrationConfig::from_toml(
        &TINY
            .replace(
                "seeds = [1, 2]",
                "seeds = [1, 2]\n[relax]\ncontinuation = true",
            )
            .replace("max_iterations = 20", "max_iterations = 1")
            .replace("[verification]", "[verification]\nskip = true"),
    )
    .unwrap();
    let card = calibrate(&one, &out_c.join("run"), Parallelism::Sequential, None)
        .unwrap()
        .card;
    assert!(card.relax.continuation && card.verification.is_none());
    let patch = std::fs::read_to_string(out_c.join("run").join("patch.toml")).unwrap();
    assert!(patch.contains("continuation = true"), "{patch}");
    let source = calibrate::MaterialSource {
        card: Some(out_c.join("run").join("card.toml")),
        ..Default::default()
    };
    let material = source
        .resolve(
            Path::new("."),
            calibrate::Units::Reduced,
            dem::material::ForceLaw::Cohesive,
        )
        .unwrap();
    assert!(
        material
            .relax_for(dem::sample::RelaxConfig::default())
            .continuation
    );
    for o in [&out_p, &out_c] {
        let _ = std::fs::remove_dir_all(o);
    }
}

#[test]
fn verification_seeds_must_be_fresh() {
    let text = TINY.replace("{ seed = 11 }", "{ seed = 2 }");
    let e = CalibrationConfig::from_toml(&text)
        .unwrap()
        .prepare()
        .unwrap_err();
    assert!(e.to_string().contains("never saw"), "{e}");
}

/// Issue 16's acceptance on a config of `configs/`: the calibration converges (no budget stop), and
/// the card on its verification samples (fresh seeds, one twice as thick) gives E, nu, sigma_N,
/// sigma_T within 5 % of target in the mean and within 10 % on each sample. Runs in
/// `runs/<config stem>` so that a rerun resumes (`cgdem calibrate` on the same config and directory
/// shares the work).
fn issue16_acceptance(config_file: &str) {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let cfg =
        CalibrationConfig::from_toml(&std::fs::read_to_string(root.join(config_file)).unwrap())
            .unwrap();
    let stem = Path::new(config_file)
        .file_stem()
        .unwrap()
        .to_string_lossy();
    let out = root.join("runs").join(stem.as_ref());
    let o = calibrate(&cfg, &out, Parallelism::Threads(2), None).unwrap();
    let v = o.card.verification.as_ref().expect("[verification]");
    let mut report = String::new();
    for t in [
        calibrate::Target::YoungModulus,
        calibrate::Target::PoissonRatio,
        calibrate::Target::TensileStrength,
        calibrate::Target::ShearStrength,
    ] {
        let c = v.get(t);
        report.push_str(&format!(
            "{}: mean {:+.2} %, spread {:.2} %\n",
            t.name(),
            100.0 * c.mean_error(),
            100.0 * c.spread
        ));
    }
    eprintln!(
        "{config_file}:\n{report}status {:?}",
        o.card.provenance.status
    );
    assert_eq!(v.failures(), 0, "{:?}", v.samples);
    assert_eq!(o.card.provenance.status, Status::Converged, "{report}");
    for t in [
        calibrate::Target::YoungModulus,
        calibrate::Target::PoissonRatio,
        calibrate::Target::TensileStrength,
        calibrate::Target::ShearStrength,
    ] {
        let c = v.get(t);
        assert!(c.mean_error().abs() <= 0.05, "{}: {report}", t.name());
        assert!(c.spread <= 0.10, "{}: {report}", t.name());
    }
}

#[test]
#[ignore = "issue 16 acceptance, ~20 min on 2 cores (not met yet: docs/calibration.md)"]
fn table4_amorphous_card_holds_on_fresh_samples() {
    issue16_acceptance("configs/calibrate-amorphous.toml");
}

#[test]
#[ignore = "issue 16 acceptance, ~25 min on 2 cores (not met yet: stalls, sigma_N -5.5 %; docs/calibration.md)"]
fn silica_card_holds_on_fresh_samples() {
    issue16_acceptance("configs/calibrate-silica.toml");
}
