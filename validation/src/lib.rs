//! DEM-vs-MD validation: figures, and the validation report.
//!
//! - `figures`: the figures of the stages (patch campaigns, calibration, MD, plastic wear), drawn with
//!   plotters as PNG (plastic wear also as SVG and CSV). Text needs a font file for bitmaps; the crate ships DejaVu Sans (`assets/`, with its
//!   licence) and registers it once, so figures look the same on every machine.
//! - `report`: `cgdem report`, every claim of the papers the workbench reproduces with its figure,
//!   tolerance and verdict, as one self-contained HTML page, `summary.csv` and the figures' data.
//! - `plastic`: the claims of paper 001 (plastic wear by impact and scratching) and the quick profile
//!   of cached jobs that measures them for the report.

pub mod bench;
pub mod compare;
pub mod error;
pub mod figures;
pub mod plastic;
pub mod report;
pub mod wear;

pub use error::{Result, ValidationError};
