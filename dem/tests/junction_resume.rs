//! A junction run interrupted (Ctrl-C) continues from its progress file to the same result, to the last
//! bit, as an uninterrupted one, and its dump holds each frame once. One test in this binary: the
//! interrupt flag is process-wide.

use dem::material::{Material, PairModel, SiMaterial};
use dem::sample::{make_sample, RelaxConfig, SampleSpec};
use dem::scenario::junction::{run_resumable, JunctionConfig, JunctionResult};
use dem::{Parallelism, UnitSystem};

mod common;

fn timeless(r: &JunctionResult) -> String {
    let mut r = r.clone();
    r.wall_seconds = 0.0;
    format!("{r:?}")
}

#[test]
fn an_interrupted_junction_resumes_bit_identically() {
    let u = UnitSystem::NANO;
    let model = PairModel::cohesive(Material::from_si(&SiMaterial::table5(), u));
    let cfg = JunctionConfig {
        lengths: [36.0, 30.0, 24.0],
        diameter: 10.0,
        d0: 6.0,
        duration: 1.0,
        frames: 20,
        force_samples: 100,
        dump_frames: 10,
        ..JunctionConfig::default()
    };
    let spec = SampleSpec::Amorphous {
        d0_over_dc: cfg.d0 / model.material.critical_diameter(),
        l_over_d0: 6.0,
        w_over_d0: 4.0,
        h_over_d0: Some(5.0),
        ds_over_d0: 0.75,
        dl_over_d0: 1.25,
        dl_over_l: None,
        seed: 5,
        insert_fraction: 0.75,
    };
    let sample = make_sample(
        &spec,
        &model,
        &RelaxConfig::default(),
        Parallelism::Sequential,
    )
    .unwrap();
    common::assert_resumes_bit_identically(
        "junction",
        &|dump, progress, report| {
            run_resumable(
                &sample,
                &model,
                &cfg,
                Parallelism::Sequential,
                Some(dump),
                progress,
                report,
            )
        },
        timeless,
    );
}
