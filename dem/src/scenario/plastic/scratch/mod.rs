//! Scratching (paper 001 sections 3, 3.1, 4.3, 4.4): the indenter is pushed into the surface at a
//! constant speed V_z until the contact force reaches a load F_z (Fig. 8), then slides at a constant
//! V_x under that fixed load, without rotation, free to sink or rise (Fig. 9). Measured per load:
//! the wear volume per distance in the steady part of the slide (Figs. 3a, 10), the lateral force
//! F_x and the contact area A_z (section 3.1: H_l = dF_x / dA_z, Fig. 3b), the load-bearing areas
//! A_LB^V and A_LB^L (eqs 19-20) and the energy ledger against the external work (eq 23, Fig. 13).
//!
//! Decision (one job per load): the paper saves the indentation's states at several loads and slides
//! from each. Here each load is one job that indents from the flat surface to its own load and slides:
//! the indentation is deterministic, so each job starts from the state the paper saves, and jobs need
//! no other job's output (a Slurm array or mpirun ranks take any of them in any order), at the cost of
//! indenting once per load.
//!
//! Decision (external work, eq 23): the paper integrates F_ext V_x; the load F_z also works when the
//! indenter sinks (it does, Fig. 9a), so the work counted is that of the drive along x and y and of
//! the load along z. The indentation's energy is not in the ledger, which starts with the slide; the
//! strain energy stored then is its initial value.
//!
//! Decision (indenter density): paper 001 gives the indenter's radius (1 cm) but not its mass, which
//! matters once the indenter moves vertically under the load; the default is the 8 g/cm^3 of the
//! same-sized particle of Fig. 4.
//!
//! A slide of the paper's length runs for millions of steps: the job saves its progress (the whole
//! state) every two minutes and on Ctrl-C, and the same call resumes it to the same bits.

mod fit;
mod run;

use serde::{Deserialize, Serialize};

use super::ledger::{EnergyReport, EnergySeries};
use super::model::{PlasticModel, PlasticTimeStep, Projectile};
use super::{RunSettings, SurfaceInfo};
use crate::error::{not_positive, DemError, Result};
pub use fit::fit_line;
pub use run::run_scratch_load;
pub(crate) use run::scratch_rig;

/// A scratch test as its config file gives it (SI), for every load of `indent.loads`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScratchConfig {
    /// Surface and contact; default the paper's (H = 1.7 GPa, mu = 0.5, mu_a = 0.25).
    #[serde(default)]
    pub model: PlasticModel,
    /// The indenter; default R_p = 1 cm, 8 g/cm^3 (see the module).
    #[serde(default = "ScratchConfig::default_indenter")]
    pub indenter: Projectile,
    /// Indentation speed and the loads to slide under.
    pub indent: Indent,
    /// Sliding speed, duration, where it starts and what part of it is measured.
    #[serde(default)]
    pub slide: Slide,
    /// Time step and sampling; default 5 % of the stable step (the ledger then closes within 0.1 %
    /// of the external work).
    #[serde(default = "ScratchConfig::default_run")]
    pub run: RunSettings,
}

/// The indentation (Fig. 8).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Indent {
    /// Speed of the indenter into the surface (m/s); default 1 mm/s (paper). The indentation is
    /// kinematic and the surface has no rate: any speed gives the same curve, a faster one in fewer
    /// steps (tests/plastic_scratch.rs).
    #[serde(default = "d_indent_speed")]
    pub speed: f64,
    /// Normal loads F_z (N) at which to stop and slide.
    pub loads: Vec<f64>,
}

/// The slide (Figs. 9-10, 13).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Slide {
    /// V_x (m/s); default 20 cm/s (paper).
    pub speed: f64,
    /// Duration (s); default 0.4 s (paper: long enough for a stationary state).
    pub duration: f64,
    /// Start of the slide along the strip (m from its left end); default (absent): the slide centred
    /// on the strip.
    pub start_x: Option<f64>,
    /// Fraction of the slide after which the steady state is measured; default 0.5.
    pub measure_from: f64,
}

impl Default for Slide {
    fn default() -> Self {
        Slide {
            speed: 0.2,
            duration: 0.4,
            start_x: None,
            measure_from: 0.5,
        }
    }
}

fn d_indent_speed() -> f64 {
    1e-3
}

/// The indentation curve (Fig. 8): depth below first touch, normal force, indented area
/// A_ind = sum a_i i_V.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct IndentCurve {
    pub depth: Vec<f64>,
    pub force: Vec<f64>,
    pub area_indented: Vec<f64>,
}

/// What the slide recorded (SI), every `record_every` steps.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct SlideSeries {
    /// Distance slid and time since the slide began.
    pub distance: Vec<f64>,
    pub time: Vec<f64>,
    /// Depth of the indenter below first touch (Fig. 9a).
    pub depth: Vec<f64>,
    /// Lateral force resisting the motion and normal contact force on the indenter.
    pub force_x: Vec<f64>,
    pub force_z: Vec<f64>,
    /// A_z (contact), A_LB^V and A_LB^L (eqs 19-20).
    pub area_contact: Vec<f64>,
    pub area_vertical: Vec<f64>,
    pub area_lateral: Vec<f64>,
    /// Wear volume since the slide began.
    pub wear_volume: Vec<f64>,
    /// Energies since the slide began (Fig. 13).
    pub energy: EnergySeries,
}

/// One load's scratch (SI).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ScratchRun {
    /// The load asked for and the one applied (the contact force when the indentation reached it).
    pub load_requested: f64,
    pub load: f64,
    pub hardness: f64,
    pub mu_a: f64,
    pub friction: f64,
    pub speed: f64,
    pub distance: f64,
    pub surface: SurfaceInfo,
    pub time_step: f64,
    pub steps: u64,
    /// Wear volume per distance in the steady window (m^3/m).
    pub wear_per_distance: f64,
    /// The same over the first and the second half of the window, whose difference says how steady.
    pub wear_per_distance_halves: [f64; 2],
    /// Wear volume left by the indentation, and added by the slide.
    pub wear_volume_indent: f64,
    pub wear_volume_slide: f64,
    /// Means over the steady window: lateral force F_x, normal force, A_z, A_LB^V, A_LB^L, depth.
    pub lateral_force: f64,
    pub normal_force: f64,
    pub contact_area: f64,
    pub area_vertical: f64,
    pub area_lateral: f64,
    pub depth: f64,
    /// Depth at the end of the indentation.
    pub depth_indent: f64,
    pub energy: EnergyReport,
    pub series: SlideSeries,
    pub indentation: IndentCurve,
}

/// A scratch test over all its loads.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ScratchResult {
    /// Applied loads (N) and wear per distance (m^3/m), in the order of the config.
    pub loads: Vec<f64>,
    pub wear_per_distance: Vec<f64>,
    /// Archard's law near the threshold (Fig. 10's inset): the linear fit at small loads.
    pub archard: Option<ArchardFit>,
    /// Shear hardness from the runs at and above the wear threshold (section 3.1, Fig. 3b).
    pub shear_hardness: Option<ShearHardness>,
    pub runs: Vec<ScratchRun>,
}

/// The wear coefficient from which a load counts as wearing: K = W_V H / (F_z d) >= 0.02, two per
/// cent of the fully plastic Archard value. Below it the track is a few worn spheres (the paper:
/// "no wear is visible"); measured K is 0.001 at 500 N and 0.009 at 1000 N, then 0.04 at 1500 N.
pub const WEARING: f64 = 0.02;

/// Archard's law at small loads (Fig. 10 and its inset): a least-squares line of the wear per
/// distance against the load from the wear threshold to `span` times it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ArchardFit {
    /// The lowest load that wears (K >= [`WEARING`]) and the largest load fitted (N).
    pub threshold_load: f64,
    pub last_load: f64,
    /// The line: wear per distance = slope (F - onset) (m^3/m per N; N).
    pub slope: f64,
    pub onset_load: f64,
    /// Coefficient of determination of the fit.
    pub r2: f64,
    /// Loads fitted.
    pub points: usize,
    /// Wear per distance at the largest load of the test over the line's value there: 1 if Archard's
    /// law held up to it.
    pub excess_at_largest: f64,
}

impl ScratchRun {
    /// Archard's wear coefficient K = (W_V / d) H / F_z.
    pub fn wear_coefficient(&self) -> f64 {
        self.wear_per_distance * self.hardness / self.load
    }
}

/// H_l = dF_x / dA_z (section 3.1): least-squares slope of F_x against A_z at the first load that
/// wears and the (up to) four loads above it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShearHardness {
    /// The slope (Pa) and intercept (N) of the fit.
    pub slope: f64,
    pub intercept: f64,
    /// mu_a H (Pa), what the slope is expected near.
    pub reference: f64,
    /// The lowest load that wears (N).
    pub threshold_load: f64,
    /// The points fitted, (A_z in m^2, F_x in N).
    pub points: Vec<[f64; 2]>,
}

impl ScratchConfig {
    /// R_p = 1 cm (paper), 8 g/cm^3 (see the module).
    pub fn default_indenter() -> Projectile {
        Projectile {
            radius: 0.01,
            density: 8000.0,
        }
    }

    /// 5 % of the stable step; samples every 1/1000 of the slide.
    pub fn default_run() -> RunSettings {
        RunSettings {
            time_step: PlasticTimeStep::FractionOfStable(0.05),
            max_advance: 0.01,
            record_every: 0,
        }
    }

    /// Rejects bad input before anything runs.
    pub fn validate(&self) -> Result<()> {
        self.model.validate()?;
        self.indenter.validate("indenter")?;
        let s = &self.slide;
        if let Some(m) = not_positive(&[
            ("indent.speed", self.indent.speed),
            ("slide.speed", s.speed),
            ("slide.duration", s.duration),
        ]) {
            return Err(DemError::InvalidConfig(m));
        }
        if self.indent.loads.is_empty() {
            return Err(DemError::InvalidConfig("indent.loads is empty".into()));
        }
        for &f in &self.indent.loads {
            if let Some(m) = not_positive(&[("indent.loads[..]", f)]) {
                return Err(DemError::InvalidConfig(m));
            }
        }
        if !(0.0..1.0).contains(&s.measure_from) {
            return Err(DemError::InvalidConfig(format!(
                "slide.measure_from = {} must lie in [0, 1)",
                s.measure_from
            )));
        }
        if let Some(x) = s.start_x {
            if !x.is_finite() {
                return Err(DemError::InvalidConfig(
                    "slide.start_x must be finite".into(),
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_scratch_configs_are_errors() {
        let text = "[indent]\nloads = [1000.0]\n";
        let ok: ScratchConfig = toml::from_str(text).unwrap();
        ok.validate().unwrap();
        let mut c = ok.clone();
        c.indent.loads = vec![];
        assert!(c.validate().is_err());
        let mut c = ok.clone();
        c.indent.loads = vec![-5.0];
        assert!(c.validate().is_err());
        let mut c = ok.clone();
        c.slide.measure_from = 1.0;
        assert!(c.validate().is_err());
        let mut c = ok;
        c.model.hardness = 0.0;
        assert!(c.validate().is_err());
        assert!(toml::from_str::<ScratchConfig>("[indent]\nloads = [1.0]\nlod = 2\n").is_err());
    }
}
