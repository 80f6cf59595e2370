//! What the comparison concludes from the runs, as pure functions of their results (so tests can
//! feed synthetic probes): the brackets in sigma, whether they overlap and how far their centres
//! lie apart, the MD/DEM cost ratio for the same junction, both materials' properties side by side,
//! and the output files.
//!
//! Brackets are (lower, upper] as [`wear::dstar::Bracket`] gives them: two overlap when each lower
//! bound lies below the other's upper bound. A centre is (lower + upper) / 2.

use std::fmt::Write as _;
use std::path::Path;

use dem::io::checkpoint::write_atomic;
use md_bridge::model::ModelResult;
use serde::{Deserialize, Serialize};
use wear::detachment::FitStatus;
use wear::Outcome;

use super::md::{MdRun, MdSearch};
use super::scan::Detachment;
use crate::error::{Result, ValidationError};
use crate::figures::detachment::{draw_detachment, ProbabilitySeries};
use crate::figures::dstar::{draw_outcomes, OutcomeRow};
use crate::wear::dstar::{DstarResult, Measured};

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

fn fmt_span(b: &Span) -> String {
    let f = |v: Option<f64>| v.map_or("-".to_string(), |x| format!("{x}"));
    format!("({}, {}]", f(b[0]), f(b[1]))
}

fn outcome_name(o: Outcome) -> &'static str {
    match o {
        Outcome::PlasticSmoothing => "plastic",
        Outcome::WearParticle => "debris",
    }
}

/// The markdown fragment: brackets, properties side by side, every run.
pub fn markdown(r: &CompareResult) -> String {
    let mut s = String::new();
    let g = |v: Option<f64>| v.map_or("-".to_string(), |x| format!("{x:.3}"));
    let _ = writeln!(
        s,
        "d* of eq 22 from the MD card: {:.1} sigma\n\n| side | d0 (sigma) | bracket (sigma) | width | D / d*_theory | runs | cost (s) |\n| --- | --- | --- | --- | --- | --- | --- |",
        r.dstar_theory
    );
    let over = |b: &Span| {
        let f =
            |v: Option<f64>| v.map_or("-".to_string(), |x| format!("{:.2}", x / r.dstar_theory));
        format!("({}, {}]", f(b[0]), f(b[1]))
    };
    let _ = writeln!(
        s,
        "| MD | atoms | {} | {} | {} | {} | {:.0} |",
        fmt_span(&r.md_bracket),
        g(r.md_relative_width),
        over(&r.md_bracket),
        r.md.runs.len(),
        r.md_cost_seconds
    );
    for e in &r.dem {
        let _ = writeln!(
            s,
            "| DEM | {} | {} | {} | {} | {} | {:.0} |",
            e.d0,
            fmt_span(&e.bracket),
            g(e.relative_width),
            over(&e.bracket),
            e.runs.len(),
            e.cost_seconds
        );
    }
    if r.md_detachment.is_some() || r.dem.iter().any(|e| e.detachment.is_some()) {
        s.push_str(&detachment_markdown(r));
    }
    let _ = write!(s, "\n| property | MD card | unit |");
    for e in &r.dem {
        let _ = write!(s, " DEM d0 = {} |", e.d0);
    }
    let _ = write!(s, "\n| --- | --- | --- |");
    for _ in &r.dem {
        s.push_str(" --- |");
    }
    for p in &r.properties {
        let _ = write!(s, "\n| {} | {:.4} | {} |", p.property, p.md, p.md_unit);
        for v in &p.dem {
            let _ = write!(s, " {} |", g(*v));
        }
    }
    s.push_str("\n\nMD runs (1 process each):\n\n| D (sigma) | seed | lattice offset | verdict | turn (rad) | rigidity | debris fraction | atoms | wall (s) |\n| --- | --- | --- | --- | --- | --- | --- | --- | --- |\n");
    for m in &r.md.runs {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {:.2} | {:.2} | {} | {} | {:.0} |",
            m.diameter,
            m.seed,
            m.lattice_offset,
            outcome_name(m.outcome),
            m.turn,
            m.rigidity,
            g(m.debris_fraction),
            m.atoms,
            m.wall_seconds
        );
    }
    for e in &r.dem {
        let _ = write!(s, "\nDEM runs, d0 = {} sigma:\n\n| D (sigma) | seed | verdict | turn (rad) | rigidity | particles | run (s) | relax (s) |\n| --- | --- | --- | --- | --- | --- | --- | --- |\n", e.d0);
        for m in &e.runs {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {:.2} | {:.2} | {} | {:.0} | {:.0} |",
                m.diameter,
                m.seed,
                outcome_name(m.outcome),
                m.turn,
                m.rigidity,
                m.particles,
                m.run_seconds,
                m.relax_seconds
            );
        }
    }
    if !r.cost_ratios.is_empty() {
        s.push_str("\nMD / DEM cost for the same junction:\n\n| D (sigma) | DEM d0 | MD (s) | DEM (s) | MD / DEM | how |\n| --- | --- | --- | --- | --- | --- |\n");
        for c in &r.cost_ratios {
            let _ = writeln!(
                s,
                "| {} | {} | {:.1} | {:.1} | {:.3} | {} |",
                c.diameter, c.d0, c.md_seconds, c.dem_seconds, c.ratio, c.how
            );
        }
    }
    s
}

/// The scan's table: per side the runs, D50 with its interval, the slope, D50 / d0 and the ratio to
/// MD's D50, then the wear fraction at every size.
fn detachment_markdown(r: &CompareResult) -> String {
    let mut s = String::new();
    let g = |v: Option<f64>, digits: usize| v.map_or("-".to_string(), |x| format!("{x:.digits$}"));
    let _ = writeln!(
        s,
        "\nDetachment probability: P(wear | D) = 1 / (1 + exp(-k ln(D / D50))) fitted by maximum \
         likelihood to every run of a side (search and scan); interval: profile likelihood (open: \
         reaches a factor 2 beyond the sizes run).\n\n| side | d0 (sigma) | runs (scan) | scan seeds | \
         D50 (sigma) | interval (sigma) | k | D50 / d0 | DEM D50 / MD D50 (range) | scan cost (s) |\n\
         | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
    );
    let row = |s: &mut String, side: &str, d0: String, d: &Detachment, ratio: String| {
        let f = &d.fit;
        let seeds: Vec<String> = d.seeds.iter().map(|x| x.to_string()).collect();
        let _ = writeln!(
            s,
            "| {side} | {d0} | {} ({}) | {} | {} | ({}, {}) | {}{} | {} | {ratio} | {:.0} |",
            f.runs,
            d.scan_runs,
            seeds.join(", "),
            match f.d50 {
                Some(x) => format!("{x:.2}"),
                None => status_name(f.status).to_string(),
            },
            g(f.interval[0], 2),
            g(f.interval[1], 2),
            g(f.slope, 1),
            if f.slope_at_bound { " (bound)" } else { "" },
            match (f.d50, d0.parse::<f64>()) {
                (Some(x), Ok(d0)) => format!("{:.1}", x / d0),
                _ => "-".into(),
            },
            d.scan_seconds
        );
    };
    if let Some(d) = &r.md_detachment {
        row(&mut s, "MD", "atoms".into(), d, "1".into());
    }
    for e in &r.dem {
        let Some(d) = &e.detachment else { continue };
        let ratio = r
            .d50_ratios
            .iter()
            .find(|q| q.d0 == e.d0)
            .map_or("-".into(), |q| {
                format!(
                    "{} ({}-{})",
                    g(q.ratio, 2),
                    g(q.range[0], 2),
                    g(q.range[1], 2)
                )
            });
        row(&mut s, "DEM", format!("{}", e.d0), d, ratio);
    }
    s.push_str("\nWear runs / runs at each size (sigma):\n\n");
    let fr = |d: &Detachment| {
        d.fractions
            .iter()
            .map(|f| format!("{}: {}/{}", f.diameter, f.wear, f.runs))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let majority = |d: &Detachment| {
        let [lo, hi] = d.majority_bracket;
        let end = |v: Option<f64>| v.map_or("open".to_string(), |x| format!("{x}"));
        format!("; majority of every run: ({}, {}]", end(lo), end(hi))
    };
    if let Some(d) = &r.md_detachment {
        let _ = writeln!(s, "- MD: {}{}", fr(d), majority(d));
    }
    for e in &r.dem {
        if let Some(d) = &e.detachment {
            let _ = writeln!(s, "- DEM d0 = {}: {}{}", e.d0, fr(d), majority(d));
        }
    }
    s
}

/// The outcome map: one row per seed and side (the scan's seeds included), x = D / d*_theory.
pub fn figure_rows(r: &CompareResult) -> Vec<OutcomeRow> {
    let t = r.dstar_theory;
    // Every run of a side: the scan's trials (which hold the search's runs too), else the search's.
    let runs = |det: Option<&Detachment>, search: Vec<(f64, u64, Outcome)>| match det {
        Some(d) => d
            .trials
            .iter()
            .map(|x| (x.diameter, x.seed, x.outcome))
            .collect(),
        None => search,
    };
    let rows_of = |label: &dyn Fn(u64) -> String, all: Vec<(f64, u64, Outcome)>| {
        let mut seeds: Vec<u64> = all.iter().map(|m| m.1).collect();
        seeds.sort_unstable();
        seeds.dedup();
        seeds
            .into_iter()
            .rev()
            .map(|seed| OutcomeRow {
                label: label(seed),
                points: all
                    .iter()
                    .filter(|m| m.1 == seed)
                    .map(|m| (m.0 / t, m.2))
                    .collect(),
            })
            .collect::<Vec<_>>()
    };
    let mut rows = Vec::new();
    for e in r.dem.iter().rev() {
        let all = runs(
            e.detachment.as_ref(),
            e.runs
                .iter()
                .map(|m| (m.diameter, m.seed, m.outcome))
                .collect(),
        );
        rows.extend(rows_of(
            &|seed| format!("DEM d0 = {} sigma, seed {seed}", e.d0),
            all,
        ));
    }
    let all = runs(
        r.md_detachment.as_ref(),
        r.md.runs
            .iter()
            .map(|m| (m.diameter, m.seed, m.outcome))
            .collect(),
    );
    rows.extend(rows_of(&|seed| format!("MD (LAMMPS), seed {seed}"), all));
    rows
}

/// Writes compare.json, compare.md, compare.svg and compare.png into `out`.
pub fn write_outputs(out: &Path, r: &CompareResult) -> Result<()> {
    let path = out.join("compare.json");
    let bytes = serde_json::to_vec_pretty(r).map_err(|e| ValidationError::Config {
        path: path.display().to_string(),
        reason: e.to_string(),
    })?;
    write_atomic(&path, &bytes)?;
    write_atomic(&out.join("compare.md"), markdown(r).as_bytes())?;
    let t = r.dstar_theory;
    let scaled = |b: &Span| [b[0].map(|v| v / t), b[1].map(|v| v / t)];
    let mut brackets = vec![("MD bracket".to_string(), scaled(&r.md_bracket))];
    for e in &r.dem {
        brackets.push((
            format!("DEM bracket, d0 = {} sigma", e.d0),
            scaled(&e.bracket),
        ));
    }
    let refs = vec![(format!("eq 22 from the MD card ({t:.1} sigma)"), 1.0)];
    let rows = figure_rows(r);
    let label = "junction width D / d* of eq 22";
    let series = probability_series(r);
    let p_label = format!("junction width D / d* of eq 22 ({t:.1} sigma)");
    let p_refs = vec![("eq 22 from the MD card".to_string(), 1.0)];
    for ext in ["svg", "png"] {
        draw_detachment(
            &out.join(format!("compare.{ext}")),
            &p_label,
            &series,
            &p_refs,
        )?;
        draw_outcomes(
            &out.join(format!("outcomes.{ext}")),
            label,
            &rows,
            &brackets,
            &refs,
        )?;
    }
    Ok(())
}

/// What a fit says in a few words: "D50 = 24.1 sigma (21.9-26.3)", or why there is none.
pub fn d50_words(d: Option<&Detachment>) -> String {
    let Some(d) = d else {
        return "no scan".into();
    };
    let f = &d.fit;
    let end = |v: Option<f64>, open: &str| v.map_or(open.to_string(), |x| format!("{x:.1}"));
    match (f.status, f.d50) {
        (FitStatus::Fitted | FitStatus::Separated, Some(x)) => format!(
            "D50 = {x:.1} sigma ({:.0} %: {}-{}){}",
            100.0 * f.level,
            end(f.interval[0], "open"),
            end(f.interval[1], "open"),
            if f.slope_at_bound {
                ", slope at its bound"
            } else {
                ""
            }
        ),
        (s, _) => format!("no D50 ({})", status_name(s)),
    }
}

fn status_name(s: FitStatus) -> &'static str {
    match s {
        FitStatus::Fitted => "fitted",
        FitStatus::Separated => "separated outcomes",
        FitStatus::NoRuns => "no runs",
        FitStatus::AllPlastic => "every run plastic: above the sizes run",
        FitStatus::AllWear => "every run detached: below the sizes run",
        FitStatus::NoRise => "the wear fraction does not rise with D",
    }
}

/// The figure's series: MD, then each DEM d0, x = D / d*_theory.
pub fn probability_series(r: &CompareResult) -> Vec<ProbabilitySeries> {
    let t = r.dstar_theory;
    let one = |label: String, runs: Vec<(f64, Outcome)>, det: Option<&Detachment>, b: &Span| {
        let fractions = match det {
            Some(d) => d
                .fractions
                .iter()
                .map(|f| (f.diameter / t, f.runs, f.wear))
                .collect(),
            None => {
                let mut v: Vec<(f64, usize, usize)> = Vec::new();
                for (d, o) in runs {
                    let w = usize::from(o == Outcome::WearParticle);
                    match v.iter_mut().find(|e| e.0 == d / t) {
                        Some(e) => {
                            e.1 += 1;
                            e.2 += w;
                        }
                        None => v.push((d / t, 1, w)),
                    }
                }
                v
            }
        };
        let fit = det.map(|d| &d.fit);
        ProbabilitySeries {
            label: format!(
                "{label}: {}, bracket {}",
                d50_words(det),
                fmt_span(&[b[0], b[1]])
            ),
            fractions,
            curve: fit.and_then(|f| Some((f.d50? / t, f.slope?))),
            interval: fit.map_or([None, None], |f| {
                [f.interval[0].map(|v| v / t), f.interval[1].map(|v| v / t)]
            }),
            bracket: [b[0].map(|v| v / t), b[1].map(|v| v / t)],
        }
    };
    let mut v = vec![one(
        "MD (LAMMPS)".into(),
        r.md.runs.iter().map(|m| (m.diameter, m.outcome)).collect(),
        r.md_detachment.as_ref(),
        &r.md_bracket,
    )];
    for e in &r.dem {
        v.push(one(
            format!("DEM d0 = {} sigma", e.d0),
            e.runs.iter().map(|m| (m.diameter, m.outcome)).collect(),
            e.detachment.as_ref(),
            &e.bracket,
        ));
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;
    use md_bridge::loading::Strength;
    use wear::dstar::{next_step, Bracket, Probe, SearchSettings, Step};

    fn strength(peak: f64) -> Strength {
        Strength {
            peak_stress: peak,
            peak_strain: 0.1,
            peak_reached: true,
            curve: vec![],
        }
    }

    fn card() -> ModelResult {
        ModelResult {
            n_atoms: 672,
            number_density: 1.0,
            atoms_per_nm2: 8.0,
            c11: 1.0,
            c12: 1.0,
            c66: 1.0,
            young_modulus: 66.0,
            poisson_ratio: 1.0 / 3.0,
            shear_modulus: 24.75,
            tension: strength(2.36),
            shear: strength(3.11),
            surface_energy: 0.306,
            d_min: 1.0,
            d_c: 5.0,
            d_star: 25.0,
            d_star_nm: 8.5,
        }
    }

    /// The bisection against a sharp threshold at `t`, as both sides run it.
    fn probes(t: f64, range: [f64; 2], width: f64) -> Vec<Probe> {
        let s = SearchSettings {
            range,
            limits: [4.0, 200.0],
            relative_width: width,
            widen: 1.5,
            max_rounds: 10,
        };
        let mut p: Vec<Probe> = Vec::new();
        let mut rounds = 0;
        while let Step::Probe(ds) = next_step(&s, &p, rounds).unwrap() {
            for d in ds {
                let o = if d >= t {
                    Outcome::WearParticle
                } else {
                    Outcome::PlasticSmoothing
                };
                p.push(Probe {
                    size: d,
                    outcomes: vec![o, o],
                });
            }
            rounds += 1;
        }
        p
    }

    fn md_of(p: &[Probe]) -> MdSearch {
        let b = Bracket::of(p);
        let runs: Vec<MdRun> = p
            .iter()
            .flat_map(|q| {
                q.outcomes.iter().enumerate().map(|(k, &o)| MdRun {
                    diameter: q.size,
                    seed: k as u64 + 1,
                    lattice_offset: super::super::md::lattice_offset(k as u64 + 1),
                    outcome: o,
                    turn: 0.0,
                    rigidity: 1.0,
                    debris_fraction: None,
                    force_late_over_peak: None,
                    atoms: 100,
                    junction_atoms: 10,
                    // MD cost grows as D^3 (atoms D^2, steps D).
                    wall_seconds: 1e-3 * q.size.powi(3),
                    ranks: 1,
                    job: String::new(),
                })
            })
            .collect();
        MdSearch {
            bracket: [b.lower, b.upper],
            converged: true,
            reason: String::new(),
            split: vec![],
            non_monotonic: vec![],
            seeds: vec![1, 2],
            rounds: 1,
            cost_seconds: runs.iter().map(|r| r.wall_seconds).sum(),
            runs,
        }
    }

    fn dem_of(p: &[Probe], d0: f64) -> DemEntry {
        let b = Bracket::of(p);
        let bracket = [b.lower, b.upper];
        DemEntry {
            config: "c.toml".into(),
            out: "o".into(),
            d0,
            bracket,
            relative_width: relative_width(&bracket),
            converged: true,
            reason: String::new(),
            split: vec![],
            non_monotonic: vec![],
            dstar_eq22_measured: Some(30.0),
            measured: Some(Measured {
                young_modulus: 60.0,
                poisson_ratio: 0.3,
                tensile_strength: 2.0,
                shear_strength: 3.0,
                surface_energy: None,
                seed: 1,
                particles: 100,
                seconds: 1.0,
            }),
            runs: p
                .iter()
                .flat_map(|q| {
                    q.outcomes.iter().enumerate().map(|(k, &o)| DemRun {
                        diameter: q.size,
                        seed: k as u64 + 1,
                        outcome: o,
                        turn: 0.0,
                        rigidity: 1.0,
                        particles: 10,
                        run_seconds: 1e-4 * q.size.powi(2),
                        relax_seconds: 0.0,
                    })
                })
                .collect(),
            cost_seconds: 1.0,
            detachment: None,
        }
    }

    #[test]
    fn brackets_overlap_when_each_lower_bound_is_below_the_other_upper() {
        let s = |l: f64, u: f64| [Some(l), Some(u)];
        assert_eq!(overlap(&s(20.0, 30.0), &s(25.0, 35.0)), Some(true));
        assert_eq!(overlap(&s(25.0, 35.0), &s(20.0, 30.0)), Some(true));
        // (20, 25] and (25, 30] share no size: a bound is exclusive below.
        assert_eq!(overlap(&s(20.0, 25.0), &s(25.0, 30.0)), Some(false));
        assert_eq!(overlap(&s(20.0, 25.0), &s(26.0, 30.0)), Some(false));
        assert_eq!(overlap(&[None, Some(3.0)], &s(1.0, 2.0)), None);
        assert_eq!(centre(&s(20.0, 30.0)), Some(25.0));
        assert_eq!(relative_width(&s(20.0, 30.0)), Some(0.4));
    }

    #[test]
    fn the_same_threshold_on_both_sides_gives_overlapping_brackets_and_centres_near_one() {
        let md = md_of(&probes(27.0, [35.0, 50.0], 0.2));
        let dem = vec![
            dem_of(&probes(27.0, [20.0, 40.0], 0.15), 2.0),
            dem_of(&probes(27.0, [20.0, 40.0], 0.15), 1.0),
        ];
        let r = CompareResult::new(&card(), 3.0, md, None, dem);
        let [l, u] = r.md_bracket;
        assert!(
            l.unwrap() < 27.0 && 27.0 <= u.unwrap(),
            "{:?}",
            r.md_bracket
        );
        assert!(r.md_relative_width.unwrap() <= 0.2);
        assert_eq!(r.md_seeds_at_bounds, [2, 2]);
        for a in &r.agreement {
            assert_eq!(a.overlap, Some(true), "{a:?}");
            let c = a.centre_ratio.unwrap();
            assert!((c - 1.0).abs() < 0.2, "{c}");
            assert_eq!(a.centres_within_25_percent, Some(true));
        }
        assert_eq!(r.dem_brackets_overlap, Some(true));
        // Different thresholds: no overlap, the centre ratio says by how much.
        let md = md_of(&probes(27.0, [35.0, 50.0], 0.2));
        let dem = vec![dem_of(&probes(60.0, [20.0, 40.0], 0.15), 2.0)];
        let r = CompareResult::new(&card(), 3.0, md, None, dem);
        let a = &r.agreement[0];
        assert_eq!(a.overlap, Some(false));
        let c = a.centre_ratio.unwrap();
        assert!((c - 60.0 / 27.0).abs() < 0.3, "{c}");
        assert_eq!(a.centres_within_25_percent, Some(false));
    }

    #[test]
    fn cost_ratios_pair_equal_sizes_and_interpolate_dem_between_its_sizes() {
        let md = md_of(&probes(27.0, [35.0, 50.0], 0.2));
        let dem = dem_of(&probes(27.0, [20.0, 40.0], 0.15), 2.0);
        let c = cost_ratios(&md.runs, &dem);
        assert!(!c.is_empty());
        for r in &c {
            // MD 1e-3 D^3 against DEM 1e-4 D^2: ratio 10 D, exact at equal sizes and for the
            // log-log interpolation of a power law.
            assert!(
                (r.ratio - 10.0 * r.diameter).abs() < 1e-9 * r.ratio,
                "{r:?}"
            );
            assert!(r.how == "same D" || r.how == "DEM interpolated");
        }
        // An MD size outside the DEM sizes gets no ratio rather than an extrapolation.
        let top = dem.runs.iter().map(|r| r.diameter).fold(0.0, f64::max);
        assert!(c.iter().all(|r| r.diameter <= top));
    }

    #[test]
    fn the_json_holds_what_checks_read_and_the_markdown_both_materials() {
        let md = md_of(&probes(27.0, [35.0, 50.0], 0.2));
        let dem = vec![dem_of(&probes(27.0, [20.0, 40.0], 0.15), 2.0)];
        let r = CompareResult::new(&card(), 3.0, md, None, dem);
        let v = serde_json::to_value(&r).unwrap();
        let b = v["md_bracket"].as_array().unwrap();
        assert_eq!(b.len(), 2);
        assert!(b[0].as_f64().unwrap() < b[1].as_f64().unwrap());
        assert_eq!(v["dstar_theory"].as_f64(), Some(25.0));
        let d = v["dem"].as_array().unwrap();
        assert_eq!(d.len(), 1);
        assert_eq!(d[0]["bracket"].as_array().unwrap().len(), 2);
        assert!(v["md"]["runs"][0]["wall_seconds"].as_f64().unwrap() > 0.0);
        assert!(v["cost_ratios"].as_array().is_some());
        // Six properties, the MD card's values and the DEM's measured ones.
        let p = v["properties"].as_array().unwrap();
        assert_eq!(p.len(), 6);
        assert_eq!(p[0]["md"].as_f64(), Some(66.0));
        assert_eq!(p[0]["dem"][0].as_f64(), Some(60.0));
        assert!(p[4]["dem"][0].is_null(), "gamma not measured: null");
        let m = markdown(&r);
        assert!(m.contains("| Young's modulus E | 66.0000 |"), "{m}");
        assert!(m.contains("DEM d0 = 2"));
        assert!(m.contains("| MD | atoms |"));
        // The figure rows: one per seed and side, x in units of d*_theory.
        let rows = figure_rows(&r);
        assert_eq!(rows.len(), 4);
        assert!(rows
            .iter()
            .all(|row| row.points.iter().all(|p| p.0 > 0.1 && p.0 < 4.0)));
    }

    #[test]
    fn d50_ratios_divide_the_fits_and_the_markdown_and_json_carry_them() {
        use super::super::scan::Trial;
        use wear::detachment::FitSettings;
        // Each side's trials: plastic below its threshold, wear above, two split sizes between.
        let trials = |lo: f64, hi: f64| -> Vec<Trial> {
            let mut v = Vec::new();
            for (k, d) in [0.6, 0.8, 0.9, 1.1, 1.2, 1.4].iter().enumerate() {
                for seed in 1..=8u64 {
                    // Wear fraction rises 0, 0, 3/8, 5/8, 1, 1 with size.
                    let wear = match k {
                        0 | 1 => false,
                        2 => seed <= 3,
                        3 => seed <= 5,
                        _ => true,
                    };
                    v.push(Trial {
                        diameter: d * (lo + hi) / 2.0,
                        seed,
                        outcome: if wear {
                            Outcome::WearParticle
                        } else {
                            Outcome::PlasticSmoothing
                        },
                        scan: seed > 2,
                        seconds: 1.0,
                    });
                }
            }
            v
        };
        let det =
            |t: Vec<Trial>| Detachment::new(vec![], vec![3], t, &FitSettings::default()).unwrap();
        let md = md_of(&probes(27.0, [35.0, 50.0], 0.2));
        let mut e = dem_of(&probes(54.0, [20.0, 40.0], 0.15), 2.0);
        e.detachment = Some(det(trials(50.0, 58.0)));
        let r = CompareResult::new(&card(), 3.0, md, Some(det(trials(25.0, 29.0))), vec![e]);
        let (m, d) = (
            r.md_detachment.as_ref().unwrap().fit.clone(),
            r.dem[0].detachment.as_ref().unwrap().fit.clone(),
        );
        // Same shape at twice the size: D50 twice, the same slope, ratio 2.
        let q = &r.d50_ratios[0];
        assert!((d.d50.unwrap() / m.d50.unwrap() - 2.0).abs() < 1e-6);
        assert!((q.ratio.unwrap() - 2.0).abs() < 1e-6, "{q:?}");
        assert!((d.slope.unwrap() - m.slope.unwrap()).abs() < 1e-6 * m.slope.unwrap());
        let (lo, hi) = (q.range[0].unwrap(), q.range[1].unwrap());
        assert!(lo < 2.0 && 2.0 < hi, "{lo} {hi}");
        assert_eq!(lo, d.interval[0].unwrap() / m.interval[1].unwrap());
        assert!((q.d50_over_d0.unwrap() - d.d50.unwrap() / 2.0).abs() < 1e-12);
        let v = serde_json::to_value(&r).unwrap();
        assert!(v["md_detachment"]["fit"]["d50"].as_f64().unwrap() > 25.0);
        assert_eq!(v["dem"][0]["detachment"]["fit"]["runs"].as_u64(), Some(48));
        let text = markdown(&r);
        assert!(text.contains("Detachment probability"), "{text}");
        assert!(text.contains("| MD | atoms | 48 (36) |"), "{text}");
        assert!(text.contains("- DEM d0 = 2: "), "{text}");
        // The figure's series: MD first, a curve through D50 on each side.
        let p = probability_series(&r);
        assert_eq!(p.len(), 2);
        assert!(p
            .iter()
            .all(|s| s.curve.is_some() && s.fractions.len() == 6));
        assert!(
            p[0].label.starts_with("MD (LAMMPS): D50 = "),
            "{}",
            p[0].label
        );
        // Without a scan: no ratio, the words say so.
        let md = md_of(&probes(27.0, [35.0, 50.0], 0.2));
        let r = CompareResult::new(
            &card(),
            3.0,
            md,
            None,
            vec![dem_of(&probes(54.0, [20.0, 40.0], 0.15), 2.0)],
        );
        assert!(r.d50_ratios.is_empty());
        assert_eq!(d50_words(None), "no scan");
        assert!(!markdown(&r).contains("Detachment probability"));
    }
}
