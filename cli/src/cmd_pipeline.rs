//! `cgdem pipeline --out DIR`: the workbench's main job. Material (paper 000 Table 4, or an SI card
//! such as the one `cgdem md silica` writes) -> samples -> uncalibrated patch tests -> calibration ->
//! calibrated card -> verification on fresh samples of the recipe, then a summary table (target,
//! uncalibrated, calibrated, verified mean with its error and spread, d*). Everything goes under DIR:
//! `calibration/` (checkpoint, history, samples, card), `card.toml`, `verification.json`,
//! `summary.txt`, `calibration.png`. Resumable like `cgdem calibrate`.
//!
//! Table 4 runs on an HCP lattice of `--size` d0 (default 8). An SI card runs the recipe and solver
//! of `configs/calibrate-silica.toml` (the junction's discretisation: amorphous, d0 = 3 nm,
//! d_s = 0.75 d0, d_l = 7.5 nm, s = 1/2) with the card's material, on five samples 12 d0 thick
//! (that config's are three, 6 d0 thick; [`calibrate::SI_SEEDS`] says why).

use std::path::PathBuf;

use anyhow::{Context, Result};
use calibrate::{card_material, CalibrationConfig};
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
    /// Sample edge L in particle diameters; default 8 (HCP, Table 4) or the silica config's.
    #[arg(long)]
    pub size: Option<f64>,
    /// Samples every evaluation relaxes with the trial parameters (seeds 1..=K) on an amorphous
    /// recipe; default 5 for an SI card. More seeds lower the noise the solver sees, at K times the
    /// cost of one.
    #[arg(long)]
    pub seeds: Option<u64>,
    /// Thickness W of the calibration's samples in particle diameters (the verification keeps its
    /// rule: one sample twice as thick); default 12 for an SI card.
    #[arg(long)]
    pub thickness: Option<f64>,
}

fn config(args: &PipelineArgs) -> Result<CalibrationConfig> {
    let mut cfg = match &args.material {
        None => CalibrationConfig::table4_hcp(args.nu, 8.0),
        Some(path) => CalibrationConfig::si_card(
            card_material(path)
                .with_context(|| format!("reading the material card {}", path.display()))?,
        )?,
    };
    if let Some(k) = args.seeds {
        if k == 0 {
            anyhow::bail!("--seeds must be at least 1");
        }
        cfg.recipe.seeds = Some((1..=k).collect());
    }
    if let Some(w) = args.thickness {
        if !(w.is_finite() && w > 0.0) {
            anyhow::bail!("--thickness must be a positive number of particle diameters, not {w}");
        }
    }
    cfg.set_sample_size(args.size, args.thickness);
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
        "material -> samples -> uncalibrated patch tests -> calibration -> verification ({})",
        dir.display()
    );
    let o = super::cmd_calibrate::run_config(&cfg, &dir, threads)?;
    o.card.write(&args.out.join("card.toml"))?;
    let card = calibrate::CalibratedCard::read(&args.out.join("card.toml"))?;
    let v = card
        .verification
        .as_ref()
        .context("the card has no verification")?;
    std::fs::write(
        args.out.join("verification.json"),
        serde_json::to_string_pretty(&serde_json::json!({
            "targets": card.targets, "uncalibrated": card.uncalibrated,
            "calibrated": card.calibrated, "verified": v.means(), "verification": v,
        }))?,
    )?;
    let sample = match &card.sample {
        SampleSpec::Hcp { .. } => "HCP",
        SampleSpec::Amorphous { .. } => "amorphous",
        SampleSpec::HexMonolayer { .. } => "hex monolayer",
        SampleSpec::File { .. } => "file",
    };
    let text = format!(
        "cgdem pipeline: {} recipe, {} calibration sample(s), units {}\n{}\n{}{} iterations, {} evaluations, status {:?}; total {:.1} s\n",
        sample,
        o.problem.samples.len(),
        card.units,
        super::cmd_calibrate::table(&card.targets, &card.uncalibrated, &card.calibrated, Some(v)),
        super::cmd_calibrate::verification_lines(v, &card.units),
        card.provenance.iterations,
        card.provenance.evaluations,
        card.provenance.status,
        t0.elapsed().as_secs_f64()
    );
    print!("{text}");
    std::fs::write(args.out.join("summary.txt"), text)?;
    super::cmd_calibrate::draw_figure(&o, &args.out.join("calibration.png"))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use calibrate::{SI_SEEDS, SI_THICKNESS};

    fn args(seeds: Option<u64>) -> PipelineArgs {
        PipelineArgs {
            out: "out".into(),
            material: None,
            nu: 0.15,
            size: None,
            seeds,
            thickness: None,
        }
    }

    #[test]
    fn seeds_set_the_recipe_and_zero_is_refused() {
        assert_eq!(
            config(&args(Some(5))).unwrap().recipe.seeds,
            Some(vec![1, 2, 3, 4, 5])
        );
        assert_eq!(
            config(&args(None)).unwrap().recipe.seeds,
            CalibrationConfig::table4_hcp(0.15, 8.0).recipe.seeds
        );
        let e = config(&args(Some(0))).unwrap_err().to_string();
        assert!(e.contains("--seeds"), "{e}");
    }

    fn w(cfg: &CalibrationConfig) -> f64 {
        match cfg.sample {
            SampleSpec::Hcp { w_over_d0, .. } | SampleSpec::Amorphous { w_over_d0, .. } => {
                w_over_d0
            }
            _ => unreachable!("the pipeline's recipes are HCP or amorphous"),
        }
    }

    #[test]
    fn an_si_card_is_calibrated_on_five_12_d0_samples_unless_told_otherwise() {
        let card =
            std::env::temp_dir().join(format!("cgdem-pipeline-card-{}.toml", std::process::id()));
        std::fs::write(
            &card,
            "[material]\nyoung_modulus = 98.7e9\npoisson_ratio = 0.233\ntensile_strength = 16.0e9\n\
             shear_strength = 9.91e9\nsurface_energy = 1.36\nrestitution = 0.9\ndensity = 2495.0\n",
        )
        .unwrap();
        let a = PipelineArgs {
            material: Some(card.clone()),
            ..args(None)
        };
        let cfg = config(&a).unwrap();
        assert_eq!(cfg.recipe.seeds, Some((1..=SI_SEEDS).collect()));
        assert_eq!(w(&cfg), SI_THICKNESS);
        let a = PipelineArgs {
            material: Some(card.clone()),
            thickness: Some(6.0),
            ..args(Some(3))
        };
        let cfg = config(&a).unwrap();
        assert_eq!(cfg.recipe.seeds, Some(vec![1, 2, 3]));
        assert_eq!(w(&cfg), 6.0);
        std::fs::remove_file(card).unwrap();
    }

    #[test]
    fn thickness_sets_the_recipe_and_a_bad_one_is_refused() {
        let a = PipelineArgs {
            thickness: Some(12.0),
            ..args(None)
        };
        assert_eq!(w(&config(&a).unwrap()), 12.0);
        assert_ne!(w(&config(&args(None)).unwrap()), 12.0);
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let a = PipelineArgs {
                thickness: Some(bad),
                ..args(None)
            };
            let e = config(&a).unwrap_err().to_string();
            assert!(e.contains("--thickness"), "{e}");
        }
    }
}
