//! From MD to DEM (paper profile): the MD silica card of the `md-silica` section (LAMMPS,
//! SiO.1990.vashishta) calibrated by the recipe of `cgdem pipeline --material CARD`
//! ([`CalibrationConfig::si_card`]: five samples 12 d0 thick per evaluation, d0 = 3 nm, s = 1/2),
//! verified on three samples no evaluation saw (issue 16's MD line: E, nu, sigma_N, sigma_T within
//! 5 % in the mean and 10 % per sample, the packing holding under shear), then sheared in the ridge
//! junction of paper 000 section 4 at d0 = 3 nm beside d* of eq 22 from the MD card. The calibration
//! takes about 45 minutes on 2 cores (docs/calibration.md, "The MD card on five 12 d0 samples"), so
//! the quick profile only says how to run it.

use std::path::Path;

use calibrate::{CalibrationConfig, MaterialSource, Units, Verification};
use dem::jobs::JobCache;
use dem::material::ForceLaw;
use dem::scenario::junction::JunctionConfig;
use md_bridge::card::SiMaterial;
use serde::{Deserialize, Serialize};

use super::calibration::{calibrate_case, Case as CalibrationCase, Outcome as Calibration};
use super::junction::debris_fraction;
use super::md::{provenance, silica, silica_result};
use crate::report::claim::sig;
use crate::report::{
    Claim, Context, Figure, Kind, Panel, Profile, Section, SectionOutput, Tolerance,
};
use crate::wear::junction::{run_junction, JunctionSummary};
use crate::{Result, ValidationError};

/// Bumped when the runs' code changes what they give (retires cached results).
const VERSION: u32 = 1;

pub const SECTION: Section = Section {
    id: "md-chain",
    title: "From MD to DEM: the MD silica card calibrated, verified and sheared in the junction",
    run,
};

/// Junction diameters (nm) at d0 = 3 nm: from well below eq 22's d* of the MD card (17.7 nm for the
/// documented card) to beyond it, the sizes of `configs/junction-md-silica-3nm-D*.toml`.
const DIAMETERS: [f64; 4] = [10.0, 15.0, 20.0, 30.0];
const SEEDS: [u64; 3] = [1, 2, 3];
const D0: f64 = 3.0;

/// The calibration and the card it wrote.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct Calibrated {
    outcome: Calibration,
    card: String,
}

/// A junction run, keyed by what decides the card's model: the MD material and the calibrated
/// multipliers (not the card's text, whose provenance records the wall time of the process that wrote
/// it).
#[derive(Debug, Clone, PartialEq, Serialize)]
struct RunCase {
    version: u32,
    material: SiMaterial,
    multipliers: [f64; 5],
    junction: JunctionConfig,
}

fn run(ctx: &Context) -> Result<SectionOutput> {
    if ctx.profile == Profile::Quick {
        return Ok(SectionOutput {
            claims: vec![],
            figures: vec![],
            html: "<p>Runs in the paper profile only (about an hour on 2 cores: the 648-atom MD \
                   card, its calibration on five 12 d0 samples per evaluation, twelve junction runs): \
                   <code>cgdem report --profile paper --only md-chain</code>. The same chain by hand: \
                   <code>cgdem md silica --np 2</code>, <code>cgdem pipeline --material CARD</code>, \
                   <code>cgdem junction configs/junction-md-silica-3nm-D20.toml</code> \
                   (docs/calibration.md, docs/junction.md).</p>\n"
                .into(),
            provenance: vec![],
        });
    }
    let rec = silica(ctx)?;
    let material = silica_result(&rec)?.material().ok_or_else(|| {
        ValidationError::Report(
            "the MD silica job measured no strengths or no surface energy".into(),
        )
    })?;
    let case = CalibrationCase {
        version: VERSION,
        config: CalibrationConfig::si_card(material.clone())?,
    };
    let cal = ctx
        .jobs(
            "MD card calibration",
            std::slice::from_ref(&case),
            |c, dir, par| {
                let outcome = calibrate_case(c, dir, par)?;
                let path = dir.join("card.toml");
                let card =
                    std::fs::read_to_string(&path).map_err(|e| ValidationError::io(&path, e))?;
                Ok(Calibrated { outcome, card })
            },
        )?
        .pop()
        .ok_or_else(|| ValidationError::Report("MD card calibration: no result".into()))?;
    let v = cal.outcome.verification.as_ref().ok_or_else(|| {
        ValidationError::Report("the calibrated MD card has no verification".into())
    })?;
    // The card as a file, which the junction's material source reads.
    let card_dir = ctx.cache.root().join("md-chain");
    std::fs::create_dir_all(&card_dir).map_err(|e| ValidationError::io(&card_dir, e))?;
    let card_path = card_dir.join("card.toml");
    std::fs::write(&card_path, &cal.card).map_err(|e| ValidationError::io(&card_path, e))?;
    let resolved = MaterialSource {
        card: Some(card_path),
        ..MaterialSource::default()
    }
    .resolve(Path::new("."), Units::Nano, ForceLaw::Cohesive)?;
    let samples = JobCache::new(ctx.cache.root().join("md-chain-samples"));
    let cases: Vec<RunCase> = DIAMETERS
        .iter()
        .flat_map(|&d| SEEDS.iter().map(move |&seed| (d, seed)))
        .map(|(diameter, seed)| RunCase {
            version: VERSION,
            material: material.clone(),
            multipliers: cal.outcome.multipliers,
            junction: JunctionConfig {
                diameter,
                d0: D0,
                seed,
                dump_frames: 0,
                ..JunctionConfig::default()
            },
        })
        .collect();
    let runs: Vec<JunctionSummary> = ctx.jobs("MD card junction runs", &cases, |c, dir, par| {
        run_junction(&c.junction, &resolved, &samples, dir, par, &mut |_, _| {})
    })?;
    // Eq 22 from the MD card's own properties, in nm.
    let dstar = material.length_scales().d_star * 1e9;
    let fractions = wear_fractions(&runs);
    Ok(SectionOutput {
        claims: claims(v, &cal.outcome.status, &fractions, dstar),
        figures: vec![figure(&fractions, dstar)],
        html: page(&material, &cal.outcome, v, &runs, dstar),
        provenance: [(
            "MD chain".to_string(),
            "MD silica card (the paper profile's md-silica job) -> cgdem pipeline's SI recipe -> \
             junction at d0 = 3 nm"
                .to_string(),
        )]
        .into_iter()
        .chain(provenance(&rec))
        .collect(),
    })
}

/// (D, fraction of the seeds that detached a wear particle), in the order of [`DIAMETERS`].
fn wear_fractions(runs: &[JunctionSummary]) -> Vec<(f64, f64)> {
    DIAMETERS
        .iter()
        .filter_map(|&d| debris_fraction(runs, D0, d).map(|f| (d, f)))
        .collect()
}

fn claims(v: &Verification, status: &str, fractions: &[(f64, f64)], dstar: f64) -> Vec<Claim> {
    let mut c = vec![Claim::new(
        "workbench",
        "MD chain",
        "the calibration of the MD card converged (1 = yes)",
        1.0,
        if status == "Converged" { 1.0 } else { 0.0 },
        Tolerance::Absolute(0.0),
    )
    .note(format!(
        "Status {status}; issue 16 asks for convergence, not a budget stop."
    ))];
    for t in calibrate::Target::ALL {
        let check = v.get(t);
        if t == calibrate::Target::SurfaceEnergy {
            c.push(
                Claim::new(
                    "workbench",
                    "MD chain",
                    "surface energy on fresh samples / the MD card's gamma",
                    1.0,
                    check.mean / check.target,
                    Tolerance::Info,
                )
                .note(
                    "Measured, not a target: paper 000's law cannot meet 2 gamma together with \
                     sigma_N (docs/calibration.md); d* of eq 22 scales with it.",
                ),
            );
            continue;
        }
        c.push(
            Claim::new(
                "workbench",
                "MD chain",
                format!(
                    "{}: verified mean error on fresh samples (relative)",
                    t.name()
                ),
                0.0,
                check.mean_error(),
                Tolerance::Absolute(0.05),
            )
            .note(
                "Issue 16: within 5 % of the MD card in the mean over samples no evaluation saw.",
            ),
        );
        c.push(
            Claim::new(
                "workbench",
                "MD chain",
                format!("{}: largest error of one fresh sample (relative)", t.name()),
                0.10,
                check.spread,
                Tolerance::Below,
            )
            .note("Issue 16: within 10 % for each sample."),
        );
    }
    if let Some(k) = &v.compaction {
        c.push(
            Claim::new(
                "workbench",
                "MD chain",
                format!(
                    "largest compaction under shear ({} E, strain {}) of a fresh sample",
                    k.pressure, k.strain
                ),
                k.limit,
                k.largest(),
                Tolerance::Below,
            )
            .note("A card whose packing collapses when it flows cannot be used in the junction."),
        );
    }
    for &(d, f) in fractions {
        c.push(
            Claim::new(
                "000",
                "eq 22",
                format!(
                    "MD card, D = {} nm (D / d* = {}): fraction of seeds detaching a wear particle",
                    d,
                    sig(d / dstar, 3)
                ),
                if d > dstar { 1.0 } else { 0.0 },
                f,
                Tolerance::Info,
            )
            .note(format!(
                "Eq 22 reads wear above d* and plastic smoothing below it; shown, not judged: d* \
                 here is the MD card's, while the calibrated card's own properties (its surface \
                 energy {} times the MD gamma) give {} nm (docs/junction.md).",
                sig(v.surface_energy.mean / v.surface_energy.target, 2),
                sig(v.dstar, 3)
            )),
        );
    }
    c
}

fn figure(fractions: &[(f64, f64)], dstar: f64) -> Figure {
    let x_end = fractions.iter().map(|p| p.0).fold(dstar, f64::max) * 1.1;
    let panel = Panel::new(
        "junction outcome with the calibrated MD card, d0 = 3 nm",
        "junction diameter D (nm)",
        "fraction of seeds detaching a wear particle (-)",
    )
    .with(
        "DEM, MD card calibrated",
        Kind::SimulationMarks,
        fractions.to_vec(),
    )
    .with(
        "eq 22 from the MD card",
        Kind::Reference,
        vec![(0.0, 0.0), (dstar, 0.0), (dstar, 1.0), (x_end, 1.0)],
    );
    Figure::new(
        "md-chain-junction",
        "paper 000 section 4, eq 22 (no figure for this material)",
        "Fraction of three seeds whose ridge junction detached a wear particle, with the DEM card \
         calibrated on the MD silica card; dashed: eq 22's step at d* from the MD card's E, nu, \
         sigma_T and gamma.",
    )
    .panel(panel)
}

fn page(
    m: &SiMaterial,
    o: &Calibration,
    v: &Verification,
    runs: &[JunctionSummary],
    dstar: f64,
) -> String {
    let s = o.multipliers;
    let mut rows = String::new();
    for r in runs {
        rows += &format!(
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
            r.diameter,
            r.seed,
            r.outcome,
            r.particles,
            sig(r.run_seconds, 3)
        );
    }
    format!(
        "<p>The MD silica card (E {} GPa, nu {}, sigma_N {} GPa, sigma_T {} GPa, gamma {} J/m^2) \
         calibrated by <code>cgdem pipeline --material CARD</code>'s recipe (amorphous, d0 = 3 nm, \
         five samples 12 d0 thick per evaluation): status {}, {} iterations, {} evaluations; \
         multipliers k_N {}, k_T {}, delta_e {}, delta_f {}, F_mT {}. Verified on seeds {:?} (the \
         last twice as thick). d* of eq 22: {} nm from the MD card, {} nm from the verified \
         properties.</p>\n<table>\n<tr><th>D (nm)</th><th>seed</th><th>outcome</th>\
         <th>particles</th><th>run (s)</th></tr>\n{rows}</table>\n",
        sig(m.young_modulus / 1e9, 3),
        sig(m.poisson_ratio, 3),
        sig(m.tensile_strength / 1e9, 3),
        sig(m.shear_strength / 1e9, 3),
        sig(m.surface_energy, 3),
        o.status,
        o.iterations,
        o.evaluations,
        sig(s[0], 4),
        sig(s[1], 4),
        sig(s[2], 4),
        sig(s[3], 4),
        sig(s[4], 4),
        v.seeds,
        sig(dstar, 3),
        sig(v.dstar, 3),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::Verdict;
    use calibrate::verification::CompactionCheck;
    use calibrate::Check;
    use dem::sample::SampleSpec;
    use wear::Outcome;

    fn check(target: f64, values: &[f64]) -> Check {
        let mean = values.iter().sum::<f64>() / values.len() as f64;
        let spread = values
            .iter()
            .map(|v| (v - target).abs() / target)
            .fold(0.0, f64::max);
        Check {
            target,
            mean,
            spread,
            values: values.to_vec(),
        }
    }

    /// A verification within the lines but for the shear strength given.
    fn verification(shear: &[f64], compaction: &[f64]) -> Verification {
        Verification {
            seeds: vec![101, 102, 103],
            dstar: 225.0,
            dstar_target: 25.0,
            recipe: SampleSpec::Hcp {
                d0_over_dc: 0.6,
                l_over_d0: 8.0,
                w_over_d0: 3.0,
            },
            samples: vec![],
            young_modulus: check(100.0, &[101.0, 99.0, 102.8]),
            poisson_ratio: check(0.23, &[0.23, 0.229, 0.231]),
            tensile_strength: check(16.0, &[16.0, 16.1, 15.9]),
            shear_strength: check(10.0, shear),
            surface_energy: check(1.36, &[11.0, 11.5, 11.3]),
            compaction: Some(CompactionCheck {
                pressure: 0.01,
                strain: 1.0,
                limit: 0.05,
                values: compaction.to_vec(),
                collapsed: compaction.iter().filter(|&&c| c > 0.05).count(),
            }),
        }
    }

    fn verdicts(c: &[Claim], starts: &str) -> Vec<Verdict> {
        c.iter()
            .filter(|k| k.quantity.starts_with(starts))
            .map(|k| k.verdict())
            .collect()
    }

    #[test]
    fn the_chain_judges_issue_16s_md_line_and_shows_the_junction_beside_eq_22() {
        let ok = claims(
            &verification(&[9.8, 9.5, 10.2], &[0.041, 0.049, 0.044]),
            "Converged",
            &[(10.0, 0.0), (20.0, 1.0 / 3.0), (30.0, 0.0)],
            17.7,
        );
        assert!(ok
            .iter()
            .filter(|k| k.tolerance != Tolerance::Info)
            .all(|k| k.verdict() == Verdict::Pass));
        // Eq 22's reading: plastic below d*, wear above; shown, not judged.
        let junction: Vec<_> = ok.iter().filter(|k| k.item == "eq 22").collect();
        assert_eq!(junction.len(), 3);
        assert_eq!(
            junction.iter().map(|k| k.reference).collect::<Vec<_>>(),
            [0.0, 1.0, 1.0]
        );
        assert!(junction.iter().all(|k| k.verdict() == Verdict::Info));

        // A 6 % low shear strength fails the mean; one sample 12 % high fails the spread; a stalled
        // calibration and a collapsing packing fail their lines.
        let bad = claims(
            &verification(&[9.4, 9.4, 9.4], &[0.041, 0.06, 0.044]),
            "Stalled",
            &[],
            17.7,
        );
        assert_eq!(
            verdicts(&bad, "shear_strength: verified mean"),
            [Verdict::Fail]
        );
        assert_eq!(
            verdicts(&bad, "young_modulus: verified mean"),
            [Verdict::Pass]
        );
        assert_eq!(verdicts(&bad, "the calibration"), [Verdict::Fail]);
        assert_eq!(verdicts(&bad, "largest compaction"), [Verdict::Fail]);
        let spread = claims(
            &verification(&[11.2, 9.6, 9.5], &[0.04]),
            "Converged",
            &[],
            17.7,
        );
        assert_eq!(
            verdicts(&spread, "shear_strength: largest error"),
            [Verdict::Fail]
        );
        assert_eq!(
            verdicts(&spread, "shear_strength: verified mean"),
            [Verdict::Pass]
        );
    }

    #[test]
    fn wear_fractions_count_the_seeds_that_detached_at_each_size() {
        let run = |d: f64, seed: u64, outcome: Outcome| JunctionSummary {
            diameter: d,
            d0: D0,
            seed,
            outcome,
            turn: 0.0,
            rigidity: 0.0,
            force_late_over_peak: None,
            detachment: None,
            particles: 0,
            junction_members: 0,
            steps: 0,
            dt: 0.0,
            slide: 0.0,
            run_seconds: 0.0,
            relax_seconds: 0.0,
            wall_descent_over_height: None,
        };
        let runs = [
            run(10.0, 1, Outcome::PlasticSmoothing),
            run(20.0, 1, Outcome::WearParticle),
            run(20.0, 2, Outcome::PlasticSmoothing),
            run(20.0, 3, Outcome::PlasticSmoothing),
            run(30.0, 1, Outcome::WearParticle),
        ];
        assert_eq!(
            wear_fractions(&runs),
            [(10.0, 0.0), (20.0, 1.0 / 3.0), (30.0, 1.0)]
        );
    }
}
