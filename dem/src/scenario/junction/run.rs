//! Running a junction: the rig, the observers, the progress file, the verdict.

use std::path::Path;

use serde::{Deserialize, Serialize};
use wear::outcome::{detachment, Bonding};
use wear::{classify, Outcome, Verdict};

use super::{build, JunctionConfig};
use crate::error::{DemError, Result};
use crate::io::progress::{self, ProgressFile};
use crate::io::Sig;
use crate::material::PairModel;
use crate::observe::{
    periodicity, unwrapped, Dump, ForceSample, GroupForce, MemberFrames, Observer,
};
use crate::sample::Sample;
use crate::scenario::driven::{self, dump_for, sliding_top, Recorders, Schedule, Snapshot};
use crate::scenario::rig::{Rig, RigSpec};
use crate::sim::{Parallelism, RunConfig, Simulation, TimeStep};

/// What a junction run gives.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JunctionResult {
    pub outcome: Outcome,
    pub verdict: Verdict,
    pub particles: usize,
    pub junction_members: usize,
    pub wall_particles: usize,
    pub steps: u64,
    pub dt: f64,
    /// Top-wall displacement along x at the end.
    pub slide: f64,
    /// Pair force on the top wall (x: tangential, y: normal) and its displacement, over the run.
    pub force: Vec<ForceSample>,
    /// The junction members' unwrapped positions, `frames.frames[k]` at `frames.steps[k]`.
    pub frames: MemberFrames,
    pub first: Snapshot,
    pub last: Snapshot,
    /// Wall-clock seconds of the stepping (relaxation and set-up excluded), summed over resumed parts.
    pub wall_seconds: f64,
}

/// What a junction run records: the members' frames (the classifier's input) and the top wall's force,
/// whose recorder also stops a collapsing run.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct Records {
    frames: MemberFrames,
    top: TopWall,
}

impl Recorders for Records {
    fn observers(&mut self) -> Vec<&mut dyn Observer> {
        vec![&mut self.frames, &mut self.top]
    }
}

/// How far the top wall has descended at a force sample (its displacement is measured from the start).
fn descent(s: &ForceSample) -> f64 {
    -s.displacement[1]
}

impl JunctionResult {
    /// The top wall's largest descent over the run (0 if it only rose).
    pub fn largest_wall_descent(&self) -> f64 {
        self.force.iter().map(descent).fold(0.0, f64::max)
    }
}

/// The top wall's force recorder, which also stops the run once the wall has descended further than
/// a junction squashed flat allows ([`JunctionConfig::max_descent_over_height`]): the solids are then
/// compacting, and no verdict on the junction means anything.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct TopWall {
    force: GroupForce,
    /// Junction height H and the largest descent allowed.
    height: f64,
    limit: f64,
}

impl Observer for TopWall {
    fn every(&self) -> u64 {
        self.force.every
    }
    fn observe(&mut self, sim: &Simulation) -> Result<()> {
        self.force.observe(sim)?;
        let Some(d) = self.force.samples.last().map(descent) else {
            return Ok(());
        };
        if d > self.limit {
            return Err(DemError::MaterialCollapsed {
                step: sim.step_count(),
                reason: format!(
                    "the top wall has descended by {}, more than the limit of {} x the junction \
                     height H = {}: a junction squashed flat lowers it by less than H, so the solids \
                     themselves are compacting, their particles pulled into each other under the \
                     shear. The material's relaxed packing is not stable (a card whose relaxed \
                     samples interpenetrate does this; docs/junction.md, \"Calibrated cards \
                     collapse under shear\"); no verdict is given",
                    Sig(d, 4),
                    Sig(self.limit / self.height, 3),
                    Sig(self.height, 4)
                ),
            });
        }
        Ok(())
    }
}

/// [`run_resumable`] without a progress file.
pub fn run(
    relaxed: &Sample,
    model: &PairModel,
    cfg: &JunctionConfig,
    par: Parallelism,
    dump: Option<&Path>,
) -> Result<JunctionResult> {
    run_resumable(relaxed, model, cfg, par, dump, None, &mut |_, _| {})
}

/// Carves `relaxed`, shears the junction and classifies the outcome. With `dump`, writes LAMMPS-style
/// frames there (with `body` and `junction` columns). With `progress`, saves the run's state every few
/// minutes and on an interrupt, and continues from it when it holds the same inputs' progress (the
/// result is then bit-identical to an uninterrupted run). `report(step, total)` is called at every
/// member frame.
pub fn run_resumable(
    relaxed: &Sample,
    model: &PairModel,
    cfg: &JunctionConfig,
    par: Parallelism,
    dump: Option<&Path>,
    progress: Option<&ProgressFile>,
    report: &mut dyn FnMut(u64, u64),
) -> Result<JunctionResult> {
    let geo = build(relaxed, cfg)?;
    let run_cfg = RunConfig {
        time_step: TimeStep::FractionOfCritical(cfg.time_step_fraction),
        skin_fraction: cfg.skin_fraction,
        planar: cfg.monolayer.is_some(),
        ..RunConfig::default()
    };
    // A monolayer's pressure is a force per unit length of the wall (module docs).
    let traction = match cfg.monolayer {
        Some(_) => cfg.pressure / geo.sample.sim_box.lengths().z,
        None => cfg.pressure,
    };
    let mut rig = Rig::new(
        &geo.sample,
        model,
        RigSpec::y_normal(cfg.wall_thickness()),
        run_cfg,
        par,
    )?;
    let walls: Vec<usize> = (0..rig.free.len()).filter(|&i| !rig.free[i]).collect();
    if rig
        .top_members
        .iter()
        .chain(&walls)
        .any(|i| geo.members.contains(i))
    {
        return Err(DemError::InvalidConfig(
            "junction: the walls reach into the junction (thicker solids or thinner walls)".into(),
        ));
    }
    rig.set_top(sliding_top(cfg.velocity, traction));
    let dt = rig.sim.dt();
    let total = cfg.steps(dt)?;
    let frame_every = (total / cfg.frames).max(1);
    let force_every = (total / cfg.force_samples).max(1);
    let roles: Vec<u8> = (0..rig.free.len())
        .map(|i| {
            if geo.members.binary_search(&i).is_ok() {
                1
            } else if rig.free[i] {
                0
            } else {
                2
            }
        })
        .collect();
    let first = Snapshot::of(&rig.sim, &geo.body, &roles);
    let first_path = unwrapped(&rig.sim);
    let schedule = Schedule {
        name: "junction",
        total,
        chunk: frame_every,
        progress,
        key: progress::key(&(cfg, model), relaxed)?,
    };
    let fresh = |sim: &Simulation| -> Result<(Records, Option<Dump>)> {
        let records = Records {
            frames: MemberFrames::new(sim, geo.members.clone(), frame_every)?,
            top: TopWall {
                force: GroupForce::new(sim, rig.top_members.clone(), force_every)?,
                height: cfg.height(),
                limit: cfg.max_descent_over_height * cfg.height(),
            },
        };
        let dump = dump_for(sim, dump, cfg.dump_frames, total, || {
            let mut member = vec![0u32; geo.body.len()];
            geo.members.iter().for_each(|&i| member[i] = 1);
            vec![
                ("body".to_string(), geo.body.clone()),
                ("junction".to_string(), member),
            ]
        })?;
        Ok((records, dump))
    };
    let recorded = driven::run_resumable(&mut rig.sim, par, schedule, fresh, report)?;
    let Records { frames, mut top } = recorded.records;
    // The series ends at the last step, whatever the sampling interval (and the guard reads it too).
    if top.force.samples.last().is_none_or(|s| s.step != total) {
        top.observe(&rig.sim)?;
    }
    let force = top.force;
    let wear_err = |e: wear::WearError| DemError::InvalidConfig(format!("junction outcome: {e}"));
    let tangential: Vec<f64> = frames.steps.iter().map(|&s| force_at(&force, s)).collect();
    let last = Snapshot::of(&rig.sim, &geo.body, &roles);
    // Bonds of the cluster analysis: pairs within the cohesive range of a d0 pair.
    let r0 = 0.5 * cfg.d0;
    let bonding = Bonding {
        radii: Some(rig.sim.particles.radius.clone()),
        margin: model.params(r0, r0, 1.0, 1.0).delta_f,
        periodicity: periodicity(&rig.sim.sim_box),
    };
    let detached = detachment(
        &first_path,
        &unwrapped(&rig.sim),
        &bonding,
        &geo.members,
        &walls,
    )
    .map_err(wear_err)?;
    let verdict =
        classify(&frames.frames, &tangential, Some(detached), &cfg.classify).map_err(wear_err)?;
    let slide = force.samples.last().map_or(0.0, |s| s.displacement[0]);
    Ok(JunctionResult {
        outcome: verdict.outcome,
        verdict,
        particles: rig.sim.particles.len(),
        junction_members: geo.members.len(),
        wall_particles: walls.len(),
        steps: total,
        dt,
        slide,
        force: force.samples,
        frames,
        first,
        last,
        wall_seconds: recorded.wall_seconds,
    })
}

/// The tangential force at the sample nearest to `step` (0 before the first sample).
fn force_at(f: &GroupForce, step: u64) -> f64 {
    f.samples
        .iter()
        .min_by_key(|s| s.step.abs_diff(step))
        .filter(|_| step > 0)
        .map_or(0.0, |s| s.force[0])
}
