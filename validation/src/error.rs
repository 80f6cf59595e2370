//! The crate's error type.

/// What can go wrong while drawing figures, reading their data or building the report.
#[derive(Debug, thiserror::Error)]
pub enum ValidationError {
    /// A curve file could not be read or parsed.
    #[error("curve file {path}: {reason}")]
    Curve { path: String, reason: String },
    /// plotters failed to draw or to write the image.
    #[error("figure {path}: {reason}")]
    Draw { path: String, reason: String },
    /// A report file could not be written or read.
    #[error("{path}: {reason}")]
    Io { path: String, reason: String },
    /// The engine refused or failed a case (including an interrupt).
    #[error(transparent)]
    Dem(#[from] dem::DemError),
    /// A calibration failed.
    #[error(transparent)]
    Calibrate(#[from] calibrate::CalibrateError),
    /// An MD job failed (LAMMPS, the venv, the worker).
    #[error(transparent)]
    Md(#[from] md_bridge::MdError),
    /// A report case gave something it cannot give (a bug or a damaged cache).
    #[error("report: {0}")]
    Report(String),
}

pub type Result<T> = std::result::Result<T, ValidationError>;
