//! The one error type of the `calibrate` crate.

use thiserror::Error;

/// Everything calibration can refuse or fail at. A failed *evaluation* (a patch test that diverges or
/// gives NaN) is not an error: the executor records it and rejects the step; only failures that leave
/// nothing to iterate on end up here.
#[derive(Debug, Error)]
pub enum CalibrateError {
    /// The targets cannot be reached by the chosen force law; refused before any simulation runs.
    #[error("unreachable target: {0}")]
    Unreachable(String),
    /// A configuration value that makes no sense.
    #[error("invalid calibration config: {0}")]
    InvalidConfig(String),
    /// The engine refused an input (sample, material, test settings).
    #[error(transparent)]
    Dem(#[from] dem::DemError),
    /// The starting point itself cannot be evaluated, so there is no residual to reduce.
    #[error("the first guess cannot be evaluated: {0}")]
    StartFailed(String),
    /// A checkpoint written for other inputs: resuming from it would mix two calibrations.
    #[error("checkpoint {path} belongs to other inputs (fingerprint {found}, expected {expected}); use another --out or delete it")]
    ForeignCheckpoint {
        path: String,
        found: String,
        expected: String,
    },
    /// Interrupted (Ctrl-C) between two rounds of evaluations: everything computed is on disk, and
    /// the same command resumes.
    #[error("interrupted; the evaluations so far are saved: rerun the same command to continue")]
    Interrupted,
    /// A calibrated card whose verification samples compacted under shear: a scenario run with it
    /// collapses (docs/junction.md), so it is refused before any simulation.
    #[error("card {path} is not usable in a scenario: {detail}; recalibrate with [tests.compaction] (docs/calibration.md, \"Shear under load\")")]
    CardCollapses { path: String, detail: String },
    /// Reading or writing a file failed.
    #[error("i/o error on {path}: {reason}")]
    Io { path: String, reason: String },
    /// A file that cannot be parsed or serialised.
    #[error("format error on {path}: {reason}")]
    Format { path: String, reason: String },
}

/// Result alias of the crate.
pub type Result<T, E = CalibrateError> = std::result::Result<T, E>;

impl CalibrateError {
    pub(crate) fn io(path: &std::path::Path, e: impl std::fmt::Display) -> Self {
        CalibrateError::Io {
            path: path.display().to_string(),
            reason: e.to_string(),
        }
    }
    pub(crate) fn format(path: &std::path::Path, e: impl std::fmt::Display) -> Self {
        CalibrateError::Format {
            path: path.display().to_string(),
            reason: e.to_string(),
        }
    }
}
