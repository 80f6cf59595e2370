//! `cgdem md ...`, `cgdem md-worker`, `cgdem bench-md`: the MD stage. Jobs run in a child process
//! (this same binary, `md-worker`), optionally under the venv's `mpirun`, and are cached on disk.

use anyhow::{bail, Context, Result};
use clap::{Args, Subcommand};
use md_bridge::card::{compare_with_table5, MaterialCard, Provenance, SiMaterial};
use md_bridge::job::{run_job, Job, JobOutput, JobRecord, RunOptions};
use md_bridge::silica::{SilicaConfig, SilicaResult};
use md_bridge::Venv;
use std::path::{Path, PathBuf};

#[derive(Debug, Args)]
pub struct MdArgs {
    #[command(subcommand)]
    what: MdWhat,
}

#[derive(Debug, Args)]
pub struct Launch {
    /// MPI ranks (runs the worker under the venv's mpirun when > 1).
    #[arg(long, default_value_t = 1)]
    np: u32,
    /// Job cache directory (default: runs/md-cache in the repository).
    #[arg(long)]
    cache: Option<PathBuf>,
    /// Re-run even when an identical request is cached.
    #[arg(long)]
    no_cache: bool,
}

#[derive(Debug, Subcommand)]
enum MdWhat {
    /// Amorphous silica (Vashishta 1990): melt-quench, properties, material card.
    Silica {
        /// TOML with [`SilicaConfig`] fields; missing fields take the defaults.
        #[arg(long)]
        config: Option<PathBuf>,
        /// Output directory (card.toml, silica.json).
        #[arg(long)]
        out: PathBuf,
        #[command(flatten)]
        launch: Launch,
    },
    /// The 2D Lennard-Jones model material: properties and d* (reduced units).
    Model {
        /// TOML with `ModelConfig` fields; missing fields take the defaults.
        #[arg(long)]
        config: Option<PathBuf>,
        /// Output directory (model.json).
        #[arg(long)]
        out: PathBuf,
        #[command(flatten)]
        launch: Launch,
    },
    /// Junction shear of the model material (2D), classified as plastic or wear particle.
    Junction {
        /// TOML with `JunctionConfig` fields; missing fields take the defaults.
        #[arg(long)]
        config: Option<PathBuf>,
        /// Junction width D in sigma (overrides the config).
        #[arg(long)]
        width: Option<f64>,
        /// Output directory (junction.json).
        #[arg(long)]
        out: PathBuf,
        #[command(flatten)]
        launch: Launch,
    },
    /// Writes (does not run) the silica junction cluster job of paper 000 section 4: LAMMPS input,
    /// glass block data and potential in OUT, and prints the `mpirun` command line.
    SilicaJunction {
        /// TOML with `SilicaJunctionConfig` fields; missing fields take the defaults (paper geometry).
        #[arg(long)]
        config: Option<PathBuf>,
        /// Junction diameter D in nm (overrides the config; paper: 10 and 20).
        #[arg(long)]
        diameter: Option<f64>,
        /// Glass block (LAMMPS data file, orthogonal box) to replicate; default: melt-quench one.
        #[arg(long)]
        glass: Option<PathBuf>,
        /// TOML with `SilicaConfig` fields for that melt-quench (measurements are not run).
        #[arg(long)]
        glass_config: Option<PathBuf>,
        /// MPI ranks for the printed cluster command line.
        #[arg(long, default_value_t = 64)]
        ranks: u32,
        /// Output directory (in.junction, glass.data, the potential, junction.toml).
        #[arg(long)]
        out: PathBuf,
        #[command(flatten)]
        launch: Launch,
    },
    /// Runs a LAMMPS input file in a worker and prints the listed equal-style variables as JSON.
    Script {
        input: PathBuf,
        /// Variables to read after the run (comma separated).
        #[arg(long, value_delimiter = ',')]
        read: Vec<String>,
        #[command(flatten)]
        launch: Launch,
    },
    /// Starts a worker that aborts on purpose: shows that a dying MD job leaves the workbench alive.
    #[command(hide = true)]
    AbortSelfTest {
        #[command(flatten)]
        launch: Launch,
    },
}

#[derive(Debug, Args)]
pub struct WorkerArgs {
    job: PathBuf,
    report: PathBuf,
}

#[derive(Debug, Args)]
pub struct BenchMdArgs {
    /// fcc cells per side of the Lennard-Jones benchmark (4 atoms each).
    #[arg(long, default_value_t = 20)]
    cells: u32,
    #[arg(long, default_value_t = 1000)]
    steps: u32,
    /// Runs per side (alternating ABBA); paired ratios and the best of each are compared.
    #[arg(long, default_value_t = 3)]
    repeats: usize,
    /// Use this LAMMPS input instead of the Lennard-Jones melt.
    #[arg(long)]
    input: Option<PathBuf>,
}

fn options(l: &Launch) -> Result<RunOptions> {
    Ok(RunOptions {
        exe: std::env::current_exe().context("cannot locate the cgdem executable")?,
        np: l.np,
        cache_dir: l
            .cache
            .clone()
            .unwrap_or_else(|| md_bridge::venv::repo_root().join("runs/md-cache")),
        venv: Venv::locate(),
        reuse_cache: !l.no_cache,
    })
}

/// Writes the job record (request, output, provenance) as pretty JSON to `out/file`.
fn save_record(rec: &JobRecord, out: &Path, file: &str) -> Result<()> {
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    std::fs::write(out.join(file), serde_json::to_string_pretty(rec)?)?;
    Ok(())
}

fn launch(job: &Job, l: &Launch) -> Result<JobRecord> {
    let (record, cached) = run_job(job, &options(l)?)?;
    let p = &record.provenance;
    eprintln!(
        "{} job {} ({} rank(s), {:.1} s)",
        if cached { "cached" } else { "ran" },
        &p.input_hash[..12],
        p.mpi_ranks,
        p.wall_seconds
    );
    Ok(record)
}

pub fn run(a: MdArgs) -> Result<()> {
    match a.what {
        MdWhat::Silica {
            config,
            out,
            launch: l,
        } => silica(config.as_deref(), &out, &l),
        MdWhat::Model {
            config,
            out,
            launch: l,
        } => model(config.as_deref(), &out, &l),
        MdWhat::Junction {
            config,
            width,
            out,
            launch: l,
        } => junction(config.as_deref(), width, &out, &l),
        MdWhat::SilicaJunction {
            config,
            diameter,
            glass,
            glass_config,
            ranks,
            out,
            launch: l,
        } => silica_junction(
            config.as_deref(),
            diameter,
            glass.as_deref(),
            glass_config.as_deref(),
            ranks,
            &out,
            &l,
        ),
        MdWhat::Script {
            input,
            read,
            launch: l,
        } => {
            let commands = std::fs::read_to_string(&input)
                .with_context(|| format!("reading {}", input.display()))?;
            let rec = launch(
                &Job::Script {
                    commands,
                    read_variables: read,
                    seed: 0,
                },
                &l,
            )?;
            match rec.output {
                JobOutput::Script { variables } => {
                    println!("{}", serde_json::to_string_pretty(&variables)?)
                }
                other => bail!("unexpected output {other:?}"),
            }
            Ok(())
        }
        MdWhat::AbortSelfTest { launch: l } => {
            launch(&Job::AbortSelfTest, &l)?;
            bail!("the abort self-test worker did not abort")
        }
    }
}

fn silica(config: Option<&Path>, out: &Path, l: &Launch) -> Result<()> {
    let cfg: SilicaConfig = read_config(config, "silica")?;
    cfg.validate()?;
    let rec = launch(&Job::Silica(cfg.clone()), l)?;
    let JobOutput::Silica(res) = &rec.output else {
        bail!("unexpected output {:?}", rec.output)
    };
    save_record(&rec, out, "silica.json")?;
    print_summary(res, &cfg);
    if res.tension.is_some() || res.shear.is_some() {
        let path = out.join("silica.png");
        let t5 = SiMaterial::table5();
        let reference = (t5.tensile_strength, t5.shear_strength);
        validation::figures::md::draw(&path, res.tension.as_ref(), res.shear.as_ref(), reference)
            .context("drawing the loading curves (silica.json above is complete)")?;
        println!("figure: {}", path.display());
    }
    match card(res, &rec, &cfg) {
        Some(card) => {
            card.write(&out.join("card.toml"))?;
            println!("\n{}", compare_with_table5(&card.material));
            println!("card written to {}", out.join("card.toml").display());
        }
        None => println!("strength or surface measurement disabled: no card written"),
    }
    Ok(())
}

fn print_summary(r: &SilicaResult, cfg: &SilicaConfig) {
    println!(
        "atoms {}  density {:.0} kg/m3 at {} K (0 K: {:.0})",
        r.n_atoms, r.density, cfg.quench_end_temperature, r.density_0k
    );
    println!(
        "C11 {:.1} GPa  C12 {:.1} GPa  C44 {:.1} GPa  ->  E {:.1} GPa  nu {:.3}  ({})",
        r.c11 / 1e9,
        r.c12 / 1e9,
        r.c44 / 1e9,
        r.young_modulus / 1e9,
        r.poisson_ratio,
        if cfg.elastic_temperature > 0.0 {
            format!("thermal average at {} K", cfg.elastic_temperature)
        } else {
            "0 K, relaxed ions".to_owned()
        }
    );
    for (name, s) in [("tension", &r.tension), ("shear", &r.shear)] {
        if let Some(s) = s {
            println!(
                "{name}: peak {:.2} GPa at strain {:.3}{}",
                s.peak_stress / 1e9,
                s.peak_strain,
                if s.peak_reached {
                    ""
                } else {
                    " (NOT past the peak: raise the max strain)"
                }
            );
        }
    }
    if let (Some(g0), Some(g)) = (r.surface_energy_unrelaxed, r.surface_energy) {
        println!(
            "surface energy {g:.3} J/m2, mean of {} cleave plane(s): {} (cleaved + minimised only: {g0:.3})",
            r.surface_cleaves.len(),
            annealed_planes(r)
        );
    }
    let t: Vec<String> = r
        .timings
        .iter()
        .map(|(n, s)| format!("{n} {s:.0}s"))
        .collect();
    println!("timings: {}", t.join(", "));
}

/// The annealed surface energy of each cleave plane, J/m^2, as a list.
fn annealed_planes(r: &SilicaResult) -> String {
    let g: Vec<String> = r
        .surface_cleaves
        .iter()
        .map(|c| format!("{:.3}", c[1]))
        .collect();
    g.join(", ")
}

/// The card needs every property; None when a measurement was switched off.
fn card(r: &SilicaResult, rec: &JobRecord, cfg: &SilicaConfig) -> Option<MaterialCard> {
    let p = &rec.provenance;
    Some(MaterialCard {
        material: r.material()?,
        provenance: Provenance {
            source: "cgdem md silica (md-bridge, LAMMPS via PyO3, worker process)".into(),
            lammps_version: p.lammps_version.clone(),
            potential: p.potential.clone().unwrap_or_default(),
            potential_sha256: p.potential_sha256.clone().unwrap_or_default(),
            input_hash: p.input_hash.clone(),
            seed: p.seed,
            mpi_ranks: p.mpi_ranks,
            cgdem_version: p.cgdem_version.clone(),
            notes: vec![
                "restitution = 0.9 is not measured: taken from paper 000 Table 5 (chosen arbitrarily there)".into(),
                format!(
                    "{} atoms; melt {} K, quench {} K/ps to {} K; density averaged over the anneal",
                    r.n_atoms, cfg.melt_temperature, cfg.quench_rate, cfg.quench_end_temperature
                ),
                format!(
                    "E, nu: Voigt average of C11 {:.1}, C12 {:.1}, C44 {:.1} GPa {}",
                    r.c11 / 1e9,
                    r.c12 / 1e9,
                    r.c44 / 1e9,
                    if cfg.elastic_temperature > 0.0 {
                        format!(
                            "at {} K (stress averaged {} ps per +-{} strain)",
                            cfg.elastic_temperature, cfg.elastic_md_ps, cfg.elastic_strain
                        )
                    } else {
                        format!("at 0 K, relaxed ions (+-{} strain)", cfg.elastic_strain)
                    }
                ),
                format!(
                    "strengths: peak stress at {} K, strain rate {}/ps; tension lateral stress-free, simple shear xy",
                    cfg.strength_temperature, cfg.strain_rate
                ),
                format!(
                    "surface energy: glass replicated {:?} (x, y, z), cleaved along z, annealed {} ps at {} K, minimised; the bulk reference replicated, annealed and minimised alike; mean of {} cleave planes z = lo + k Lz / {}: {}",
                    cfg.surface_replicate,
                    cfg.surface_anneal_ps,
                    cfg.surface_anneal_temperature,
                    cfg.surface_cleaves,
                    cfg.surface_cleaves,
                    annealed_planes(r)
                ),
            ],
        },
    })
}

pub fn worker(a: WorkerArgs) -> Result<()> {
    md_bridge::worker::worker_main(&a.job, &a.report)?;
    Ok(())
}

pub fn bench(a: BenchMdArgs) -> Result<()> {
    let venv = Venv::locate();
    venv.check()?;
    let dir = std::env::temp_dir().join(format!("cgdem-bench-md-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;
    let input = match &a.input {
        Some(p) => p.clone(),
        None => {
            let p = dir.join("in.lj");
            std::fs::write(&p, md_bridge::bench::lj_input(a.cells, a.steps))?;
            p
        }
    };
    let load = loadavg();
    let r = md_bridge::bench::bench_overhead(&venv, &input, a.repeats)?;
    let _ = std::fs::remove_dir_all(&dir);
    let fmt = |v: &[f64]| {
        v.iter()
            .map(|s| format!("{s:.3}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    println!(
        "input: {}",
        a.input.as_ref().map_or(
            format!("LJ melt, {} atoms, {} steps", 4 * a.cells.pow(3), a.steps),
            |p| p.display().to_string()
        )
    );
    println!("bridge (s): {}", fmt(&r.bridge_seconds));
    println!("lmp    (s): {}", fmt(&r.lmp_seconds));
    println!("bridge cpu (s): {}", fmt(&r.bridge_cpu_seconds));
    println!("lmp    cpu (s): {}", fmt(&r.lmp_cpu_seconds));
    let stats = |name: &str, v: &[f64]| {
        let (lo, hi) = md_bridge::bench::range(v);
        let m = md_bridge::bench::median(v);
        println!(
            "{name} ratio bridge/lmp, paired per repeat: median {m:.4} ({:+.2} %), range {lo:.4} .. {hi:.4}",
            (m - 1.0) * 100.0
        );
    };
    stats("wall", &r.pair_ratios);
    stats("cpu ", &r.cpu_pair_ratios);
    println!(
        "best of each: wall ratio {:.4} ({:+.2} %), cpu ratio {:.4} ({:+.2} %)",
        r.ratio,
        (r.ratio - 1.0) * 100.0,
        r.cpu_ratio,
        (r.cpu_ratio - 1.0) * 100.0
    );
    println!(
        "load average before/after: {} / {}",
        load.trim(),
        loadavg().trim()
    );
    Ok(())
}

/// The 1, 5 and 15 minute load averages (other users of the machine perturb the timings).
fn loadavg() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".into())
}

fn model(config: Option<&Path>, out: &Path, l: &Launch) -> Result<()> {
    let cfg: md_bridge::model::ModelConfig = read_config(config, "model")?;
    cfg.validate()?;
    let rec = launch(&Job::Model(cfg.clone()), l)?;
    let JobOutput::Model(r) = &rec.output else {
        bail!("unexpected output {:?}", rec.output)
    };
    save_record(&rec, out, "model.json")?;
    println!(
        "2D LJ hex crystal, cutoff {} sigma, {} atoms ({:.0} atoms/nm2 at sigma = {} nm)",
        cfg.cutoff, r.n_atoms, r.atoms_per_nm2, cfg.sigma_nm
    );
    println!(
        "C11 {:.2}  C12 {:.2}  C66 {:.2}  ->  E {:.2}  nu {:.3}  G {:.2}  (epsilon/sigma^2)",
        r.c11, r.c12, r.c66, r.young_modulus, r.poisson_ratio, r.shear_modulus
    );
    println!(
        "tension peak {:.3} at strain {:.3}; shear peak {:.3} at strain {:.3}",
        r.tension.peak_stress, r.tension.peak_strain, r.shear.peak_stress, r.shear.peak_strain
    );
    println!("surface energy {:.3} epsilon/sigma", r.surface_energy);
    println!(
        "d_min {:.2}  d_c {:.2}  d* {:.2} sigma  (d* = {:.2} nm)",
        r.d_min, r.d_c, r.d_star, r.d_star_nm
    );
    Ok(())
}

fn junction(config: Option<&Path>, width: Option<f64>, out: &Path, l: &Launch) -> Result<()> {
    let mut cfg: md_bridge::junction::JunctionConfig = read_config(config, "junction")?;
    if let Some(w) = width {
        cfg.width = w;
    }
    cfg.validate()?;
    let rec = launch(&Job::Junction(cfg.clone()), l)?;
    let JobOutput::Junction(r) = &rec.output else {
        bail!("unexpected output {:?}", rec.output)
    };
    save_record(&rec, out, "junction.json")?;
    let v = &r.verdict;
    println!(
        "D = {} sigma, cutoff {}: {} atoms ({} in the junction)",
        cfg.width, cfg.cutoff, r.n_atoms, r.junction_atoms
    );
    println!(
        "verdict {:?}: turn {:.2} rad, rigidity {:.2}, peak force {:.2}, late/peak {:.2}",
        v.outcome,
        v.turn,
        v.rigidity,
        v.force_peak.unwrap_or(f64::NAN),
        v.force_late_over_peak.unwrap_or(f64::NAN)
    );
    println!("frames: LAMMPS dump `junction.dump` in the job's cache directory");
    Ok(())
}

fn silica_junction(
    config: Option<&Path>,
    diameter: Option<f64>,
    glass: Option<&Path>,
    glass_config: Option<&Path>,
    ranks: u32,
    out: &Path,
    l: &Launch,
) -> Result<()> {
    use md_bridge::silica::junction::{mpirun_command, write_job, SilicaJunctionConfig};
    let mut cfg: SilicaJunctionConfig = read_config(config, "silica junction")?;
    if let Some(d) = diameter {
        cfg.diameter_nm = d;
    }
    cfg.validate()?;
    if ranks == 0 {
        bail!("--ranks must be >= 1");
    }
    let data = match glass {
        Some(p) => {
            if glass_config.is_some() {
                bail!("give either --glass or --glass-config, not both");
            }
            std::fs::read_to_string(p).with_context(|| format!("reading {}", p.display()))?
        }
        None => {
            let gcfg: SilicaConfig = read_config(glass_config, "silica glass")?;
            gcfg.validate()?;
            let rec = launch(&Job::SilicaGlass(gcfg), l)?;
            let JobOutput::SilicaGlass { density, data } = rec.output else {
                bail!("unexpected output {:?}", rec.output)
            };
            println!("glass block: melt-quenched, {density:.0} kg/m3");
            data
        }
    };
    let venv = Venv::locate();
    let pot = venv.potential(md_bridge::silica::POTENTIAL)?;
    let p = write_job(&cfg, &data, &pot, out)?;
    println!(
        "silica junction D = {} nm, H = {:.2} nm, box {:.2} x {:.2} x {:.2} nm ({} x {} x {} blocks)",
        cfg.diameter_nm,
        p.height_nm,
        p.box_nm[0],
        p.box_nm[1],
        p.box_nm[2],
        p.replicas[0],
        p.replicas[1],
        p.replicas[2]
    );
    println!(
        "~{:.2} M atoms; relax {} steps, shear {} steps ({:.2} ns, slide {} D at {} m/s, {} MPa)",
        p.atoms_estimate as f64 / 1e6,
        p.relax_steps,
        p.shear_steps,
        p.shear_steps as f64 * cfg.timestep_fs * 1e-6,
        cfg.slide_factor,
        cfg.velocity_m_s,
        cfg.normal_pressure_mpa
    );
    println!(
        "estimated cost: {:.0} core-hours at {} us per atom-step and core ({:.0} h on {ranks} ranks with ideal scaling)",
        p.core_hours_estimate,
        md_bridge::silica::junction::SECONDS_PER_ATOM_STEP * 1e6,
        p.core_hours_estimate / ranks as f64
    );
    println!("written to {} (not run here)", out.display());
    println!("launch on the cluster, from that directory:");
    println!("  {}", mpirun_command(ranks));
    println!(
        "quick check of the input (a few steps of each stage, one rank):\n  lmp -var min_iter 10 -var relax_steps 10 -var shear_steps 10 -in {}",
        md_bridge::silica::junction::INPUT_FILE
    );
    Ok(())
}

/// An optional TOML config file, or the defaults when none is given.
fn read_config<T: serde::de::DeserializeOwned + Default>(
    config: Option<&Path>,
    what: &str,
) -> Result<T> {
    let Some(p) = config else {
        return Ok(T::default());
    };
    crate::config::read(p).with_context(|| format!("reading the {what} config"))
}
