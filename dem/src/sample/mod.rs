//! Sample generators.
pub mod hcp;
