//! Pair forces. One specialised kernel per formulation over flat arrays (no per-pair dispatch):
//! - [`cohesive`]: paper 000 eqs (2)-(5), normal + tangential with history;
//! - the normal-only law of paper 004 is the same kernel with the tangential part compiled out
//!   (its parameters differ only through A_eff, see [`crate::material`]).
//!
//! The phase driver ([`compute`]) evaluates every pair in parallel into a per-pair buffer, then gathers
//! forces per particle in a fixed order: results are bit-identical for any number of threads.

pub mod cohesive;
mod compute;

pub use cohesive::{normal_energy, normal_force, tangential_cap};
pub(crate) use compute::{ForceBuffers, ForcePhase};
