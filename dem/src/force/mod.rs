//! Pair forces. One specialised kernel per formulation over flat arrays (no per-pair dispatch):
//! - [`cohesive`]: paper 000 eqs (2)-(5), normal + tangential with history;
//! - the normal-only law of paper 004 is the same kernel with the tangential part compiled out
//!   (its parameters differ only through A_eff, see [`crate::material`]);
//! - [`hertz`]: Hertz normal force with Coulomb friction and tangential history, the contact of the
//!   plastic-wear model of paper 001; pure functions used by its own small contact loop
//!   ([`crate::scenario::plastic`]), not by the cohesive force phase.
//!
//! The phase driver (`compute`) walks fixed particle blocks in parallel. Inside a block, consecutive
//! pairs are loaded into batches of `LANES` (structure of arrays) that the kernel evaluates
//! lane-wise, which the compiler turns into vector instructions; the per-pair constants of eqs (7)-(13)
//! are computed once per neighbour-list build. Forces are then summed per particle in pair order, so
//! results are bit-identical for any number of threads.

pub mod cohesive;
mod compute;
pub mod hertz;
mod pair_consts;

pub use cohesive::{normal_energy, normal_force, tangential_cap};
pub(crate) use compute::{ForceBuffers, ForcePhase, IntegratorView, Kin};
