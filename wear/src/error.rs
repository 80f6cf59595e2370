//! The crate's one error type: inputs that cannot be classified or searched are refused with the reason.

/// What the classifier and the search refuse.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum WearError {
    /// Frames or series that do not describe one set of members over time.
    #[error("invalid frames: {0}")]
    Frames(String),
    /// A search or classification setting that makes no sense.
    #[error("invalid setting: {0}")]
    Setting(String),
}

/// Result alias of the crate.
pub type Result<T, E = WearError> = std::result::Result<T, E>;
