//! The simulation: state, model and scratch, advanced by a pipeline of named, timed phases:
//! neighbour list -> pair forces -> rigid bodies -> free particles -> box.
//!
//! Parallelism is a value passed in ([`Parallelism`]); every parallel phase computes per pair or per
//! particle in fixed chunks and combines them in a fixed order, so trajectories are bit-identical for any
//! number of threads.

use std::sync::Arc;

use nalgebra::Matrix3;
use serde::{Deserialize, Serialize};

use crate::domain::{BoxControl, SimBox};
use crate::energy::EnergyLedger;
use crate::error::{DemError, Result};
use crate::force::{ForceBuffers, ForcePhase};
use crate::integrate::{advance_free, StepParams};
use crate::material::{PairCoefficients, PairModel};
use crate::neighbor::{NeighborList, PairRange, Rebuild};
use crate::state::Particles;
use crate::walls::{Group, RigidIndex};
use crate::Vec3;

/// How many threads the engine uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum Parallelism {
    /// One thread, no rayon.
    #[default]
    Sequential,
    /// A dedicated rayon pool of this many threads, at every system size (what the tests that compare
    /// thread counts use, so that small systems exercise the parallel path too).
    Threads(usize),
    /// A pool of this many threads for systems of at least [`SERIAL_BELOW`] particles; smaller ones
    /// step on the calling thread, to the same bits. What the command line's `--threads` gives.
    Adaptive(usize),
}

impl Parallelism {
    /// The threads it may use (at least 1).
    pub fn threads(&self) -> usize {
        match *self {
            Parallelism::Sequential => 1,
            Parallelism::Threads(n) | Parallelism::Adaptive(n) => n.max(1),
        }
    }
}

/// Under [`Parallelism::Adaptive`], systems with fewer particles step on one thread whatever the
/// pool: their step (~0.1 ms) is too short for the pool's hand-offs. Measured on this project's
/// 2-core machine (docs/performance.md, 5 Dec): HCP packings of 144 / 384 / 800 particles ran
/// 0.90x / 1.0x / 1.29x as fast on two threads as on one, and the 508-particle paper-000 junction
/// (d0 = 6 nm) 0.86x.
pub const SERIAL_BELOW: usize = 600;

/// The time step, absolute or relative to the critical one of eq (6).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TimeStep {
    /// Fraction of dt_c.
    FractionOfCritical(f64),
    /// Absolute value in engine units.
    Absolute(f64),
}

/// Run settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunConfig {
    /// Time step; default 0.1 dt_c, the value of every run in paper 000.
    #[serde(default = "default_dt")]
    pub time_step: TimeStep,
    /// Accept a time step above dt_c (for stability studies only); default false because such runs diverge.
    #[serde(default)]
    pub allow_supercritical_dt: bool,
    /// Global viscous damping as a fraction of c_c (eq 21); default 0, the pair dampers alone.
    #[serde(default)]
    pub global_damping: f64,
    /// Neighbour skin as a fraction of the median diameter; default 0.05, small enough for a dense HCP
    /// packing to exclude second neighbours and large enough to rebuild only every tens of steps.
    /// (The median, not the smallest: in a wide size distribution, such as paper 000's silica with
    /// diameters from 0.75 d0 to 5 d0, a skin tied to the smallest particles rebuilds the list twice
    /// as often for a handful more pairs, docs/performance.md. Equal spheres are unaffected.)
    #[serde(default = "default_skin")]
    pub skin_fraction: f64,
    /// Rebuild only the neighbour rows of the particles that moved (`neighbor::local`); default false,
    /// because where everything moves (relaxations, patch tests) a full build is cheaper.
    #[serde(default)]
    pub local_rebuilds: bool,
    /// Keep the energy ledger up to date every step; default false (it costs a pass over the pairs).
    #[serde(default)]
    pub track_energy: bool,
    /// Planar motion (a quasi-2D monolayer in the x-y plane): every free particle's force and velocity
    /// along z and its torque and spin about x and y are zeroed before each update, so z never changes
    /// (to the bit) and particles roll about z only; default false (3D). The z forces are the reaction
    /// of an ideal frictionless constraint: they do no work, so the energy balance is unchanged.
    #[serde(default)]
    pub planar: bool,
}

fn default_dt() -> TimeStep {
    TimeStep::FractionOfCritical(0.1)
}
fn default_skin() -> f64 {
    0.05
}

impl Default for RunConfig {
    fn default() -> Self {
        RunConfig {
            time_step: default_dt(),
            allow_supercritical_dt: false,
            global_damping: 0.0,
            skin_fraction: default_skin(),
            local_rebuilds: false,
            track_energy: false,
            planar: false,
        }
    }
}

impl PairRange for PairCoefficients {
    fn cutoff(&self, ri: f64, rj: f64) -> f64 {
        PairCoefficients::cutoff(self, ri, rj)
    }
    fn max_cutoff(&self, r_max: f64) -> f64 {
        PairCoefficients::max_cutoff(self, r_max)
    }
    fn beyond_contact(&self, r: f64) -> f64 {
        // The largest delta_f of a pair with r_i + r_j <= 2 r.
        PairCoefficients::max_cutoff(self, r) - 2.0 * r
    }
}

/// A running DEM simulation.
#[derive(Debug)]
pub struct Simulation {
    /// Particle state.
    pub particles: Particles,
    /// The box.
    pub sim_box: SimBox,
    /// How the box moves.
    pub box_control: BoxControl,
    /// Groups; index 0 is the default group.
    pub groups: Vec<Group>,
    pub(crate) model: PairModel,
    pub(crate) coef: PairCoefficients,
    pub(crate) config: RunConfig,
    pub(crate) rigid: RigidIndex,
    pub(crate) list: NeighborList,
    pub(crate) buffers: ForceBuffers,
    pub(crate) dt: f64,
    pub(crate) damping_coef: f64,
    pub(crate) step: u64,
    pub(crate) time: f64,
    pub(crate) ledger: EnergyLedger,
    pub(crate) want_virial: bool,
    pub(crate) have_virial_at: Option<u64>,
    pub(crate) parallelism: Parallelism,
    pub(crate) pool: Option<Arc<rayon::ThreadPool>>,
    /// `Some(largest distance from the list's reference positions)` while the integrator's last pass
    /// is the particles' state: it wrote the force phase's kinematics records and measured that
    /// distance, and nothing has moved a particle since. Cleared at the start of every `run` (since
    /// `particles` is public), by list rebuilds (they wrap positions) and by box moves.
    pub(crate) integrated: Option<f64>,
}

impl Simulation {
    /// Assembles and validates a simulation. `groups` must contain every group index the particles use
    /// (an empty list means one free group named "all").
    pub fn new(
        particles: Particles,
        sim_box: SimBox,
        model: PairModel,
        mut groups: Vec<Group>,
        config: RunConfig,
        parallelism: Parallelism,
    ) -> Result<Self> {
        if groups.is_empty() {
            groups.push(Group::free("all"));
        }
        let mut sim = Simulation {
            coef: PairCoefficients::new(&model),
            particles,
            sim_box,
            box_control: BoxControl::Fixed,
            groups,
            model,
            config,
            rigid: RigidIndex::default(),
            list: NeighborList::new(0.0)?,
            buffers: ForceBuffers::default(),
            dt: 0.0,
            damping_coef: 0.0,
            step: 0,
            time: 0.0,
            ledger: EnergyLedger::default(),
            want_virial: false,
            have_virial_at: None,
            parallelism,
            pool: None,
            integrated: None,
        };
        sim.set_parallelism(parallelism)?;
        sim.reconfigure()?;
        Ok(sim)
    }

    /// Re-derives everything that depends on particles, model, groups and config, and validates them.
    fn reconfigure(&mut self) -> Result<()> {
        self.model.validate()?;
        self.particles.validate()?;
        if self.particles.is_empty() {
            return Err(DemError::InvalidConfig(
                "a simulation needs at least one particle".into(),
            ));
        }
        let c = &self.config;
        if !(c.global_damping.is_finite() && c.global_damping >= 0.0) {
            return Err(DemError::InvalidConfig(format!(
                "global_damping {} must be >= 0",
                c.global_damping
            )));
        }
        if !(c.skin_fraction.is_finite() && c.skin_fraction >= 0.0) {
            return Err(DemError::InvalidConfig(format!(
                "skin_fraction {} must be >= 0",
                c.skin_fraction
            )));
        }
        self.coef = PairCoefficients::new(&self.model);
        // Per-pair constants depend on radii, masses and the model: recompute them before the next step.
        self.buffers.invalidate();
        self.rigid = RigidIndex::new(&self.groups, &self.particles)?;
        self.rigid.check_overlaps(&self.groups, &self.particles)?;
        self.box_control.validate(&self.sim_box)?;
        let dt_c = self.critical_time_step();
        self.dt = match c.time_step {
            TimeStep::FractionOfCritical(f) => f * dt_c,
            TimeStep::Absolute(dt) => dt,
        };
        if !(self.dt.is_finite() && self.dt > 0.0) {
            return Err(DemError::InvalidConfig(format!(
                "time step {} must be positive",
                self.dt
            )));
        }
        if self.dt > dt_c && !c.allow_supercritical_dt {
            return Err(DemError::TimeStepAboveCritical {
                dt: self.dt,
                dt_critical: dt_c,
            });
        }
        // c_c of eq (21), for the smallest particle.
        let i_min = (0..self.particles.len())
            .min_by(|&a, &b| self.particles.radius[a].total_cmp(&self.particles.radius[b]))
            .unwrap_or(0);
        let (r, m) = (self.particles.radius[i_min], self.particles.mass[i_min]);
        self.damping_coef = c.global_damping * self.model.critical_damping(r, m);
        let mut radii = self.particles.radius.clone();
        let mid = radii.len() / 2;
        let (_, r_median, _) = radii.select_nth_unstable_by(mid, f64::total_cmp);
        let skin = c.skin_fraction * 2.0 * *r_median;
        if self.list.skin != skin || self.list.row_start.len() != self.particles.len() + 1 {
            let hist_kept = self.list.row_start.len() == self.particles.len() + 1;
            if hist_kept {
                self.list.skin = skin;
            } else {
                self.list = NeighborList::new(skin)?;
            }
        }
        self.list.local = c.local_rebuilds;
        self.list.mark_stale();
        Ok(())
    }

    /// Critical time step of eq (6): min over particles of sqrt(2 m / k_N) for the particle paired with
    /// its twin; for polydisperse packings the smallest particle gives the minimum.
    pub fn critical_time_step(&self) -> f64 {
        (0..self.particles.len())
            .map(|i| {
                self.model
                    .critical_time_step(self.particles.radius[i], self.particles.mass[i])
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// Replaces the pair model (e.g. switching cohesion on between relaxation phases).
    pub fn set_model(&mut self, model: PairModel) -> Result<()> {
        self.model = model;
        self.reconfigure()
    }

    /// Replaces the run settings.
    pub fn set_config(&mut self, config: RunConfig) -> Result<()> {
        self.config = config;
        self.reconfigure()
    }

    /// Replaces the groups (e.g. after carving walls).
    pub fn set_groups(&mut self, groups: Vec<Group>) -> Result<()> {
        self.groups = groups;
        self.reconfigure()
    }

    /// Sets how the box moves.
    pub fn set_box_control(&mut self, control: BoxControl) -> Result<()> {
        control.validate(&self.sim_box)?;
        self.box_control = control;
        Ok(())
    }

    /// Call after changing particle masses, radii or count directly.
    pub fn particles_changed(&mut self) -> Result<()> {
        if self.list.row_start.len() != self.particles.len() + 1 {
            self.list.invalidate();
        }
        self.reconfigure()
    }

    /// Uses `parallelism` from now on.
    pub fn set_parallelism(&mut self, parallelism: Parallelism) -> Result<()> {
        self.pool = match parallelism {
            Parallelism::Sequential
            | Parallelism::Threads(0 | 1)
            | Parallelism::Adaptive(0 | 1) => None,
            Parallelism::Threads(n) | Parallelism::Adaptive(n) => Some(Arc::new(
                rayon::ThreadPoolBuilder::new()
                    .num_threads(n)
                    .build()
                    .map_err(|e| {
                        DemError::InvalidConfig(format!("cannot start {n} threads: {e}"))
                    })?,
            )),
        };
        self.parallelism = parallelism;
        Ok(())
    }

    /// The pair model.
    pub fn model(&self) -> &PairModel {
        &self.model
    }
    /// The run settings.
    pub fn config(&self) -> &RunConfig {
        &self.config
    }
    /// The time step in use.
    pub fn dt(&self) -> f64 {
        self.dt
    }
    /// Steps done.
    pub fn step_count(&self) -> u64 {
        self.step
    }
    /// Simulated time.
    pub fn time(&self) -> f64 {
        self.time
    }
    /// Energy ledger (kinetic and potential terms at the last force evaluation; up to date only with
    /// `track_energy`).
    pub fn energy(&self) -> EnergyLedger {
        self.ledger
    }
    /// Absolute global damping coefficient c (force per velocity).
    pub fn global_damping_coefficient(&self) -> f64 {
        self.damping_coef
    }
    /// The neighbour list.
    pub fn neighbors(&self) -> &NeighborList {
        &self.list
    }
    /// Number of neighbour-list builds so far.
    pub fn neighbor_builds(&self) -> u64 {
        self.list.builds
    }
    /// Position of particle `i` on its continuous trajectory: the stored position is wrapped into the
    /// box at list builds, so a wall's travel or a displacement is read from this one.
    pub fn unwrapped_position(&self, i: usize) -> Vec3 {
        let x = self.particles.pos[i];
        match self.list.wraps.get(i) {
            Some(w) => {
                let l = self.sim_box.lengths();
                x + Vec3::new(w[0] as f64 * l.x, w[1] as f64 * l.y, w[2] as f64 * l.z)
            }
            None => x,
        }
    }
    /// Pair forces on each particle at the last step.
    pub fn forces(&self) -> &[Vec3] {
        &self.buffers.force
    }
    /// Pair torques on each particle at the last step.
    pub fn torques(&self) -> &[Vec3] {
        &self.buffers.torque
    }
    /// Index of a group by name.
    pub fn group_index(&self, name: &str) -> Result<usize> {
        self.groups
            .iter()
            .position(|g| g.name == name)
            .ok_or_else(|| DemError::InvalidConfig(format!("no group named '{name}'")))
    }

    /// Ask for per-particle virials at the next step (stress queries read them).
    pub fn request_virial(&mut self) {
        self.want_virial = true;
    }

    /// Advances `n` steps. With a thread pool, the steps run inside one `install` of the pool: handing
    /// every step to the pool and back cost ~5 us, 7 % of a 1 000-particle step on two threads. Under
    /// [`Parallelism::Adaptive`] a system below [`SERIAL_BELOW`] particles steps on the calling thread
    /// (the result is the same to the bit either way).
    pub fn run(&mut self, n: u64) -> Result<()> {
        self.integrated = None;
        let serial = matches!(self.parallelism, Parallelism::Adaptive(_))
            && self.particles.len() < SERIAL_BELOW;
        match self.pool.clone() {
            Some(pool) if !serial => {
                pool.install(|| (0..n).try_for_each(|_| self.checked_step(true)))
            }
            _ => (0..n).try_for_each(|_| self.checked_step(false)),
        }
    }

    /// One step of the pipeline.
    pub fn step(&mut self) -> Result<()> {
        self.run(1)
    }

    fn checked_step(&mut self, parallel: bool) -> Result<()> {
        if crate::interrupt::requested() {
            return Err(DemError::Interrupted { step: self.step });
        }
        if self.rigid.is_rigid.len() != self.particles.len() {
            return Err(DemError::InvalidConfig(
                "the particle count changed: call particles_changed() before stepping".into(),
            ));
        }
        self.step_inner(parallel)
    }

    fn step_inner(&mut self, parallel: bool) -> Result<()> {
        let _step = tracing::trace_span!("step", n = self.step).entered();
        {
            let _s = tracing::trace_span!("neighbor").entered();
            // The integrator measured the displacement as it moved the particles; nothing has
            // moved them since when the records are fresh.
            let known = self.integrated;
            let rebuilt = self.list.update_known(
                &mut self.particles.pos,
                &self.particles.radius,
                &self.sim_box,
                &self.coef,
                parallel,
                known,
            )?;
            if !matches!(rebuilt, Rebuild::None) {
                self.integrated = None;
            }
        }
        let stress_control = matches!(self.box_control, BoxControl::Stress { .. });
        let virial = self.want_virial || stress_control;
        let phase = ForcePhase {
            energy: self.config.track_energy,
            virial,
            parallel,
        };
        let totals = {
            let _s = tracing::trace_span!("forces").entered();
            self.buffers.compute(
                phase,
                &self.coef,
                &self.particles,
                &self.sim_box,
                &mut self.list,
                self.dt,
                self.integrated.is_some(),
            )
        };
        let wall_work = {
            let _s = tracing::trace_span!("walls").entered();
            self.rigid.advance(
                &mut self.groups,
                &mut self.particles,
                &self.buffers.force,
                &self.sim_box,
                self.dt,
            )
        };
        let sums = {
            let _s = tracing::trace_span!("integrate").entered();
            let forces = self.buffers.for_integrator(self.particles.len());
            let params = StepParams {
                damping: self.damping_coef,
                dt: self.dt,
                energy: self.config.track_energy,
                planar: self.config.planar,
                parallel,
            };
            advance_free(
                &mut self.particles,
                forces,
                &self.rigid.is_rigid,
                self.list.reference_positions(),
                &params,
            )
        };
        self.integrated = Some(sums.max_displacement2.sqrt());
        if self.config.track_energy {
            let l = &mut self.ledger;
            l.kinetic = sums.kinetic;
            l.normal = totals.normal;
            l.tangential = totals.tangential;
            l.wall_work += wall_work;
            l.damping += (totals.damping_power + sums.damping_power) * self.dt;
            l.sliding += totals.slid;
        }
        {
            let _s = tracing::trace_span!("box").entered();
            self.advance_box()?;
        }
        self.step += 1;
        self.time += self.dt;
        if virial {
            self.want_virial = false;
            self.have_virial_at = Some(self.step);
        }
        // The integrator screened every state it wrote; an affine box move with finite lengths keeps
        // finite positions finite. Only a failed screen pays for the full scan that names the culprit.
        if sums.finite && self.sim_box.lengths().iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            self.check_finite(parallel)
        }
    }

    fn advance_box(&mut self) -> Result<()> {
        if !matches!(self.box_control, BoxControl::Fixed) {
            // A remap moves the particles after the integrator recorded them.
            self.integrated = None;
        }
        let strain: Vec3 = match self.box_control {
            BoxControl::Fixed => return Ok(()),
            BoxControl::StrainRate { rate, remap } => {
                let de = rate * self.dt;
                self.deform(de, remap);
                return Ok(());
            }
            BoxControl::Stress {
                target,
                axes,
                modulus,
                gain,
                max_strain_step,
            } => {
                let s = self.virial_stress(None, None);
                let mut de = Vec3::zeros();
                for a in 0..3 {
                    if axes[a] {
                        // Too much tension (sigma > target): shrink; too much compression: expand.
                        de[a] = (gain * (target[a] - s[(a, a)]) / modulus)
                            .clamp(-max_strain_step, max_strain_step);
                    }
                }
                de
            }
        };
        self.deform(strain, true);
        Ok(())
    }

    /// Applies the strain increment `de` (per axis) to the box, remapping particles affinely if asked.
    pub fn deform(&mut self, de: Vec3, remap: bool) {
        let c = self.sim_box.centre();
        for a in 0..3 {
            if de[a] == 0.0 {
                continue;
            }
            let f = self.sim_box.strain_axis(a, de[a]);
            if remap {
                for x in self.particles.pos.iter_mut() {
                    x[a] = c[a] + (x[a] - c[a]) * f;
                }
            }
        }
    }

    fn check_finite(&self, parallel: bool) -> Result<()> {
        use rayon::prelude::*;
        let p = &self.particles;
        let bad_at = |i: usize| {
            !(p.pos[i].iter().all(|x| x.is_finite())
                && p.vel[i].iter().all(|x| x.is_finite())
                && p.omega[i].iter().all(|x| x.is_finite()))
        };
        let bad = if parallel {
            (0..p.len())
                .into_par_iter()
                .with_min_len(4096)
                .find_first(|&i| bad_at(i))
        } else {
            (0..p.len()).find(|&i| bad_at(i))
        };
        match bad {
            Some(i) => Err(DemError::NonFinite {
                step: self.step,
                index: i,
                what: "position or velocity",
            }),
            None => Ok(()),
        }
    }

    /// Virial stress (tension positive) of the particles selected by `select` (all when `None`), over
    /// `volume` (the box volume when `None`): sigma = -(1/V) sum_i [ m_i v_i (x) v_i + sum_j 1/2 (x_i - x_j)
    /// (x) F_ij ]. Uses the per-particle virials of the last step that had them (see
    /// [`Simulation::request_virial`]); the kinetic part uses the current velocities.
    pub fn virial_stress(
        &self,
        select: Option<&dyn Fn(usize) -> bool>,
        volume: Option<f64>,
    ) -> Matrix3<f64> {
        let v = volume.unwrap_or_else(|| self.sim_box.volume());
        let p = &self.particles;
        let mut acc = Matrix3::zeros();
        let have = self.buffers.virial.len() == p.len();
        for i in 0..p.len() {
            if select.is_some_and(|f| !f(i)) {
                continue;
            }
            acc += p.mass[i] * p.vel[i] * p.vel[i].transpose();
            if have {
                acc += self.buffers.virial[i];
            }
        }
        -acc / v
    }

    /// Step at which the per-particle virials were last computed.
    pub fn virial_step(&self) -> Option<u64> {
        self.have_virial_at
    }
}
