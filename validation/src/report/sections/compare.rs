//! DEM against MD on the model material's d* (issue 17, docs/compare.md): the comparison of
//! `configs/compare-model.toml` run through [`crate::compare`] as one report case (its MD runs are
//! jobs in the report's MD cache, its DEM searches jobs under the case's folder). The quick profile
//! runs the MD side alone (the config's DEM searches cost hours); the paper profile runs the whole
//! config.

use serde::{Deserialize, Serialize};
use wear::Outcome;

use super::junction::{bracket_box, with_outcomes};
use crate::compare::summary::{centre, d50_words, probability_series, CompareResult, Span};
use crate::compare::{compare, CompareFile, CompareRun};
use crate::report::claim::sig;
use crate::report::html::esc;
use crate::report::{
    Claim, Context, Figure, Kind, Panel, Profile, Section, SectionOutput, Tolerance,
};
use crate::{Result, ValidationError};

pub const SECTION: Section = Section {
    id: "compare",
    title: "DEM against MD: the model material's d* from both sides (issue 17)",
    run,
};

const VERSION: u32 = 1;
const CONFIG: &str = "configs/compare-model.toml";

#[derive(Debug, Clone, Serialize, Deserialize)]
struct Case {
    version: u32,
    /// The config as read (its DEM searches dropped in the quick profile).
    file: CompareFile,
}

fn run(ctx: &Context) -> Result<SectionOutput> {
    let md = ctx.md()?;
    let repo = md_bridge::venv::repo_root();
    let path = repo.join(CONFIG);
    let text = std::fs::read_to_string(&path).map_err(|e| ValidationError::io(&path, e))?;
    let mut file: CompareFile = toml::from_str(&text).map_err(|e| ValidationError::Config {
        path: path.display().to_string(),
        reason: e.to_string(),
    })?;
    if ctx.profile == Profile::Quick {
        // The quick profile keeps to the MD bisection (~3 min); the scan's extra seeds (another
        // ~3 min of MD) and the DEM searches run in the paper profile.
        file.dem.clear();
        file.scan = None;
    }
    let base = repo.join("configs");
    let case = Case {
        version: VERSION,
        file,
    };
    let r: CompareResult = ctx
        .jobs(
            "DEM against MD",
            std::slice::from_ref(&case),
            |c, dir, par| {
                let how = CompareRun {
                    md: md_bridge::job::RunOptions {
                        exe: md.exe.clone(),
                        np: 1,
                        cache_dir: md.cache_dir.clone(),
                        venv: md.venv.clone(),
                        reuse_cache: true,
                    },
                    dem: dem::jobs::RunJobs {
                        at_once: ctx.at_once.max(1),
                        ..dem::jobs::RunJobs::default()
                    },
                    par,
                    base: &base,
                };
                compare(&c.file, &how, dir, &mut |_, _| {})
            },
        )?
        .pop()
        .ok_or_else(|| ValidationError::Report("compare: no result".into()))?;
    Ok(SectionOutput {
        claims: claims(&r),
        figures: vec![figure(&r)],
        html: page(&r, ctx.profile),
        provenance: vec![(
            "MD junction jobs (sha256 of each request)".into(),
            r.md.runs
                .iter()
                .map(|m| format!("D {} seed {}: {:.12}", m.diameter, m.seed, m.job))
                .collect::<Vec<_>>()
                .join("; "),
        )],
    })
}

fn show(b: &Span) -> String {
    let f = |v: Option<f64>| v.map_or("-".to_string(), |x| format!("{x}"));
    format!("({}, {}]", f(b[0]), f(b[1]))
}

fn claims(r: &CompareResult) -> Vec<Claim> {
    let state = format!("MD bracket {} sigma; {}", show(&r.md_bracket), r.md.reason);
    let mut c = vec![
        Claim::new(
            "issue 17",
            "acceptance",
            "width of the MD d* bracket, (upper - lower) / centre (at most 0.2)",
            0.2,
            r.md_relative_width.unwrap_or(f64::NAN),
            Tolerance::Below,
        )
        .note(state.clone()),
        Claim::new(
            "issue 17",
            "acceptance",
            "seeds at each bound of the MD bracket, the fewer of the two (at least 2)",
            1.0,
            r.md_seeds_at_bounds[0].min(r.md_seeds_at_bounds[1]) as f64,
            Tolerance::Above,
        ),
        Claim::new(
            "000",
            "eq 22",
            "MD bracket centre against d* of eq 22 from the MD card (sigma)",
            r.dstar_theory,
            centre(&r.md_bracket).unwrap_or(f64::NAN),
            Tolerance::Info,
        )
        .note("eq 22 is an order-of-magnitude estimate; the paper's silica DEM bracket is 10-20 nm for 18.5"),
    ];
    for (e, a) in r.dem.iter().zip(&r.agreement) {
        c.push(
            Claim::new(
                "issue 17",
                "acceptance",
                format!(
                    "DEM bracket centre / MD bracket centre, d0 = {} sigma",
                    sig(e.d0, 3)
                ),
                1.0,
                a.centre_ratio.unwrap_or(f64::NAN),
                Tolerance::Relative(0.25),
            )
            .note(format!(
                "DEM bracket {} sigma, {}; overlap with the MD bracket: {}",
                show(&e.bracket),
                e.reason,
                a.overlap.map_or("unknown".into(), |o| o.to_string())
            )),
        );
    }
    if let Some(d) = &r.md_detachment {
        c.push(
            Claim::new(
                "000",
                "eq 22",
                "MD D50, the size where half the junctions detach (sigma), against d* of eq 22",
                r.dstar_theory,
                d.fit.d50.unwrap_or(f64::NAN),
                Tolerance::Info,
            )
            .note(format!(
                "{}; {} runs, {} of them the scan's (seeds {:?} at {:?} sigma)",
                d50_words(Some(d)),
                d.fit.runs,
                d.scan_runs,
                d.seeds,
                d.sizes
            )),
        );
    }
    for (e, q) in r.dem.iter().filter_map(|e| {
        let q = r.d50_ratios.iter().find(|q| q.d0 == e.d0)?;
        Some((e, q))
    }) {
        let f = |v: Option<f64>| v.map_or("open".to_string(), |x| sig(x, 3));
        c.push(
            Claim::new(
                "issue 17",
                "acceptance",
                format!("DEM D50 / MD D50, d0 = {} sigma", sig(e.d0, 3)),
                1.0,
                q.ratio.unwrap_or(f64::NAN),
                Tolerance::Relative(0.25),
            )
            .note(format!(
                "DEM {}; ratio range from the two intervals {}-{}; D50 / d0 = {}; majority of \
                 every run: DEM {}, MD {} sigma",
                d50_words(e.detachment.as_ref()),
                f(q.range[0]),
                f(q.range[1]),
                f(q.d50_over_d0),
                e.detachment
                    .as_ref()
                    .map_or("-".into(), |d| show(&d.majority_bracket)),
                r.md_detachment
                    .as_ref()
                    .map_or("-".into(), |d| show(&d.majority_bracket)),
            )),
        );
    }
    for k in &r.cost_ratios {
        c.push(
            Claim::new(
                "000",
                "Table 6",
                format!(
                    "MD / DEM wall time of one D = {} sigma junction, d0 = {} sigma",
                    k.diameter,
                    sig(k.d0, 3)
                ),
                1e5,
                k.ratio,
                Tolerance::Info,
            )
            .note(format!(
                "{}; paper 000 Table 6 claims five orders of magnitude for silica in 3D",
                k.how
            )),
        );
    }
    c
}

/// One row per side and seed; marks at D / d*_theory; brackets as dashed boxes; eq 22 at 1.
fn figure(r: &CompareResult) -> Figure {
    let t = r.dstar_theory;
    let mut rows: Vec<(String, Vec<(f64, Outcome)>)> = Vec::new();
    for &seed in &r.md.seeds {
        rows.push((
            format!("MD seed {seed}"),
            r.md.runs
                .iter()
                .filter(|m| m.seed == seed)
                .map(|m| (m.diameter / t, m.outcome))
                .collect(),
        ));
    }
    for e in &r.dem {
        let mut seeds: Vec<u64> = e.runs.iter().map(|m| m.seed).collect();
        seeds.sort_unstable();
        seeds.dedup();
        for seed in seeds {
            rows.push((
                format!("DEM d0 {} seed {seed}", sig(e.d0, 3)),
                e.runs
                    .iter()
                    .filter(|m| m.seed == seed)
                    .map(|m| (m.diameter / t, m.outcome))
                    .collect(),
            ));
        }
    }
    let n = rows.len() as f64;
    let marks = |o: Outcome| -> Vec<(f64, f64)> {
        rows.iter()
            .enumerate()
            .flat_map(|(k, (_, p))| {
                p.iter()
                    .filter(move |q| q.1 == o)
                    .map(move |q| (q.0, k as f64))
            })
            .collect()
    };
    let boxed = |b: &Span, lo: f64, hi: f64| -> Vec<(f64, f64)> {
        match b {
            [Some(l), Some(u)] => bracket_box(l / t, u / t, lo, hi),
            _ => vec![],
        }
    };
    let md_rows = r.md.seeds.len() as f64;
    let mut p = with_outcomes(
        Panel::new(
            "outcome of each run against D / d* of eq 22",
            "junction width D / d* of eq 22 (-)",
            "run",
        )
        .rows(rows.iter().map(|(name, _)| name.clone()).collect()),
        marks,
    )
    .with(
        format!("eq 22 from the MD card ({} sigma)", sig(t, 3)),
        Kind::Reference,
        vec![(1.0, -0.5), (1.0, n - 0.5)],
    )
    .with(
        "MD bracket",
        Kind::Reference,
        boxed(&r.md_bracket, -0.4, md_rows - 0.6),
    );
    let mut first = md_rows;
    for e in &r.dem {
        let k = e
            .runs
            .iter()
            .map(|m| m.seed)
            .collect::<std::collections::BTreeSet<_>>()
            .len() as f64;
        p = p.with(
            format!("DEM bracket, d0 = {} sigma", sig(e.d0, 3)),
            Kind::Reference,
            boxed(&e.bracket, first - 0.4, first + k - 0.6),
        );
        first += k;
    }
    let mut fig = Figure::new(
        "compare-outcomes",
        "issue 17 (paper 000 section 4, eq 22)",
        "Junction outcomes of the 2D LJ model material (cut-off 1.3 sigma) from LAMMPS and from the DEM, against D over d* of eq 22 from the MD card; the brackets as dashed boxes; with a scan, the wear fraction per size and the fitted P(wear | D).",
    )
    .panel(p);
    if r.md_detachment.is_some() || r.dem.iter().any(|e| e.detachment.is_some()) {
        let mut q = Panel::new(
            "fraction of runs that detach, and the fitted P(wear | D)",
            "junction width D / d* of eq 22 (-)",
            "P(wear particle)",
        )
        .log_x();
        for (s, name) in probability_series(r).into_iter().zip(
            std::iter::once("MD".to_string())
                .chain(r.dem.iter().map(|e| format!("DEM d0 {}", sig(e.d0, 3)))),
        ) {
            q = q.with(
                format!("{name}: wear fraction"),
                Kind::SimulationMarks,
                s.fractions
                    .iter()
                    .map(|&(x, n, w)| (x, w as f64 / n as f64))
                    .collect(),
            );
            if let Some((x50, k)) = s.curve {
                let xs = s.fractions.iter().map(|f| f.0);
                let (lo, hi) = xs.fold((f64::INFINITY, 0.0f64), |(a, b), x| (a.min(x), b.max(x)));
                let pts = (0..=60)
                    .map(|i| {
                        let x = lo * (hi / lo).powf(i as f64 / 60.0);
                        (x, 1.0 / (1.0 + (-k * (x / x50).ln()).exp()))
                    })
                    .collect();
                q = q.with(format!("{name}: fitted P"), Kind::Simulation, pts);
            }
        }
        fig = fig.panel(q);
    }
    fig
}

fn page(r: &CompareResult, profile: Profile) -> String {
    let mut h = format!(
        "<p>The 2D LJ model material (cut-off 1.3 sigma): d* of eq 22 from its MD card {} sigma; MD \
         bracket {} sigma ({} runs, {} s of MD on one process each). {}</p>\n",
        sig(r.dstar_theory, 3),
        esc(&show(&r.md_bracket)),
        r.md.runs.len(),
        sig(r.md_cost_seconds, 3),
        match profile {
            Profile::Quick => "Quick profile: the MD side only (the DEM searches of configs/compare-model.toml run in the paper profile and with <code>cgdem compare</code>).",
            Profile::Paper => "Paper profile: every search of configs/compare-model.toml.",
        }
    );
    h.push_str("<table><tr><th>property</th><th>MD card</th><th>unit</th>");
    for e in &r.dem {
        h.push_str(&format!("<th>DEM d0 = {} sigma</th>", sig(e.d0, 3)));
    }
    h.push_str("</tr>\n");
    for p in &r.properties {
        h.push_str(&format!(
            "<tr><td>{}</td><td>{}</td><td>{}</td>",
            esc(&p.property),
            sig(p.md, 4),
            esc(&p.md_unit)
        ));
        for v in &p.dem {
            h.push_str(&format!(
                "<td>{}</td>",
                v.map_or("-".to_string(), |x| sig(x, 4))
            ));
        }
        h.push_str("</tr>\n");
    }
    h.push_str("</table>\n<table><tr><th>side</th><th>D (sigma)</th><th>seed</th><th>verdict</th><th>turn (rad)</th><th>rigidity</th><th>wall (s)</th></tr>\n");
    let name = |o: Outcome| match o {
        Outcome::PlasticSmoothing => "plastic",
        Outcome::WearParticle => "debris",
    };
    for m in &r.md.runs {
        h.push_str(&format!(
            "<tr><td>MD</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
            m.diameter,
            m.seed,
            name(m.outcome),
            sig(m.turn, 3),
            sig(m.rigidity, 3),
            sig(m.wall_seconds, 3)
        ));
    }
    for e in &r.dem {
        for m in &e.runs {
            h.push_str(&format!(
                "<tr><td>DEM d0 = {}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
                sig(e.d0, 3),
                sig(m.diameter, 4),
                m.seed,
                name(m.outcome),
                sig(m.turn, 3),
                sig(m.rigidity, 3),
                sig(m.run_seconds, 3)
            ));
        }
    }
    h.push_str("</table>\n");
    h
}
