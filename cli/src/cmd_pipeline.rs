//! `cgdem pipeline --out DIR`: the workbench's main job on small default settings. Material (paper 000
//! Table 4, or an SI card such as the one `cgdem md silica` writes) -> sample -> uncalibrated patch
//! tests -> calibration -> calibrated card -> verification patch tests (re-run with the card's model),
//! then a summary table (target, uncalibrated, calibrated, verified, errors). Everything goes under DIR:
//! `calibration/` (checkpoint, history, sample, card), `card.toml`, `verification.json`, `summary.txt`.
//! Resumable like `cgdem calibrate`.

use std::path::PathBuf;

use anyhow::{Context, Result};
use calibrate::{CalibrationConfig, SiMaterial};
use clap::Args;
use dem::sample::SampleSpec;

/// Arguments of `cgdem pipeline`.
#[derive(Debug, Args)]
pub struct PipelineArgs {
    /// Output directory.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// SI material card (`[material]` with young_modulus, poisson_ratio, tensile_strength,
    /// shear_strength, surface_energy, restitution, density, optional scaling); default Table 4.
    #[arg(long)]
    pub material: Option<PathBuf>,
    /// Poisson's ratio of the Table 4 material.
    #[arg(long, default_value_t = 0.15)]
    pub nu: f64,
    /// Sample edge in particle diameters (HCP for Table 4, amorphous for an SI card).
    #[arg(long, default_value_t = 8.0)]
    pub size: f64,
}

fn config(args: &PipelineArgs) -> Result<CalibrationConfig> {
    let base = |sample| format!("{sample}\n[solver]\nmax_iterations = 12\n");
    let text = match &args.material {
        None => base(&format!(
            "[material]\nyoung_modulus = 1.0\npoisson_ratio = {}\ntensile_strength = 0.2\n\
             shear_strength = 0.1\nsurface_energy = 1.5\nrestitution = 0.95\ndensity = 1.0\n\
             [sample]\nkind = \"hcp\"\nd0_over_dc = 0.6\nl_over_d0 = {}\nw_over_d0 = 3.0\n",
            args.nu, args.size
        )),
        Some(_) => base(&format!(
            "d0_m = 3e-9\n[sample]\nkind = \"amorphous\"\nd0_over_dc = 1.0\nl_over_d0 = {}\n\
             w_over_d0 = 3.0\nds_over_d0 = 0.75\ndl_over_d0 = 2.5\nseed = 1\n",
            args.size
        )),
    };
    let mut cfg = CalibrationConfig::from_toml(&text)?;
    if let Some(path) = &args.material {
        cfg.material_si = Some(SiMaterial::from_card(path)?);
    }
    Ok(cfg)
}

/// Runs `cgdem pipeline`.
pub fn run(args: PipelineArgs, threads: usize) -> Result<()> {
    let t0 = std::time::Instant::now();
    let cfg = config(&args)?;
    // Refuse unreachable targets before any simulation.
    cfg.prepare().context("checking the material")?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let dir = args.out.join("calibration");
    std::fs::write(
        args.out.join("calibration.toml"),
        toml::to_string_pretty(&cfg)?,
    )?;
    println!(
        "material -> sample -> uncalibrated patch tests -> calibration ({})",
        dir.display()
    );
    let o = super::cmd_calibrate::run_config(&cfg, &dir, threads)?;
    o.card.write(&args.out.join("card.toml"))?;
    println!("verification: re-running the patch tests with the card's model");
    let t1 = std::time::Instant::now();
    let card = calibrate::CalibratedCard::read(&args.out.join("card.toml"))?;
    let verified = calibrate::verify(&o.problem, &card)?;
    let verify_s = t1.elapsed().as_secs_f64();
    std::fs::write(
        args.out.join("verification.json"),
        serde_json::to_string_pretty(&serde_json::json!({
            "targets": card.targets, "uncalibrated": card.uncalibrated,
            "calibrated": card.calibrated, "verified": verified, "seconds": verify_s,
        }))?,
    )?;
    let sample = match &card.sample {
        SampleSpec::Hcp { .. } => "HCP",
        SampleSpec::Amorphous { .. } => "amorphous",
        SampleSpec::File { .. } => "file",
    };
    let text = format!(
        "cgdem pipeline: {} sample of {} particles, units {}\n{}\n{} iterations, {} evaluations, status {:?}; total {:.1} s\n",
        sample,
        o.problem.sample.particles.len(),
        card.units,
        super::cmd_calibrate::table(&card.targets, &card.uncalibrated, &card.calibrated, Some(&verified)),
        card.provenance.iterations,
        card.provenance.evaluations,
        card.provenance.status,
        t0.elapsed().as_secs_f64()
    );
    print!("{text}");
    std::fs::write(args.out.join("summary.txt"), text)?;
    super::cmd_calibrate::draw_figure(&o, Some(&verified), &args.out.join("calibration.png"))?;
    Ok(())
}
