//! Running a sliding system: the rig, the profile and force observers, the progress file, the
//! measures of the steady state.

use std::path::Path;

use serde::{Deserialize, Serialize};
use wear::tbl::{
    classify_regime, measure_layer, shear_traction, tbl_bounds, touches_body, Bins, LayerMeasures,
    LayerParams, Profile, ProfileParticles, ProfileSums, Regime, RegimeData, RegimeParams,
    TblBounds,
};

use super::wear_probe::{WearProbe, WearProbeSpec, WearRecord, WearSummary};
use super::{build, SlidingConfig};
use crate::error::{DemError, Result};
use crate::io::progress::{self, ProgressFile};
use crate::material::PairModel;
use crate::observe::{Dump, ForceSample, GroupForce, Observer};
use crate::sample::Sample;
use crate::scenario::driven::{self, dump_for, sliding_top, Recorders, Schedule, Snapshot};
use crate::scenario::rig::{Rig, RigSpec, BOTTOM, TOP};
use crate::sim::{Parallelism, RunConfig, Simulation, TimeStep};
use crate::walls::AxisControl;

/// Colour bands of the initial height in dumps and snapshots (Fig. 3 colours by initial height).
pub const HEIGHT_BANDS: u32 = 20;

/// The measures of one window of the run (Fig. 5).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WindowRecord {
    /// Last step and time of the window, and the top body's slide along x by then.
    pub step: u64,
    pub time: f64,
    pub slide: f64,
    /// Mean height H of the window's samples.
    pub height: f64,
    /// h_TBL / H (`None`: nothing slid inside the system, the velocity never crossed a threshold).
    pub h_tbl: Option<f64>,
    /// The TBL's boundaries over H (`None` as for h_TBL; records of older runs have none).
    #[serde(default)]
    pub bounds: Option<TblBounds>,
    /// rho_TBL / rho_0 of the window's profile (`None` when its fit failed).
    pub rho_tbl: Option<f64>,
}

/// The windows whose TBL lies inside the material, after the start-up (module docs of
/// [`super`]): what paper 004's "first stationary phase" measures.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct InteriorPhase {
    pub windows: usize,
    /// Mean p_T over the force samples inside those windows (engine units).
    pub p_t: f64,
    /// Mean of the windows' rho_TBL / rho_0 (over those whose fit succeeded) and h_TBL / H.
    pub rho_tbl: f64,
    pub h_tbl: f64,
}

/// The step after which each of `windows` opened (its predecessor's last step; 0 for the first).
fn opened(windows: &[WindowRecord]) -> impl Iterator<Item = u64> + '_ {
    std::iter::once(0).chain(windows.iter().map(|w| w.step))
}

/// The interior phase of `windows` (each closing at its `step`): the windows that opened at or after
/// `from_step` and are flagged `inside`, with p_T from the `p_t` samples (step, value) that fall in
/// them. `None` without such a window or without a sample in one.
pub fn interior_phase(
    windows: &[WindowRecord],
    from_step: u64,
    inside: &[bool],
    p_t: &[(u64, f64)],
) -> Option<InteriorPhase> {
    let (mut n, mut h_sum) = (0usize, 0.0);
    let (mut rho_sum, mut rho_n) = (0.0, 0usize);
    let (mut p_sum, mut p_n) = (0.0, 0usize);
    for ((w, start), &is_inside) in windows.iter().zip(opened(windows)).zip(inside) {
        if start < from_step || !is_inside {
            continue;
        }
        n += 1;
        h_sum += w.h_tbl.unwrap_or(0.0);
        if let Some(r) = w.rho_tbl {
            rho_sum += r;
            rho_n += 1;
        }
        for &(_, v) in p_t.iter().filter(|(s, _)| *s > start && *s <= w.step) {
            p_sum += v;
            p_n += 1;
        }
    }
    (n > 0 && rho_n > 0 && p_n > 0).then(|| InteriorPhase {
        windows: n,
        p_t: p_sum / p_n as f64,
        rho_tbl: rho_sum / rho_n as f64,
        h_tbl: h_sum / n as f64,
    })
}

/// The top body's slide by time `t` at speed `v0`, reached from rest at acceleration `ramp` (`None`:
/// at once): a t^2 / 2 during the ramp, v0 t - v0^2 / (2 a) after it.
pub fn slide(v0: f64, ramp: Option<f64>, t: f64) -> f64 {
    match ramp {
        Some(a) if t < v0 / a => 0.5 * a * t * t,
        Some(a) => v0 * t - v0 * v0 / (2.0 * a),
        None => v0 * t,
    }
}

/// The time the top body takes to slide `distance`, the inverse of [`slide`]: sqrt(2 d / a) while
/// it ramps, d / v0 + v0 / (2 a) (the ramp's lag) after it, d / v0 without a ramp.
pub fn time_to_slide(v0: f64, ramp: Option<f64>, distance: f64) -> f64 {
    match ramp {
        Some(a) if distance < v0 * v0 / (2.0 * a) => (2.0 * distance / a).sqrt(),
        Some(a) => distance / v0 + v0 / (2.0 * a),
        None => distance / v0,
    }
}

/// The profile observer: samples binned over the current height, closed into windows.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct ProfileProbe {
    every: u64,
    per_window: u64,
    bins: usize,
    /// Bottom of the bottom body (fixed) and the top body's top above its reference particle.
    base: f64,
    top_ref: usize,
    top_above_ref: f64,
    area: f64,
    v0: f64,
    rho0: f64,
    /// The top body's start-up acceleration (`None`: a velocity step); records of older runs have
    /// none.
    #[serde(default)]
    ramp: Option<f64>,
    /// Bins within this distance of either end are outside the fit (the rigid bodies).
    margin: f64,
    d0: f64,
    layer: LayerParams,
    steady_step: u64,
    current: ProfileSums,
    steady: ProfileSums,
    windows: Vec<WindowRecord>,
}

impl ProfileProbe {
    fn height(&self, sim: &Simulation) -> f64 {
        sim.particles.pos[self.top_ref].y + self.top_above_ref - self.base
    }

    /// The fitted range over H, and the smallest Gaussian width, for a system of height `h`.
    fn fit_params(&self, h: f64) -> ((f64, f64), LayerParams) {
        let m = self.margin / h;
        let layer = LayerParams {
            min_width: self.d0 / h,
            ..self.layer
        };
        ((m, 1.0 - m), layer)
    }

    /// Whether window `w`'s TBL lies against a body: within `params`' reach of the bodies' inner
    /// faces, the fitted range's ends.
    fn at_body(&self, w: &WindowRecord, params: &RegimeParams) -> bool {
        let faces = self.fit_params(w.height).0;
        let reach = params.boundary_reach * self.d0 / w.height;
        w.bounds.is_some_and(|b| touches_body(&b, faces, reach))
    }

    fn measure(&self, profile: &Profile) -> Result<LayerMeasures> {
        let (range, layer) = self.fit_params(profile.height);
        measure_layer(profile, self.rho0, range, &layer)
            .map_err(|e| DemError::InvalidConfig(format!("sliding profile: {e}")))
    }
}

impl Observer for ProfileProbe {
    fn every(&self) -> u64 {
        self.every
    }
    fn observe(&mut self, sim: &Simulation) -> Result<()> {
        let h = self.height(sim);
        let bins = Bins::new(self.base, h, self.bins)
            .map_err(|e| DemError::InvalidConfig(format!("sliding profile: {e}")))?;
        let p = &sim.particles;
        let y: Vec<f64> = p.pos.iter().map(|x| x.y).collect();
        let vx: Vec<f64> = p.vel.iter().map(|v| v.x).collect();
        let v2: Vec<f64> = p.vel.iter().map(|v| v.norm_squared()).collect();
        self.current
            .add(
                &bins,
                ProfileParticles {
                    y: &y,
                    radius: &p.radius,
                    mass: &p.mass,
                    vx: &vx,
                    speed_sq: &v2,
                },
                self.area,
                self.v0,
            )
            .map_err(|e| DemError::InvalidConfig(format!("sliding profile: {e}")))?;
        if self.current.samples < self.per_window {
            return Ok(());
        }
        let profile = self.current.profile();
        let bounds = tbl_bounds(
            &profile.centres(),
            &profile.velocity_over_v0,
            self.layer.v_lower,
            self.layer.v_upper,
        );
        let rho_tbl = self.measure(&profile).ok().map(|m| m.rho_tbl);
        // The window began after its previous one ended; it is steady if it began at or after the
        // steady step (the same test as the run's steady windows).
        if sim.step_count() + 1 >= self.steady_step + self.every * self.per_window {
            self.steady
                .merge(&self.current)
                .map_err(|e| DemError::InvalidConfig(format!("sliding profile: {e}")))?;
        }
        self.windows.push(WindowRecord {
            step: sim.step_count(),
            time: sim.time(),
            // Velocity control (positions wrap along x): the top body has moved v0 t, less the lag
            // of its ramp.
            slide: slide(self.v0, self.ramp, sim.time()),
            height: profile.height,
            h_tbl: bounds.map(|b| b.thickness()),
            bounds,
            rho_tbl,
        });
        self.current.clear();
        Ok(())
    }
}

/// What a sliding run gives.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SlidingResult {
    pub particles: usize,
    pub body_particles: usize,
    pub steps: u64,
    pub dt: f64,
    /// Sliding velocity v0, interface area (x z), bulk density rho_0 of the relaxed box.
    pub v0: f64,
    pub area: f64,
    pub rho0: f64,
    /// Shift and lift of the top half (see `geometry`).
    pub shift: f64,
    pub lift: f64,
    /// d* (eq 13) and d_m = d* / 8 (eq 12) over d0.
    pub d_star: f64,
    pub d_m_over_d0: f64,
    /// The windows' measures over time.
    pub windows: Vec<WindowRecord>,
    /// Pair forces on the top and bottom bodies over the run.
    pub force_top: Vec<ForceSample>,
    pub force_bottom: Vec<ForceSample>,
    /// First step of the steady part, and the windows it holds.
    pub steady_step: u64,
    pub steady_windows: usize,
    /// Steady windows whose TBL lies against a body, and the slide (length units) of the first
    /// window after the start-up whose TBL did (paper 004: "the TBL can travel vertically and reach
    /// the system's boundary"; its analysis drops that phase).
    pub steady_windows_at_body: usize,
    pub body_reached_at: Option<f64>,
    /// Whether each window's TBL lay against a body (one per `windows`).
    pub windows_at_body: Vec<bool>,
    /// The interior phase (module docs); `None` when no window after `startup` had its TBL
    /// inside the material.
    pub interior: Option<InteriorPhase>,
    /// The steady profiles and their measures.
    pub profile: Profile,
    pub layer: LayerMeasures,
    /// rho_TBL / rho_0 of the steady profile, mean h_TBL / H of the steady windows, mean p_T over the
    /// steady force samples, p_N, and the tau_m the run was given (all in the engine's units).
    pub rho_tbl: f64,
    pub h_tbl: f64,
    pub p_t: f64,
    pub p_n: f64,
    pub tau_m: f64,
    pub regime: Regime,
    /// The layer's wear particles at the end of every window (module `wear_probe`; results of older
    /// runs have none).
    #[serde(default)]
    pub wear: Vec<WearRecord>,
    /// Their summary (lengths over L; none without records).
    #[serde(default)]
    pub wear_summary: Option<WearSummary>,
    /// Every particle at the start and the end (`body` holds the initial-height band).
    pub first: Snapshot,
    pub last: Snapshot,
    /// Wall-clock seconds of the stepping (relaxation and set-up excluded), summed over resumed parts.
    pub wall_seconds: f64,
    /// Neighbour-list builds of the run, and how many of them were local (`dem::neighbor`).
    #[serde(default)]
    pub neighbour_builds: u64,
    #[serde(default)]
    pub local_builds: u64,
}

/// What a sliding run records: the profiles and the forces on both bodies.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct Records {
    probe: ProfileProbe,
    top: GroupForce,
    bottom: GroupForce,
    /// None in the progress files of older runs, which resume without it.
    #[serde(default)]
    wear: Option<WearProbe>,
}

impl Recorders for Records {
    fn observers(&mut self) -> Vec<&mut dyn Observer> {
        let mut o: Vec<&mut dyn Observer> = vec![&mut self.probe, &mut self.top, &mut self.bottom];
        if let Some(w) = self.wear.as_mut() {
            o.push(w);
        }
        o
    }
}

/// [`run_resumable`] without a progress file.
pub fn run(
    relaxed: &Sample,
    model: &PairModel,
    cfg: &SlidingConfig,
    tau_m: f64,
    par: Parallelism,
    dump: Option<&Path>,
) -> Result<SlidingResult> {
    run_resumable(relaxed, model, cfg, tau_m, par, dump, None, &mut |_, _| {})
}

/// Cuts `relaxed` into two halves, slides them and measures the layer. `model` must be the
/// normal-only law (paper 004); `tau_m` is the material's shear strength (measured by
/// [`super::measure_strength`], or [`SlidingConfig::given_shear_strength`]), which the regime label
/// compares p_T with. With `dump`, writes LAMMPS-style frames there (columns `half` and
/// `height0`, the initial-height band for Fig. 3's colours). With `progress`, saves the run's state
/// every few minutes and on an interrupt, and continues from it when it holds the same inputs'
/// progress (bit-identical to an uninterrupted run). `report(step, total)` is called at every window.
#[allow(clippy::too_many_arguments)]
pub fn run_resumable(
    relaxed: &Sample,
    model: &PairModel,
    cfg: &SlidingConfig,
    tau_m: f64,
    par: Parallelism,
    dump: Option<&Path>,
    progress: Option<&ProgressFile>,
    report: &mut dyn FnMut(u64, u64),
) -> Result<SlidingResult> {
    SlidingConfig::check_model(model)?;
    if !(tau_m.is_finite() && tau_m > 0.0) {
        return Err(DemError::InvalidConfig(format!(
            "sliding: the shear strength tau_m = {tau_m} must be positive"
        )));
    }
    let geo = build(relaxed, cfg)?;
    let d0 = cfg.d0();
    let run_cfg = RunConfig {
        time_step: TimeStep::FractionOfCritical(cfg.time_step_fraction),
        skin_fraction: cfg.skin_fraction,
        local_rebuilds: cfg.local_rebuilds,
        ..RunConfig::default()
    };
    let mut rig = Rig::new(
        &geo.sample,
        model,
        RigSpec::y_normal(cfg.body_thickness_over_d0 * d0),
        run_cfg,
        par,
    )?;
    let v0 = cfg.velocity();
    let mut top_motion = sliding_top(v0, cfg.pressure);
    let ramp = cfg.ramp_acceleration(tau_m);
    if let Some(acceleration) = ramp {
        top_motion.axes[0] = AxisControl::Ramp {
            to: v0,
            acceleration,
        };
        top_motion.velocity.x = 0.0;
    }
    rig.set_top(top_motion);
    let dt = rig.sim.dt();
    let total = cfg.steps(dt, ramp)?;
    let every = (total / (cfg.windows * cfg.samples_per_window)).max(1);
    let window_steps = every * cfg.samples_per_window;
    let force_every = (total / cfg.force_samples).max(1);
    let steady_step = (cfg.steady_from * total as f64).ceil() as u64;
    // A window is steady if it opened at or after the steady step (it closes at `step`).
    let steady = |step: u64| step + 1 >= steady_step + window_steps;
    let p = &rig.sim.particles;
    let members = |g: u32| -> Vec<usize> { (0..p.len()).filter(|&i| p.group[i] == g).collect() };
    let (bottom, top) = (members(BOTTOM), members(TOP));
    let base = bottom
        .iter()
        .map(|&i| p.pos[i].y - p.radius[i])
        .fold(f64::INFINITY, f64::min);
    let top_above_ref = top
        .iter()
        .map(|&i| p.pos[i].y + p.radius[i])
        .fold(f64::NEG_INFINITY, f64::max)
        - p.pos[rig.top_ref].y;
    let lengths = rig.sim.sim_box.lengths();
    let rho0 = relaxed.particles.mass.iter().sum::<f64>() / relaxed.sim_box.volume();
    let volume_fraction = relaxed.volume_fraction();
    let r0 = 0.5 * d0;
    let bond_margin = model.params(r0, r0, 1.0, 1.0).delta_f;
    let band: Vec<u32> = geo
        .height0
        .iter()
        .map(|&h| ((h * HEIGHT_BANDS as f64) as u32).min(HEIGHT_BANDS - 1))
        .collect();
    let roles: Vec<u8> = (0..p.len())
        .map(|i| if rig.free[i] { 0 } else { 2 })
        .collect();
    let first = Snapshot::of(&rig.sim, &band, &roles);
    let schedule = Schedule {
        name: "sliding",
        total,
        chunk: window_steps,
        progress,
        key: progress::key(&(cfg, model), relaxed)?,
    };
    let fresh = |sim: &Simulation| -> Result<(Records, Option<Dump>)> {
        let records = Records {
            probe: ProfileProbe {
                every,
                per_window: cfg.samples_per_window,
                bins: cfg.bins,
                base,
                top_ref: rig.top_ref,
                top_above_ref,
                area: lengths.x * lengths.z,
                v0,
                rho0,
                ramp,
                margin: (cfg.body_thickness_over_d0 + 1.0) * d0,
                d0,
                layer: cfg.layer,
                steady_step,
                current: ProfileSums::new(cfg.bins),
                steady: ProfileSums::new(cfg.bins),
                windows: Vec::new(),
            },
            top: GroupForce::new(sim, top.clone(), force_every)?,
            bottom: GroupForce::new(sim, bottom.clone(), force_every)?,
            wear: Some(WearProbe::new(
                sim,
                WearProbeSpec {
                    every: window_steps,
                    margin: bond_margin,
                    free: rig.free.clone(),
                    volume_fraction,
                    min_members: cfg.wear_particle_members,
                    v0,
                    ramp,
                },
            )?),
        };
        let dump = dump_for(sim, dump, cfg.dump_frames, total, || {
            vec![
                ("half".to_string(), geo.body.clone()),
                ("height0".to_string(), band.clone()),
            ]
        })?;
        Ok((records, dump))
    };
    let recorded = driven::run_resumable(&mut rig.sim, par, schedule, fresh, report)?;
    let st = recorded.records;
    let steady_windows: Vec<&WindowRecord> =
        st.probe.windows.iter().filter(|w| steady(w.step)).collect();
    if st.probe.steady.samples == 0 {
        return Err(DemError::InvalidConfig(format!(
            "sliding: no complete window after steady_from = {} of the run ({} steps, windows of {}); \
             a longer distance or more windows",
            cfg.steady_from, total, window_steps
        )));
    }
    let profile = st.probe.steady.profile();
    let layer = st.probe.measure(&profile)?;
    let h: Vec<f64> = steady_windows
        .iter()
        .map(|w| w.h_tbl.unwrap_or(0.0))
        .collect();
    let h_tbl = h.iter().sum::<f64>() / h.len().max(1) as f64;
    let area = st.probe.area;
    let steady_forces: Vec<f64> = st
        .top
        .samples
        .iter()
        .zip(&st.bottom.samples)
        .filter(|(a, _)| a.step >= steady_step)
        .map(|(a, b)| shear_traction(a.force[0], b.force[0], area))
        .collect();
    let p_t = steady_forces.iter().sum::<f64>() / steady_forces.len().max(1) as f64;
    let faces = st.probe.fit_params(profile.height).0;
    let wear = st.wear.map(|w| w.records).unwrap_or_default();
    let wear_summary = WearSummary::of(
        &wear,
        |w| steady(w.step),
        cfg.wear_particle_members,
        cfg.length,
    );
    let regime = classify_regime(
        &RegimeData {
            rho_tbl: layer.rho_tbl,
            p_t,
            tau_m,
            h_tbl: h,
            bounds: layer.bounds,
            faces,
            d0: d0 / profile.height,
            wear_particle_size: wear_summary.map(|w| w.steady_largest_over_l),
        },
        &cfg.regime,
    )
    .map_err(|e| DemError::InvalidConfig(format!("sliding regime: {e}")))?;
    let windows = &st.probe.windows;
    let windows_at_body: Vec<bool> = windows
        .iter()
        .map(|w| st.probe.at_body(w, &cfg.regime))
        .collect();
    let startup_step = (cfg.startup * total as f64).round() as u64;
    // A window counts once it opened at or after the start-up's end.
    let body_reached_at = windows
        .iter()
        .zip(opened(windows))
        .zip(&windows_at_body)
        .find(|((_, start), &at)| *start >= startup_step && at)
        .map(|((w, _), _)| w.slide);
    let steady_windows_at_body = windows
        .iter()
        .zip(&windows_at_body)
        .filter(|(w, &at)| at && steady(w.step))
        .count();
    let inside: Vec<bool> = windows
        .iter()
        .zip(&windows_at_body)
        .map(|(w, &at)| w.bounds.is_some() && !at)
        .collect();
    let all_p_t: Vec<(u64, f64)> = st
        .top
        .samples
        .iter()
        .zip(&st.bottom.samples)
        .map(|(a, b)| (a.step, shear_traction(a.force[0], b.force[0], area)))
        .collect();
    let interior = interior_phase(windows, startup_step, &inside, &all_p_t);
    let d_star = cfg.d_star()?;
    let last = Snapshot::of(&rig.sim, &band, &roles);
    Ok(SlidingResult {
        particles: rig.sim.particles.len(),
        body_particles: top.len() + bottom.len(),
        steps: total,
        dt,
        v0,
        area,
        rho0,
        shift: geo.shift,
        lift: geo.lift,
        d_star,
        d_m_over_d0: d_star / 8.0 / d0,
        steady_step,
        steady_windows: steady_windows.len(),
        steady_windows_at_body,
        body_reached_at,
        windows_at_body,
        interior,
        windows: st.probe.windows.clone(),
        wear_summary,
        wear,
        force_top: st.top.samples.clone(),
        force_bottom: st.bottom.samples.clone(),
        rho_tbl: layer.rho_tbl,
        profile,
        layer,
        h_tbl,
        p_t,
        p_n: cfg.pressure,
        tau_m,
        regime,
        first,
        last,
        wall_seconds: recorded.wall_seconds,
        neighbour_builds: rig.sim.neighbors().builds,
        local_builds: rig.sim.neighbors().local_builds,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn window(step: u64, lo: f64, hi: f64, rho: Option<f64>) -> WindowRecord {
        WindowRecord {
            step,
            time: step as f64,
            slide: step as f64,
            height: 1.0,
            h_tbl: Some(hi - lo),
            bounds: Some(TblBounds { lo, hi }),
            rho_tbl: rho,
        }
    }

    #[test]
    fn the_interior_phase_keeps_the_windows_inside_the_material_after_the_start() {
        // Four windows of 10 steps; p_T sampled every 5 steps, equal to the step number.
        let w = [
            window(10, 0.1, 0.9, Some(0.5)),  // start-up: before from_step
            window(20, 0.4, 0.6, Some(0.9)),  // inside
            window(30, 0.05, 0.3, Some(0.1)), // against the bottom body
            window(40, 0.3, 0.7, None),       // inside, its fit failed
        ];
        let p: Vec<(u64, f64)> = (1..=8).map(|k| (5 * k, 5.0 * k as f64)).collect();
        let inside: Vec<bool> = w
            .iter()
            .map(|w| w.bounds.is_some_and(|b| b.lo > 0.1))
            .collect();
        let i = interior_phase(&w, 10, &inside, &p).unwrap();
        assert_eq!(i.windows, 2);
        // Samples at steps 15, 20 and 35, 40.
        assert_eq!(i.p_t, (15.0 + 20.0 + 35.0 + 40.0) / 4.0);
        // The failed fit is left out of rho_TBL, not of h_TBL.
        assert_eq!(i.rho_tbl, 0.9);
        assert!((i.h_tbl - (0.2 + 0.4) / 2.0).abs() < 1e-12);
        // Nothing inside after the start: no phase.
        assert!(interior_phase(&w, 10, &[false; 4], &p).is_none());
        assert!(interior_phase(&w, 40, &inside, &p).is_none());
    }

    #[test]
    fn the_slide_lags_a_ramped_start_by_half_its_ramp() {
        // v0 = 2 reached at a = 4: 0.5 a t^2 until t = 0.5, then v0 t - v0^2 / (2 a), continuous.
        assert_eq!(slide(2.0, None, 3.0), 6.0);
        assert_eq!(slide(2.0, Some(4.0), 0.25), 0.125);
        assert_eq!(slide(2.0, Some(4.0), 0.5), 0.5);
        assert_eq!(slide(2.0, Some(4.0), 3.0), 5.5);
        // The inverse, during the ramp and after it.
        for d in [0.125, 0.5, 5.5] {
            assert!((slide(2.0, Some(4.0), time_to_slide(2.0, Some(4.0), d)) - d).abs() < 1e-15);
        }
        assert_eq!(time_to_slide(2.0, None, 6.0), 3.0);
    }
}
