//! Running a junction: the rig, the observers, the progress file, the verdict.

use std::path::Path;
use std::time::Instant;

use serde::{Deserialize, Serialize};
use wear::outcome::{detachment, Bonding};
use wear::{classify, Outcome, Verdict};

use super::{build, JunctionConfig};
use crate::error::{DemError, Result};
use crate::io::checkpoint::Checkpoint;
use crate::io::progress::{self, ProgressFile, SaveClock};
use crate::material::PairModel;
use crate::observe::{periodicity, Dump, ForceSample, GroupForce, MemberFrames, Observer};
use crate::sample::Sample;
use crate::scenario::rig::{Rig, RigSpec};
use crate::sim::{Parallelism, RunConfig, Simulation, TimeStep};
use crate::walls::{AxisControl, RigidMotion};
use crate::Vec3;

/// Every particle at one instant, for the side-view snapshot.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Snapshot {
    pub step: u64,
    pub lo: [f64; 3],
    pub hi: [f64; 3],
    pub pos: Vec<[f64; 3]>,
    pub radius: Vec<f64>,
    /// Initial body (see [`super::BODY_LOWER`]).
    pub body: Vec<u32>,
    /// Junction member, wall or free: 1 member, 2 wall, 0 other.
    pub role: Vec<u8>,
}

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
    /// Wall-clock seconds of the run (relaxation excluded), summed over resumed parts.
    pub wall_seconds: f64,
}

/// What a run has done so far: enough to continue it exactly.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct Progress {
    sim: Checkpoint,
    frames: MemberFrames,
    force: GroupForce,
    dump: Option<Dump>,
    seconds: f64,
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
    let t0 = Instant::now();
    let geo = build(relaxed, cfg)?;
    let run_cfg = RunConfig {
        time_step: TimeStep::FractionOfCritical(cfg.time_step_fraction),
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
    rig.set_top(RigidMotion {
        axes: [
            AxisControl::Velocity(cfg.velocity),
            AxisControl::Traction(-traction),
            AxisControl::Velocity(0.0),
        ],
        velocity: Vec3::new(cfg.velocity, 0.0, 0.0),
    });
    let dt = rig.sim.dt();
    let total = cfg.steps(dt);
    let frame_every = (total / cfg.frames).max(1);
    let force_every = (total / cfg.force_samples).max(1);
    let labels = || {
        let mut member = vec![0u32; geo.body.len()];
        geo.members.iter().for_each(|&i| member[i] = 1);
        vec![
            ("body".to_string(), geo.body.clone()),
            ("junction".to_string(), member),
        ]
    };
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
    let first = snapshot(&rig.sim, &geo.body, &roles);
    let key = progress::key(&(cfg, model), relaxed)?;
    let saved = progress.and_then(|f| progress::load::<Progress>(&f.path, &key));
    let mut st = match saved {
        Some(p) => {
            rig.sim = Simulation::from_checkpoint(p.sim.clone(), par)?;
            if let Some(d) = &p.dump {
                d.truncate_to_recorded()?;
            }
            tracing::info!(
                step = rig.sim.step_count(),
                "junction run resumed from its progress file"
            );
            p
        }
        None => Progress {
            frames: MemberFrames::new(&rig.sim, geo.members.clone(), frame_every)?,
            force: GroupForce::new(&rig.sim, rig.top_members.clone(), force_every)?,
            dump: match (dump, cfg.dump_frames) {
                (Some(path), n) if n > 0 => Some(Dump::new(
                    &rig.sim,
                    path.to_path_buf(),
                    labels(),
                    (total / n).max(1),
                )?),
                _ => None,
            },
            sim: rig.sim.checkpoint(),
            seconds: 0.0,
        },
    };
    let mut clock = SaveClock::new();
    let save = |st: &mut Progress, sim: &Simulation, f: &ProgressFile| -> Result<()> {
        st.sim = sim.checkpoint();
        let mut copy = st.clone();
        copy.seconds += t0.elapsed().as_secs_f64();
        progress::save(&f.path, &key, &copy)
    };
    while rig.sim.step_count() < total {
        let chunk =
            (frame_every - rig.sim.step_count() % frame_every).min(total - rig.sim.step_count());
        let mut observers: Vec<&mut dyn Observer> = vec![&mut st.frames, &mut st.force];
        if let Some(d) = st.dump.as_mut() {
            observers.push(d);
        }
        if let Err(e) = rig.sim.run_observed(chunk, &mut observers) {
            if let (DemError::Interrupted { .. }, Some(f)) = (&e, progress) {
                // The failed step left the state of the previous step boundary, as every observer saw it.
                save(&mut st, &rig.sim, f)?;
                tracing::info!(path = %f.path.display(), "junction progress saved: rerun to continue");
            }
            return Err(e);
        }
        report(rig.sim.step_count(), total);
        if let Some(f) = progress.filter(|f| clock.due(f.every)) {
            save(&mut st, &rig.sim, f)?;
        }
    }
    // The series ends at the last step, whatever the sampling interval.
    if st.force.samples.last().is_none_or(|s| s.step != total) {
        st.force.observe(&rig.sim)?;
    }
    let wear_err = |e: wear::WearError| DemError::InvalidConfig(format!("junction outcome: {e}"));
    let tangential: Vec<f64> = st
        .frames
        .steps
        .iter()
        .map(|&s| force_at(&st.force, s))
        .collect();
    let last = snapshot(&rig.sim, &geo.body, &roles);
    // Bonds of the cluster analysis: pairs within the cohesive range of a d0 pair.
    let r0 = 0.5 * cfg.d0;
    let bonding = Bonding {
        radii: Some(rig.sim.particles.radius.clone()),
        margin: model.params(r0, r0, 1.0, 1.0).delta_f,
        periodicity: periodicity(&rig.sim.sim_box),
    };
    let detached =
        detachment(&first.pos, &last.pos, &bonding, &geo.members, &walls).map_err(wear_err)?;
    let verdict = classify(
        &st.frames.frames,
        &tangential,
        Some(detached),
        &cfg.classify,
    )
    .map_err(wear_err)?;
    let slide = st.force.samples.last().map_or(0.0, |s| s.displacement[0]);
    Ok(JunctionResult {
        outcome: verdict.outcome,
        verdict,
        particles: rig.sim.particles.len(),
        junction_members: geo.members.len(),
        wall_particles: walls.len(),
        steps: total,
        dt,
        slide,
        force: st.force.samples.clone(),
        frames: st.frames.clone(),
        first,
        last,
        wall_seconds: st.seconds + t0.elapsed().as_secs_f64(),
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

fn snapshot(sim: &Simulation, body: &[u32], role: &[u8]) -> Snapshot {
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
