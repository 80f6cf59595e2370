//! Performance: the engine against LAMMPS on the same packing (`validation::bench`, the system of
//! `cgdem bench`), in one run so that the ratio is measured under one load. DESIGN.md section 8 sets
//! the floor: at least 1.6x LAMMPS per core on the bench packing. The junction runs against paper 000
//! Table 6 arrive with the junction scenario.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::bench::{time_cgdem, time_lammps, write_lammps_inputs};
use crate::report::claim::sig;
use crate::report::provenance::{load_average, utc_now};
use crate::report::{
    Claim, Context, Figure, Kind, Panel, Profile, Section, SectionOutput, Tolerance,
};
use crate::{Result, ValidationError};

pub const SECTION: Section = Section {
    id: "performance",
    title: "Performance: the engine against LAMMPS (DESIGN.md section 8; paper 000 Table 6)",
    run,
};

const VERSION: u32 = 1;

#[derive(Debug, Clone, Serialize, Deserialize)]
struct Case {
    version: u32,
    cells: usize,
    steps: u64,
    threads: Vec<usize>,
}

/// Rates in particle-steps per second, and the conditions they were measured under.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct Timing {
    particles: usize,
    cgdem: Vec<(usize, f64)>,
    lammps: f64,
    load_before: String,
    load_after: String,
    date: String,
}

fn measure(ctx: &Context, case: &Case, dir: &Path) -> Result<Timing> {
    let venv = &ctx.md()?.venv;
    venv.check()?;
    let load_before = load_average();
    let mut cgdem = Vec::new();
    let (mut dt, mut particles) = (0.0, 0);
    for &t in &case.threads {
        let (secs, n, pairs, step) = time_cgdem(t, case.steps, case.cells)?;
        if pairs != 6 * n {
            return Err(ValidationError::Report(format!(
                "bench packing: {pairs} pairs for {n} spheres, expected 6 per sphere"
            )));
        }
        dt = step;
        particles = n;
        cgdem.push((t, n as f64 * case.steps as f64 / secs));
    }
    let input = write_lammps_inputs(dir, case.cells, case.steps, dt)?;
    let (secs, n) = time_lammps(venv, &input, case.steps)?;
    Ok(Timing {
        particles,
        cgdem,
        lammps: n as f64 * case.steps as f64 / secs,
        load_before,
        load_after: load_average(),
        date: utc_now(),
    })
}

fn run(ctx: &Context) -> Result<SectionOutput> {
    // The bench packing of `cgdem bench` (40 cells, 51 200 spheres); the paper profile times longer.
    let (cells, steps) = match ctx.profile {
        Profile::Quick => (40, 200),
        Profile::Paper => (40, 1000),
    };
    let case = Case {
        version: VERSION,
        cells,
        steps,
        threads: vec![1, 2],
    };
    let t = ctx
        .jobs(
            "engine vs LAMMPS",
            std::slice::from_ref(&case),
            |c, dir, _| measure(ctx, c, dir),
        )?
        .pop()
        .ok_or_else(|| ValidationError::Report("performance: no result".into()))?;
    let one = t.cgdem.iter().find(|c| c.0 == 1).map_or(f64::NAN, |c| c.1);
    let ratio = one / t.lammps;
    let fig = "performance";
    let title = "particle-steps per second on the bench packing";
    let engine = format!("cgdem, {} spheres", t.particles);
    let lammps = "LAMMPS gran/hooke/history, 1 process";
    let floor = "1.6 x LAMMPS per core (the floor)";
    let xs = |v: f64| vec![(0.8, v), (2.2, v)];
    let panel = Panel::new(title, "cgdem threads (-)", "million particle-steps / s")
        .x_ticks(t.cgdem.iter().map(|&(n, _)| n as f64).collect())
        .with(
            &engine,
            Kind::SimulationPoints,
            t.cgdem.iter().map(|&(n, r)| (n as f64, r / 1e6)).collect(),
        )
        .with(lammps, Kind::Reference, xs(t.lammps / 1e6))
        .with(floor, Kind::Reference, xs(1.6 * t.lammps / 1e6));
    let claims = vec![
        Claim::new("workbench", "DESIGN.md 8", "cgdem 1 thread / LAMMPS 1 process, particle-steps per second", 1.6, ratio, Tolerance::Above)
            .note(format!("Measured in one run at load average {} (before) / {} (after); a shared machine moves single runs by ~10 %.", t.load_before, t.load_after)),
        Claim::new("workbench", "bench", "cgdem rate at 1 thread (million particle-steps/s)", 0.0, one / 1e6, Tolerance::Above).plotted(fig, title, &engine, 1.0),
    ];
    let mut figure = Figure::new(fig, "DESIGN.md section 8 (no paper figure)", "cgdem against LAMMPS on the same periodic HCP packing (12 contacts per sphere, cohesive force with tangential history), one run.");
    figure.columns = 1;
    figure = figure.panel(panel);
    let html = format!(
        "<p>{} spheres, {} steps per side, measured {} UTC (cached: a rerun shows this measurement; \
         clear the case cache to measure again). Ratio per core {}x. <code>cgdem bench --repeats 5</code> \
         gives medians over rounds; <code>cgdem bench --workload amorphous</code> times paper 000's silica \
         recipe (sizes 0.75-5 d0). The junction runs against paper 000 Table 6 are in the junction \
         section.</p>\n",
        t.particles, steps, t.date, sig(ratio, 3)
    );
    Ok(SectionOutput {
        claims,
        figures: vec![figure],
        html,
        provenance: vec![],
    })
}
