//! Shear under normal load (`dem::scenario::patch::compaction`): the check that tells a packing that
//! holds its volume when it flows from one that is pulled into itself. Paper 000 Table 5 silica on a
//! 12 x 12 x 4 d0 sample of the junction's recipe (d0 = 3 nm, d_s = 0.75 d0, d_l = 7.5 nm, s = 1/2,
//! 393 particles): with the closed-form parameters it dilates once it flows, with the long attraction
//! range the calibrated silica cards chose (delta_e x 1.22, delta_f x 2) it compacts past the limit,
//! as those cards did in the junction (docs/junction.md, "Calibrated cards collapse under shear").

use dem::material::{Material, PairModel, ParamScale, SiMaterial};
use dem::sample::{make_sample, RelaxConfig, Sample, SampleSpec};
use dem::scenario::patch::{compaction, CompactionConfig, CompactionResult};
use dem::{DemError, Parallelism, UnitSystem};

fn silica_sample(model: &PairModel) -> Sample {
    let d_c = model.material.critical_diameter();
    let spec = SampleSpec::Amorphous {
        d0_over_dc: 3.0 / d_c,
        l_over_d0: 12.0,
        w_over_d0: 4.0,
        h_over_d0: None,
        ds_over_d0: 0.75,
        dl_over_d0: 2.5,
        dl_over_l: None,
        seed: 1,
        insert_fraction: 0.75,
    };
    make_sample(
        &spec,
        model,
        &RelaxConfig::default(),
        Parallelism::Sequential,
    )
    .unwrap()
}

fn closed_form() -> PairModel {
    PairModel::cohesive(Material::from_si(&SiMaterial::table5(), UnitSystem::NANO))
}

fn long_range() -> PairModel {
    let mut m = closed_form();
    m.scale = ParamScale {
        delta_e: 1.22,
        delta_f: 2.0,
        ..ParamScale::default()
    };
    m
}

fn timeless(r: &CompactionResult) -> String {
    let mut r = r.clone();
    r.wall_seconds = 0.0;
    format!("{r:?} {:?}", r.curve)
}

#[test]
fn closed_form_silica_holds_its_volume_when_it_flows() {
    let model = closed_form();
    let sample = silica_sample(&model);
    let cfg = CompactionConfig::default();
    let r = compaction(&sample, &model, &cfg, Parallelism::Sequential).unwrap();
    assert!(!r.collapsed, "{r:?}");
    assert!(
        (r.shear_strain - 1.0).abs() < 0.01,
        "ran to strain 1: {r:?}"
    );
    // Measured 1.33 % at most (near the shear peak), then a dilation: -2.3 % at strain 1.
    assert!(r.largest_compaction < 0.02, "{r:?}");
    assert!(
        r.compaction < 0.0,
        "a flowing cohesive packing dilates: {r:?}"
    );
    // Under the load alone the sample is compressed by about p / C11 (C11 ~ E here: 1 %).
    let p = cfg.pressure * model.material.young_modulus;
    assert_eq!(r.pressure, p);
    assert!(
        r.loaded_strain < -0.3 * cfg.pressure && r.loaded_strain > -5.0 * cfg.pressure,
        "{r:?}"
    );
    // It flows: the wall is resisted by a shear traction of the order of the shear strength, far
    // above the pressure (cohesion), and the curve covers the load and the shear phases.
    assert!(r.friction > 1.0 && r.friction < 20.0, "{r:?}");
    let steps = r.curve.points.last().unwrap().step;
    assert_eq!(steps, r.steps);
    assert!(r.curve.points.iter().all(|c| c.strain_yy.is_finite()));
}

#[test]
fn a_long_attraction_range_pulls_the_packing_into_itself_and_the_test_stops_there() {
    let model = long_range();
    let sample = silica_sample(&model);
    let cfg = CompactionConfig::default();
    let r = compaction(&sample, &model, &cfg, Parallelism::Sequential).unwrap();
    // Measured: 5.2 % at shear strain 0.26, while the closed form had 1.33 % at most.
    assert!(r.collapsed, "{r:?}");
    assert!(r.largest_compaction > cfg.max_compaction, "{r:?}");
    assert!(r.shear_strain < 0.6, "stopped at the limit: {r:?}");
    // The same bits on two threads.
    let two = compaction(&sample, &model, &cfg, Parallelism::Threads(2)).unwrap();
    assert_eq!(timeless(&r), timeless(&two));
}

#[test]
fn bad_settings_are_refused_with_the_reason() {
    let model = closed_form();
    let sample = silica_sample(&model);
    for (cfg, what) in [
        (
            CompactionConfig {
                pressure: 0.0,
                ..CompactionConfig::default()
            },
            "pressure",
        ),
        (
            CompactionConfig {
                strain: -1.0,
                ..CompactionConfig::default()
            },
            "strain",
        ),
        (
            CompactionConfig {
                max_compaction: f64::NAN,
                ..CompactionConfig::default()
            },
            "max_compaction",
        ),
        (
            CompactionConfig {
                record_every: 0,
                ..CompactionConfig::default()
            },
            "record_every",
        ),
    ] {
        match compaction(&sample, &model, &cfg, Parallelism::Sequential) {
            Err(DemError::InvalidConfig(m)) => assert!(m.contains(what), "{what}: {m}"),
            other => panic!("{what}: {other:?}"),
        }
    }
}
