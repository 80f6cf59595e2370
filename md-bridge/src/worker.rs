//! The worker side of [`crate::job`]: runs inside `cgdem md-worker JOB REPORT` (one process per MPI
//! rank under `mpirun`). Every rank runs the same LAMMPS commands; rank 0 writes the report.

use crate::error::{MdError, Result};
use crate::job::{Job, JobOutput, WorkerFailure, WorkerReport};
use crate::lammps::Lammps;
use crate::stages::{Stages, STAGES_DIR};
use crate::venv::Venv;
use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

fn execute(lmp: &Lammps, venv: &Venv, job: &Job) -> Result<JobOutput> {
    match job {
        Job::Silica(cfg) => {
            let pot = venv.potential(crate::silica::POTENTIAL)?;
            let stages = Stages::open(Path::new(STAGES_DIR), lmp.rank() == 0)?;
            if !stages.finished().is_empty() {
                tracing::info!("resuming after the finished stages {:?}", stages.finished());
            }
            crate::silica::run(lmp, &pot, cfg, &stages).map(|r| JobOutput::Silica(Box::new(r)))
        }
        Job::SilicaGlass(cfg) => {
            let pot = venv.potential(crate::silica::POTENTIAL)?;
            let path = Path::new(crate::silica::junction::GLASS_FILE);
            let density = crate::silica::junction::write_glass(lmp, &pot, cfg, path)?;
            let data = std::fs::read_to_string(path).map_err(|e| MdError::io(path, e))?;
            Ok(JobOutput::SilicaGlass { density, data })
        }
        Job::Model(cfg) => crate::model::run(lmp, cfg).map(|r| JobOutput::Model(Box::new(r))),
        Job::Junction(cfg) => {
            crate::junction::run(lmp, cfg).map(|r| JobOutput::Junction(Box::new(r)))
        }
        Job::Script {
            commands,
            read_variables,
            ..
        } => {
            let pots = venv.potentials_dir()?.to_string_lossy().into_owned();
            lmp.commands(&commands.replace("{potentials}", &pots))?;
            let mut variables = BTreeMap::new();
            for v in read_variables {
                variables.insert(v.clone(), lmp.variable(v)?);
            }
            Ok(JobOutput::Script { variables })
        }
        Job::AbortSelfTest => {
            eprintln!("md-worker: AbortSelfTest aborting the process on purpose");
            std::process::abort()
        }
    }
}

/// Entry point of `cgdem md-worker`. Returns an error (non-zero exit) when the job failed; the
/// typed failure is in the report either way.
pub fn worker_main(job_path: &Path, report_path: &Path) -> Result<()> {
    let started = Instant::now();
    let text = std::fs::read_to_string(job_path).map_err(|e| MdError::io(job_path, e))?;
    let job: Job = serde_json::from_str(&text)
        .map_err(|e| MdError::config(job_path.display().to_string(), e))?;
    let venv = Venv::locate();
    // LAMMPS's own log (commands echoed) sits next to the report in the job directory (the cwd).
    let lmp = match Lammps::new(
        &venv,
        &[
            "-log",
            "log.lammps",
            "-echo",
            "log",
            "-screen",
            "none",
            "-nocite",
        ],
    ) {
        Ok(l) => l,
        Err(e) => {
            write_report(report_path, None, 1, started, Err(WorkerFailure::from(&e)))?;
            return Err(e);
        }
    };
    let date = lmp.version().ok();
    let outcome = execute(&lmp, &venv, &job);
    let (rank, nprocs) = (lmp.rank(), lmp.nprocs().max(1) as u32);
    if rank == 0 {
        let result = outcome
            .as_ref()
            .map(Clone::clone)
            .map_err(WorkerFailure::from);
        write_report(report_path, date, nprocs, started, result)?;
    }
    lmp.finalize_mpi()?;
    outcome.map(|_| ())
}

fn write_report(
    path: &Path,
    lammps_date: Option<i64>,
    mpi_ranks: u32,
    started: Instant,
    result: std::result::Result<JobOutput, WorkerFailure>,
) -> Result<()> {
    let report = WorkerReport {
        lammps_date,
        mpi_ranks,
        wall_seconds: started.elapsed().as_secs_f64(),
        result,
    };
    let text =
        serde_json::to_string_pretty(&report).map_err(|e| MdError::config("worker report", e))?;
    std::fs::write(path, text).map_err(|e| MdError::io(path, e))
}
