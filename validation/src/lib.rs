//! DEM-vs-MD validation: figures, and the validation report.
//!
//! - `figures`: the figures of the stages (patch campaigns, calibration, MD), drawn with plotters as
//!   PNG. Text needs a font file for bitmaps; the crate ships DejaVu Sans (`assets/`, with its
//!   licence) and registers it once, so figures look the same on every machine.
//! - `report`: `cgdem report`, every claim of the papers the workbench reproduces with its figure,
//!   tolerance and verdict, as one self-contained HTML page, `summary.csv` and the figures' data.

pub mod bench;
pub mod error;
pub mod figures;
pub mod report;
pub mod wear;

pub use error::{Result, ValidationError};
