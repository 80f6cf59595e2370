//! `cgdem sliding <config.toml> --out DIR`: sliding with a third-body layer (paper 004; see
//! `validation::wear::sliding` for the file and its outputs). One run writes `DIR/summary.json`; a
//! grid (`[[grid]]` entries) relaxes each material's box once in `DIR/samples/`, measures each
//! material's strength in `DIR/strength/`, and runs its points as cached jobs in `DIR/runs/` side by
//! side (`--jobs`), under `mpirun -np N` / `srun` (each rank its share) or as a Slurm array
//! (`--shard i/n`), and writes `DIR/grid.csv`. Rerunning after Ctrl-C or a crash continues every run
//! from its progress file.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use validation::wear::sliding::{run_grid, run_sliding, SlidingFile};

use crate::job_args::RunArgs;

/// Arguments of `cgdem sliding`.
#[derive(Debug, Args)]
pub struct SlidingArgs {
    /// TOML sliding config (see configs/sliding-*.toml).
    pub config: PathBuf,
    /// Output directory.
    #[arg(long, default_value = "out/sliding")]
    pub out: PathBuf,
    #[command(flatten)]
    pub run: RunArgs,
}

/// Runs `cgdem sliding`.
pub fn run(args: SlidingArgs, threads: usize) -> Result<()> {
    let file: SlidingFile = crate::config::read(&args.config)?;
    let runs = file.runs()?;
    if file.grid.is_empty() {
        let cfg = &runs[0];
        tracing::info!(
            p_n = cfg.pressure,
            sigma_m = cfg.material.strength,
            d_star = cfg.d_star()?,
            l_over_d0 = 1.0 / cfg.d0_over_l,
            distance_over_l = cfg.distance_over_l,
            "sliding (paper 004, units E = rho = L = 1)"
        );
        let bar = crate::progress::Bar::new("sliding", "steps");
        let s = run_sliding(
            cfg,
            &args.out,
            crate::parallelism(threads),
            &mut |step, total| bar.update(step, total),
        )?;
        bar.finish();
        let flow = s.p_t_over_tau_flow.zip(s.tau_flow_over_sigma_m).map_or(
            String::new(),
            |(ratio, flow)| {
                format!(", p_T / tau_flow = {ratio:.2} with tau_flow = {flow:.3} sigma_m")
            },
        );
        let agitation = s
            .agitation
            .map_or(String::new(), |a| format!(", agitation {a:.3} v0"));
        println!(
            "{}: rho_TBL = {:.3} rho_0, h_TBL = {:.3} H{agitation}, p_T = {:.4e} E (p_T / tau_m = {:.2}, \
             p_T / (tau_m rho_TBL) = {:.2}; tau_m = {:.3} sigma_m, {}{flow}) at p_N = {} E ({} particles, \
             {} steps, {:.1} s + {:.1} s relaxation)",
            s.regime.label(),
            s.rho_tbl,
            s.h_tbl,
            s.p_t,
            s.p_t_over_tau_m,
            s.p_t_over_tau_rho,
            s.tau_m_over_sigma_m,
            if s.sigma_t.is_some() { "measured" } else { "given" },
            s.p_n,
            s.particles,
            s.steps,
            s.run_seconds,
            s.relax_seconds
        );
        if let Some(at) = s.body_reached_at_l {
            println!(
                "the TBL lay against a rigid body from {at:.2} L of sliding on ({} of {} steady windows): \
                 paper 004 drops that phase as unphysical",
                s.steady_windows_at_body, s.steady_windows
            );
        }
        match &s.interior {
            Some(i) => println!(
                "interior phase (TBL inside the material, {} windows): p_T = {:.4e} E, p_T / tau_m = {:.2}{}, \
                 rho_TBL = {:.3} rho_0, h_TBL = {:.3} H",
                i.windows,
                i.p_t,
                i.p_t_over_tau_m,
                i.p_t_over_tau_flow
                    .map_or(String::new(), |r| format!(", p_T / tau_flow = {r:.2}")),
                i.rho_tbl,
                i.h_tbl
            ),
            None => println!("interior phase: no window after the start-up had its TBL inside the material"),
        }
        println!("wrote {}", args.out.join("summary.json").display());
        return Ok(());
    }
    let how = args.run.resolve()?;
    tracing::info!(runs = runs.len(), at_once = how.at_once, "sliding grid");
    let results = run_grid(&runs, &args.out, &how, crate::parallelism(threads))?;
    let done = results.iter().flatten().count();
    for s in results.iter().flatten() {
        println!(
            "p_N = {:<5} sigma_m = {:<5} d* = {:<5}: rho_TBL = {:.3}, h_TBL = {:.3}, p_T = {:.4e} \
             ({:.2} tau_m, tau_m = {:.3} sigma_m), {}",
            s.p_n,
            s.strength,
            s.d_star,
            s.rho_tbl,
            s.h_tbl,
            s.p_t,
            s.p_t_over_tau_m,
            s.tau_m_over_sigma_m,
            s.regime.label()
        );
    }
    println!(
        "{done} of {} runs done; wrote {}",
        runs.len(),
        args.out.join("grid.csv").display()
    );
    Ok(())
}
