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
    /// A config file that cannot be read as its kind.
    #[error("config {path}: {reason}")]
    Config { path: String, reason: String },
    /// Reading or writing a file failed (the cause is in the message only, as elsewhere).
    #[error("i/o error on {path}: {cause}")]
    Io { path: String, cause: std::io::Error },
    /// The engine refused an input or failed.
    #[error(transparent)]
    Dem(#[from] dem::DemError),
    /// A material source or card that cannot be used.
    #[error(transparent)]
    Calibrate(#[from] calibrate::CalibrateError),
    /// A Slurm array task ran its share of the pending jobs; the collected outputs come from a later
    /// run of the same command.
    #[error("this task ran its share of the jobs in {0}; run the command again without --shard once every task has finished, to collect the results and continue")]
    ShardDone(String),
    /// The classifier or the d* search refused its input.
    #[error(transparent)]
    Wear(#[from] wear::WearError),
}

impl ValidationError {
    pub(crate) fn io(path: &std::path::Path, cause: std::io::Error) -> Self {
        ValidationError::Io {
            path: path.display().to_string(),
            cause,
        }
    }
}

pub type Result<T> = std::result::Result<T, ValidationError>;
