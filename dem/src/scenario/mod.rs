//! Scenarios: complete numerical experiments built on the engine. Each is a function with a typed serde
//! configuration (defaults are the papers' values) and a typed result, deterministic for a given sample
//! and model, returning errors rather than panicking.
//! - [`pair`]: two-particle experiments against paper 000's closed forms (period, stability limit,
//!   restitution, bond work), shared by the engine's tests and the validation report;
//! - [`rig`]: the shared ground: a sample between two rigid walls along a chosen axis;
//! - [`driven`]: the top wall dragged under pressure, and the resumable observed run the junction and
//!   the sliding layer share;
//! - [`patch`]: the patch tests of paper 000 section 3 (elastic constants, tensile and shear strength,
//!   fracture energy), the inner loop of the calibration;
//! - [`junction`]: junction shear of paper 000 section 4, plastic smoothing or a rolling wear particle;
//! - [`monolayer`]: the quasi-2D hex monolayer as a material (closed form to 2D properties, and their
//!   measurement), the DEM side of the comparison with the 2D MD model material;
//! - [`plastic`]: plastic wear by impact and scratching (paper 001), a rigid sphere against a surface
//!   of non-interacting spheres, with its own contact loop;
//! - [`sliding`]: sliding with a third-body layer (paper 004), its profiles, rho_TBL, p_T and regime.

pub mod driven;
pub mod junction;
pub mod monolayer;
pub mod pair;
pub mod patch;
pub mod plastic;
pub mod rig;
pub mod sliding;

use crate::error::{DemError, Result};

/// The most steps a scenario plans before it refuses to start: hours of the smallest loop (the
/// impact's, ~1e6 steps/s) and years of a paper-size box. The papers' runs need 1e3-1e6 steps; a plan
/// far beyond that comes from an input in the wrong units (a hardness of 1.7 for 1.7 GPa takes the
/// impact's contact time to 1e9 times the real one), which otherwise runs silently for ever.
pub const MAX_PLANNED_STEPS: f64 = 1e9;

/// `steps` (a plan: a time or a distance over a speed, divided by the time step, rounded by the caller)
/// as a count, or an error naming `what` when the plan is not finite or exceeds
/// [`MAX_PLANNED_STEPS`].
pub fn step_budget(what: &str, steps: f64) -> Result<u64> {
    if steps.is_finite() && steps <= MAX_PLANNED_STEPS {
        return Ok(steps.max(0.0) as u64);
    }
    Err(DemError::InvalidConfig(format!(
        "{what} would take {steps:.3e} steps, more than the {MAX_PLANNED_STEPS:.0e} any scenario \
         plans: check the inputs' units (SI where the config says so)"
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_plan_beyond_the_budget_or_not_finite_is_refused_with_its_figures() {
        assert_eq!(step_budget("run", 20.0).unwrap(), 20);
        let e = step_budget("the impact", 1e15).unwrap_err().to_string();
        assert!(e.contains("the impact would take 1.000e15 steps"), "{e}");
        for n in [f64::INFINITY, f64::NAN, 2e9] {
            assert!(step_budget("run", n).is_err(), "{n}");
        }
    }
}
