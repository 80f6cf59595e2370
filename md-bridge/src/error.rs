//! The crate's one error type. LAMMPS failures keep LAMMPS's own message and the command that
//! caused them, so a caller (or a user reading the CLI output) sees exactly what LAMMPS objected to.

use std::path::PathBuf;

/// The command that provisions (or repairs) the project's Python venv.
pub const SETUP_COMMAND: &str = "bash scripts/setup-venv";

/// Everything that can go wrong between the workbench and LAMMPS.
#[derive(Debug, thiserror::Error)]
pub enum MdError {
    /// The venv is missing or broken; the message names the fix.
    #[error("Python venv at {path} is unusable: {problem}; fix it with `{SETUP_COMMAND}` (from the repo root)")]
    Venv { path: PathBuf, problem: String },
    /// A Python-level failure outside a LAMMPS command (import, conversion).
    #[error("Python error: {0}")]
    Python(String),
    /// LAMMPS rejected a command; the instance is still usable.
    #[error("LAMMPS error in command `{command}`: {message}")]
    Lammps { command: String, message: String },
    /// A LAMMPS query returned nothing (unknown compute/variable, atom map missing...).
    #[error("LAMMPS query `{query}` failed: {reason}")]
    Query { query: String, reason: String },
    /// Reading or writing a file failed. The cause is part of the message (which the worker's report
    /// carries as text) and not also the error's source, which reports would print a second time.
    #[error("I/O error on {path}: {cause}")]
    Io {
        path: PathBuf,
        cause: std::io::Error,
    },
    /// A config or job file that does not parse or holds values out of range.
    #[error("invalid input {what}: {message}")]
    Config { what: String, message: String },
    /// The MD child process died or failed without a typed report.
    #[error("MD worker failed ({status}); last stderr lines:\n{stderr_tail}")]
    Worker { status: String, stderr_tail: String },
    /// A measurement that ran but could not produce a meaningful number.
    #[error("measurement `{what}` failed: {reason}")]
    Measurement { what: String, reason: String },
}

pub type Result<T, E = MdError> = std::result::Result<T, E>;

impl MdError {
    pub(crate) fn io(path: impl Into<PathBuf>, cause: std::io::Error) -> Self {
        Self::Io {
            path: path.into(),
            cause,
        }
    }
    pub(crate) fn config(what: impl Into<String>, message: impl ToString) -> Self {
        Self::Config {
            what: what.into(),
            message: message.to_string(),
        }
    }
    pub(crate) fn measurement(what: impl Into<String>, reason: impl Into<String>) -> Self {
        Self::Measurement {
            what: what.into(),
            reason: reason.into(),
        }
    }

    /// A [`MdError::Config`] of `what` naming the first of `fields` that is not a finite positive
    /// number.
    pub(crate) fn require_positive(what: &str, fields: &[(&str, f64)]) -> Result<()> {
        match fields.iter().find(|(_, v)| !(v.is_finite() && *v > 0.0)) {
            Some((n, v)) => Err(Self::config(
                what,
                format!("{n} must be a positive number, got {v}"),
            )),
            None => Ok(()),
        }
    }
}
