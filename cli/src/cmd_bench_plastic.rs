//! `cgdem bench-plastic`: what one impact and one scratch of the plastic-wear model (paper 001) cost
//! on this machine, beside LAMMPS running the same contact loop without wear (`pair_style granular`,
//! Hertz + Coulomb friction with history, the decks of `dem::scenario::plastic::lammps`).
//!
//! Timed, each on one thread: the impact of `--impact` with wear, the same impact on a surface too hard
//! to flow (the contact loop without wear) at the same time step, and LAMMPS on that elastic impact for
//! the same number of steps; then the scratch of `--scratch` at `--load` (indentation and slide) with
//! wear, without wear at the same time step, and LAMMPS sliding the indenter under the load for the
//! slide's steps from the same depth. The
//! elastic impact's rebound from LAMMPS is printed beside ours (the two integrators differ at O(dt)).
//! Figures are wall-clock seconds on a shared machine: the load average is printed with them, and the
//! ratios, measured one after the other, are the figures to quote.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};
use clap::Args;
use dem::scenario::plastic::lammps::{impact_deck, read_result, slide_deck, LammpsDeck, DATA_FILE};
use dem::scenario::plastic::{
    run_impact, run_scratch_load, ImpactFile, PlasticTimeStep, ScratchConfig, ScratchFile,
};
use md_bridge::venv::Venv;

/// Arguments of `cgdem bench-plastic`.
#[derive(Debug, Args)]
pub struct BenchPlasticArgs {
    /// Impact config (one impact; default configs/impact-normal.toml).
    #[arg(long)]
    impact: Option<PathBuf>,
    /// Scratch config (default configs/scratch.toml); `--load` picks the load.
    #[arg(long)]
    scratch: Option<PathBuf>,
    /// Scratch load (N); default 21 kN, the load of the paper's Fig. 9.
    #[arg(long, default_value_t = 21000.0)]
    load: f64,
    /// Directory for the LAMMPS decks and logs.
    #[arg(long, default_value = "out/bench-plastic")]
    out: PathBuf,
    /// Skip LAMMPS.
    #[arg(long)]
    no_lammps: bool,
}

/// A surface hard enough never to flow: the contact loop without wear.
const UNWORN: f64 = 1e15;

fn repo_config(name: &str) -> PathBuf {
    md_bridge::venv::repo_root().join("configs").join(name)
}

/// Runs `cgdem bench-plastic`.
pub fn run(args: BenchPlasticArgs) -> Result<()> {
    let impact_path = args
        .impact
        .clone()
        .unwrap_or_else(|| repo_config("impact-normal.toml"));
    let scratch_path = args
        .scratch
        .clone()
        .unwrap_or_else(|| repo_config("scratch.toml"));
    let file: ImpactFile = crate::config::read(&impact_path)?;
    if file.sweep.is_some() {
        bail!(
            "{} is a sweep: bench-plastic times one impact",
            impact_path.display()
        );
    }
    let impact = file.base();
    let scratch: ScratchConfig = crate::config::read::<ScratchFile>(&scratch_path)?.base();
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let venv = if args.no_lammps {
        None
    } else {
        let v = Venv::locate();
        v.check().context(
            "the LAMMPS comparison needs the project venv (CGDEM_VENV, or `bash scripts/setup-venv`); or pass --no-lammps",
        )?;
        Some(v)
    };
    println!("load average before: {}", loadavg());

    let t = Instant::now();
    let worn = run_impact(&impact)?;
    let worn_s = t.elapsed().as_secs_f64();
    let mut hard = impact.clone();
    hard.model.hardness = UNWORN;
    hard.run.time_step = PlasticTimeStep::Seconds(worn.time_step);
    let t = Instant::now();
    let elastic = run_impact(&hard)?;
    let elastic_s = t.elapsed().as_secs_f64();
    row("impact, with wear", worn_s, worn.steps);
    row("impact, without wear", elastic_s, elastic.steps);
    if let Some(v) = &venv {
        let deck = impact_deck(&hard, elastic.steps)?;
        let (loop_s, log) = run_lammps(v, &deck, &args.out.join("impact"))?;
        row("impact, LAMMPS without wear", loop_s, deck.steps);
        println!(
            "  LAMMPS / cgdem per step (without wear): {:.2}",
            loop_s / elastic_s
        );
        if let Some(r) = read_result(&log) {
            let speed = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
            println!(
                "  rebound without wear: cgdem COR {:.6}, angle {:.4} deg, spin {:.2} rad/s; LAMMPS COR {:.6}, angle {:.4} deg, spin {:.2} rad/s",
                elastic.cor,
                elastic.rebound_angle_deg,
                elastic.rebound_spin,
                speed / impact.impact.speed,
                r[2].atan2(r[0]).to_degrees(),
                (r[3] * r[3] + r[4] * r[4] + r[5] * r[5]).sqrt(),
            );
        }
    }

    let t = Instant::now();
    let worn = run_scratch_load(&scratch, args.load, None)?;
    let worn_s = t.elapsed().as_secs_f64();
    let mut hard = scratch.clone();
    hard.model.hardness = UNWORN;
    hard.run.time_step = PlasticTimeStep::Seconds(worn.time_step);
    let t = Instant::now();
    let elastic = run_scratch_load(&hard, args.load, None)?;
    let elastic_s = t.elapsed().as_secs_f64();
    row("scratch, with wear (indent + slide)", worn_s, worn.steps);
    row(
        "scratch, without wear (indent + slide)",
        elastic_s,
        elastic.steps,
    );
    if let Some(v) = &venv {
        let slide_steps = (elastic.distance / elastic.speed / elastic.time_step).round() as u64;
        let deck = slide_deck(&hard, args.load, elastic.depth_indent, slide_steps)?;
        let (loop_s, _) = run_lammps(v, &deck, &args.out.join("scratch"))?;
        row("scratch slide, LAMMPS without wear", loop_s, deck.steps);
        println!(
            "  LAMMPS slide / cgdem indent + slide without wear: {:.2} (cgdem's slide is {:.0} % of its steps)",
            loop_s / elastic_s,
            100.0 * slide_steps as f64 / elastic.steps as f64
        );
    }
    println!("load average after: {}", loadavg());
    Ok(())
}

fn row(what: &str, seconds: f64, steps: u64) {
    println!(
        "{what:<42} {seconds:9.3} s  {steps:>9} steps  {:8.3} us/step",
        1e6 * seconds / steps.max(1) as f64
    );
}

fn loadavg() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".into())
}

/// Writes the deck into `dir`, runs the venv's `lmp` on one process there, and returns the loop time
/// of the run (seconds) and the log.
fn run_lammps(venv: &Venv, deck: &LammpsDeck, dir: &Path) -> Result<(f64, String)> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    std::fs::write(dir.join("in.plastic"), &deck.input)?;
    std::fs::write(dir.join(DATA_FILE), &deck.data)?;
    let log = venv.run_lmp(dir, "in.plastic", "log.lammps", 1)?;
    let line = log
        .lines()
        .find(|l| l.starts_with("Loop time of"))
        .context("no loop time in the LAMMPS log")?;
    let w: Vec<&str> = line.split_whitespace().collect();
    Ok((w[3].parse()?, log))
}
