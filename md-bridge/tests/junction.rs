//! MD junction shear of the 2D model material (cut-off 1.3 sigma, measured d* ~ 25 sigma) on both
//! sides of d*: D ~ 0.5 d* must smooth plastically, D ~ 2 d* must come off as a rolling wear
//! particle, and the shared classifier must say so. Compact geometry (period 2 D, slabs 0.35 D)
//! keeps the large case near a minute.

mod common;

use md_bridge::junction::{run, JunctionConfig};
use wear::Outcome;

fn config(width: f64) -> JunctionConfig {
    JunctionConfig {
        width,
        length_factor: 2.0,
        slab_factor: 0.35,
        dump_file: None,
        ..JunctionConfig::default()
    }
}

#[test]
fn junctions_below_and_above_d_star_give_opposite_outcomes() {
    let small = run(&common::lammps(), &config(12.0)).unwrap();
    let v = &small.verdict;
    eprintln!(
        "D = 12: {:?} turn {:.2} rigidity {:.2} {:?}",
        v.outcome, v.turn, v.rigidity, v.detachment
    );
    assert_eq!(v.outcome, Outcome::PlasticSmoothing, "{v:?}");
    assert!(
        v.turn.abs() < 1.0,
        "a smoothed junction does not roll: {}",
        v.turn
    );
    // The cluster analysis agrees: no body of junction atoms lost the walls (measured 0.08).
    let d = v.detachment.as_ref().unwrap();
    assert!(d.debris_fraction < 0.3, "{d:?}");

    let large = run(&common::lammps(), &config(50.0)).unwrap();
    let v = &large.verdict;
    eprintln!(
        "D = 50: {:?} turn {:.2} rigidity {:.2} {:?}",
        v.outcome, v.turn, v.rigidity, v.detachment
    );
    assert_eq!(
        v.outcome,
        Outcome::WearParticle,
        "turn {} rigidity {}",
        v.turn,
        v.rigidity
    );
    // Corroboration from the force history: once detached, the top wall drags a rolling particle.
    assert!(v.force_late_over_peak.unwrap() < 0.5, "{v:?}");
    // ... and from the cluster analysis: the junction came off as one body (measured 0.997).
    let d = v.detachment.as_ref().unwrap();
    assert!(d.debris_fraction > 0.9, "{d:?}");
    assert!(large.junction_atoms > 1000 && small.junction_atoms < 100);
}
