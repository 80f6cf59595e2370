//! `cgdem doctor`: checks the MD side of the workbench (venv, LAMMPS, packages, potentials, MPI)
//! and fails with the fixing command when something is wrong.

use anyhow::{bail, Result};

pub fn run() -> Result<()> {
    let report = md_bridge::doctor::doctor(&md_bridge::Venv::locate());
    print!("{}", report.render());
    if !report.healthy() {
        bail!(
            "MD environment has problems; fix with `{}` from the repo root",
            md_bridge::SETUP_COMMAND
        );
    }
    Ok(())
}
