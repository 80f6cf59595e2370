//! Shear under normal load: does the packing hold its volume when it flows?
//!
//! The patch tests of paper 000 (Fig. 4) load a sample one way at a time and keep the wall separation
//! fixed in shear, so a packing that is metastable, whose particles can be pushed into each other once
//! the contacts slide, passes them all: the calibrated silica cards of 3 Dec measured E, nu and both
//! strengths within 10 % of their targets on fresh samples and then compacted until the walls met in
//! the junction (docs/junction.md, "Calibrated cards collapse under shear"). This test is the
//! junction's loading without the junction: the top wall is pressed along -y with a constant pressure
//! (traction control, the rig's [`sliding_top`]) and dragged along x at the strength tests' strain
//! rate, the bottom wall fixed, x and z periodic.
//!
//! Two phases: `load_steps` under the pressure alone (the elastic compression p / C11, about 1 % at the
//! default pressure), then shear to `strain`. The measure is the *compaction* eps_c = eps_yy(loaded) -
//! eps_yy(t), the shear-induced decrease of the wall separation over L0 (positive when the sample
//! shrinks); the test stops early once it exceeds `max_compaction` and reports the packing as
//! collapsing. A sound amorphous packing dilates or compacts by a few 1e-3 when it flows (measured in
//! docs/calibration.md, "Shear under load"); the collapsing cards lose tens of percent.

use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::{Curve, CurvePoint, WallConfig};
use crate::error::{not_positive, DemError, Result};
use crate::io::Sig;
use crate::material::PairModel;
use crate::sample::Sample;
use crate::scenario::driven::sliding_top;
use crate::scenario::rig::Rig;
use crate::sim::{Parallelism, RunConfig, TimeStep};

/// Settings of the shear-under-load test.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CompactionConfig {
    /// Normal pressure on the top wall as a fraction of E; default 0.01: the mean contact pressure of
    /// the paper's silica junction (100 MPa over the 60 x 40 nm wall carried by a 20 nm junction,
    /// 0.76 GPa = 0.010 E), the load under which the calibrated cards collapsed.
    pub pressure: f64,
    /// Shear strain per time step; default 1e-5, the strength tests' rate (the junction's 10 m/s over
    /// its 23 nm gap at d0 = 3 nm is 1.7e-5).
    pub strain_rate: f64,
    /// Shear strain at which the test ends; default 1 (the calibrated junctions had compacted by one
    /// junction height when the wall had slid 0.35-0.46 gap heights).
    pub strain: f64,
    /// Steps under the pressure alone before the shear; default 5 000 (tens of sound crossings of a
    /// 20 d0 sample, the elastic compression settles).
    pub load_steps: u64,
    /// Compaction (fraction of L0) above which the packing is reported as collapsing and the test
    /// stops; default 0.05: ten times what the sound packings measured.
    pub max_compaction: f64,
    /// Global damping as a fraction of c_c; default 0.01 (the strength tests').
    pub damping: f64,
    /// Time step as a fraction of dt_c; default 0.1 (paper).
    pub time_step_fraction: f64,
    /// Steps between curve points; default 200 (strain resolution 2e-3).
    pub record_every: u64,
    /// Walls.
    pub walls: WallConfig,
}

impl Default for CompactionConfig {
    fn default() -> Self {
        CompactionConfig {
            pressure: 0.01,
            strain_rate: 1e-5,
            strain: 1.0,
            load_steps: 5000,
            max_compaction: 0.05,
            damping: 0.01,
            time_step_fraction: 0.1,
            record_every: 200,
            walls: WallConfig::default(),
        }
    }
}

impl CompactionConfig {
    fn validate(&self) -> Result<()> {
        if let Some(m) = not_positive(&[
            ("pressure", self.pressure),
            ("strain_rate", self.strain_rate),
            ("strain", self.strain),
            ("max_compaction", self.max_compaction),
            ("time_step_fraction", self.time_step_fraction),
        ]) {
            return Err(DemError::InvalidConfig(format!("compaction {m}")));
        }
        if !(self.damping.is_finite() && self.damping >= 0.0) || self.record_every == 0 {
            return Err(DemError::InvalidConfig(
                "compaction damping >= 0 and record_every >= 1".into(),
            ));
        }
        Ok(())
    }
}

/// What the shear-under-load test measured.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CompactionResult {
    /// Applied normal pressure (engine units).
    pub pressure: f64,
    /// Normal strain under the pressure before the shear, averaged over the second half of the load
    /// phase (negative: compressed).
    pub loaded_strain: f64,
    /// Shear strain reached.
    pub shear_strain: f64,
    /// Compaction at the end (fraction of L0, positive when the sample shrank under the shear).
    pub compaction: f64,
    /// Largest compaction of the run.
    pub largest_compaction: f64,
    /// Whether the largest compaction passed `max_compaction` (the test then stopped there).
    pub collapsed: bool,
    /// Mean shear traction on the top wall over the second half of the shear, over the pressure: the
    /// sample's sliding friction coefficient.
    pub friction: f64,
    pub steps: u64,
    pub particles: usize,
    pub wall_seconds: f64,
    /// The recorded curve (load and shear phases).
    #[serde(skip)]
    pub curve: Curve,
}

/// Runs the shear-under-load test on `sample` with `model`.
pub fn compaction(
    sample: &Sample,
    model: &PairModel,
    cfg: &CompactionConfig,
    par: Parallelism,
) -> Result<CompactionResult> {
    cfg.validate()?;
    let t0 = Instant::now();
    let run = RunConfig {
        time_step: TimeStep::FractionOfCritical(cfg.time_step_fraction),
        global_damping: cfg.damping,
        ..RunConfig::default()
    };
    let mut rig = Rig::new(sample, model, cfg.walls.rig_spec(sample, model), run, par)?;
    let pressure = cfg.pressure * model.material.young_modulus;
    let mut curve = Curve::default();
    let mut steps = 0u64;
    let mut record = |rig: &mut Rig, steps: &mut u64, n: u64| -> Result<(f64, f64)> {
        for k in 0..n {
            if k + 1 == n {
                rig.sim.request_virial();
            }
            rig.sim.step()?;
        }
        *steps += n;
        let (exy, eyy) = rig.strains();
        let tr = rig.top_traction();
        curve.points.push(CurvePoint {
            step: *steps,
            strain_xy: exy,
            strain_yy: eyy,
            stress: CurvePoint::components(&rig.stress()),
            wall_traction_y: tr.y,
            wall_traction_x: tr.x,
        });
        Ok((exy, eyy))
    };
    rig.set_top(sliding_top(0.0, pressure));
    // The wall rings on the sample under the suddenly applied load (the strength tests' light
    // damping): the reference is the mean normal strain over the second half of the load phase, not
    // one sample of the oscillation (which moved the compaction by up to 0.6 % of L0).
    let (mut sum, mut count) = (0.0, 0u32);
    while steps < cfg.load_steps {
        let n = cfg.record_every.min(cfg.load_steps - steps);
        let eyy = record(&mut rig, &mut steps, n)?.1;
        if 2 * steps > cfg.load_steps {
            sum += eyy;
            count += 1;
        }
    }
    let loaded = if count > 0 {
        sum / f64::from(count)
    } else {
        0.0
    };
    let speed = cfg.strain_rate * rig.l0 / rig.sim.dt();
    rig.set_top(sliding_top(speed, pressure));
    let (mut compaction, mut largest, mut exy) = (0.0, 0.0f64, 0.0);
    let every = 25 * cfg.record_every;
    // A diverging run stops inside `record` (the engine's non-finite check of every step).
    while exy < cfg.strain {
        let (x, y) = record(&mut rig, &mut steps, cfg.record_every)?;
        (exy, compaction) = (x, loaded - y);
        largest = largest.max(compaction);
        if steps % every < cfg.record_every {
            tracing::info!(target: "stage", step = steps, shear_strain = %Sig(exy, 4), compaction = %Sig(compaction, 4), "compaction test");
        }
        if largest > cfg.max_compaction {
            break;
        }
    }
    // Friction from the curve's shear phase: the x traction the sample exerts on the wall resists the
    // drag (negative), hence minus it.
    let half: Vec<f64> = curve
        .points
        .iter()
        .filter(|c| c.step > cfg.load_steps && c.strain_xy >= 0.5 * exy)
        .map(|c| -c.wall_traction_x)
        .collect();
    let friction = half.iter().sum::<f64>() / half.len().max(1) as f64 / pressure;
    let res = CompactionResult {
        pressure,
        loaded_strain: loaded,
        shear_strain: exy,
        compaction,
        largest_compaction: largest,
        collapsed: largest > cfg.max_compaction,
        friction,
        steps,
        particles: rig.sim.particles.len(),
        wall_seconds: t0.elapsed().as_secs_f64(),
        curve,
    };
    tracing::info!(target: "stage", compaction = %Sig(res.compaction, 4), largest = %Sig(largest, 4), collapsed = res.collapsed, friction = %Sig(friction, 3), steps, seconds = %Sig(res.wall_seconds, 3), "compaction test");
    Ok(res)
}
