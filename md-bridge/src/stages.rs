//! Stage checkpoints: the finished stages of one MD job, saved as they complete, so a job that
//! is interrupted (Ctrl-C, a crash, a killed cluster allocation) resumes after its last finished
//! stage instead of starting over.
//!
//! Layout: `<job dir>/stages/<name>.json`, one file per stage, written atomically by MPI rank 0.
//! The job dir is the cache entry `<cache>/<input_hash>/` of [`crate::job`], whose hash covers
//! every setting, the LAMMPS version, the potential and the rank count: a stage file can only be
//! reused by the identical request.
//!
//! Resuming is bit-identical by construction, not by luck: every stage after the first starts
//! from a state rebuilt from stage data (e.g. the silica glass: a fresh LAMMPS cell holding the
//! saved positions), in an uninterrupted run as in a resumed one, and floats round-trip exactly
//! through JSON (serde_json `float_roundtrip`). So the two runs execute the same commands on the
//! same atoms in the same memory order.
//!
//! The set of finished stages is read once, when the store is opened, so every MPI rank takes the
//! same decisions even while rank 0 writes new stages.

use crate::error::{MdError, Result};
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Subdirectory of a job dir that holds its stages.
pub const STAGES_DIR: &str = "stages";

/// One finished stage as stored.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct StageFile<T> {
    stage: String,
    /// Wall seconds the stage took when it ran.
    seconds: f64,
    value: T,
}

/// How a stage's value was obtained.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StageRun {
    /// Wall seconds of the run that computed it (the original run when resumed).
    pub seconds: f64,
    /// True when it was read back from a stage file.
    pub resumed: bool,
}

/// The stage files of one job (or none, for in-process runs that keep nothing).
#[derive(Debug, Default)]
pub struct Stages {
    dir: Option<PathBuf>,
    /// Only one process writes (MPI rank 0); all read.
    writer: bool,
    /// Stage name -> its file's JSON, as found when the store was opened.
    finished: BTreeMap<String, serde_json::Value>,
}

impl Stages {
    /// Keeps nothing: every stage runs.
    pub fn none() -> Self {
        Self::default()
    }

    /// Opens (and, for the writer, creates) `dir`, reading the stages already finished there.
    /// An unreadable stage file is logged and recomputed, never trusted.
    pub fn open(dir: &Path, writer: bool) -> Result<Self> {
        if writer {
            std::fs::create_dir_all(dir).map_err(|e| MdError::io(dir, e))?;
        }
        let mut finished = BTreeMap::new();
        if let Ok(entries) = std::fs::read_dir(dir) {
            let mut paths: Vec<PathBuf> = entries.filter_map(|e| Some(e.ok()?.path())).collect();
            paths.sort();
            for path in paths {
                if path.extension().and_then(|e| e.to_str()) != Some("json") {
                    continue;
                }
                let parsed = std::fs::read_to_string(&path)
                    .map_err(|e| e.to_string())
                    .and_then(|t| {
                        serde_json::from_str::<serde_json::Value>(&t).map_err(|e| e.to_string())
                    });
                let name = path
                    .file_stem()
                    .and_then(|s| s.to_str())
                    .unwrap_or_default();
                match parsed {
                    Ok(v) => {
                        finished.insert(name.to_owned(), v);
                    }
                    Err(e) => tracing::warn!("ignoring stage file {}: {e}", path.display()),
                }
            }
        }
        Ok(Self {
            dir: Some(dir.to_owned()),
            writer,
            finished,
        })
    }

    /// Names of the stages found finished when the store was opened.
    pub fn finished(&self) -> Vec<&str> {
        self.finished.keys().map(String::as_str).collect()
    }

    /// The stage's stored value, or runs `compute` and stores its value. Stage names are file
    /// stems: lowercase words and underscores.
    pub fn run<T, F>(&self, name: &str, compute: F) -> Result<(T, StageRun)>
    where
        T: Serialize + DeserializeOwned,
        F: FnOnce() -> Result<T>,
    {
        if let Some(v) = self.finished.get(name) {
            match serde_json::from_value::<StageFile<T>>(v.clone()) {
                Ok(f) if f.stage == name => {
                    tracing::info!(
                        target: "stage",
                        "stage {name}: resumed from its stage file (ran {:.1} s)",
                        f.seconds
                    );
                    let run = StageRun {
                        seconds: f.seconds,
                        resumed: true,
                    };
                    return Ok((f.value, run));
                }
                _ => tracing::warn!("stage {name}: stage file does not match, recomputing"),
            }
        }
        let started = Instant::now();
        let value = compute()?;
        let seconds = started.elapsed().as_secs_f64();
        tracing::info!(target: "stage", "stage {name}: done in {seconds:.1} s");
        if let (Some(dir), true) = (&self.dir, self.writer) {
            let file = StageFile {
                stage: name.to_owned(),
                seconds,
                value: &value,
            };
            let text = serde_json::to_string(&file).map_err(|e| MdError::config(name, e))?;
            crate::job::write_atomic(&dir.join(format!("{name}.json")), &text)?;
        }
        let run = StageRun {
            seconds,
            resumed: false,
        };
        Ok((value, run))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::Cell;

    fn tmp(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("cgdem-stages-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        d
    }

    #[test]
    fn a_finished_stage_is_read_back_bit_identically_and_not_recomputed() {
        let d = tmp("resume");
        let value = vec![0.1 + 0.2, 1.0 / 3.0, f64::MIN_POSITIVE, 6.02214076e23, -0.0];
        let s = Stages::open(&d, true).unwrap();
        let (v, run) = s.run("glass", || Ok(value.clone())).unwrap();
        assert!(!run.resumed);
        assert_eq!(v, value);
        let calls = Cell::new(0);
        let s = Stages::open(&d, true).unwrap();
        assert_eq!(s.finished(), ["glass"]);
        let (back, run): (Vec<f64>, _) = s
            .run("glass", || {
                calls.set(calls.get() + 1);
                Ok(vec![])
            })
            .unwrap();
        assert!(run.resumed);
        assert_eq!(calls.get(), 0);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&back), bits(&value));
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn a_failed_stage_leaves_no_file_and_a_corrupt_file_is_recomputed() {
        let d = tmp("fail");
        let s = Stages::open(&d, true).unwrap();
        let err = s.run::<f64, _>("tension", || {
            Err(MdError::measurement("tension", "no peak"))
        });
        assert!(err.is_err());
        assert!(Stages::open(&d, true).unwrap().finished().is_empty());
        std::fs::write(d.join("shear.json"), "{ truncated").unwrap();
        let s = Stages::open(&d, true).unwrap();
        let (v, run) = s.run("shear", || Ok(2.5)).unwrap();
        assert_eq!((v, run.resumed), (2.5, false));
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn readers_that_are_not_the_writer_store_nothing() {
        let d = tmp("reader");
        let s = Stages::open(&d, false).unwrap();
        s.run("glass", || Ok(1.0)).unwrap();
        assert!(!d.join("glass.json").exists());
        assert!(Stages::none().run("glass", || Ok(1.0)).is_ok());
    }
}
