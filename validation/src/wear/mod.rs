//! Adhesive wear as the workbench's commands run it: a junction run from a config file, with its
//! relaxed sample cached and its outputs written ([`junction`]), and the search for d* over such runs
//! ([`dstar`]); the sliding layer of paper 004 ([`sliding`]); relaxed boxes as jobs that these share
//! ([`samples`]).

use std::path::Path;

use dem::io::checkpoint::write_atomic;
use serde::Serialize;

use crate::{Result, ValidationError};

pub mod dstar;
pub mod junction;
pub mod samples;
pub mod sliding;

/// Writes `v` as pretty JSON to `path` atomically (a crash never leaves half a summary).
pub(crate) fn json(path: &Path, v: &impl Serialize) -> Result<()> {
    let bytes = serde_json::to_vec_pretty(v).map_err(|e| ValidationError::Config {
        path: path.display().to_string(),
        reason: e.to_string(),
    })?;
    write_atomic(path, &bytes)?;
    Ok(())
}
