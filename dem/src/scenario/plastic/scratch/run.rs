//! One load's scratch job: indent at constant V_z to the load, then slide at constant V_x under it,
//! saving the whole state every two minutes and on Ctrl-C (the same call resumes to the same bits).

use serde::{Deserialize, Serialize};

use super::{IndentCurve, ScratchConfig, ScratchRun, SlideSeries};
use crate::error::{DemError, Result};
use crate::io::progress::{self, ProgressFile, SaveClock};
use crate::scenario::plastic::ledger::{EnergyReport, PlasticLedger};
use crate::scenario::plastic::model::Params;
use crate::scenario::plastic::rig::{Body, Drive, Rig, RigState, StepReport};
use crate::scenario::plastic::surface::Surface;
use crate::scenario::plastic::SurfaceInfo;
use crate::units::UnitSystem;
use crate::Vec3;

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
    let slide_steps = crate::scenario::step_budget(
        "the slide (slide.speed x slide.duration at slide.speed)",
        (distance / slide_speed / rig.dt).round().max(1.0),
    )?;
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
            tracing::info!(target: "stage", step = p.rig.step, "scratch resumed from its progress file");
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
    // The indentation stops at the load or at max_depth, whichever comes first.
    crate::scenario::step_budget(
        "the indentation (half the indenter's radius at indent.speed)",
        (max_depth / (u.velocity_from_m_s(cfg.indent.speed) * rig.dt)).ceil(),
    )?;
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
