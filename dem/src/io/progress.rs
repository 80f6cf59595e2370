//! Progress files of long runs (a strength test or a relaxation of a large sample runs for hours):
//! the run saves its state (the simulation's checkpoint plus its own counters and records) every few
//! minutes and when it is interrupted (Ctrl-C), and the same call with the same inputs continues from
//! it. The resumed run gives the same numbers to the last bit as an uninterrupted one (the checkpoint
//! is exact, and the file is only written at step boundaries).
//!
//! A progress file belongs to one set of inputs: it carries a key made from the test's settings, the
//! pair model and a fingerprint of the sample, and a file with another key is left unused (and later
//! overwritten) rather than resumed.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use serde::de::DeserializeOwned;
use serde::Serialize;

use crate::error::{DemError, Result};
use crate::io::checkpoint::write_atomic;
use crate::sample::Sample;

/// Where a test keeps its progress and how often it rewrites it.
#[derive(Debug, Clone, PartialEq)]
pub struct ProgressFile {
    pub path: PathBuf,
    /// Wall-clock time between saves (also saved on an interrupt); default 2 minutes: a save of a
    /// 50 000-particle state takes well under a second.
    pub every: Duration,
}

impl ProgressFile {
    /// Saves every two minutes to `path`.
    pub fn new(path: impl Into<PathBuf>) -> Self {
        ProgressFile {
            path: path.into(),
            every: Duration::from_secs(120),
        }
    }
}

/// Identifies inputs by their settings alone, as JSON (exact floats).
pub(crate) fn settings_key(settings: &impl Serialize) -> Result<String> {
    serde_json::to_string(settings).map_err(|e| DemError::InvalidConfig(e.to_string()))
}

/// Identifies the inputs a test's progress file belongs to: the settings and model as JSON (exact
/// floats) and an FNV-1a hash of the sample's particles and box.
pub(crate) fn key(settings: &impl Serialize, sample: &Sample) -> Result<String> {
    let json = settings_key(settings)?;
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |x: f64| {
        for b in x.to_bits().to_le_bytes() {
            h = (h ^ b as u64).wrapping_mul(0x0100_0000_01b3);
        }
    };
    let p = &sample.particles;
    for i in 0..p.len() {
        p.pos[i].iter().for_each(|&x| eat(x));
        eat(p.radius[i]);
        eat(p.mass[i]);
    }
    sample.sim_box.lengths().iter().for_each(|&x| eat(x));
    Ok(format!("{json} sample {} {h:016x}", p.len()))
}

/// Reads the progress saved for `key`, if any (a file for other inputs, or one that cannot be read,
/// is reported and ignored: the test then starts afresh and overwrites it).
pub(crate) fn load<T: DeserializeOwned>(path: &Path, key: &str) -> Option<T> {
    #[derive(serde::Deserialize)]
    struct Keyed<T> {
        key: String,
        state: T,
    }
    let bytes = std::fs::read(path).ok()?;
    match serde_json::from_slice::<Keyed<T>>(&bytes) {
        Ok(k) if k.key == key => Some(k.state),
        Ok(_) => {
            tracing::warn!(path = %path.display(), "progress file of other inputs: starting afresh");
            None
        }
        Err(e) => {
            tracing::warn!(path = %path.display(), error = %e, "unreadable progress file: starting afresh");
            None
        }
    }
}

/// Writes `state` under `key` atomically.
pub(crate) fn save<T: Serialize>(path: &Path, key: &str, state: &T) -> Result<()> {
    #[derive(Serialize)]
    struct Keyed<'a, T> {
        key: &'a str,
        state: &'a T,
    }
    let bytes = serde_json::to_vec(&Keyed { key, state }).map_err(|e| DemError::Format {
        path: path.display().to_string(),
        reason: e.to_string(),
    })?;
    write_atomic(path, &bytes)
}

/// Removes a progress file that is no longer needed (absent is fine).
pub fn remove(path: &Path) -> Result<()> {
    match std::fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(DemError::io(path, e)),
        _ => Ok(()),
    }
}

/// Decides when the periodic save is due.
pub(crate) struct SaveClock {
    last: Instant,
}

impl SaveClock {
    pub fn new() -> Self {
        SaveClock {
            last: Instant::now(),
        }
    }

    /// Whether `every` has passed since the last save (and if so, restarts the clock).
    pub fn due(&mut self, every: Duration) -> bool {
        let due = self.last.elapsed() >= every;
        if due {
            self.last = Instant::now();
        }
        due
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Vec3;

    fn sample(d: f64) -> Sample {
        Sample::hcp(Vec3::new(4.0, 4.0, 4.0), d, 1.0).unwrap()
    }

    #[test]
    fn keys_follow_settings_and_sample() {
        let a = key(&(1.0, "x"), &sample(1.0)).unwrap();
        assert_eq!(a, key(&(1.0, "x"), &sample(1.0)).unwrap());
        assert_ne!(a, key(&(1.0 + 1e-15, "x"), &sample(1.0)).unwrap());
        let mut moved = sample(1.0);
        moved.particles.pos[3].y += 1e-12;
        assert_ne!(a, key(&(1.0, "x"), &moved).unwrap());
    }

    #[test]
    fn only_the_same_key_is_loaded() {
        let path = std::env::temp_dir().join(format!("cgdem_progress_{}.json", std::process::id()));
        save(&path, "k1", &vec![0.1, 0.2 + 0.1]).unwrap();
        assert_eq!(load::<Vec<f64>>(&path, "k1"), Some(vec![0.1, 0.2 + 0.1]));
        assert_eq!(load::<Vec<f64>>(&path, "k2"), None);
        std::fs::write(&path, b"{ not json").unwrap();
        assert_eq!(load::<Vec<f64>>(&path, "k1"), None);
        remove(&path).unwrap();
        remove(&path).unwrap();
        assert_eq!(load::<Vec<f64>>(&path, "k1"), None);
    }
}
