//! An interrupted sliding run (paper 004) resumes bit-identically, dump included. Alone in its file:
//! the interrupt flag is process-wide.

use dem::material::PairModel;
use dem::sample::Sample;
use dem::scenario::sliding::{run_resumable, SlidingConfig, SlidingResult};
use dem::Parallelism;

mod common;

/// The common small box with 0.5 L of sliding.
fn small() -> (Sample, PairModel, SlidingConfig) {
    common::small_sliding(0.5)
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
