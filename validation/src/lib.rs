//! DEM-vs-MD validation: figures and (later) the comparison of d* and the report.
//!
//! What exists so far: figures of the patch-test campaigns (`figures::patch`), drawn with plotters as
//! PNG. Text needs a font file for bitmaps; the crate ships DejaVu Sans (`assets/`, with its licence)
//! and registers it once, so figures look the same on every machine.

pub mod error;
pub mod figures;
pub mod wear;

pub use error::{Result, ValidationError};
