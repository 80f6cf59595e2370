//! Patch tests (paper 000 section 3): the HCP lattice (E and nu against the target nu, Figs. A.4-A.5;
//! strengths against d0 for s = 0 and 1/2, Figs. 5-6) and relaxed amorphous samples (volume
//! fraction, E, nu and strengths against d0, Figs. 7-8 and A.6-A.8). Every case is one
//! `dem::scenario::patch` campaign of one case, run in its job directory (so an interrupted case
//! resumes from its progress files) and cached by its configuration.

use std::path::Path;

use dem::material::{Material, ParamScale};
use dem::sample::{RelaxConfig, SampleSpec};
use dem::scenario::patch::suite::{PatchCase, PatchKind, Sweep};
use dem::scenario::patch::{
    run_suite, ElasticConfig, PatchSuite, StrengthConfig, StrengthMode, StrengthResult,
};
use dem::Parallelism;
use serde::{Deserialize, Serialize};

use crate::figures::patch::HCP_VOLUME_FRACTION;
use crate::report::claim::sig;
use crate::report::{
    Claim, Context, Figure, Kind, Panel, Profile, Section, SectionOutput, Tolerance,
};
use crate::{Result, ValidationError};

pub const HCP: Section = Section {
    id: "patch-hcp",
    title: "Patch tests on the HCP lattice (paper 000 section 3.1, Figs. 5-6, A.4-A.5)",
    run: run_hcp,
};

pub const AMORPHOUS: Section = Section {
    id: "patch-amorphous",
    title: "Patch tests on amorphous samples (paper 000 section 3.2, Figs. 7-8, A.6-A.8)",
    run: run_amorphous,
};

/// Bumped when a case's settings or measurement change in code (not in its inputs).
const VERSION: u32 = 1;

/// One case: a campaign of one case (the cache key).
#[derive(Debug, Clone, Serialize, Deserialize)]
struct Case {
    version: u32,
    suite: PatchSuite,
}

fn run_case(case: &Case, dir: &Path, par: Parallelism) -> Result<PatchCase> {
    let report = run_suite(&case.suite, Some(dir), par)?;
    report
        .cases
        .into_iter()
        .next()
        .ok_or_else(|| ValidationError::Report("a patch campaign of one case gave none".into()))
}

/// A campaign of one case on Table 4 with target nu and s, the paper's test settings, and strength
/// tests stopped `post_peak` strain after their peak (the peak is all the report reads).
fn suite(nu: f64, s: f64, sample: SampleSpec, tests: Vec<PatchKind>, post_peak: f64) -> PatchSuite {
    let strength = |mode| StrengthConfig {
        post_peak_strain: post_peak,
        ..StrengthConfig::paper(mode)
    };
    PatchSuite {
        material: Material {
            scaling: s,
            ..Material::table4(nu)
        },
        scale: ParamScale::default(),
        model: None,
        sample,
        relax: RelaxConfig::default(),
        tests,
        elastic: ElasticConfig::default(),
        tensile: strength(StrengthMode::Tensile),
        shear: strength(StrengthMode::Shear),
        compaction: Default::default(),
        sweep: Sweep::default(),
        save_samples: false,
    }
}

/// Sizes per profile: (HCP edge for the elastic sweep, HCP edge for the strengths, HCP d0 sweep,
/// amorphous edge, amorphous d0 sweep, post-peak strain).
struct Sizes {
    hcp_l: f64,
    hcp_strength_l: f64,
    hcp_d0: Vec<f64>,
    amorphous_l: f64,
    amorphous_d0: Vec<f64>,
    post_peak: f64,
}

fn sizes(p: Profile) -> Sizes {
    match p {
        // A lattice deforms homogeneously up to its peak: strengths do not depend on L (1.029 at
        // 10 d0, 1.038 at 25 d0; docs/patch-tests.md), so 8 d0 gives Figs. 5-6 in seconds.
        Profile::Quick => Sizes {
            hcp_l: 10.0,
            hcp_strength_l: 8.0,
            hcp_d0: vec![0.6, 2.4, 9.6, 38.4],
            amorphous_l: 8.0,
            amorphous_d0: vec![0.6, 2.4, 9.6, 19.2],
            post_peak: 0.02,
        },
        // Paper 000 sections 3.1-3.2: L = 25 d0 (lattice), 100 d0 (amorphous), W = 3 d0.
        Profile::Paper => Sizes {
            hcp_l: 25.0,
            hcp_strength_l: 25.0,
            hcp_d0: vec![0.6, 1.2, 2.4, 4.8, 9.6, 19.2, 38.4, 76.8],
            amorphous_l: 100.0,
            amorphous_d0: vec![0.6, 1.2, 2.4, 4.8, 9.6, 19.2],
            post_peak: 0.05,
        },
    }
}

const NUS: [f64; 5] = [0.0, 0.1, 0.15, 0.2, 0.25];
const SCALINGS: [f64; 2] = [0.0, 0.5];

fn hcp(d0: f64, l: f64) -> SampleSpec {
    SampleSpec::Hcp {
        d0_over_dc: d0,
        l_over_d0: l,
        w_over_d0: 3.0,
    }
}

fn run_hcp(ctx: &Context) -> Result<SectionOutput> {
    let z = sizes(ctx.profile);
    let all = vec![PatchKind::Elastic, PatchKind::Tensile, PatchKind::Shear];
    let strengths = vec![PatchKind::Tensile, PatchKind::Shear];
    let elastic_only = vec![PatchKind::Elastic];
    let mut cases: Vec<Case> = NUS
        .iter()
        .map(|&nu| {
            let tests = if ctx.profile == Profile::Paper {
                all.clone()
            } else {
                elastic_only.clone()
            };
            Case {
                version: VERSION,
                suite: suite(nu, 0.0, hcp(0.6, z.hcp_l), tests, z.post_peak),
            }
        })
        .collect();
    for &s in &SCALINGS {
        for &d0 in &z.hcp_d0 {
            cases.push(Case {
                version: VERSION,
                suite: suite(
                    0.0,
                    s,
                    hcp(d0, z.hcp_strength_l),
                    strengths.clone(),
                    z.post_peak,
                ),
            });
        }
    }
    let results = ctx.jobs("HCP patch cases", &cases, run_case)?;
    let (by_nu, by_d0) = results.split_at(NUS.len());
    let fig = "patch-hcp";
    let mut claims = Vec::new();
    let l_label = format!("HCP, L = {} d0", z.hcp_l);
    let (e_title, nu_title) = (
        "E: measured vs target (Fig. A.4)",
        "nu: measured vs target (Fig. A.5)",
    );
    let (mut e_pts, mut nu_pts) = (vec![], vec![]);
    for (c, &nu) in by_nu.iter().zip(&NUS) {
        let e = c.elastic.as_ref().ok_or_else(|| missing("elastic"))?;
        let ratio = e.young_modulus / e.target_young_modulus;
        e_pts.push((nu, ratio));
        nu_pts.push((nu, e.poisson_ratio));
        claims.push(
            Claim::new(
                "000",
                "Fig. A.4",
                format!("HCP E / E_target, target nu = {nu}"),
                1.0,
                ratio,
                Tolerance::Relative(0.12),
            )
            .note("Paper: within 12 %, worst at nu = 1/4.")
            .plotted(fig, e_title, &l_label, nu),
        );
        let tol = if nu == 0.0 {
            Tolerance::Absolute(0.01)
        } else {
            Tolerance::Relative(0.12)
        };
        claims.push(
            Claim::new(
                "000",
                "Fig. A.5",
                format!("HCP nu, target nu = {nu}"),
                nu,
                e.poisson_ratio,
                tol,
            )
            .plotted(fig, nu_title, &l_label, nu),
        );
    }
    let e_panel = Panel::new(e_title, "target nu (-)", "E / E_target (-)")
        .with(&l_label, Kind::SimulationPoints, e_pts)
        .with(
            &l_label,
            Kind::Reference,
            NUS.iter().map(|&n| (n, 1.0)).collect(),
        );
    let nu_panel = Panel::new(nu_title, "target nu (-)", "measured nu (-)")
        .with(&l_label, Kind::SimulationPoints, nu_pts)
        .with(
            &l_label,
            Kind::Reference,
            NUS.iter().map(|&n| (n, n)).collect(),
        );

    // Figs. 5-6: strength over the target of eq (20) against d0 / d_c, per s.
    let t_title = "tensile strength / eq 20 (Fig. 5), nu = 0";
    let s_title = "shear strength / eq 20 (Fig. 6), nu = 0";
    let mut t_panel = Panel::new(t_title, "d0 / d_c (-)", "sigma_N / target of eq 20 (-)").log_x();
    let mut s_panel = Panel::new(s_title, "d0 / d_c (-)", "sigma_T / target of eq 20 (-)").log_x();
    let n = z.hcp_d0.len();
    for (k, &s) in SCALINGS.iter().enumerate() {
        let label = format!("s = {s}, L = {} d0", z.hcp_strength_l);
        let (mut tp, mut sp) = (vec![], vec![]);
        for (c, &d0) in by_d0[k * n..(k + 1) * n].iter().zip(&z.hcp_d0) {
            let t = c.tensile.as_ref().ok_or_else(|| missing("tensile"))?;
            let sh = c.shear.as_ref().ok_or_else(|| missing("shear"))?;
            let (t_ratio, sh_ratio) = (of_target(t)?, of_target(sh)?);
            tp.push((d0, t_ratio));
            sp.push((d0, sh_ratio));
            claims.push(
                Claim::new("000", "Fig. 5, eq 20", format!("HCP tensile strength / eq 20, nu = 0, s = {s}, d0 = {d0} d_c"), 1.0, t_ratio, Tolerance::Relative(0.1))
                    .note("Paper: measured = target at nu = 0 (no number given; 10 % here). Above d_c with s = 0 the lattice reaches 93 %.")
                    .plotted(fig, t_title, &label, d0),
            );
            // The paper: "the measured [shear] values are instead lower than the target ones when
            // d0 < d_c", and equal to it at nu = 0 otherwise.
            let below_dc = d0 < 1.0;
            claims.push(
                Claim::new(
                    "000",
                    "Fig. 6, eq 20",
                    format!("HCP shear strength / eq 20, nu = 0, s = {s}, d0 = {d0} d_c"),
                    1.0,
                    sh_ratio,
                    if below_dc {
                        Tolerance::Below
                    } else {
                        Tolerance::Relative(0.1)
                    },
                )
                .note(if below_dc {
                    SHEAR_NOTE_BELOW_DC
                } else {
                    SHEAR_ROW_NOTE
                })
                .plotted(fig, s_title, &label, d0),
            );
        }
        // The paper's trend for s = 1/2 (both strengths fall with d0), as a claim of its own.
        if s == 0.5 {
            let (first, last) = (sp[0], sp[n - 1]);
            claims.push(Claim::new("000", "Fig. 6", format!("HCP shear strength, s = 1/2: sigma_T({} d_c) / sigma_T({} d_c) (falls with d0)", last.0, first.0), 1.0, last.1 * eq20(last.0, s) / (first.1 * eq20(first.0, s)), Tolerance::Below));
        }
        let target: Vec<(f64, f64)> = z.hcp_d0.iter().map(|&d| (d, 1.0)).collect();
        t_panel = t_panel.with(&label, Kind::SimulationPoints, tp).with(
            &label,
            Kind::Reference,
            target.clone(),
        );
        s_panel =
            s_panel
                .with(&label, Kind::SimulationPoints, sp)
                .with(&label, Kind::Reference, target);
    }
    let figure = Figure::new(fig, "paper 000 Figs. 5, 6, A.4, A.5", "HCP lattice, Table 4 material: elastic constants against the target Poisson's ratio (d0 = 0.6 d_c) and strengths against d0 over the targets of eq 20.")
        .panel(e_panel)
        .panel(nu_panel)
        .panel(t_panel)
        .panel(s_panel);
    let html = format!(
        "<p>Samples L x L x 3 d0 (L = {} d0 for the elastic sweep, {} d0 for the strengths; the paper: 25 d0). \
         Strength tests stop {} strain after their peak.</p>\n<ul>\n<li>Known difference (Fig. 6): {SHEAR_NOTE}</li>\n\
         <li>Known difference (Fig. 5): tensile strength 93 % of target above d_c for s = 0 (the paper: equal at nu = 0).</li>\n</ul>\n",
        z.hcp_l, z.hcp_strength_l, z.post_peak
    );
    Ok(SectionOutput {
        claims,
        figures: vec![figure],
        html,
        provenance: vec![],
    })
}

/// The row's pointer to the section's "Known difference (Fig. 6)", which gives the reasons in full.
const SHEAR_ROW_NOTE: &str = "Above the target by the normal forces' share: see the section's known difference (Fig. 6) and docs/patch-tests.md.";
const SHEAR_NOTE_BELOW_DC: &str = "Paper: below the target for d0 < d_c. Here above it by the normal forces' share (the section's known difference, Fig. 6); LAMMPS's rule of dropping the springs of separated pairs at each rebuild gives 0.58.";
const SHEAR_NOTE: &str = "The lattice's shear strength sits above eq 20 at nu = 0: eq 11 sizes the tangential caps to carry sigma_T alone (all at F_mT they carry 0.88-0.95 sigma_T in an affine estimate), and the normal forces of the bonds inclined to the shear add to them (affine peak 1.4-1.7 sigma_T in each orientation of the lattice, measured 1.08-1.62; docs/patch-tests.md). Dropping the springs of separated pairs at each neighbour-list rebuild, as LAMMPS's neigh/history does, gives the paper's Fig. 6 (0.58 below d_c; 0.90 above for s = 0, 0.94-1.10 along eq 20 for s = 1/2) but lowers the tensile strength to 0.72-0.76. For s = 1/2 it falls more slowly than eq 20: the cap does not scale with s, only delta_f does, so confined contacts keep a frictional strength; calibration adjusts F_mT.";

/// Eq (20) over sigma_N: (d0 / d_c)^(-s) above d_c.
fn eq20(d0: f64, s: f64) -> f64 {
    if d0 <= 1.0 {
        1.0
    } else {
        d0.powf(-s)
    }
}

fn missing(test: &str) -> ValidationError {
    ValidationError::Report(format!("a patch case has no {test} result"))
}

/// A strength over its target of eq (20); the cohesive law of these campaigns always has one.
fn of_target(r: &StrengthResult) -> Result<f64> {
    r.ratio.ok_or_else(|| {
        ValidationError::Report(format!("a {:?} test with no target strength", r.mode))
    })
}

fn run_amorphous(ctx: &Context) -> Result<SectionOutput> {
    let z = sizes(ctx.profile);
    let tests = vec![PatchKind::Elastic, PatchKind::Tensile, PatchKind::Shear];
    let seed = 1;
    let mut cases = Vec::new();
    for &s in &SCALINGS {
        for &d0 in &z.amorphous_d0 {
            let sample = SampleSpec::Amorphous {
                d0_over_dc: d0,
                l_over_d0: z.amorphous_l,
                w_over_d0: 3.0,
                h_over_d0: None,
                ds_over_d0: 0.75,
                dl_over_d0: 1.25,
                dl_over_l: None,
                seed,
                insert_fraction: 0.75,
            };
            cases.push(Case {
                version: VERSION,
                suite: suite(0.15, s, sample, tests.clone(), z.post_peak),
            });
        }
    }
    let results = ctx.jobs("amorphous patch cases", &cases, run_case)?;
    let fig = "patch-amorphous";
    let n = z.amorphous_d0.len();
    let titles = [
        "relaxed volume fraction (Fig. 7)",
        "E / E_target (Fig. 8)",
        "nu, target 0.15 (Fig. A.6)",
        "tensile strength / eq 20 (Fig. A.7)",
        "shear strength / eq 20 (Fig. A.8)",
    ];
    let ylabels = [
        "volume fraction (-)",
        "E / E_target (-)",
        "nu (-)",
        "sigma_N / target (-)",
        "sigma_T / target (-)",
    ];
    let mut panels: Vec<Panel> = titles
        .iter()
        .zip(ylabels)
        .map(|(t, y)| Panel::new(t, "d0 / d_c (-)", y).log_x())
        .collect();
    let mut claims = Vec::new();
    let d0s = &z.amorphous_d0;
    let grid = |v: f64| -> Vec<(f64, f64)> { vec![(d0s[0], v), (d0s[n - 1], v)] };
    let mut per_s: Vec<[Vec<(f64, f64)>; 5]> = Vec::new();
    for (k, &s) in SCALINGS.iter().enumerate() {
        let label = format!("s = {s}, L = {} d0", z.amorphous_l);
        let mut v: [Vec<(f64, f64)>; 5] = Default::default();
        for (c, &d0) in results[k * n..(k + 1) * n].iter().zip(d0s) {
            let e = c.elastic.as_ref().ok_or_else(|| missing("elastic"))?;
            let t = c.tensile.as_ref().ok_or_else(|| missing("tensile"))?;
            let sh = c.shear.as_ref().ok_or_else(|| missing("shear"))?;
            let vals = [
                c.volume_fraction,
                e.young_modulus / e.target_young_modulus,
                e.poisson_ratio,
                of_target(t)?,
                of_target(sh)?,
            ];
            for (slot, x) in v.iter_mut().zip(vals) {
                slot.push((d0, x));
            }
        }
        for (p, pts) in panels.iter_mut().zip(v.iter()) {
            let taken = std::mem::take(p);
            *p = taken.with(&label, Kind::SimulationPoints, pts.clone());
        }
        // Trends above d_c: from the second d0 (the first above d_c) to the last.
        let (a, b) = (1, n - 1);
        let ratio = |q: usize| v[q][b].1 / v[q][a].1;
        let span = format!("{} d_c / {} d_c", d0s[b], d0s[a]);
        if s == 0.0 {
            claims.push(
                Claim::new(
                    "000",
                    "Fig. 7",
                    format!("amorphous vf({span}), s = 0 (independent of d0)"),
                    1.0,
                    ratio(0),
                    Tolerance::Relative(0.01),
                )
                .note(
                    "One seed for every d0: above d_c with s = 0 the samples are exact rescalings.",
                ),
            );
            claims.push(Claim::new(
                "000",
                "Fig. 8",
                format!("amorphous E({span}), s = 0 (independent of d0)"),
                1.0,
                ratio(1),
                Tolerance::Relative(0.02),
            ));
        } else {
            claims.push(Claim::new(
                "000",
                "Fig. 7",
                format!("amorphous vf({span}), s = 1/2 (falls with d0)"),
                1.0,
                ratio(0),
                Tolerance::Below,
            ));
            claims.push(Claim::new(
                "000",
                "Fig. 8",
                format!("amorphous E({span}), s = 1/2 (falls with d0)"),
                1.0,
                ratio(1),
                Tolerance::Below,
            ));
            claims.push(Claim::new(
                "000",
                "Fig. A.7",
                format!("amorphous sigma_N({span}), s = 1/2 (falls with d0)"),
                1.0,
                v[3][b].1 * eq20(d0s[b], s) / (v[3][a].1 * eq20(d0s[a], s)),
                Tolerance::Below,
            ));
        }
        per_s.push(v);
        let _ = k;
    }
    // The paper's uncalibrated figures, shown beside ours, not targets (DESIGN.md section 8).
    let s0 = &per_s[0];
    let mean = |q: usize| s0[q].iter().map(|p| p.1).sum::<f64>() / s0[q].len() as f64;
    claims.push(
        Claim::new(
            "000",
            "Fig. A.6",
            "amorphous nu, mean over d0 (s = 0), paper ~0.20 for a target 0.15",
            0.20,
            mean(2),
            Tolerance::Info,
        )
        .note(NU_NOTE),
    );
    claims.push(
        Claim::new(
            "000",
            "Fig. A.7",
            "amorphous tensile strength / target, mean over d0 (s = 0), paper ~50 %",
            0.50,
            mean(3),
            Tolerance::Info,
        )
        .note(STRENGTH_NOTE),
    );
    claims.push(
        Claim::new(
            "000",
            "Fig. A.8",
            "amorphous shear strength / target, mean over d0 (s = 0), paper ~56 %",
            0.56,
            mean(4),
            Tolerance::Info,
        )
        .note(STRENGTH_NOTE),
    );
    let paper = "paper 000 (uncalibrated, not a target)";
    let refs: [Vec<(&str, f64)>; 5] = [
        vec![("HCP lattice (Fig. 7's reference)", HCP_VOLUME_FRACTION)],
        vec![("target", 1.0)],
        vec![("target", 0.15), (paper, 0.20)],
        vec![("target", 1.0), (paper, 0.50)],
        vec![("target", 1.0), (paper, 0.56)],
    ];
    for (p, r) in panels.iter_mut().zip(refs) {
        for (label, value) in r {
            let taken = std::mem::take(p);
            *p = taken.with(label, Kind::Reference, grid(value));
        }
    }
    let mut figure = Figure::new(fig, "paper 000 Figs. 7, 8, A.6, A.7, A.8", "Relaxed amorphous samples, Table 4 material (nu = 0.15), uncalibrated closed-form parameters, against d0.");
    figure.panels = panels;
    let html = format!(
        "<p>Samples L x L x 3 d0 with L = {} d0 (the paper: 100 d0), one seed ({seed}), d in [0.75, 1.25] d0, \
         relaxed as in section 3.2. Known differences, each investigated in docs/patch-tests.md:</p>\n<ul>\n\
         <li>{NU_NOTE}</li>\n<li>{STRENGTH_NOTE}</li>\n<li>{VF_NOTE}</li>\n</ul>\n",
        sig(z.amorphous_l, 3)
    );
    Ok(SectionOutput {
        claims,
        figures: vec![figure],
        html,
        provenance: vec![("seeds".into(), format!("amorphous samples: {seed}"))],
    })
}

const NU_NOTE: &str = "nu stays at the affine value of eqs 15-16 (0.156-0.165), not the paper's 0.20: no protocol variation moves it there; the paper's samples would need about half our effective tangential stiffness.";
const STRENGTH_NOTE: &str = "Strengths are reduced by the pre-stretched pairs of a relaxed packing, as the paper explains, but less than its 50 % / 56 %, which only packings with holes reach here; calibration replaces these figures (DESIGN.md section 8).";
const VF_NOTE: &str = "Below d_c, delta_f = 4 gamma / sigma_N is a longer relative range, so the packing is denser (vf 0.86 at 0.6 d_c); the paper gives no number.";
