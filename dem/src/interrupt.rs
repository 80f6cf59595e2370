//! Cooperative interruption (Ctrl-C): the binary's signal handler calls [`request`]; every
//! [`crate::Simulation::step`] checks the flag and returns [`crate::DemError::Interrupted`], so long
//! loops stop at a step boundary and their callers can write what they computed (checkpoints, partial
//! curves, calibration history) before exiting.
//!
//! Decision: a process-wide flag rather than a token threaded through every scenario: an interrupt is a
//! property of the process (a signal), and the check costs one relaxed atomic load per step.

use std::sync::atomic::{AtomicBool, Ordering};

static REQUESTED: AtomicBool = AtomicBool::new(false);

/// Asks every running simulation to stop at its next step.
pub fn request() {
    REQUESTED.store(true, Ordering::Relaxed);
}

/// Whether an interrupt was requested.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::Relaxed)
}

/// Clears the flag (after the interrupted work was saved, or in tests).
pub fn clear() {
    REQUESTED.store(false, Ordering::Relaxed);
}
