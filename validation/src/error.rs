//! The crate's error type.

/// What can go wrong while drawing figures or reading their data.
#[derive(Debug, thiserror::Error)]
pub enum ValidationError {
    /// A curve file could not be read or parsed.
    #[error("curve file {path}: {reason}")]
    Curve { path: String, reason: String },
    /// plotters failed to draw or to write the image.
    #[error("figure {path}: {reason}")]
    Draw { path: String, reason: String },
    /// A run the report needs failed or is not finished.
    #[error("run: {0}")]
    Run(String),
    /// The engine refused or failed a run.
    #[error(transparent)]
    Dem(#[from] dem::DemError),
}

pub type Result<T> = std::result::Result<T, ValidationError>;
