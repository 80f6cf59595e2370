//! The one error type of the `dem` crate.
//!
//! Numerical and input failures are values (`DemError`), never panics: a researcher's script must be able
//! to report which particle, which parameter or which step went wrong.

use thiserror::Error;

/// Everything the engine can refuse or fail at.
#[derive(Debug, Error)]
pub enum DemError {
    /// A material property outside the range the model can represent.
    #[error("invalid material: {0}")]
    InvalidMaterial(String),
    /// A particle with a non-physical attribute (radius, mass, position ...).
    #[error("invalid particle {index}: {reason}")]
    InvalidParticle { index: usize, reason: String },
    /// The simulation box cannot hold the requested configuration.
    #[error("invalid box: {0}")]
    InvalidBox(String),
    /// A configuration value that makes no sense (negative skin, unknown group ...).
    #[error("invalid configuration: {0}")]
    InvalidConfig(String),
    /// Time step above the critical one of paper 000 eq (6).
    #[error(
        "time step {dt:.6e} exceeds the critical time step {dt_critical:.6e} (paper 000 eq 6); \
         lower it or set allow_supercritical_dt = true"
    )]
    TimeStepAboveCritical { dt: f64, dt_critical: f64 },
    /// Two rigid groups (walls) whose particles overlap in space.
    #[error("rigid groups '{a}' and '{b}' overlap: {detail}")]
    OverlappingRigidGroups {
        a: String,
        b: String,
        detail: String,
    },
    /// A NaN or infinity appeared during integration.
    #[error("non-finite value at step {step} for particle {index} ({what}); the run diverged (time step too large, or overlapping particles?)")]
    NonFinite {
        step: u64,
        index: usize,
        what: &'static str,
    },
    /// The two-phase relaxation of an amorphous sample failed under the given pair model (its stresses
    /// grew to the order of E instead of decaying): no sample, with the reason.
    #[error("relaxation failed at phase-2 step {step}: {reason}")]
    RelaxationFailed { step: u64, reason: String },
    /// A driven run whose material gave way as a whole (the junction's solids compacting under the
    /// shear): no result, with the evidence.
    #[error("the material collapsed at step {step}: {reason}")]
    MaterialCollapsed { step: u64, reason: String },
    /// The run was interrupted (Ctrl-C) before this step; the state is that of the end of the previous step.
    #[error("interrupted at step {step}")]
    Interrupted { step: u64 },
    /// Reading or writing a file failed. The cause is part of the message and not also the error's
    /// source: reports would print it twice, and messages flattened to text keep it.
    #[error("i/o error on {path}: {cause}")]
    Io { path: String, cause: std::io::Error },
    /// A job of a shared list failed (on this process or on another rank); its folder says why.
    #[error("job {key} failed: {reason}")]
    JobFailed { key: String, reason: String },
    /// A checkpoint or sample file that cannot be parsed.
    #[error("malformed file {path}: {reason}")]
    Format { path: String, reason: String },
}

/// Result alias used throughout the crate.
pub type Result<T, E = DemError> = std::result::Result<T, E>;

impl DemError {
    pub(crate) fn io(path: &std::path::Path, cause: std::io::Error) -> Self {
        DemError::Io {
            path: path.display().to_string(),
            cause,
        }
    }
}

/// Names the first of `fields` (name, value) that is not a finite positive number, as
/// "name = value must be positive", for the caller to wrap in its own error; None when all are.
pub fn not_positive(fields: &[(&str, f64)]) -> Option<String> {
    fields
        .iter()
        .find(|(_, v)| !(v.is_finite() && *v > 0.0))
        .map(|(n, v)| format!("{n} = {v} must be positive"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn not_positive_names_the_first_offender() {
        assert_eq!(not_positive(&[("a", 1.0), ("b", 2e-300)]), None);
        assert_eq!(
            not_positive(&[("a", 1.0), ("b", 0.0), ("c", -1.0)]).as_deref(),
            Some("b = 0 must be positive")
        );
        assert!(not_positive(&[("a", f64::NAN)])
            .unwrap()
            .starts_with("a = NaN"));
        assert!(not_positive(&[("a", f64::INFINITY)]).is_some());
    }
}
