//! `cgdem patch <config.toml>`: a campaign of patch tests (paper 000 section 3), and
//! `cgdem sample <config.toml>`: make and save one sample (HCP or relaxed amorphous) for reuse.
//!
//! The TOML of `patch` is [`dem::scenario::patch::PatchSuite`]; results go to `--out` (default
//! `out/patch`): `report.json` (rewritten after every case) and one CSV stress-strain curve per test
//! and case. Rerunning the same campaign into the same directory continues it: finished cases are
//! reused (Ctrl-C or a crash loses at most the case in progress); another campaign's report there is
//! refused, not overwritten. The TOML of `sample` is [`SampleConfig`].

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use dem::material::{Material, PairModel, ParamScale};
use dem::sample::RelaxConfig;
use dem::sample::{make_sample_resumable, SampleSpec};
use dem::scenario::patch::{run_suite, ModelSource, PatchSuite, ProgressFile};
use serde::Deserialize;

/// Arguments of `cgdem patch`.
#[derive(Debug, Args)]
pub struct PatchArgs {
    /// TOML campaign (see configs/patch-*.toml).
    pub config: PathBuf,
    /// Output directory.
    #[arg(long, default_value = "out/patch")]
    pub out: PathBuf,
    /// A calibrated card (`cgdem calibrate` writes `card.toml`): its pair model replaces the
    /// campaign's `material` and `scale` (same as `[model] card = "FILE"` in the campaign).
    #[arg(long)]
    pub card: Option<PathBuf>,
    /// The seed of the campaign's amorphous sample recipe (re-measure a card on a sample of one's
    /// choosing).
    #[arg(long)]
    pub seed: Option<u64>,
}

/// Arguments of `cgdem sample`.
#[derive(Debug, Args)]
pub struct SampleArgs {
    /// TOML sample description (see configs/sample-*.toml).
    pub config: PathBuf,
    /// Output file (JSON).
    #[arg(long, default_value = "out/sample.json")]
    pub out: PathBuf,
}

/// What `cgdem sample` reads.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SampleConfig {
    /// Target material; default Table 4 with nu = 0.15 (paper 000 section 3).
    #[serde(default = "table4")]
    pub material: Material,
    /// Calibration multipliers; default all 1.
    #[serde(default)]
    pub scale: ParamScale,
    pub sample: SampleSpec,
    /// Relaxation (amorphous samples); default the paper's.
    #[serde(default)]
    pub relax: RelaxConfig,
}

fn table4() -> Material {
    Material::table4(0.15)
}

fn read_toml<T: serde::de::DeserializeOwned>(path: &std::path::Path) -> Result<T> {
    crate::config::read(path)
}

/// The campaign of `args`: its file, with the card's pair model read in (`--card`, or `[model] card`
/// relative to the campaign's folder) and the seed replaced.
fn campaign(args: &PatchArgs) -> Result<PatchSuite> {
    let mut suite: PatchSuite = read_toml(&args.config)?;
    let card = match (&args.card, &suite.model) {
        (Some(path), _) => Some(path.clone()),
        (None, Some(m)) => Some(
            args.config
                .parent()
                .unwrap_or(std::path::Path::new("."))
                .join(&m.card),
        ),
        (None, None) => None,
    };
    if let Some(path) = card {
        let c = calibrate::CalibratedCard::read(&path)
            .with_context(|| format!("reading the card {}", path.display()))?;
        suite.model = Some(ModelSource {
            card: path,
            pair_model: Some(c.pair_model()?),
        });
    }
    if let Some(seed) = args.seed {
        if suite.sample.seed().is_none() {
            anyhow::bail!(
                "--seed needs an amorphous [sample] recipe (a lattice or a file has no seed)"
            );
        }
        suite.sample = suite.sample.with_seed(seed);
    }
    Ok(suite)
}

/// Runs `cgdem patch`.
pub fn run(args: PatchArgs, threads: usize) -> Result<()> {
    let suite = campaign(&args)?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let report = run_suite(&suite, Some(&args.out), crate::parallelism(threads))?;
    for (k, c) in report.cases.iter().enumerate() {
        let e = c
            .elastic
            .as_ref()
            .map(|r| format!(" E {:.4} nu {:.4}", r.young_modulus, r.poisson_ratio));
        let t = c
            .tensile
            .as_ref()
            .map(|r| format!(" tensile {:.4}{}", r.strength, of_target(r.ratio)));
        let s = c
            .shear
            .as_ref()
            .map(|r| format!(" shear {:.4}{}", r.strength, of_target(r.ratio)));
        let co = c.compaction.as_ref().map(|r| {
            format!(
                " compaction under shear {:.2} % (largest {:.2} %{}) at strain {:.2}, friction {:.2}",
                100.0 * r.compaction,
                100.0 * r.largest_compaction,
                if r.collapsed { ", COLLAPSING" } else { "" },
                r.shear_strain,
                r.friction
            )
        });
        println!(
            "case {k}: d0/dc {:?} nu {} s {} n {} vf {:.4} Z {:.2} compressed {:.0} % gap 5-95 % [{:+.3}, {:+.3}]{}{}{}{}",
            c.d0_over_dc,
            c.poisson_ratio,
            c.scaling,
            c.particles,
            c.volume_fraction,
            c.coordination.interacting,
            100.0 * c.gaps.compressed,
            c.gaps.quantiles[0],
            c.gaps.quantiles[4],
            e.unwrap_or_default(),
            t.unwrap_or_default(),
            s.unwrap_or_default(),
            co.unwrap_or_default()
        );
    }
    println!("report: {}", args.out.join("report.json").display());
    let figures = validation::figures::patch::draw(&report, &args.out)
        .context("drawing the campaign's figures (the report above is complete)")?;
    for f in figures {
        println!("figure: {}", f.display());
    }
    Ok(())
}

/// Runs `cgdem sample`.
pub fn run_sample(args: SampleArgs, threads: usize) -> Result<()> {
    let cfg: SampleConfig = read_toml(&args.config)?;
    let mut model = PairModel::cohesive(cfg.material);
    model.scale = cfg.scale;
    // A long relaxation keeps its progress beside the output: rerun the command to continue it.
    let mut progress = args.out.clone().into_os_string();
    progress.push(".progress.json");
    let progress = ProgressFile::new(PathBuf::from(progress));
    let par = crate::parallelism(threads);
    let sample = make_sample_resumable(&cfg.sample, &model, &cfg.relax, par, Some(&progress))?;
    sample.save(&args.out)?;
    dem::io::progress::remove(&progress.path)?;
    println!(
        "{} particles, volume fraction {:.4}, written to {}",
        sample.particles.len(),
        sample.volume_fraction(),
        args.out.display()
    );
    if let Some(r) = &sample.relaxation {
        println!("{}", serde_json::to_string_pretty(r)?);
    }
    Ok(())
}

/// " (x.x %)" of a strength's target, or nothing where the law has none.
fn of_target(ratio: Option<f64>) -> String {
    ratio.map_or(String::new(), |r| format!(" ({:.1} %)", 100.0 * r))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn configs() -> PathBuf {
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../configs")
    }

    #[test]
    fn shipped_configs_parse() {
        for entry in std::fs::read_dir(configs()).unwrap() {
            let path = entry.unwrap().path();
            let name = path.file_name().unwrap().to_string_lossy().to_string();
            if name.starts_with("patch-") {
                read_toml::<PatchSuite>(&path).unwrap();
            } else if name.starts_with("sample-") {
                read_toml::<SampleConfig>(&path).unwrap();
            }
        }
    }

    #[test]
    fn bad_configs_are_errors_not_panics() {
        let dir = std::env::temp_dir().join(format!("cgdem_patch_cfg_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let bad = dir.join("bad.toml");
        std::fs::write(
            &bad,
            "[sample]\nkind = \"hcp\"\nd0_over_dc = 0.6\nl_over_d0 = 8.0\nw_over_d0 = 3.0\ncolour = 1\n",
        )
        .unwrap();
        assert!(read_toml::<PatchSuite>(&bad).is_err(), "unknown field");
        assert!(read_toml::<PatchSuite>(&dir.join("missing.toml")).is_err());
        // Parses, but the sample is too thin for two walls: an error from the run.
        std::fs::write(
            &bad,
            "tests = [\"elastic\"]\n[sample]\nkind = \"hcp\"\nd0_over_dc = 0.6\nl_over_d0 = 2.0\nw_over_d0 = 3.0\n",
        )
        .unwrap();
        let out = dir.join("out");
        assert!(run(
            PatchArgs {
                config: bad.clone(),
                out,
                card: None,
                seed: None,
            },
            1
        )
        .is_err());
        std::fs::remove_dir_all(&dir).ok();
    }
}
