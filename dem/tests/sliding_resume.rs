//! An interrupted sliding run (paper 004) resumes bit-identically, dump included. Alone in its file:
//! the interrupt flag is process-wide.

use dem::material::PairModel;
use dem::sample::{make_sample, RelaxConfig, Sample};
use dem::scenario::sliding::{run_resumable, SlidingConfig, SlidingMaterial, SlidingResult};
use dem::Parallelism;

mod common;

/// L = 10 d0 (d0 = 0.1 L), d* = 0.3 L, p_N = 0.02 E, half an L of sliding in 4 windows of 5 samples.
fn small() -> (Sample, PairModel, SlidingConfig) {
    let cfg = SlidingConfig {
        d0_over_l: 0.1,
        material: SlidingMaterial {
            strength: 0.1,
            surface_energy: None,
            d_star: Some(0.3),
        },
        pressure: 0.02,
        distance_over_l: 0.5,
        bins: 40,
        windows: 4,
        samples_per_window: 5,
        force_samples: 100,
        dump_frames: 0,
        ..SlidingConfig::default()
    };
    let model = cfg.model().unwrap();
    let sample = make_sample(
        &cfg.recipe().unwrap(),
        &model,
        &RelaxConfig::default(),
        Parallelism::Sequential,
    )
    .unwrap();
    (sample, model, cfg)
}

fn timeless(r: &SlidingResult) -> String {
    let mut r = r.clone();
    r.wall_seconds = 0.0;
    format!("{r:?}")
}

#[test]
fn an_interrupted_sliding_run_resumes_bit_identically() {
    let (sample, model, cfg) = small();
    let cfg = SlidingConfig {
        dump_frames: 5,
        ..cfg
    };
    common::assert_resumes_bit_identically(
        "sliding",
        &|dump, progress, report| {
            run_resumable(
                &sample,
                &model,
                &cfg,
                0.022,
                Parallelism::Sequential,
                Some(dump),
                progress,
                report,
            )
        },
        timeless,
    );
}
