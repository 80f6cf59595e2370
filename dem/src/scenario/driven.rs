//! The driven run the junction and the sliding layer share (DESIGN.md section 7): the top wall of a
//! [`Rig`](super::rig::Rig) dragged at constant velocity under constant normal pressure, and the
//! resumable observed run that carries a scenario's recorders to the end.
//!
//! A scenario keeps what it records (frames, wall forces, profiles) in one serde type implementing
//! [`Recorders`]; [`run_resumable`] steps the engine in chunks between observations, saves that type
//! beside the engine checkpoint and the dump in the progress file every few minutes and on an
//! interrupt, and a rerun with the same inputs continues to the same bits (the checkpoint is exact and
//! saves happen at step boundaries, where every observer has seen the same states).

use std::path::Path;
use std::time::Instant;

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use crate::error::{DemError, Result};
use crate::io::checkpoint::Checkpoint;
use crate::io::progress::{self, ProgressFile, SaveClock};
use crate::observe::{Dump, Observer};
use crate::sim::{Parallelism, Simulation};
use crate::walls::{AxisControl, RigidMotion};
use crate::Vec3;

/// The top wall of paper 000 Fig. 7 and paper 004 Fig. 2: dragged along x at `velocity`, pressed
/// along -y with `pressure` (traction control, so the gap follows the material), held along z.
pub fn sliding_top(velocity: f64, pressure: f64) -> RigidMotion {
    RigidMotion {
        axes: [
            AxisControl::Velocity(velocity),
            AxisControl::Traction(-pressure),
            AxisControl::Velocity(0.0),
        ],
        velocity: Vec3::new(velocity, 0.0, 0.0),
    }
}

/// Every particle at one instant, for the side-view snapshot.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Snapshot {
    pub step: u64,
    pub lo: [f64; 3],
    pub hi: [f64; 3],
    pub pos: Vec<[f64; 3]>,
    pub radius: Vec<f64>,
    /// A colour label per particle: the initial body (junction, see
    /// [`super::junction::BODY_LOWER`]) or the initial-height band (sliding).
    pub body: Vec<u32>,
    /// Role: 1 junction member, 2 wall, 0 other.
    pub role: Vec<u8>,
}

impl Snapshot {
    /// `sim`'s particles now, with a colour label and a role per particle.
    pub fn of(sim: &Simulation, body: &[u32], role: &[u8]) -> Self {
        let p = &sim.particles;
        let b = &sim.sim_box;
        Snapshot {
            step: sim.step_count(),
            lo: [b.lo.x, b.lo.y, b.lo.z],
            hi: [b.hi.x, b.hi.y, b.hi.z],
            pos: p.pos.iter().map(|x| [x.x, x.y, x.z]).collect(),
            radius: p.radius.clone(),
            body: body.to_vec(),
            role: role.to_vec(),
        }
    }
}

/// What a scenario records while it runs: plain serde data, so that it rides in the progress file.
pub trait Recorders: Clone + Serialize + DeserializeOwned {
    /// The observers the engine calls, borrowed from the records.
    fn observers(&mut self) -> Vec<&mut dyn Observer>;
}

/// How a driven run is stepped, saved and named.
#[derive(Debug)]
pub struct Schedule<'a> {
    /// The scenario's name in log lines ("junction", "sliding").
    pub name: &'static str,
    /// Steps of the whole run.
    pub total: u64,
    /// Steps between two calls of `report` and two chances to save (a frame or window interval).
    pub chunk: u64,
    /// The progress file, if the run keeps one.
    pub progress: Option<&'a ProgressFile>,
    /// The inputs the progress file belongs to (the settings, the model and the sample's fingerprint).
    pub key: String,
}

/// The records at the end of a run.
#[derive(Debug)]
pub struct Recorded<R> {
    pub records: R,
    /// Wall-clock seconds of the stepping, summed over resumed parts.
    pub wall_seconds: f64,
}

/// What a run has done so far: enough to continue it exactly.
#[derive(Clone, Serialize, Deserialize)]
#[serde(bound = "R: Recorders")]
struct Progress<R> {
    sim: Checkpoint,
    records: R,
    dump: Option<Dump>,
    seconds: f64,
}

/// A dump of `n` frames over `total` steps, labelled per particle, when `path` is given and `n > 0`.
pub fn dump_for(
    sim: &Simulation,
    path: Option<&Path>,
    n: u64,
    total: u64,
    labels: impl FnOnce() -> Vec<(String, Vec<u32>)>,
) -> Result<Option<Dump>> {
    match path {
        Some(p) if n > 0 => Ok(Some(Dump::new(
            sim,
            p.to_path_buf(),
            labels(),
            (total / n).max(1),
        )?)),
        _ => Ok(None),
    }
}

/// Runs `sim` to `schedule.total` steps under the recorders `fresh` makes (or those of a matching
/// progress file, whose engine state then replaces `sim`'s), calling `report(step, total)` after
/// every chunk. On an interrupt the progress is saved (with a progress file) and the error returned.
pub fn run_resumable<R: Recorders>(
    sim: &mut Simulation,
    par: Parallelism,
    schedule: Schedule<'_>,
    fresh: impl FnOnce(&Simulation) -> Result<(R, Option<Dump>)>,
    report: &mut dyn FnMut(u64, u64),
) -> Result<Recorded<R>> {
    let t0 = Instant::now();
    let Schedule {
        name,
        total,
        chunk,
        progress,
        key,
    } = schedule;
    let chunk = chunk.max(1);
    let saved = progress.and_then(|f| progress::load::<Progress<R>>(&f.path, &key));
    let mut st = match saved {
        Some(p) => {
            *sim = Simulation::from_checkpoint(p.sim.clone(), par)?;
            if let Some(d) = &p.dump {
                // Frames written after the last save are written again by the resumed run.
                d.truncate_to_recorded()?;
            }
            tracing::info!(
                target: "stage",
                step = sim.step_count(),
                "{name} run resumed from its progress file"
            );
            p
        }
        None => {
            let (records, dump) = fresh(sim)?;
            Progress {
                sim: sim.checkpoint(),
                records,
                dump,
                seconds: 0.0,
            }
        }
    };
    let mut clock = SaveClock::new();
    let save = |st: &mut Progress<R>, sim: &Simulation, f: &ProgressFile| -> Result<()> {
        st.sim = sim.checkpoint();
        let mut copy = st.clone();
        copy.seconds += t0.elapsed().as_secs_f64();
        progress::save(&f.path, &key, &copy)
    };
    while sim.step_count() < total {
        let n = (chunk - sim.step_count() % chunk).min(total - sim.step_count());
        let mut observers = st.records.observers();
        if let Some(d) = st.dump.as_mut() {
            observers.push(d);
        }
        if let Err(e) = sim.run_observed(n, &mut observers) {
            if let (DemError::Interrupted { .. }, Some(f)) = (&e, progress) {
                // The failed step left the state of the previous step boundary, as every observer saw it.
                save(&mut st, sim, f)?;
                tracing::info!(target: "stage", path = %f.path.display(), "{name} progress saved: rerun to continue");
            }
            return Err(e);
        }
        report(sim.step_count(), total);
        if let Some(f) = progress.filter(|f| clock.due(f.every)) {
            save(&mut st, sim, f)?;
        }
    }
    Ok(Recorded {
        records: st.records,
        wall_seconds: st.seconds + t0.elapsed().as_secs_f64(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sliding_top_drags_along_x_and_presses_down() {
        let m = sliding_top(2.0, 0.1);
        assert_eq!(m.velocity, Vec3::new(2.0, 0.0, 0.0));
        assert!(matches!(m.axes[0], AxisControl::Velocity(v) if v == 2.0));
        assert!(matches!(m.axes[1], AxisControl::Traction(t) if t == -0.1));
        assert!(matches!(m.axes[2], AxisControl::Velocity(v) if v == 0.0));
    }
}
