//! What the comparison concludes from the runs, as pure functions of their results (so tests can
//! feed synthetic probes): the brackets in sigma, whether they overlap and how far their centres
//! lie apart, the MD/DEM cost ratio for the same junction, both materials' properties side by side,
//! and the output files (written by `outputs`).
//!
//! Brackets are (lower, upper] as [`wear::dstar::Bracket`] gives them: two overlap when each lower
//! bound lies below the other's upper bound. A centre is (lower + upper) / 2.

mod outputs;
#[cfg(test)]
mod tests;

use std::path::Path;

use md_bridge::model::ModelResult;
use serde::{Deserialize, Serialize};
use wear::Outcome;

use super::md::{MdRun, MdSearch};
use super::scan::Detachment;
use crate::wear::dstar::{DstarResult, Measured};
pub use outputs::{d50_words, figure_rows, markdown, probability_series, write_outputs};

/// A bracket (lower, upper], either end possibly missing.
pub type Span = [Option<f64>; 2];

/// (lower + upper) / 2 when both ends exist.
pub fn centre(b: &Span) -> Option<f64> {
    match b {
        [Some(l), Some(u)] => Some(0.5 * (l + u)),
        _ => None,
    }
}

/// (upper - lower) / centre when both ends exist.
pub fn relative_width(b: &Span) -> Option<f64> {
    match b {
        [Some(l), Some(u)] => Some((u - l) / (0.5 * (l + u))),
        _ => None,
    }
}

/// Whether (l1, u1] and (l2, u2] share a size; None when an end is missing.
pub fn overlap(a: &Span, b: &Span) -> Option<bool> {
    match (a, b) {
        ([Some(l1), Some(u1)], [Some(l2), Some(u2)]) => Some(l1 < u2 && l2 < u1),
        _ => None,
    }
}

/// One DEM run, lengths in sigma.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DemRun {
    pub diameter: f64,
    pub seed: u64,
    pub outcome: Outcome,
    pub turn: f64,
    pub rigidity: f64,
    pub particles: usize,
    /// Wall time of the run, and of relaxing its box (s).
    pub run_seconds: f64,
    pub relax_seconds: f64,
}

/// One DEM discretisation's search, lengths in sigma.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DemEntry {
    /// The dstar config and its output folder.
    pub config: String,
    pub out: String,
    /// Particle diameter d0 (sigma).
    pub d0: f64,
    /// [lower, upper] (sigma).
    pub bracket: Span,
    pub relative_width: Option<f64>,
    pub converged: bool,
    pub reason: String,
    pub split: Vec<f64>,
    pub non_monotonic: Vec<f64>,
    /// Eq 22 from the properties the DEM material has on the search's recipe (sigma).
    pub dstar_eq22_measured: Option<f64>,
    /// Those properties, in the DEM engine's units.
    pub measured: Option<Measured>,
    pub runs: Vec<DemRun>,
    /// Every run and relaxation of the search (s).
    pub cost_seconds: f64,
    /// The scan's runs and the fit of P(wear | D) (sigma); None without `[scan]`.
    #[serde(default)]
    pub detachment: Option<Detachment>,
}

impl DemEntry {
    /// Converts a dstar result (lengths times `to_sigma`).
    pub fn new(config: &Path, out: &Path, to_sigma: f64, r: DstarResult) -> Self {
        let s = |v: f64| v * to_sigma;
        let b = [r.bracket[0].map(s), r.bracket[1].map(s)];
        DemEntry {
            config: config.display().to_string(),
            out: out.display().to_string(),
            d0: s(r.d0),
            relative_width: relative_width(&b),
            bracket: b,
            converged: r.converged,
            reason: r.reason,
            split: r.split.iter().copied().map(s).collect(),
            non_monotonic: r.non_monotonic.iter().copied().map(s).collect(),
            dstar_eq22_measured: r.dstar_eq22_measured.map(s),
            measured: r.measured,
            runs: r
                .runs
                .iter()
                .map(|j| DemRun {
                    diameter: s(j.diameter),
                    seed: j.seed,
                    outcome: j.outcome,
                    turn: j.turn,
                    rigidity: j.rigidity,
                    particles: j.particles,
                    run_seconds: j.run_seconds,
                    relax_seconds: j.relax_seconds,
                })
                .collect(),
            cost_seconds: r.cost_seconds,
            detachment: None,
        }
    }
}

/// A DEM discretisation's D50 against the MD one.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct D50Ratio {
    pub d0: f64,
    /// DEM D50 / MD D50 (None when either side has no D50).
    pub ratio: Option<f64>,
    /// [DEM lower / MD upper, DEM upper / MD lower] from the two intervals' ends: a conservative
    /// range (the sides are independent), None where an end is open.
    pub range: [Option<f64>; 2],
    /// DEM D50 / d0: the size in particles (a d*-independent-of-d0 DEM keeps D50 fixed in sigma,
    /// one that scales with d0 keeps this fixed).
    pub d50_over_d0: Option<f64>,
}

/// The D50 ratios of every DEM discretisation with a fit against the MD fit.
pub fn d50_ratios(md: Option<&Detachment>, dem: &[DemEntry]) -> Vec<D50Ratio> {
    dem.iter()
        .filter_map(|e| {
            let f = &e.detachment.as_ref()?.fit;
            let m = md.map(|m| &m.fit);
            let div = |a: Option<f64>, b: Option<f64>| a.zip(b).map(|(a, b)| a / b);
            Some(D50Ratio {
                d0: e.d0,
                ratio: div(f.d50, m.and_then(|m| m.d50)),
                range: [
                    div(f.interval[0], m.and_then(|m| m.interval[1])),
                    div(f.interval[1], m.and_then(|m| m.interval[0])),
                ],
                d50_over_d0: f.d50.map(|d| d / e.d0),
            })
        })
        .collect()
}

/// How one DEM discretisation's bracket stands against the MD one.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Agreement {
    pub d0: f64,
    /// The brackets share a size.
    pub overlap: Option<bool>,
    /// DEM centre / MD centre.
    pub centre_ratio: Option<f64>,
    /// |DEM centre - MD centre| / MD centre below 0.25 (issue 17's tolerance).
    pub centres_within_25_percent: Option<bool>,
}

/// MD against DEM cost for the same junction (same D): seconds of one run each.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CostRatio {
    /// D (sigma) and the DEM discretisation.
    pub diameter: f64,
    pub d0: f64,
    /// Mean wall time of the MD seeds at D, and of the DEM seeds at D (run, without relaxation).
    pub md_seconds: f64,
    pub dem_seconds: f64,
    /// md_seconds / dem_seconds.
    pub ratio: f64,
    /// "same D" when both sides ran D, "DEM interpolated" when the DEM time is interpolated
    /// (log-log, between the DEM sizes around D).
    pub how: String,
}

/// Mean run time per size, sorted by size.
fn mean_by_size(points: impl Iterator<Item = (f64, f64)>) -> Vec<(f64, f64)> {
    let mut v: Vec<(f64, f64, usize)> = Vec::new();
    for (d, t) in points {
        match v.iter_mut().find(|e| e.0 == d) {
            Some(e) => {
                e.1 += t;
                e.2 += 1;
            }
            None => v.push((d, t, 1)),
        }
    }
    v.sort_by(|a, b| a.0.total_cmp(&b.0));
    v.into_iter().map(|(d, t, n)| (d, t / n as f64)).collect()
}

/// The MD/DEM cost ratio at every MD size inside the DEM entry's range of sizes.
pub fn cost_ratios(md: &[MdRun], dem: &DemEntry) -> Vec<CostRatio> {
    let m = mean_by_size(md.iter().map(|r| (r.diameter, r.wall_seconds)));
    let d = mean_by_size(dem.runs.iter().map(|r| (r.diameter, r.run_seconds)));
    let same = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(1.0);
    m.iter()
        .filter_map(|&(size, md_s)| {
            let (dem_s, how) = if let Some(&(_, t)) = d.iter().find(|p| same(p.0, size)) {
                (t, "same D")
            } else {
                let k = d.windows(2).find(|w| w[0].0 < size && size < w[1].0)?;
                let ((d1, t1), (d2, t2)) = (k[0], k[1]);
                if t1 <= 0.0 || t2 <= 0.0 {
                    return None;
                }
                let f = (size / d1).ln() / (d2 / d1).ln();
                ((t1.ln() + f * (t2 / t1).ln()).exp(), "DEM interpolated")
            };
            (dem_s > 0.0).then(|| CostRatio {
                diameter: size,
                d0: dem.d0,
                md_seconds: md_s,
                dem_seconds: dem_s,
                ratio: md_s / dem_s,
                how: how.into(),
            })
        })
        .collect()
}

/// One measured property of both materials.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PropertyRow {
    pub property: String,
    /// The MD card's value and unit (2D LJ: stresses in epsilon/sigma^2, gamma in epsilon/sigma).
    pub md: f64,
    pub md_unit: String,
    /// Each DEM discretisation's measured value (engine units of its search; None: not measured).
    pub dem: Vec<Option<f64>>,
}

/// Both materials' properties side by side (DEM columns in the order of `dem`).
pub fn property_rows(card: &ModelResult, dem: &[DemEntry]) -> Vec<PropertyRow> {
    type Get = fn(&Measured) -> Option<f64>;
    let rows: [(&str, f64, &str, Get); 5] = [
        (
            "Young's modulus E",
            card.young_modulus,
            "epsilon/sigma^2",
            |m| Some(m.young_modulus),
        ),
        ("Poisson ratio nu", card.poisson_ratio, "-", |m| {
            Some(m.poisson_ratio)
        }),
        (
            "tensile strength sigma_N",
            card.tension.peak_stress,
            "epsilon/sigma^2",
            |m| Some(m.tensile_strength),
        ),
        (
            "shear strength sigma_T",
            card.shear.peak_stress,
            "epsilon/sigma^2",
            |m| Some(m.shear_strength),
        ),
        (
            "surface energy gamma",
            card.surface_energy,
            "epsilon/sigma",
            |m| m.surface_energy,
        ),
    ];
    let mut out: Vec<PropertyRow> = rows
        .iter()
        .map(|(name, md, unit, get)| PropertyRow {
            property: name.to_string(),
            md: *md,
            md_unit: unit.to_string(),
            dem: dem
                .iter()
                .map(|e| e.measured.as_ref().and_then(get))
                .collect(),
        })
        .collect();
    out.push(PropertyRow {
        property: "d* of eq 22".into(),
        md: card.d_star,
        md_unit: "sigma".into(),
        dem: dem.iter().map(|e| e.dstar_eq22_measured).collect(),
    });
    out
}

/// What `compare.json` holds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CompareResult {
    /// MD d* bracket [lower, upper] (sigma).
    pub md_bracket: Span,
    pub md_relative_width: Option<f64>,
    /// Seeds at each MD bound (issue 17 asks for at least two).
    pub md_seeds_at_bounds: [usize; 2],
    /// d* of eq 22 from the MD model card (sigma).
    pub dstar_theory: f64,
    /// The MD search: every run with its verdict, evidence and wall time.
    pub md: MdSearch,
    /// One DEM search per discretisation.
    pub dem: Vec<DemEntry>,
    /// Each DEM bracket against the MD one.
    pub agreement: Vec<Agreement>,
    /// Whether every pair of DEM brackets overlaps (same d* whatever d0, within the brackets).
    pub dem_brackets_overlap: Option<bool>,
    /// MD/DEM cost for the same junction.
    pub cost_ratios: Vec<CostRatio>,
    /// Wall time of the MD card, the MD search and each DEM search (s).
    pub md_card_seconds: f64,
    pub md_cost_seconds: f64,
    pub dem_cost_seconds: Vec<f64>,
    /// The model card as measured, and both materials side by side.
    pub card: ModelResult,
    pub properties: Vec<PropertyRow>,
    /// The MD scan and its fit of P(wear | D) (None without `[scan]`); each DEM one is in `dem[i]`.
    #[serde(default)]
    pub md_detachment: Option<Detachment>,
    /// Each DEM D50 against the MD D50.
    #[serde(default)]
    pub d50_ratios: Vec<D50Ratio>,
}

impl CompareResult {
    pub fn new(
        card: &ModelResult,
        card_seconds: f64,
        md: MdSearch,
        md_detachment: Option<Detachment>,
        dem: Vec<DemEntry>,
    ) -> Self {
        let at =
            |v: Option<f64>| v.map_or(0, |d| md.runs.iter().filter(|r| r.diameter == d).count());
        let agreement = dem
            .iter()
            .map(|e| {
                let ratio = centre(&e.bracket)
                    .zip(centre(&md.bracket))
                    .map(|(a, b)| a / b);
                Agreement {
                    d0: e.d0,
                    overlap: overlap(&e.bracket, &md.bracket),
                    centre_ratio: ratio,
                    centres_within_25_percent: ratio.map(|r| (r - 1.0).abs() < 0.25),
                }
            })
            .collect();
        let mut pairs = Vec::new();
        for (i, a) in dem.iter().enumerate() {
            for b in &dem[i + 1..] {
                pairs.push(overlap(&a.bracket, &b.bracket));
            }
        }
        let dem_brackets_overlap = if pairs.is_empty() {
            None
        } else {
            pairs
                .into_iter()
                .try_fold(true, |acc, p| p.map(|p| acc && p))
        };
        CompareResult {
            md_bracket: md.bracket,
            md_relative_width: relative_width(&md.bracket),
            md_seeds_at_bounds: [at(md.bracket[0]), at(md.bracket[1])],
            dstar_theory: card.d_star,
            agreement,
            dem_brackets_overlap,
            cost_ratios: dem.iter().flat_map(|e| cost_ratios(&md.runs, e)).collect(),
            md_card_seconds: card_seconds,
            md_cost_seconds: md.cost_seconds,
            dem_cost_seconds: dem.iter().map(|e| e.cost_seconds).collect(),
            properties: property_rows(card, &dem),
            d50_ratios: d50_ratios(md_detachment.as_ref(), &dem),
            md_detachment,
            card: card.clone(),
            md,
            dem,
        }
    }
}
