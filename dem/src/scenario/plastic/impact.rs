//! Impact (paper 001 sections 4.1-4.2, 4.4): a free rigid sphere hits the surface at speed V and
//! angle theta from it (90 degrees: normal), ploughs its crater and leaves. Measured: the wear volume
//! (eq 6) with its normal and scratch parts (Fig. 5b), the rebound speed and angle, COR = V_r / V
//! (eq 17) and the deviation angle theta_r - theta (eq 18), and the energy ledger (Fig. 12).
//!
//! The projectile starts with its lowest point `start_gap` above touching height, on the straight
//! path that would make it touch the aimed sphere; the run ends when it has no contact, moves up and
//! is too high to touch any sphere again. No gravity (paper 001 names none; it would change the speed
//! by g t ~ 1e-3 m/s during a 0.1 ms impact).

use serde::{Deserialize, Serialize};

use super::flow::{normal_impact_depth, normal_impact_wear};
use super::ledger::{EnergyReport, EnergySeries};
use super::model::{Params, PlasticModel, PlasticTimeStep, Projectile};
use super::rig::{Body, Drive, Rig};
use super::surface::Surface;
use super::SurfaceInfo;
use crate::error::{not_positive, DemError, Result};
use crate::Vec3;

/// One impact, as its config file gives it (SI).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ImpactConfig {
    /// Surface and contact; default the paper's (H = 1.7 GPa, mu = 0.5, mu_a = 0.25).
    #[serde(default)]
    pub model: PlasticModel,
    /// The projectile (Fig. 4: R_p = 1 cm, 8 g/cm^3; Figs. 5-7: 3 mm, 2.5 g/cm^3).
    pub projectile: Projectile,
    /// Speed, angle and aim.
    pub impact: Shot,
    /// Time step and sampling.
    #[serde(default)]
    pub run: RunSettings,
}

/// How the projectile comes in.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Shot {
    /// Impact speed V (m/s).
    pub speed: f64,
    /// Impact angle theta between the velocity and the surface, in (0, 90] degrees.
    pub angle_deg: f64,
    /// Offset (m, along x and y) of the aim from the sphere nearest the strip's centre; default
    /// [0, 0]: straight onto a sphere, the symmetric case.
    #[serde(default)]
    pub aim_offset: [f64; 2],
    /// Height (m) of the projectile's lowest point above touching height at the start; default 1 um
    /// (a few steps of flight). Negative: the projectile starts inside the surface (refused).
    #[serde(default = "d_gap")]
    pub start_gap: f64,
    /// Whether the projectile rotates; default true: paper 001's kinetic energy includes rotation,
    /// which the contacts' friction drives.
    #[serde(default = "d_spin")]
    pub spin: bool,
    /// Longest simulated time (s); default (absent) 40 contact times (the plastic estimate pi / alpha
    /// of section 4.1 or Hertz's elastic one, the longer), far beyond any rebound.
    #[serde(default)]
    pub max_time: Option<f64>,
}

fn d_gap() -> f64 {
    1e-6
}
fn d_spin() -> bool {
    true
}

/// Time step and sampling, shared by impacts and scratches.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RunSettings {
    /// Time step; default 2 % of the stable step of the contacts expected, and at most
    /// `max_advance` (below).
    pub time_step: PlasticTimeStep,
    /// Largest advance of the projectile in one step, in contact overlaps (the overlap at which a
    /// sphere of the flat surface flows, or the largest a contact reaches if that is smaller), for a
    /// time step given as a fraction of the stable one; default
    /// 0.01. Why: a sphere crossing the flow threshold keeps the force of its crossing step while it
    /// flows (eq 9 moves it with the projectile), up to one step's advance of overlap above the
    /// threshold; at 45 m/s and 2 % of the stable step that is 10 % of the force and 6 % of the wear
    /// volume of Fig. 4. At 0.01 the wear volume is within 1 % of its limit (docs/plastic-wear.md).
    pub max_advance: f64,
    /// Steps between samples of the recorded series; default 0: about 400 samples per run.
    pub record_every: u64,
}

impl Default for RunSettings {
    fn default() -> Self {
        RunSettings {
            time_step: PlasticTimeStep::FractionOfStable(0.02),
            max_advance: 0.01,
            record_every: 0,
        }
    }
}

/// What an impact gave (SI: m, kg, s, J, degrees).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ImpactResult {
    /// Inputs: projectile mass, radius and density, speed, angle, hardness, mu_a, mu.
    pub mass: f64,
    pub radius: f64,
    pub density: f64,
    pub speed: f64,
    pub angle_deg: f64,
    pub hardness: f64,
    pub mu_a: f64,
    pub friction: f64,
    pub surface: SurfaceInfo,
    pub time_step: f64,
    pub steps: u64,
    /// Wear volume of eq (6), and its parts by vertical and lateral flow (Fig. 5b).
    pub wear_volume: f64,
    pub wear_volume_normal: f64,
    pub wear_volume_scratch: f64,
    /// Eq (16) with the normal speed V sin theta: m (V sin theta)^2 / (2 H).
    pub reference_wear_volume: f64,
    /// Deepest sphere below the flat surface.
    pub crater_depth: f64,
    /// Rebound speed and angle (from the surface; > 90 degrees: thrown back).
    pub rebound_speed: f64,
    pub rebound_angle_deg: f64,
    /// Eq (17) and eq (18).
    pub cor: f64,
    pub deviation_deg: f64,
    /// Spin after the impact (rad/s).
    pub rebound_spin: f64,
    /// Time of the first contact, and from first to last contact.
    pub first_contact: f64,
    pub contact_time: f64,
    pub energy: EnergyReport,
    /// Kinetic, strain, friction and wear energy against time from the launch (Fig. 12), sampled
    /// until the contact ends.
    pub series: EnergySeries,
}

impl ImpactConfig {
    /// Rejects bad input before anything runs.
    pub fn validate(&self) -> Result<()> {
        self.model.validate()?;
        self.projectile.validate("projectile")?;
        let s = &self.impact;
        if let Some(m) = not_positive(&[("impact.speed", s.speed)]) {
            return Err(DemError::InvalidConfig(m));
        }
        if !(s.angle_deg > 0.0 && s.angle_deg <= 90.0) {
            return Err(DemError::InvalidConfig(format!(
                "impact.angle_deg = {} must lie in (0, 90] (90: normal impact)",
                s.angle_deg
            )));
        }
        if s.start_gap.is_nan() || s.start_gap < 0.0 {
            return Err(DemError::InvalidConfig(format!(
                "impact.start_gap = {} m: the projectile would start inside the surface",
                s.start_gap
            )));
        }
        if !s.aim_offset.iter().all(|x| x.is_finite()) {
            return Err(DemError::InvalidConfig(
                "impact.aim_offset must be finite".into(),
            ));
        }
        if let Some(t) = s.max_time {
            if let Some(m) = not_positive(&[("impact.max_time", t)]) {
                return Err(DemError::InvalidConfig(m));
            }
        }
        Ok(())
    }
}

/// The rig of an impact, before the first step: the projectile in place, the time step chosen.
pub(crate) fn impact_rig(cfg: &ImpactConfig) -> Result<Rig> {
    cfg.validate()?;
    let u = crate::units::UnitSystem::MILLI;
    let surface = Surface::hexagonal(&cfg.model.surface, |m| u.length_from_m(m))?;
    let q = Params::new(&cfg.model, &cfg.projectile, surface.cell_area);
    let s = &cfg.impact;
    let theta = s.angle_deg.to_radians();
    let speed = u.velocity_from_m_s(s.speed);
    // Contacts expected: the crater of eq 16 at the whole speed, a bound for any angle, each at the
    // flow overlap or at the overlap the whole kinetic energy gives one Hertz contact
    // (1/2 m V^2 = 2/5 k_h delta^(5/2)) when that is smaller (a hard surface).
    let depth = normal_impact_depth(q.mass, q.radius, speed, q.hardness);
    let overlap = q.contact_overlap((1.25 * q.mass * speed * speed / q.hertz.k_h).powf(0.4));
    let stable = q.stable_step(q.contacts_at_depth(depth, overlap), s.spin, overlap);
    let dt = q.time_step(
        cfg.run.time_step,
        stable,
        (cfg.run.max_advance, overlap, speed),
    )?;

    let site = surface.nearest_site(0.5 * surface.length(), 0.5 * surface.width());
    let aim = Vec3::new(
        surface.x[site] + u.length_from_m(s.aim_offset[0]),
        surface.y[site] + u.length_from_m(s.aim_offset[1]),
        surface.top() + q.reach,
    );
    let gap = u.length_from_m(s.start_gap);
    let pos = aim + Vec3::new(-gap * theta.cos() / theta.sin(), 0.0, gap);
    let vel = Vec3::new(speed * theta.cos(), 0.0, -speed * theta.sin());
    let body = Body {
        pos,
        vel,
        omega: Vec3::zeros(),
    };
    let mut rig = Rig::new(q, surface, body, Drive::free(s.spin), dt);
    if rig.overlaps() {
        return Err(DemError::InvalidConfig(
            "the projectile starts inside the surface (it overlaps a surface sphere)".into(),
        ));
    }
    if !rig
        .st
        .surface
        .holds_disk(pos.x, pos.y, rig.reach().unwrap_or(0.0))
    {
        return Err(DemError::InvalidConfig(
            "impact.aim_offset puts the projectile beyond the surface".into(),
        ));
    }
    Ok(rig)
}

/// Runs one impact.
pub fn run_impact(cfg: &ImpactConfig) -> Result<ImpactResult> {
    let _span =
        tracing::info_span!("impact", v = cfg.impact.speed, angle = cfg.impact.angle_deg).entered();
    let mut rig = impact_rig(cfg)?;
    let q = rig.q;
    let u = q.units;
    let speed = u.velocity_from_m_s(cfg.impact.speed);
    let depth = normal_impact_depth(q.mass, q.radius, speed, q.hardness);
    // The longer of the plastic contact time of section 4.1 and the Hertz contact time of the whole
    // kinetic energy on one contact (2.94 delta_m / V): a hard surface bounces elastically.
    let delta_m = (1.25 * q.mass * speed * speed / q.hertz.k_h).powf(0.4);
    let plastic_time = (std::f64::consts::PI * depth / speed).max(2.95 * delta_m / speed);
    let max_time = cfg
        .impact
        .max_time
        .map_or(40.0 * plastic_time, |t| u.time_from_s(t));
    let max_steps = crate::scenario::step_budget(
        "the impact (impact.max_time, or 40 contact times)",
        (max_time / rig.dt).ceil(),
    )?;
    let flight =
        u.length_from_m(cfg.impact.start_gap) / (speed * cfg.impact.angle_deg.to_radians().sin());
    let expected = ((flight + 2.0 * plastic_time) / rig.dt).ceil() as u64;
    let every = match cfg.run.record_every {
        0 => (expected / 400).max(1),
        n => n,
    };

    let e0 = 0.5 * q.mass * speed * speed;
    let to_j = |e: f64| u.energy_to_j(e);
    let mut series = EnergySeries::default();
    let (mut first, mut last) = (None::<u64>, 0u64);
    let mut balance0 = None;
    let mut max_err = 0.0f64;
    let mut was_touching = false;
    let ledger = loop {
        if rig.st.step % 1024 == 0 && crate::interrupt::requested() {
            return Err(DemError::Interrupted { step: rig.st.step });
        }
        let step = rig.st.step;
        let r = rig.step()?;
        let b = r.ledger.balance();
        let b0 = *balance0.get_or_insert(b);
        max_err = max_err.max((b - b0).abs() / e0);
        if r.contacts > 0 {
            first.get_or_insert(step);
            last = step;
        }
        let body = &rig.st.body;
        let gone = first.is_some()
            && r.contacts == 0
            && body.vel.z > 0.0
            && body.pos.z - q.reach >= rig.st.surface.top();
        // Samples until the first contact and during contacts, and one as each contact ends: the
        // flight out of the crater changes nothing but the time.
        let leaving = r.contacts == 0 && was_touching;
        was_touching = r.contacts > 0;
        if (step % every == 0 && (first.is_none() || r.contacts > 0)) || leaving {
            series.push(u.time_to_s(step as f64 * rig.dt), &r.ledger, to_j);
        }
        if gone {
            break r.ledger;
        }
        if rig.st.step >= max_steps {
            return Err(DemError::InvalidConfig(format!(
                "the projectile had not left the surface after {:.4e} s ({max_steps} steps); \
                 raise impact.max_time",
                u.time_to_s(max_time),
            )));
        }
    };
    let first = first.unwrap_or(0);
    let b = rig.st.body;
    let v_r = b.vel.norm();
    let theta_r = b.vel.z.atan2(b.vel.x).to_degrees();
    let s = &rig.st.surface;
    let vol = |v: f64| u.length_to_m(u.length_to_m(u.length_to_m(v)));
    let v_z = cfg.impact.speed * cfg.impact.angle_deg.to_radians().sin();
    Ok(ImpactResult {
        mass: cfg.projectile.mass(),
        radius: cfg.projectile.radius,
        density: cfg.projectile.density,
        speed: cfg.impact.speed,
        angle_deg: cfg.impact.angle_deg,
        hardness: cfg.model.hardness,
        mu_a: cfg.model.mu_a,
        friction: cfg.model.friction,
        surface: SurfaceInfo::of(s, u),
        time_step: u.time_to_s(rig.dt),
        steps: rig.st.step,
        wear_volume: vol(s.wear_volume()),
        first_contact: u.time_to_s(first as f64 * rig.dt),
        wear_volume_normal: vol(rig.st.wear_normal),
        wear_volume_scratch: vol(rig.st.wear_lateral),
        reference_wear_volume: normal_impact_wear(cfg.projectile.mass(), v_z, cfg.model.hardness),
        crater_depth: u.length_to_m(s.max_depth()),
        rebound_speed: u.velocity_to_m_s(v_r),
        rebound_angle_deg: theta_r,
        cor: v_r / speed,
        deviation_deg: theta_r - cfg.impact.angle_deg,
        rebound_spin: b.omega.norm() / u.time_to_s(1.0),
        contact_time: u.time_to_s((last + 1 - first) as f64 * rig.dt),
        energy: EnergyReport {
            initial_kinetic: to_j(e0),
            initial_strain: 0.0,
            kinetic: to_j(ledger.kinetic),
            strain: to_j(ledger.strain()),
            friction: to_j(ledger.friction),
            wear: to_j(ledger.wear),
            external_work: to_j(ledger.external_work),
            max_balance_error: max_err,
        },
        series,
    })
}
