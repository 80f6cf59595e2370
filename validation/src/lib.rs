//! DEM-vs-MD validation: figures and (later) the comparison of d* and the report.
//!
//! What exists so far: figures of the patch-test campaigns (`figures::patch`), of the MD cards and the
//! calibration, and of the plastic-wear model (`figures::plastic`, PNG + SVG + CSV) with its claims
//! against paper 001 (`plastic`). Text needs a font file for bitmaps; the crate ships DejaVu Sans (`assets/`, with its licence)
//! and registers it once, so figures look the same on every machine.

pub mod error;
pub mod figures;
pub mod plastic;

pub use error::{Result, ValidationError};
