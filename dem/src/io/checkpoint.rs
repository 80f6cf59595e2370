//! Checkpoints: the complete dynamical state (particles, box, groups, neighbour list with tangential
//! history and its rebuild reference, step, time, ledger), so that a resumed run is bit-identical to an
//! uninterrupted one. Stored as JSON, whose shortest-representation floats round-trip f64 exactly.
//! Writes go to a temporary file that is renamed into place: a crash mid-write never destroys the
//! previous checkpoint.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::domain::{BoxControl, SimBox};
use crate::energy::EnergyLedger;
use crate::error::{DemError, Result};
use crate::material::PairModel;
use crate::neighbor::NeighborList;
use crate::sim::{Parallelism, RunConfig, Simulation};
use crate::state::Particles;
use crate::walls::Group;

/// Format version, bumped when the layout changes (2: the pair history stored per component).
const VERSION: u32 = 2;

/// Serialisable state of a [`Simulation`].
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Checkpoint {
    version: u32,
    particles: Particles,
    sim_box: SimBox,
    box_control: BoxControl,
    groups: Vec<Group>,
    model: PairModel,
    config: RunConfig,
    list: NeighborList,
    step: u64,
    time: f64,
    ledger: EnergyLedger,
}

impl Simulation {
    /// Snapshot of the state.
    pub fn checkpoint(&self) -> Checkpoint {
        Checkpoint {
            version: VERSION,
            particles: self.particles.clone(),
            sim_box: self.sim_box,
            box_control: self.box_control,
            groups: self.groups.clone(),
            model: self.model.clone(),
            config: self.config,
            list: self.list.clone(),
            step: self.step,
            time: self.time,
            ledger: self.ledger,
        }
    }

    /// Rebuilds a simulation from a snapshot.
    pub fn from_checkpoint(cp: Checkpoint, parallelism: Parallelism) -> Result<Self> {
        if cp.version != VERSION {
            return Err(DemError::Format {
                path: "<checkpoint>".into(),
                reason: format!(
                    "checkpoint version {} but this build reads {VERSION}",
                    cp.version
                ),
            });
        }
        let mut sim = Simulation::new(
            cp.particles,
            cp.sim_box,
            cp.model,
            cp.groups,
            cp.config,
            parallelism,
        )?;
        sim.set_box_control(cp.box_control)?;
        let n = sim.particles.len();
        if cp.list.row_start.len() == n + 1 {
            // The force loop indexes particles and image shifts from the list: refuse a damaged one.
            cp.list.check(n).map_err(|reason| DemError::Format {
                path: "<checkpoint>".into(),
                reason: format!("neighbour list: {reason}"),
            })?;
            sim.list = cp.list;
        }
        sim.step = cp.step;
        sim.time = cp.time;
        sim.ledger = cp.ledger;
        Ok(sim)
    }

    /// Writes a checkpoint atomically (temporary file, then rename).
    pub fn save_checkpoint(&self, path: &Path) -> Result<()> {
        write_atomic(
            path,
            &serde_json::to_vec(&self.checkpoint()).map_err(|e| format_err(path, e))?,
        )
    }

    /// Reads a checkpoint written by [`Simulation::save_checkpoint`].
    pub fn load_checkpoint(path: &Path, parallelism: Parallelism) -> Result<Self> {
        let bytes = std::fs::read(path).map_err(|e| DemError::io(path, e))?;
        let cp: Checkpoint = serde_json::from_slice(&bytes).map_err(|e| format_err(path, e))?;
        Simulation::from_checkpoint(cp, parallelism)
    }
}

fn format_err(path: &Path, e: serde_json::Error) -> DemError {
    DemError::Format {
        path: path.display().to_string(),
        reason: e.to_string(),
    }
}

/// Writes `bytes` to `path` through a temporary sibling and a rename.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| DemError::io(dir, e))?;
    }
    let tmp = path.with_extension("tmp");
    std::fs::write(&tmp, bytes).map_err(|e| DemError::io(&tmp, e))?;
    std::fs::rename(&tmp, path).map_err(|e| DemError::io(path, e))
}
