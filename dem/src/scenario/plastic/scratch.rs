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

use serde::{Deserialize, Serialize};

use super::ledger::{EnergyReport, EnergySeries, PlasticLedger};
use super::model::{Params, PlasticModel, PlasticTimeStep, Projectile};
use super::rig::{Body, Drive, Rig, RigState, StepReport};
use super::surface::Surface;
use super::{RunSettings, SurfaceInfo};
use crate::error::{not_positive, DemError, Result};
use crate::io::progress::{self, ProgressFile, SaveClock};
use crate::units::UnitSystem;
use crate::Vec3;

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

/// The phases of one load's run, as a progress file keeps them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
enum Phase {
    Indent,
    /// Sliding under `load` (engine units) since step `start`, from x = `x0`.
    Slide {
        load: f64,
        start: u64,
        x0: f64,
    },
}

/// Everything a scratch job has computed so far.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct Progress {
    rig: RigState,
    phase: Phase,
    indentation: IndentCurve,
    depth_indent: f64,
    wear_indent: f64,
    series: SlideSeries,
    balance0: Option<f64>,
    max_balance: f64,
    initial: Option<PlasticLedger>,
}

/// The engine-unit set-up of a scratch: the rig at the start of the indentation, the indentation
/// speed and the steps of the slide.
pub(crate) fn scratch_rig(cfg: &ScratchConfig, load: f64) -> Result<(Rig, f64)> {
    cfg.validate()?;
    let u = UnitSystem::MILLI;
    let surface = Surface::hexagonal(&cfg.model.surface, |m| u.length_from_m(m))?;
    let q = Params::new(&cfg.model, &cfg.indenter, surface.cell_area);
    // Contacts expected: the plastic cap that carries the load (F = 2 pi r h H) at twice its depth,
    // since sliding halves the load-bearing area and the indenter sinks (Fig. 9a).
    let f = u.force_from_n(load);
    let depth = 2.0 * f / (2.0 * std::f64::consts::PI * q.reach * q.hardness);
    let overlap = q.contact_overlap(q.hertz.overlap_at(f));
    let stable = q.stable_step(q.contacts_at_depth(depth, overlap), false, overlap);
    let fastest = u.velocity_from_m_s(cfg.slide.speed.max(cfg.indent.speed));
    let dt = q.time_step(
        cfg.run.time_step,
        stable,
        (cfg.run.max_advance, overlap, fastest),
    )?;
    let distance = u.length_from_m(cfg.slide.speed * cfg.slide.duration);
    let x_start = match cfg.slide.start_x {
        Some(x) => u.length_from_m(x),
        None => 0.5 * (surface.length() - distance),
    };
    let site = surface.nearest_site(x_start, 0.5 * surface.width());
    let (x, y) = (surface.x[site], surface.y[site]);
    // The contact while sliding: the indenter sinks to about five times its static depth under the
    // load (1 mm at 21 kN against 0.19 mm, Fig. 9a), so the check takes six.
    let cap = (2.0 * q.reach * 3.0 * depth).sqrt();
    if !(surface.holds_disk(x, y, cap) && surface.holds_disk(x + distance, y, cap)) {
        return Err(DemError::InvalidConfig(format!(
            "a slide of {:.4e} m from x = {:.4e} m does not fit on the {:.4e} m strip with the \
             contact of a {load} N load: shorten the slide or move slide.start_x",
            u.length_to_m(distance),
            u.length_to_m(x),
            u.length_to_m(surface.length())
        )));
    }
    let body = Body {
        pos: Vec3::new(x, y, surface.top() + q.reach + u.length_from_m(1e-6)),
        vel: Vec3::new(0.0, 0.0, -u.velocity_from_m_s(cfg.indent.speed)),
        omega: Vec3::zeros(),
    };
    Ok((Rig::new(q, surface, body, Drive::kinematic(), dt), distance))
}

/// Runs the scratch of `cfg` at one load (N), optionally saving its progress in `file` (and resuming
/// from it).
pub fn run_scratch_load(
    cfg: &ScratchConfig,
    load: f64,
    file: Option<&ProgressFile>,
) -> Result<ScratchRun> {
    let _span = tracing::info_span!("scratch", load).entered();
    let (mut rig, distance) = scratch_rig(cfg, load)?;
    let q = rig.q;
    let u = q.units;
    let target = u.force_from_n(load);
    let key = progress::settings_key(&(cfg, load, "scratch v1"))?;
    let slide_speed = u.velocity_from_m_s(cfg.slide.speed);
    let slide_steps = (distance / slide_speed / rig.dt).round().max(1.0) as u64;
    let every = match cfg.run.record_every {
        0 => (slide_steps / 1000).max(1),
        n => n,
    };
    let indent_every = ((u.length_from_m(1e-6) / (u.velocity_from_m_s(cfg.indent.speed) * rig.dt))
        .round() as u64)
        .max(1);
    let touch = rig.st.surface.top() + q.reach;
    let mut pr = match file.and_then(|f| progress::load::<Progress>(&f.path, &key)) {
        Some(p) => {
            tracing::info!(step = p.rig.step, "scratch resumed from its progress file");
            p
        }
        None => Progress {
            rig: rig.st.clone(),
            phase: Phase::Indent,
            indentation: IndentCurve::default(),
            depth_indent: 0.0,
            wear_indent: 0.0,
            series: SlideSeries::default(),
            balance0: None,
            max_balance: 0.0,
            initial: None,
        },
    };
    rig.st = std::mem::replace(&mut pr.rig, rig.st.clone());
    if let Phase::Slide { load, .. } = pr.phase {
        rig.set_drive_keeping(slide_drive(load));
    }
    let mut clock = SaveClock::new();
    let save = |pr: &mut Progress, rig: &Rig| -> Result<()> {
        if let Some(f) = file {
            pr.rig = rig.st.clone();
            progress::save(&f.path, &key, pr)?;
        }
        Ok(())
    };
    let max_depth = 0.5 * q.radius;
    loop {
        if crate::interrupt::requested() {
            save(&mut pr, &rig)?;
            return Err(DemError::Interrupted { step: rig.st.step });
        }
        if let Some(f) = file {
            if rig.st.step % 4096 == 0 && clock.due(f.every) {
                save(&mut pr, &rig)?;
            }
        }
        let step = rig.st.step;
        let r = rig.step()?;
        match pr.phase {
            Phase::Indent => {
                let depth = touch - (rig.st.body.pos.z - rig.st.body.vel.z * rig.dt);
                if step % indent_every == 0 || r.force.z >= target {
                    pr.indentation.depth.push(u.length_to_m(depth.max(0.0)));
                    pr.indentation.force.push(u.force_to_n(r.force.z));
                    pr.indentation
                        .area_indented
                        .push(u.length_to_m(u.length_to_m(r.area_vertical)));
                }
                if r.force.z >= target {
                    // The state is now one step past the level whose force reached the load.
                    pr.depth_indent = u.length_to_m(touch - rig.st.body.pos.z);
                    pr.wear_indent = rig.st.surface.wear_volume();
                    let applied = r.force.z;
                    rig.set_drive(slide_drive(applied));
                    rig.st.body.vel = Vec3::new(slide_speed, 0.0, 0.0);
                    pr.phase = Phase::Slide {
                        load: applied,
                        start: rig.st.step,
                        x0: rig.st.body.pos.x,
                    };
                } else if depth > max_depth {
                    return Err(DemError::InvalidConfig(format!(
                        "the indentation reached {:.4e} m, half the indenter's radius, before the \
                         load of {load} N: lower the load or raise the hardness",
                        u.length_to_m(depth)
                    )));
                }
            }
            Phase::Slide { start, x0, .. } => {
                let b = r.ledger.balance();
                let b0 = *pr.balance0.get_or_insert(b);
                pr.initial.get_or_insert(r.ledger);
                pr.max_balance = pr.max_balance.max((b - b0).abs());
                let k = step - start;
                if k % every == 0 || k + 1 >= slide_steps {
                    record(&mut pr.series, &r, &rig, touch, x0, k, u);
                }
                if k + 1 >= slide_steps {
                    break;
                }
            }
        }
    }
    let run = finish(cfg, load, &rig, &pr, distance)?;
    if let Some(f) = file {
        progress::remove(&f.path)?;
    }
    Ok(run)
}

/// The drive of the slide: x and y at their speeds, z free under the load.
fn slide_drive(load: f64) -> Drive {
    Drive {
        fixed: [true, true, false],
        load: Vec3::new(0.0, 0.0, -load),
        spin: false,
    }
}

/// Appends one sample of step `k` of the slide (SI; the level of the report, whose position is one
/// step behind the rig's).
fn record(
    s: &mut SlideSeries,
    r: &StepReport,
    rig: &Rig,
    touch: f64,
    x0: f64,
    k: u64,
    u: UnitSystem,
) {
    let b = &rig.st.body;
    let pos = b.pos - b.vel * rig.dt;
    s.distance.push(u.length_to_m(pos.x - x0));
    s.time.push(u.time_to_s(k as f64 * rig.dt));
    s.depth.push(u.length_to_m(touch - pos.z));
    s.force_x.push(u.force_to_n(-r.force.x));
    s.force_z.push(u.force_to_n(r.force.z));
    let area = |a: f64| u.length_to_m(u.length_to_m(a));
    s.area_contact.push(area(r.area_contact));
    s.area_vertical.push(area(r.area_vertical));
    s.area_lateral.push(area(r.area_lateral));
    let vol = |v: f64| u.length_to_m(u.length_to_m(u.length_to_m(v)));
    // The wear volume at the report's level: the rig has already moved the flowing spheres of
    // this step, whose wear the ledger of the next level counts.
    s.wear_volume.push(vol(r.wear_volume));
    s.energy
        .push(u.time_to_s(k as f64 * rig.dt), &r.ledger, |e| {
            u.energy_to_j(e)
        });
}

/// The run's figures from its recorded slide.
fn finish(
    cfg: &ScratchConfig,
    load: f64,
    rig: &Rig,
    pr: &Progress,
    distance: f64,
) -> Result<ScratchRun> {
    let u = rig.q.units;
    let s = &pr.series;
    let n = s.distance.len();
    let d_total = u.length_to_m(distance);
    let from = cfg.slide.measure_from * d_total;
    let i0 = s.distance.iter().position(|&d| d >= from).unwrap_or(0);
    let i1 = n - 1;
    let im = i0 + (i1 - i0) / 2;
    let rate = |a: usize, b: usize| {
        let dd = s.distance[b] - s.distance[a];
        if dd > 0.0 {
            (s.wear_volume[b] - s.wear_volume[a]) / dd
        } else {
            0.0
        }
    };
    let mean = |v: &[f64]| v[i0..=i1].iter().sum::<f64>() / (i1 - i0 + 1) as f64;
    let Phase::Slide { load: applied, .. } = pr.phase else {
        return Err(DemError::InvalidConfig(
            "the scratch never reached its load".into(),
        ));
    };
    let first = pr.initial.unwrap_or_default();
    let last = s.energy.len() - 1;
    let work = s.energy.external_work[last];
    let to_j = |e: f64| u.energy_to_j(e);
    let vol = |v: f64| u.length_to_m(u.length_to_m(u.length_to_m(v)));
    Ok(ScratchRun {
        load_requested: load,
        load: u.force_to_n(applied),
        hardness: cfg.model.hardness,
        mu_a: cfg.model.mu_a,
        friction: cfg.model.friction,
        speed: cfg.slide.speed,
        distance: d_total,
        surface: SurfaceInfo::of(&rig.st.surface, u),
        time_step: u.time_to_s(rig.dt),
        steps: rig.st.step,
        wear_per_distance: rate(i0, i1),
        wear_per_distance_halves: [rate(i0, im), rate(im, i1)],
        wear_volume_indent: vol(pr.wear_indent),
        wear_volume_slide: s.wear_volume[last],
        lateral_force: mean(&s.force_x),
        normal_force: mean(&s.force_z),
        contact_area: mean(&s.area_contact),
        area_vertical: mean(&s.area_vertical),
        area_lateral: mean(&s.area_lateral),
        depth: mean(&s.depth),
        depth_indent: pr.depth_indent,
        energy: EnergyReport {
            initial_kinetic: to_j(first.kinetic),
            initial_strain: to_j(first.strain()),
            kinetic: s.energy.kinetic[last],
            strain: s.energy.strain[last],
            friction: s.energy.friction[last],
            wear: s.energy.wear[last],
            external_work: work,
            max_balance_error: if work > 0.0 {
                to_j(pr.max_balance) / work
            } else {
                0.0
            },
        },
        series: pr.series.clone(),
        indentation: pr.indentation.clone(),
    })
}

impl ScratchResult {
    /// Collects the runs of a test (in the config's load order), fits Archard's law at small loads
    /// (up to three times the threshold) and the shear hardness.
    pub fn collect(runs: Vec<ScratchRun>) -> ScratchResult {
        let mut order: Vec<usize> = (0..runs.len()).collect();
        order.sort_by(|&a, &b| runs[a].load.total_cmp(&runs[b].load));
        let wearing: Vec<usize> = order
            .iter()
            .copied()
            .skip_while(|&k| runs[k].wear_coefficient() < WEARING)
            .collect();
        let archard = archard(&runs, &wearing, 3.0);
        let shear_hardness = (wearing.len() >= 2).then(|| {
            let pts: Vec<[f64; 2]> = wearing
                .iter()
                .take(5)
                .map(|&k| [runs[k].contact_area, runs[k].lateral_force])
                .collect();
            let (slope, intercept) = fit_line(&pts);
            let r = &runs[wearing[0]];
            ShearHardness {
                slope,
                intercept,
                reference: r.mu_a * r.hardness,
                threshold_load: r.load,
                points: pts,
            }
        });
        ScratchResult {
            loads: runs.iter().map(|r| r.load).collect(),
            wear_per_distance: runs.iter().map(|r| r.wear_per_distance).collect(),
            archard,
            shear_hardness,
            runs,
        }
    }
}

/// Archard's line through the wearing runs `wearing` (by increasing load) up to `span` times the
/// threshold (at least two runs).
fn archard(runs: &[ScratchRun], wearing: &[usize], span: f64) -> Option<ArchardFit> {
    let first = *wearing.first()?;
    let limit = span * runs[first].load;
    let pts: Vec<[f64; 2]> = wearing
        .iter()
        .map(|&k| [runs[k].load, runs[k].wear_per_distance])
        .filter(|p| p[0] <= limit)
        .collect();
    if pts.len() < 2 {
        return None;
    }
    let (slope, b) = fit_line(&pts);
    let mean = pts.iter().map(|p| p[1]).sum::<f64>() / pts.len() as f64;
    let (res, tot) = pts.iter().fold((0.0, 0.0), |(r, t), p| {
        (
            r + (p[1] - slope * p[0] - b).powi(2),
            t + (p[1] - mean).powi(2),
        )
    });
    let last = &runs[*wearing.last()?];
    Some(ArchardFit {
        threshold_load: runs[first].load,
        last_load: pts[pts.len() - 1][0],
        slope,
        onset_load: -b / slope,
        r2: if tot > 0.0 { 1.0 - res / tot } else { 1.0 },
        points: pts.len(),
        excess_at_largest: last.wear_per_distance / (slope * last.load + b),
    })
}

/// Least-squares line y = a x + b through `pts`.
pub fn fit_line(pts: &[[f64; 2]]) -> (f64, f64) {
    let n = pts.len() as f64;
    let (mx, my) = (
        pts.iter().map(|p| p[0]).sum::<f64>() / n,
        pts.iter().map(|p| p[1]).sum::<f64>() / n,
    );
    let sxy: f64 = pts.iter().map(|p| (p[0] - mx) * (p[1] - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p[0] - mx).powi(2)).sum();
    let a = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    (a, my - a * mx)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_through_points_is_found() {
        let (a, b) = fit_line(&[[1.0, 3.0], [2.0, 5.0], [4.0, 9.0]]);
        assert!((a - 2.0).abs() < 1e-12 && (b - 1.0).abs() < 1e-12);
    }

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
