//! Wear: third-body sliding (paper 004 sections 2-3, Fig. 6): the density of the third-body layer
//! rho_TBL against the normal pressure p_N (Fig. 6a) and against the strength sigma_m at fixed d*
//! (Fig. 6b), with each run's regime and p_T against the shear strength tau_m, which is measured on
//! each material's own relaxed box with the patch-test rig (simple shear to the peak, one strength job
//! per sigma_m, [`crate::wear::sliding::run_strength_job`]).
//!
//! Quick profile: L = 20 d0 (the paper's 100 d0), 5 L of sliding (the paper's 50 L), 100 bins, one
//! seed, d* = 0.2 L. At that coarse d0, d_m = d*/8 lies below every pair, so d* (gamma) does not enter
//! the runs (eq 11 of paper 004): the quick runs test the p_N and sigma_m trends only; the d* trend
//! needs the paper profile's d0 = 0.01 L. The quick profile also runs Fig. 3b's shear band on a
//! 40 d0 box (the resolution study): p_T / tau_m rises with L / d0, and the claim reads it at the
//! paper's d0 = 0.01 L off the line through the two boxes.

mod claims;
mod page;
mod resolution;

use dem::scenario::sliding::{SlidingConfig, SlidingMaterial};
use serde::{Deserialize, Serialize};
use wear::tbl::RegimeParams;

use super::super::html::png_img;
use crate::report::{longest_first, Context, Profile, Section, SectionOutput};
use crate::wear::samples::distinct;
use crate::wear::sliding::{
    box_jobs, models, run_sliding_with, run_strength_job, InteriorSummary, ShearStrength,
    SlidingSummary, StrengthJob,
};

use crate::Result;
use claims::claims;
use dem::scenario::sliding::MaterialStrength;
use page::{figure, page};

/// Bumped when the runs' code changes what they give (retires cached results).
const VERSION: u32 = 4;

/// "Near" in paper 004 section 3 ("roughly equal", "indeed near"): p_T within 30 % of tau_m (or of
/// tau_m rho_TBL / rho_0). The quick runs have one seed and 2.5 L of steady sliding, p_T wanders by
/// about 10 % between force samples' halves, and tau_m is the peak of one sample's shear curve, which
/// fluctuates by about 10 % about its rising part; 30 % is these combined with a margin, and still
/// tells a p_T at tau_m from one at half of it.
pub(super) const NEAR: f64 = 0.3;

/// Fewest interior-phase windows for a claim on them: three windows hold a few hundred force samples
/// and three profile fits, enough that one window's wander does not decide the verdict.
pub(super) const MIN_INTERIOR: usize = 3;

pub const SECTION: Section = Section {
    id: "wear-sliding",
    title: "Wear: third-body sliding (paper 004, Fig. 6)",
    run,
};

#[derive(Debug, Clone, PartialEq, Serialize)]
struct RunCase {
    version: u32,
    sliding: SlidingConfig,
}

/// A cached strength job's result and its figure as an inline image.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub(super) struct StrengthOut {
    pub(super) strength: MaterialStrength,
    pub(super) figure: String,
}

/// A cached run: its summary and its two pictures as inline images.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub(super) struct RunOut {
    pub(super) summary: SlidingSummary,
    pub(super) profiles: String,
    pub(super) snapshot: String,
}

/// The grid of Fig. 6: (p_N, sigma_m) in units of E, d* fixed.
fn grid(profile: Profile) -> Vec<(f64, f64)> {
    match profile {
        Profile::Quick => vec![
            (0.01, 0.1),
            (0.02, 0.1),
            (0.04, 0.1),
            (0.01, 0.14),
            (0.01, 0.2),
        ],
        Profile::Paper => vec![
            (0.01, 0.1),
            (0.02, 0.1),
            (0.04, 0.1),
            (0.01, 0.14),
            (0.01, 0.2),
            (0.02, 0.14),
            (0.02, 0.2),
        ],
    }
}

/// The quick profile's box, d0 = 0.05 L (L = 20 d0), and its finer one for the resolution study.
const QUICK_D0: f64 = 0.05;

/// Paper 004's own d0 / L (its L = 100 d0), where the resolution study's line is read.
pub(super) const PAPER_D0: f64 = 0.01;

/// The resolution study of the quick profile: Fig. 3b's shear band (p_N = 0.01 E, sigma_m = 0.2 E)
/// on a box of 40 d0 (d0 = 0.025 L) beside the grid's 20 d0 one, so that p_T / tau_m can be read at
/// the paper's d0 = 0.01 L (see [`at_paper_d0`]). One more relaxation, strength job and run: about
/// 3 minutes on one core.
pub(super) const FINE: (f64, f64, f64) = (0.01, 0.2, 0.025);

/// d* of the quick profile's runs in units of their d0: 4 (d* = 0.2 L on the 20 d0 box, 0.1 L on
/// the 40 d0 one), so that d_m = d*/8 = 0.5 d0 lies below every pair on both boxes, every pair
/// breaks at delta_e and the two boxes hold the same discrete material (with d* fixed in L instead,
/// gamma would enter the finer box's smaller pairs and the study would change the material with the
/// resolution: at 60 d0 and d* = 0.2 L the sigma_m = 0.2 E layer compacts to twice rho_0,
/// docs/sliding.md).
const QUICK_D_STAR_OVER_D0: f64 = 4.0;

fn cases(profile: Profile) -> Vec<RunCase> {
    let case = |(p_n, sigma_m): (f64, f64), d0_over_l: Option<f64>| {
        let mut c = SlidingConfig {
            pressure: p_n,
            material: SlidingMaterial {
                strength: sigma_m,
                surface_energy: None,
                d_star: Some(d0_over_l.map_or(0.1, |d0| QUICK_D_STAR_OVER_D0 * d0)),
            },
            dump_frames: 0,
            ..SlidingConfig::default()
        };
        if let Some(d0) = d0_over_l {
            c.d0_over_l = d0;
            c.distance_over_l = 5.0;
            // Five bins per d0 at 20 d0 as before, four per d0 (the paper's) on finer boxes.
            c.bins = if d0 == QUICK_D0 {
                100
            } else {
                (4.0 / d0).round() as usize
            };
            c.windows = 20;
            c.force_samples = 500;
        }
        RunCase {
            version: VERSION,
            sliding: c,
        }
    };
    let quick = (profile == Profile::Quick).then_some(QUICK_D0);
    let mut cases: Vec<RunCase> = grid(profile).into_iter().map(|g| case(g, quick)).collect();
    if profile == Profile::Quick {
        cases.push(case((FINE.0, FINE.1), Some(FINE.2)));
    }
    cases
}

/// L / d0 of a box given by its d0 / L, for the claims and tables.
pub(super) fn l_over_d0(d0_over_l: f64) -> f64 {
    (1.0 / d0_over_l).round()
}

/// Whether an interior phase lies in full contact (the shear band's statement): the classifier's
/// default threshold, which the report's runs use.
pub(super) fn in_full_contact(i: &InteriorSummary) -> bool {
    i.rho_tbl >= RegimeParams::default().full_contact
}

/// Whether `r` is one of the grid's runs (the profile's box), not the resolution study's finer one.
pub(super) fn on_grid(r: &SlidingSummary, grid_d0: f64) -> bool {
    r.d0_over_l == grid_d0
}

/// " on the 40 d0 box" for a run off the grid's box (empty on it), for the claims' wording.
pub(super) fn box_tag(r: &SlidingSummary, grid_d0: f64) -> String {
    if on_grid(r, grid_d0) {
        String::new()
    } else {
        format!(" on the {} d0 box", l_over_d0(r.d0_over_l))
    }
}

/// A case's cost up to a constant, to order the jobs: particle-steps of its box (L x L x 3 d0 holds
/// ~ 1 / d0^2 particles, and the step scales with d0, so a distance takes ~ 1 / d0 steps).
fn cost(c: &SlidingConfig) -> f64 {
    c.distance_over_l / c.d0_over_l.powi(3)
}

fn run(ctx: &Context) -> Result<SectionOutput> {
    let cases = cases(ctx.profile);
    // The relaxed boxes first, each once: a strength job and the runs of its material slide and
    // shear the same box, read from the report's cache. Every phase starts its costliest case first
    // (the 40 d0 box's relaxation, strength job and run beside the 20 d0 ones, not alone after
    // them); the boxes' results are only their cache entries, so their list is simply made from the
    // runs in that order.
    let runs: Vec<SlidingConfig> = longest_first(&cases, |c| cost(&c.sliding))
        .into_iter()
        .map(|k| cases[k].sliding.clone())
        .collect();
    let models = models(&runs)?;
    let boxes = box_jobs(&runs, &models)?;
    ctx.jobs("sliding boxes", &distinct(&boxes), |job, dir, par| {
        job.relax_into(dir, par)
    })?;
    let mut jobs: Vec<StrengthJob> = Vec::new();
    for c in &cases {
        let j = StrengthJob::of(&c.sliding);
        if !jobs.contains(&j) {
            jobs.push(j);
        }
    }
    let strengths: Vec<StrengthOut> = ctx.jobs_longest_first(
        "sliding strength tests",
        &jobs,
        |j| cost(&j.sliding),
        |job, dir, par| {
            let strength = run_strength_job(job, &ctx.cache, dir, par)?;
            let what = format!("sigma_m = {} E", job.sliding.material.strength);
            Ok(StrengthOut {
                strength,
                figure: png_img(
                    &dir.join("strength.png"),
                    &format!("strength tests, {what}"),
                )?,
            })
        },
    )?;
    let tau_of = |c: &SlidingConfig| -> ShearStrength {
        let k = jobs
            .iter()
            .position(|j| *j == StrengthJob::of(c))
            .expect("every case has its strength job");
        ShearStrength::measured(&strengths[k].strength)
    };
    let outs: Vec<RunOut> = ctx.jobs_longest_first(
        "sliding runs",
        &cases,
        |c| cost(&c.sliding),
        |case, dir, par| {
            let tau = tau_of(&case.sliding);
            let summary =
                run_sliding_with(&case.sliding, &tau, &ctx.cache, dir, par, &mut |_, _| {})?;
            let what = format!(
                "p_N = {} E, sigma_m = {} E",
                case.sliding.pressure, case.sliding.material.strength
            );
            Ok(RunOut {
                summary,
                profiles: png_img(&dir.join("profiles.png"), &format!("profiles, {what}"))?,
                snapshot: png_img(&dir.join("snapshot.png"), &format!("snapshot, {what}"))?,
            })
        },
    )?;
    let runs: Vec<&SlidingSummary> = outs.iter().map(|o| &o.summary).collect();
    let grid_d0 = cases[0].sliding.d0_over_l;
    Ok(SectionOutput {
        claims: claims(&runs, grid_d0),
        figures: vec![figure(&runs, grid_d0)],
        html: page(&outs, &strengths, &jobs, ctx.profile),
        provenance: vec![],
    })
}

/// The run at (p_N, sigma_m) on the box with d0 / L = `d0`, if the section has it.
pub(super) fn find<'a>(
    runs: &[&'a SlidingSummary],
    p_n: f64,
    sigma_m: f64,
    d0: f64,
) -> Option<&'a SlidingSummary> {
    runs.iter()
        .find(|r| r.p_n == p_n && r.strength == sigma_m && r.d0_over_l == d0)
        .copied()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_quick_grid_holds_both_trends_of_fig_6() {
        let g = grid(Profile::Quick);
        for p in [0.01, 0.04] {
            assert!(g.contains(&(p, 0.1)));
        }
        assert!(g.contains(&(0.01, 0.2)));
        let c = cases(Profile::Quick);
        assert!(c.iter().all(|c| c.sliding.validate().is_ok()));
        // The resolution study's run is the grid's shear band on the finer box, four bins per d0.
        let fine = c.last().unwrap();
        assert_eq!(
            (fine.sliding.pressure, fine.sliding.material.strength),
            (FINE.0, FINE.1)
        );
        assert_eq!((fine.sliding.d0_over_l, fine.sliding.bins), (0.025, 160));
        // d* = 4 d0 on both boxes: the grid's 0.2 L (its cached runs' key) and 0.1 L on the finer.
        assert_eq!(c[0].sliding.material.d_star, Some(0.2));
        assert_eq!(fine.sliding.material.d_star, Some(0.1));
        assert!(g.contains(&(FINE.0, FINE.1)));
        assert!(cases(Profile::Paper)
            .iter()
            .all(|c| c.sliding.d0_over_l == PAPER_D0));
    }
}
