//! Ctrl-C handling: a requested interrupt stops the next step with a typed error and leaves the state of
//! the last completed step, from which the run continues exactly. (Own test binary: the flag is global.)

mod common;

use common::*;
use dem::{DemError, Material, PairModel, RunConfig};

#[test]
fn interrupt_stops_at_a_step_boundary_and_the_run_can_continue() {
    let model = PairModel::cohesive(Material::table4(0.1));
    let mut a = sim(
        pair_of(45.0, -1.0),
        open_box(1e4),
        model.clone(),
        RunConfig::default(),
    );
    let mut b = sim(
        pair_of(45.0, -1.0),
        open_box(1e4),
        model,
        RunConfig::default(),
    );
    a.run(50).unwrap();
    dem::interrupt::request();
    let err = a.step().unwrap_err();
    assert!(matches!(err, DemError::Interrupted { step: 50 }), "{err}");
    assert_eq!(a.step_count(), 50, "the interrupted step did not happen");
    dem::interrupt::clear();
    a.run(50).unwrap();
    b.run(100).unwrap();
    assert_eq!(a.particles.pos, b.particles.pos);
}
