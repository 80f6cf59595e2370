//! `cgdem`: the workbench binary. One subcommand per pipeline stage; each lives in its own module.

mod cmd_bench;
mod cmd_bench_plastic;
mod cmd_calibrate;
mod cmd_compare;
mod cmd_doctor;
mod cmd_dstar;
mod cmd_impact;
mod cmd_junction;
mod cmd_md;
mod cmd_patch;
mod cmd_pipeline;
mod cmd_report;
mod cmd_scratch;
mod cmd_sliding;
mod config;
mod job_args;
mod progress;

use anyhow::Result;
use clap::{Parser, Subcommand};

#[derive(Debug, Parser)]
#[command(
    name = "cgdem",
    version,
    about = "Coarse-grained DEM workbench for wear and fracture"
)]
struct Cli {
    /// Worker threads for the DEM engine (results are bit-identical for any count; a system below
    /// 600 particles steps on one thread, which is faster there).
    #[arg(long, global = true, default_value_t = 0)]
    threads: usize,
    /// More log lines on stderr: -v every stage's info, -vv every detail (`RUST_LOG` overrides).
    /// By default warnings and progress: a bar with an ETA on a terminal (plain lines otherwise),
    /// and the periodic lines of long stages without a bar (relaxations, patch tests, calibration
    /// iterations; `cgdem report` shows only its bars).
    #[arg(short, long, global = true, action = clap::ArgAction::Count)]
    verbose: u8,
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Check the MD side: venv, LAMMPS version, packages, potentials, MPI.
    Doctor,
    /// MD reference runs through LAMMPS (worker process, cached): `cgdem md silica --out DIR`.
    Md(cmd_md::MdArgs),
    /// Internal: runs one MD job file (spawned by `cgdem md`, possibly under mpirun).
    #[command(hide = true)]
    MdWorker(cmd_md::WorkerArgs),
    /// Bridge overhead: the same LAMMPS input through the embedded bridge and through `lmp`.
    BenchMd(cmd_md::BenchMdArgs),
    /// DEM throughput (particle-steps/s at 1 and 2 threads) and the ratio against LAMMPS.
    Bench(cmd_bench::BenchArgs),
    /// Patch tests (paper 000 section 3): `cgdem patch configs/patch-hcp.toml --out DIR`.
    Patch(cmd_patch::PatchArgs),
    /// Make and save one sample (HCP or relaxed amorphous): `cgdem sample CONFIG --out FILE`.
    Sample(cmd_patch::SampleArgs),
    /// Calibrate the pair parameters against the patch tests: `cgdem calibrate CONFIG --out DIR`.
    Calibrate(cmd_calibrate::CalibrateArgs),
    /// Material -> sample -> patch tests -> calibration -> card -> verification: `cgdem pipeline --out DIR`.
    Pipeline(cmd_pipeline::PipelineArgs),
    /// Plastic wear by impact (paper 001): `cgdem impact configs/impact-normal.toml --out DIR`.
    Impact(cmd_impact::ImpactArgs),
    /// Plastic wear by scratching (paper 001): `cgdem scratch configs/scratch.toml --out DIR`.
    Scratch(cmd_scratch::ScratchArgs),
    /// Cost of one impact and one scratch (paper 001), beside LAMMPS on the same contacts without wear.
    BenchPlastic(cmd_bench_plastic::BenchPlasticArgs),
    /// Junction shear (paper 000 section 4): `cgdem junction configs/junction-silica-6nm-D20.toml --out DIR`.
    Junction(cmd_junction::JunctionArgs),
    /// Automatic d* search by bisection on the junction size: `cgdem dstar configs/dstar-silica-6nm.toml --out DIR`.
    Dstar(cmd_dstar::DstarArgs),
    /// DEM against MD on the model material's d* (issue 17): `cgdem compare configs/compare-model.toml --out DIR`.
    Compare(cmd_compare::CompareArgs),
    /// Sliding with a third-body layer (paper 004): `cgdem sliding configs/sliding-quick.toml --out DIR`.
    Sliding(cmd_sliding::SlidingArgs),
    /// The validation report: every claim with figure, tolerance and verdict (`cgdem report --out DIR`).
    Report(cmd_report::ReportArgs),
}

fn main() -> Result<()> {
    let cli = Cli::parse();
    // An MD worker's stderr is its job's `worker.log`, the record of the run: it logs every stage.
    let worker = matches!(cli.command, Command::MdWorker(_));
    // The report runs many cases side by side under its own bars: their stages' lines would
    // interleave, so it shows them only with -v.
    let stages = !matches!(cli.command, Command::Report(_));
    init_logs(
        if worker {
            cli.verbose.max(1)
        } else {
            cli.verbose
        },
        stages,
    );
    // An MD worker keeps the default Ctrl-C behaviour (the process ends at once): LAMMPS cannot
    // stop mid-run cleanly, and the stages it finished are already on disk (md_bridge::stages).
    if !matches!(cli.command, Command::MdWorker(_)) {
        install_interrupt_handler();
    }
    match cli.command {
        Command::Doctor => cmd_doctor::run(),
        Command::Md(a) => cmd_md::run(a),
        Command::MdWorker(a) => cmd_md::worker(a),
        Command::BenchMd(a) => cmd_md::bench(a),
        Command::Bench(a) => cmd_bench::run(a),
        Command::Patch(a) => cmd_patch::run(a, cli.threads),
        Command::Sample(a) => cmd_patch::run_sample(a, cli.threads),
        Command::Calibrate(a) => cmd_calibrate::run(a, cli.threads),
        Command::Pipeline(a) => cmd_pipeline::run(a, cli.threads),
        Command::Impact(a) => cmd_impact::run(a),
        Command::Scratch(a) => cmd_scratch::run(a),
        Command::BenchPlastic(a) => cmd_bench_plastic::run(a),
        Command::Junction(a) => cmd_junction::run(a, cli.threads),
        Command::Dstar(a) => cmd_dstar::run(a, cli.threads),
        Command::Compare(a) => cmd_compare::run(a, cli.threads),
        Command::Sliding(a) => cmd_sliding::run(a, cli.threads),
        Command::Report(a) => cmd_report::run(a, cli.threads),
    }
}

/// Logs on stderr: by default warnings and the progress of long runs (a bar's lines off a terminal,
/// and with `stages` the periodic lines of long stages that have no bar: a relaxation's phases, a
/// patch test's strain, a calibration's iterations), `-v` every info line, `-vv` debug (`RUST_LOG`
/// wins when set); colour escapes only when stderr is a terminal.
fn init_logs(verbose: u8, stages: bool) {
    use std::io::IsTerminal;
    let quiet = if stages {
        "warn,progress=info,stage=info"
    } else {
        "warn,progress=info"
    };
    let level = match verbose {
        0 => quiet,
        1 => "info",
        _ => "debug",
    };
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env()
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new(level)),
        )
        .with_ansi(std::io::stderr().is_terminal())
        .with_writer(|| progress::LogWriter)
        .init();
}

/// The DEM threads of `--threads`: 0 takes every core the machine offers.
fn parallelism(threads: usize) -> dem::Parallelism {
    let n = if threads == 0 {
        std::thread::available_parallelism().map_or(1, |n| n.get())
    } else {
        threads
    };
    if n <= 1 {
        dem::Parallelism::Sequential
    } else {
        dem::Parallelism::Adaptive(n)
    }
}

/// First Ctrl-C: every simulation stops at its next step and the command saves what it computed
/// (checkpoints, histories; an MD job's worker ends and keeps its finished stages); second Ctrl-C:
/// exit at once.
fn install_interrupt_handler() {
    let result = ctrlc::set_handler(|| {
        if dem::interrupt::requested() {
            eprintln!("\nsecond interrupt: exiting now");
            std::process::exit(130);
        }
        eprintln!(
            "\ninterrupt: stopping at the next step and saving; Ctrl-C again to exit at once"
        );
        dem::interrupt::request();
    });
    if let Err(e) = result {
        tracing::warn!("cannot install the Ctrl-C handler: {e}");
    }
}
