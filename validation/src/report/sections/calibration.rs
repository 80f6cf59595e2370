//! Calibration (paper 000 section 3.4, done by least squares in crate `calibrate`): the pipeline's
//! calibration of Table 4 (nu = 0.15) on an HCP sample, each target's error before and after, the
//! re-measurement with the card as written, the card's `[verification]` (the calibrated model on a
//! lattice twice as thick, a sample no evaluation saw: mean, spread and d* of eq 22 from the measured
//! values), and the cost per iteration. One case, run by `calibrate::calibrate` in its job directory,
//! which is also its checkpoint: an interrupted calibration resumes.

use std::path::Path;

use calibrate::{CalibratedCard, CalibrationConfig, Properties, Target, Verification};
use dem::Parallelism;
use serde::{Deserialize, Serialize};

use crate::figures::calibration::cost_series;
use crate::report::claim::sig;
use crate::report::{
    Claim, Context, Figure, Kind, Panel, Profile, Section, SectionOutput, Tolerance,
};
use crate::Result;

pub const SECTION: Section = Section {
    id: "calibration",
    title: "Calibration of the pair parameters (paper 000 section 3.4)",
    run,
};

const VERSION: u32 = 2;

#[derive(Debug, Clone, Serialize, Deserialize)]
pub(super) struct Case {
    pub version: u32,
    pub config: CalibrationConfig,
}

/// What the report keeps of a calibration.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub(super) struct Outcome {
    pub targets: Properties,
    pub uncalibrated: Properties,
    pub calibrated: Properties,
    /// The card re-read and re-measured on the calibration's own sample (must equal `calibrated`).
    pub verified: Properties,
    /// The card's `[verification]` table.
    pub verification: Option<Verification>,
    /// Residuals after each iteration (iteration 0: the closed form), in the order of `targets`.
    pub errors: Vec<(usize, Vec<f64>)>,
    pub costs: Vec<(usize, f64)>,
    pub tolerance: f64,
    pub iterations: usize,
    pub evaluations: usize,
    pub status: String,
    pub multipliers: [f64; 5],
    pub particles: usize,
}

/// The pipeline's default calibration (`cgdem pipeline`): Table 4 at nu = 0.15 on an HCP sample of
/// L x L x 3 d0, d0 = 0.6 d_c, at most 12 iterations.
fn config(l: f64) -> CalibrationConfig {
    let mut cfg = CalibrationConfig::table4_hcp(0.15, l);
    // A lattice has no seeds: the fresh sample is the same recipe twice as thick (one sample keeps
    // the report quick).
    cfg.verification.samples = vec![calibrate::Variant {
        seed: 101,
        length: 1.0,
        width: 2.0,
    }];
    cfg
}

pub(super) fn calibrate_case(case: &Case, dir: &Path, par: Parallelism) -> Result<Outcome> {
    let o = calibrate::calibrate(&case.config, dir, par, None)?;
    let card_path = dir.join("card.toml");
    o.card.write(&card_path)?;
    let card = CalibratedCard::read(&card_path)?;
    let verified = calibrate::remeasure(&o.problem, &card, par)?;
    // The calibration's sample (a lattice: the same for every trial model), from the sample cache.
    let p = &o.problem;
    let particles = match p.samples.first() {
        Some(spec) => p
            .cache
            .get(spec, &card.pair_model()?, &p.relax)
            .map_or(0, |s| s.particles.len()),
        None => 0,
    };
    let h = &o.checkpoint.history;
    let mut errors = Vec::new();
    if let Some(first) = h.first() {
        errors.push((
            first.iteration.saturating_sub(1),
            first_residuals(&o, first),
        ));
    }
    for rec in h {
        errors.push((rec.iteration, rec.r.clone()));
    }
    let s = &card.model.scale;
    Ok(Outcome {
        targets: card.targets,
        uncalibrated: card.uncalibrated,
        calibrated: card.calibrated,
        verified,
        verification: card.verification.clone(),
        errors,
        costs: cost_series(h),
        tolerance: case.config.solver.tolerance,
        iterations: card.provenance.iterations,
        evaluations: card.provenance.evaluations,
        status: format!("{:?}", card.provenance.status),
        multipliers: [s.k_n, s.k_t, s.delta_e, s.delta_f, s.f_mt],
        particles,
    })
}

/// The closed form's residuals (before the first step): from the card's uncalibrated properties.
fn first_residuals(o: &calibrate::Outcome, _first: &calibrate::Record) -> Vec<f64> {
    let c = &o.card;
    Target::ALL
        .iter()
        .filter_map(|&t| Some((c.uncalibrated.get(t)? - c.targets.get(t)?) / c.targets.get(t)?))
        .collect()
}

fn run(ctx: &Context) -> Result<SectionOutput> {
    let l = match ctx.profile {
        Profile::Quick => 8.0,
        Profile::Paper => 25.0,
    };
    let case = Case {
        version: VERSION,
        config: config(l),
    };
    let o = ctx
        .jobs("calibration", std::slice::from_ref(&case), calibrate_case)?
        .pop()
        .ok_or_else(|| crate::ValidationError::Report("calibration: no result".into()))?;
    let fig = "calibration";
    let e_title = "error of each target per iteration";
    let c_title = "least-squares cost per iteration";
    let mut claims = Vec::new();
    let mut e_panel = Panel::new(
        e_title,
        "Levenberg-Marquardt iteration (-)",
        "(measured - target) / target (%)",
    );
    let present: Vec<Target> = Target::ALL
        .iter()
        .copied()
        .filter(|&t| o.targets.get(t).is_some())
        .collect();
    for (k, &t) in present.iter().enumerate() {
        let target = o.targets.get(t).unwrap_or(f64::NAN);
        let err = |p: &Properties| p.get(t).map_or(f64::NAN, |v| (v - target) / target);
        let pts: Vec<(f64, f64)> = o
            .errors
            .iter()
            .filter_map(|(i, r)| r.get(k).map(|v| (*i as f64, 100.0 * v)))
            .collect();
        let last_x = pts.last().map_or(0.0, |p| p.0);
        claims.push(
            Claim::new(
                "workbench",
                "calibration",
                format!("{}: calibrated error (relative)", t.name()),
                0.0,
                err(&o.calibrated),
                Tolerance::Absolute(0.01),
            )
            .note("The acceptance band of issue 5: within 1 %."),
        );
        claims.push(
            Claim::new(
                "000",
                "eqs 7-13",
                format!(
                    "{}: error of the closed form (uncalibrated, relative)",
                    t.name()
                ),
                0.0,
                err(&o.uncalibrated),
                Tolerance::Info,
            )
            .note("Section 3.4: the closed form is a first guess that patch tests correct."),
        );
        claims.push(Claim::new(
            "workbench",
            "calibration",
            format!("{}: verification re-run / calibrated", t.name()),
            1.0,
            o.verified.get(t).unwrap_or(f64::NAN) / o.calibrated.get(t).unwrap_or(f64::NAN),
            Tolerance::Absolute(1e-9),
        ));
        let _ = last_x;
        e_panel = e_panel.with(t.name(), Kind::SimulationPoints, pts);
    }
    if let Some(v) = &o.verification {
        for &t in &Target::ALL {
            let c = v.get(t);
            let (tol, note) = if t == Target::SurfaceEnergy {
                (
                    Tolerance::Info,
                    "Measured, not a target: the fracture energy cannot meet 2 gamma together with \
                     sigma_N under paper 000's law (docs/calibration.md).",
                )
            } else {
                (
                    Tolerance::Absolute(0.05),
                    "The card on a sample no evaluation saw (the lattice twice as thick): issue \
                     16's band, 5 % in the mean.",
                )
            };
            claims.push(
                Claim::new(
                    "workbench",
                    "verification",
                    format!(
                        "{}: verified mean error on a fresh sample (relative)",
                        t.name()
                    ),
                    0.0,
                    c.mean_error(),
                    tol,
                )
                .note(note),
            );
        }
        if let Some(c) = &v.compaction {
            claims.push(
                Claim::new(
                    "workbench",
                    "verification",
                    format!(
                        "largest compaction under shear ({} E, strain {}) on the fresh sample \
                         (fraction of its height)",
                        c.pressure, c.strain
                    ),
                    c.limit,
                    c.largest(),
                    Tolerance::Below,
                )
                .note(
                    "The check a scenario needs of a card (docs/calibration.md, \"Shear under \
                     load\"): the calibrated silica cards passed every patch test and compacted \
                     until the walls met in the junction. Scenarios refuse a card past the limit.",
                ),
            );
        }
        claims.push(
            Claim::new(
                "000",
                "eq 22",
                "d* from the verified E, nu, sigma_T and surface energy / d* from the targets",
                1.0,
                v.dstar / v.dstar_target,
                Tolerance::Info,
            )
            .note(
                "d* = 32 gamma G / sigma_T^2 scales with the surface energy, which the card \
                 does not meet (see above).",
            ),
        );
    }
    let iters = o.costs.last().map_or(1.0, |c| c.0.max(1) as f64);
    let band = "acceptance band ±1 %";
    e_panel = e_panel
        .with(band, Kind::Reference, vec![(0.0, 1.0), (iters, 1.0)])
        .with(band, Kind::Reference, vec![(0.0, -1.0), (iters, -1.0)]);
    let converged = 0.5 * present.len() as f64 * o.tolerance * o.tolerance;
    let costs: Vec<(f64, f64)> = o
        .costs
        .iter()
        .filter(|c| c.1 > 0.0)
        .map(|&(i, c)| (i as f64, c.log10()))
        .collect();
    let c_panel = Panel::new(
        c_title,
        "Levenberg-Marquardt iteration (-)",
        "log10 of 1/2 |r|^2 (-)",
    )
    .with("cost", Kind::SimulationPoints, costs)
    .with(
        "cost",
        Kind::Reference,
        vec![(0.0, converged.log10()), (iters, converged.log10())],
    );
    claims.push(
        Claim::new(
            "workbench",
            "calibration",
            "iterations to converge (budget 12)",
            12.0,
            o.iterations as f64,
            Tolerance::Below,
        )
        .note(format!(
            "{} evaluations, status {}",
            o.evaluations, o.status
        )),
    );
    let figure = Figure::new(fig, "paper 000 section 3.4 (no figure in the paper)", "Least-squares calibration of k_N, k_T, delta_e, delta_f, F_mT (Table 4, nu = 0.15, HCP, d0 = 0.6 d_c); dashed: the ±1 % band and the cost at which every |r_i| reaches the solver's tolerance.")
        .panel(e_panel)
        .panel(c_panel);
    let m = o.multipliers;
    let html = format!(
        "<p>The pipeline's calibration (<code>cgdem pipeline</code>): HCP sample of L = {} d0 ({} particles), \
         Table 4 at nu = 0.15, targets E, nu, sigma_N, sigma_T. Status {}, {} iterations, {} evaluations. \
         Multipliers on the closed form: k_N {}, k_T {}, delta_e {}, delta_f {}, F_mT {}. The card was re-read \
         and the patch tests re-run with it (verification).</p>\n\
         <p>The card's <code>[verification]</code>: the calibrated model on the lattice twice as thick \
         (a sample no evaluation saw), every property measured with the tensile test run to separation; \
         d* of eq 22 from the measured values. Amorphous recipes (k seeds per evaluation, fresh seeds \
         for the verification) are in docs/calibration.md.</p>\n",
        sig(l, 3), o.particles, o.status, o.iterations, o.evaluations,
        sig(m[0], 4), sig(m[1], 4), sig(m[2], 4), sig(m[3], 4), sig(m[4], 4)
    );
    Ok(SectionOutput {
        claims,
        figures: vec![figure],
        html,
        provenance: vec![],
    })
}
