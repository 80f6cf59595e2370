//! The comparison's outputs: the markdown fragment, the figures' rows and series, and the files
//! of `cgdem compare` (`compare.json`, `compare.md`, the figures), all from a [`CompareResult`].

use std::fmt::Write as _;
use std::path::Path;

use dem::io::checkpoint::write_atomic;
use wear::detachment::FitStatus;
use wear::Outcome;

use super::{CompareResult, Span};
use crate::compare::scan::Detachment;
use crate::error::{Result, ValidationError};
use crate::figures::detachment::{draw_detachment, ProbabilitySeries};
use crate::figures::dstar::{draw_outcomes, OutcomeRow};

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
