//! Adhesive wear as the workbench's commands run it: a junction run from a config file, with its
//! relaxed sample cached and its outputs written ([`junction`]), and the search for d* over such runs
//! ([`dstar`]).

pub mod dstar;
pub mod junction;
pub mod sliding;
