//! Strength patch tests (paper 000 section 3, Fig. 4b-c) and the fracture energy.
//!
//! The top wall moves at a constant velocity L0 * rate / dt (rate = 1e-5 per step in the paper) along
//! y (tension) or x (shear, at constant wall separation), the bottom wall is fixed, dt = 0.1 dt_c,
//! global damping 0.01 c_c. The virial stress of the deformable part is recorded every `record_every`
//! steps; the strength is its peak (sigma_yy or sigma_xy).
//!
//! Fracture energy (tension only): the run continues until the sample has separated (the stress stays
//! below `stop_below` of the peak for `stop_records` records). Two numbers are reported:
//! - `work_per_area`: the work done by the wall, sum of -F_wall,y v dt over the run, per unit
//!   cross-section. It includes the elastic energy stored at the peak and then dissipated by damping,
//!   about sigma_peak^2 L0 / (2 E) per area, so it grows with the sample height;
//! - `surface_energy`: half the increase of the pair potential energy per unit area between the start
//!   and the separated state (two surfaces are created), the measured counterpart of gamma.

use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::{target_strength, Curve, CurvePoint, WallConfig};
use crate::error::{not_positive, DemError, Result};
use crate::io::checkpoint::Checkpoint;
use crate::io::progress::{self, ProgressFile, SaveClock};
use crate::io::Sig;
use crate::material::PairModel;
use crate::sample::Sample;
use crate::scenario::rig::Rig;
use crate::sim::{Parallelism, RunConfig, Simulation, TimeStep};
use crate::walls::RigidMotion;
use crate::Vec3;

/// Which strength.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StrengthMode {
    /// Top wall pulled along y; peak sigma_yy.
    Tensile,
    /// Top wall moved along x; peak sigma_xy.
    Shear,
}

/// Settings of a strength test.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StrengthConfig {
    /// Tensile or shear.
    pub mode: StrengthMode,
    /// Strain per time step; default 1e-5 (paper: 1e-5 / dt).
    #[serde(default = "d_rate")]
    pub strain_rate: f64,
    /// Global damping as a fraction of c_c; default 0.01 (paper).
    #[serde(default = "d_damping")]
    pub damping: f64,
    /// Time step as a fraction of dt_c; default 0.1 (paper).
    #[serde(default = "d_dt")]
    pub time_step_fraction: f64,
    /// Steps between curve points; default 100 (strain resolution 1e-3, a 1 % peak resolution).
    #[serde(default = "d_record")]
    pub record_every: u64,
    /// After the peak, stop when the stress stays below this fraction of the peak; default 0.01
    /// (separated, for the fracture energy).
    #[serde(default = "d_stop")]
    pub stop_below: f64,
    /// ... for this many successive records; default 10 (a few oscillations of the broken halves).
    #[serde(default = "d_stop_records")]
    pub stop_records: u32,
    /// Or stop this much strain after the peak; default 0.1 (shear keeps some residual strength).
    #[serde(default = "d_post")]
    pub post_peak_strain: f64,
    /// Hard limit on the strain; default 1.
    #[serde(default = "d_max")]
    pub max_strain: f64,
    /// Walls.
    #[serde(default)]
    pub walls: WallConfig,
}

fn d_rate() -> f64 {
    1e-5
}
fn d_damping() -> f64 {
    0.01
}
fn d_dt() -> f64 {
    0.1
}
fn d_record() -> u64 {
    100
}
fn d_stop() -> f64 {
    0.01
}
fn d_stop_records() -> u32 {
    10
}
fn d_post() -> f64 {
    0.1
}
fn d_max() -> f64 {
    1.0
}

impl StrengthConfig {
    /// The paper's settings for `mode`; tension runs up to 0.3 strain past the peak so that amorphous
    /// samples, whose bonds re-form behind the crack, separate completely.
    pub fn paper(mode: StrengthMode) -> Self {
        let post_peak_strain = if mode == StrengthMode::Tensile {
            0.3
        } else {
            d_post()
        };
        StrengthConfig {
            mode,
            strain_rate: d_rate(),
            damping: d_damping(),
            time_step_fraction: d_dt(),
            record_every: d_record(),
            stop_below: d_stop(),
            stop_records: d_stop_records(),
            post_peak_strain,
            max_strain: d_max(),
            walls: WallConfig::default(),
        }
    }

    fn validate(&self) -> Result<()> {
        if let Some(m) = not_positive(&[
            ("strain_rate", self.strain_rate),
            ("time_step_fraction", self.time_step_fraction),
            ("post_peak_strain", self.post_peak_strain),
            ("max_strain", self.max_strain),
        ]) {
            return Err(DemError::InvalidConfig(format!("strength {m}")));
        }
        if !(self.damping.is_finite() && self.damping >= 0.0 && self.stop_below.is_finite())
            || self.record_every == 0
        {
            return Err(DemError::InvalidConfig(
                "strength damping >= 0 and record_every >= 1".into(),
            ));
        }
        Ok(())
    }
}

/// Fracture energy of a tensile test.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FractureResult {
    /// Whether the stress fell below `stop_below` of the peak (complete separation).
    pub separated: bool,
    /// Work done by the wall per unit cross-section.
    pub work_per_area: f64,
    /// Half the pair-potential increase per unit cross-section (measured gamma).
    pub surface_energy: f64,
    /// Target surface energy gamma of the material.
    pub target_surface_energy: f64,
}

/// What a strength test measured.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StrengthResult {
    pub mode: StrengthMode,
    /// Peak virial stress of the deformable part.
    pub strength: f64,
    pub strain_at_peak: f64,
    /// Target strength of eq (20) at the sample's d0 (sigma_N or sigma_T).
    pub target_strength: f64,
    /// strength / target; None where the law has no target strength for this mode (the normal-only
    /// law's shear), rather than an infinity that JSON cannot hold (it wrote null, and a finished
    /// test's progress file could not be read back).
    pub ratio: Option<f64>,
    pub steps: u64,
    pub particles: usize,
    pub fracture: Option<FractureResult>,
    pub wall_seconds: f64,
    /// The recorded curve.
    #[serde(skip)]
    pub curve: Curve,
}

/// Neighbour skin of the strength tests, as a fraction of the median diameter (the engine's default
/// is 0.05). Past the peak the broken bonds release their energy and particles move at a few per
/// cent of the wave speed, a few 1e-3 d0 per step: with the default skin the list was rebuilt every
/// 4 steps and the builds took over half the test (6 507 particles, the sliding layer's shear test
/// on 2 threads, 10 000-15 000 steps: 1 184 builds in 5 000 steps, 10.6 s). At 0.15 the same steps
/// take 5.4 s with 319 builds, and the dense packing adds few pairs (its second neighbours lie
/// beyond 1.2 d0). docs/performance.md, "The strength rig's neighbour builds".
pub const STRENGTH_SKIN: f64 = 0.15;

/// Runs a strength test on `sample` with `model` (including its calibration multipliers).
pub fn strength(
    sample: &Sample,
    model: &PairModel,
    cfg: &StrengthConfig,
    par: Parallelism,
) -> Result<StrengthResult> {
    strength_resumable(sample, model, cfg, par, None)
}

/// What a strength test has done so far: enough to continue it exactly (see [`super::progress`]).
#[derive(Debug, Clone, Serialize, Deserialize)]
struct Progress {
    /// Pair potential energy at the start (for the fracture energy).
    u0: f64,
    curve: Curve,
    /// None until the first record (the peak starts at minus infinity, which JSON cannot hold).
    peak: Option<f64>,
    peak_strain: f64,
    /// Successive records below `stop_below` of the peak.
    low: u32,
    /// Wall work so far.
    work: f64,
    /// Steps up to the last record, and steps into the current one.
    steps: u64,
    in_record: u64,
    /// Wall-clock seconds of the earlier runs.
    seconds: f64,
    sim: Checkpoint,
    /// The result once the test has ended (its curve is `curve` above).
    done: Option<StrengthResult>,
}

/// [`strength`], saving its progress to `progress` (periodically and on an interrupt) and continuing
/// from it when it holds the progress of the same inputs. When the test ends the file keeps its
/// result, so that a rerun returns it at once; the caller removes the file when it no longer needs it
/// (the patch campaign does once the result is in its report).
pub fn strength_resumable(
    sample: &Sample,
    model: &PairModel,
    cfg: &StrengthConfig,
    par: Parallelism,
    progress: Option<&ProgressFile>,
) -> Result<StrengthResult> {
    cfg.validate()?;
    let t0 = Instant::now();
    let tensile = cfg.mode == StrengthMode::Tensile;
    let run = RunConfig {
        time_step: TimeStep::FractionOfCritical(cfg.time_step_fraction),
        global_damping: cfg.damping,
        track_energy: tensile,
        skin_fraction: STRENGTH_SKIN,
        ..RunConfig::default()
    };
    let mut rig = Rig::new(sample, model, cfg.walls.rig_spec(sample, model), run, par)?;
    let key = progress::key(&(cfg, model, STRENGTH_SKIN), sample)?;
    let saved = progress.and_then(|f| progress::load::<Progress>(&f.path, &key));
    let mut st = match saved {
        Some(mut p) => {
            if let Some(mut done) = p.done.take() {
                tracing::info!(target: "stage", mode = ?cfg.mode, "strength test: finished result taken from its progress file");
                done.curve = p.curve;
                return Ok(done);
            }
            tracing::info!(target: "stage", mode = ?cfg.mode, step = p.steps + p.in_record, "strength test resumed from its progress file");
            p
        }
        None => {
            rig.sim.step()?;
            let u0 = rig.sim.energy().normal + rig.sim.energy().tangential;
            rig.sim.set_config(RunConfig {
                track_energy: false,
                ..run
            })?;
            Progress {
                u0,
                curve: Curve::default(),
                peak: None,
                peak_strain: 0.0,
                low: 0,
                work: 0.0,
                steps: 1,
                in_record: 0,
                seconds: 0.0,
                sim: rig.sim.checkpoint(),
                done: None,
            }
        }
    };
    // The simulation restarts from the checkpoint in either case, so that a fresh run and a resumed
    // one step the same rebuilt state (bit-identical continuations).
    rig.sim = Simulation::from_checkpoint(st.sim.clone(), par)?;
    let dt = rig.sim.dt();
    let speed = cfg.strain_rate * rig.l0 / dt;
    let v = if tensile {
        Vec3::new(0.0, speed, 0.0)
    } else {
        Vec3::new(speed, 0.0, 0.0)
    };
    rig.set_top(RigidMotion::with_velocity(v));
    let component = if tensile { (1, 1) } else { (0, 1) };
    let every = 5000 * cfg.record_every.div_ceil(100).max(1);
    let mut clock = SaveClock::new();
    let outcome: Result<bool> = loop {
        let mut failed = None;
        while st.in_record < cfg.record_every {
            if st.in_record + 1 == cfg.record_every {
                rig.sim.request_virial();
            }
            if let Err(e) = rig.sim.step() {
                failed = Some(e);
                break;
            }
            // Work of the constraint force (minus the pair force on the wall) over this step.
            st.work -= rig.top_traction().dot(&v) * rig.area * dt;
            st.in_record += 1;
        }
        if let Some(e) = failed {
            break Err(e);
        }
        st.in_record = 0;
        st.steps += cfg.record_every;
        let s = rig.stress();
        let (exy, eyy) = rig.strains();
        let tr = rig.top_traction();
        let strain = if tensile { eyy } else { exy };
        let value = s[component];
        st.curve.points.push(CurvePoint {
            step: st.steps,
            strain_xy: exy,
            strain_yy: eyy,
            stress: CurvePoint::components(&s),
            wall_traction_y: tr.y,
            wall_traction_x: tr.x,
        });
        if st.peak.is_none_or(|p| value > p) {
            st.peak = Some(value);
            st.peak_strain = strain;
        }
        let peak = st.peak.unwrap_or(value);
        if st.steps % every < cfg.record_every {
            tracing::info!(target: "stage", mode = ?cfg.mode, step = st.steps, strain = %Sig(strain, 4), stress = %Sig(value, 4), peak = %Sig(peak, 4), "strength test");
        }
        let past_peak = strain > st.peak_strain && peak > 0.0;
        st.low = if past_peak && value.abs() < cfg.stop_below * peak {
            st.low + 1
        } else {
            0
        };
        if st.low >= cfg.stop_records {
            break Ok(true);
        }
        if (past_peak && strain - st.peak_strain > cfg.post_peak_strain) || strain > cfg.max_strain
        {
            break Ok(false);
        }
        if let Some(f) = progress.filter(|f| clock.due(f.every)) {
            save_progress(f, &key, &mut st, &rig, t0)?;
        }
    };
    let separated = match outcome {
        Ok(separated) => separated,
        Err(e) => {
            // An interrupt leaves the state at a step boundary: keep it for the rerun. (Any other
            // failure keeps the last periodic save, made from a healthy state.)
            if let (DemError::Interrupted { .. }, Some(f)) = (&e, progress) {
                save_progress(f, &key, &mut st, &rig, t0)?;
                tracing::info!(target: "stage", path = %f.path.display(), "strength test progress saved: rerun to continue");
            }
            return Err(e);
        }
    };
    let (u0, work, steps, curve) = (st.u0, st.work, st.steps, st.curve.clone());
    let (peak, peak_strain) = (st.peak.unwrap_or(f64::NEG_INFINITY), st.peak_strain);
    let fracture = if tensile {
        rig.sim.set_config(run)?;
        rig.sim.step()?;
        let u1 = rig.sim.energy().normal + rig.sim.energy().tangential;
        Some(FractureResult {
            separated,
            work_per_area: work / rig.area,
            surface_energy: 0.5 * (u1 - u0) / rig.area,
            target_surface_energy: model.material.surface_energy,
        })
    } else {
        None
    };
    let m = &model.material;
    let base = if tensile {
        m.tensile_strength
    } else {
        m.shear_strength
    };
    let target = target_strength(base, sample.d0, m.critical_diameter(), m.scaling);
    let res = StrengthResult {
        mode: cfg.mode,
        strength: peak,
        strain_at_peak: peak_strain,
        target_strength: target,
        ratio: (target > 0.0).then(|| peak / target),
        steps,
        particles: rig.sim.particles.len(),
        fracture,
        wall_seconds: st.seconds + t0.elapsed().as_secs_f64(),
        curve,
    };
    if let Some(f) = progress {
        st.done = Some(res.clone());
        save_progress(f, &key, &mut st, &rig, t0)?;
    }
    let of_target = res.ratio.map_or("-".into(), |r| Sig(r, 4).to_string());
    tracing::info!(target: "stage", mode = ?cfg.mode, strength = %Sig(peak, 4), of_target = %of_target, steps, seconds = %Sig(res.wall_seconds, 3), "strength test");
    Ok(res)
}

/// Writes the test's state with the simulation's current checkpoint.
fn save_progress(
    f: &ProgressFile,
    key: &str,
    st: &mut Progress,
    rig: &Rig,
    t0: Instant,
) -> Result<()> {
    st.sim = rig.sim.checkpoint();
    let seconds = st.seconds;
    st.seconds += t0.elapsed().as_secs_f64();
    let r = progress::save(&f.path, key, &*st);
    st.seconds = seconds;
    r
}
