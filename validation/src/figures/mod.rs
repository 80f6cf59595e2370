//! Figures drawn with plotters. Each figure is built from plain data series (functions that tests
//! check against the numbers they plot) and then drawn; drawing errors carry the file name.

pub mod calibration;
pub(crate) mod chart;
pub mod detachment;
pub mod dstar;
pub mod junction;
pub mod md;
pub mod patch;
pub mod plastic;
pub mod sliding;
pub(crate) mod style;
