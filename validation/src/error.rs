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
    /// A config file that cannot be read as its kind.
    #[error("config {path}: {reason}")]
    Config { path: String, reason: String },
    /// A file could not be written or read (the cause is in the message).
    #[error("{path}: {reason}")]
    Io { path: String, reason: String },
    /// The engine refused or failed a case (including an interrupt).
    #[error(transparent)]
    Dem(#[from] dem::DemError),
    /// A calibration failed, or a material source or card cannot be used.
    #[error(transparent)]
    Calibrate(#[from] calibrate::CalibrateError),
    /// An MD job failed (LAMMPS, the venv, the worker).
    #[error(transparent)]
    Md(#[from] md_bridge::MdError),
    /// The classifier or the d* search refused its input.
    #[error(transparent)]
    Wear(#[from] wear::WearError),
    /// A Slurm array task ran its share of the pending jobs; the collected outputs come from a later
    /// run of the same command.
    #[error("this task ran its share of the jobs in {0}; run the command again without --shard once every task has finished, to collect the results and continue")]
    ShardDone(String),
    /// A report case gave something it cannot give (a bug or a damaged cache).
    #[error("report: {0}")]
    Report(String),
}

impl ValidationError {
    /// An i/o failure on `path`.
    pub(crate) fn io(path: &std::path::Path, cause: std::io::Error) -> Self {
        ValidationError::Io {
            path: path.display().to_string(),
            reason: cause.to_string(),
        }
    }
}

pub type Result<T> = std::result::Result<T, ValidationError>;
