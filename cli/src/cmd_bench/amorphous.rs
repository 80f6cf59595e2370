//! The amorphous workload: paper 000's silica (Table 5 in SI, brought to nm, ag and ns by
//! `UnitSystem::NANO`) at d0 = 0.877 d_c (the 1.5 nm of the finest junction run, section 4), sizes
//! log-normal in [0.75, 5] d0, s = 1/2, relaxed by the paper's two-phase procedure (section 3.2) in a
//! periodic cube of `--length` d0: 32.5 d0 gives about 6 300 particles, the junction's count (Table 6).
//!
//! - The relaxed sample is a job of `dem::jobs`: made once, cached under its inputs (recipe, material,
//!   relaxation settings) in `--cache`, and resumed from its progress file if interrupted.
//! - Motion. The relaxed sample is at rest; the bench gives every particle the junction's sliding
//!   velocity, 10 m/s along x, plus a seeded random part of up to 1 m/s per component. The translation
//!   sets how often the lists are rebuilt (the junction's top slides at that speed) and moves no pair;
//!   the random part makes the tangential springs work.
//! - LAMMPS. `gran/hooke/history` computes overlapping pairs only, so its radii are enlarged by half
//!   the cohesive range of a particle paired with its twin, R = r + delta_f(r, r) / 2. A pair of equal
//!   sizes then interacts in LAMMPS exactly when it does in cgdem; for unequal sizes above d_c the two
//!   ranges differ a little, and the bench states both pair counts. Its stiffnesses are those of a
//!   d0 pair scaled by 1e-6: with the real ones, the overlaps of the enlarged radii (up to delta_f, a
//!   quarter of d0) would push the sample apart within a few steps, and LAMMPS would rebuild its list
//!   at every step. The pair loop's arithmetic does not depend on the values, so the scaled run moves
//!   like cgdem's (both translate at 10 m/s and rebuild as often; the counts are printed) and costs
//!   what the real one would per pair.

use std::path::{Path, PathBuf};

use anyhow::{bail, Result};
use dem::io::progress::ProgressFile;
use dem::jobs::{run_jobs, JobCache, RunJobs};
use dem::neighbor::{NeighborList, PairRange};
use dem::sample::{make_sample_resumable, RelaxConfig, Sample, SampleSpec};
use dem::{Material, PairModel, Parallelism, RunConfig, SiMaterial, Simulation, UnitSystem, Vec3};
use rand::{Rng, SeedableRng};
use serde::Serialize;

use super::{BenchArgs, Prepared};
use validation::bench::lammps::System;

/// d0 / d_c: 1.5 nm for silica (d_c = 1.71 nm).
const D0_OVER_DC: f64 = 0.877;
/// The junction's sliding speed (paper 000 section 4), m/s = nm/ns.
const SLIDING: f64 = 10.0;
/// Largest random velocity component, m/s.
const RANDOM: f64 = 1.0;
/// LAMMPS's stiffness over a d0 pair's (see the module docs).
const LAMMPS_STIFFNESS: f64 = 1e-6;

/// The inputs that identify the cached sample.
#[derive(Debug, Serialize)]
struct SampleJob {
    job: &'static str,
    material: Material,
    sample: SampleSpec,
    relax: RelaxConfig,
}

fn silica() -> Material {
    Material::from_si(&SiMaterial::table5(), UnitSystem::NANO)
}

fn recipe(length: f64) -> SampleSpec {
    SampleSpec::Amorphous {
        d0_over_dc: D0_OVER_DC,
        l_over_d0: length,
        w_over_d0: length,
        h_over_d0: None,
        ds_over_d0: 0.75,
        dl_over_d0: 5.0,
        dl_over_l: None,
        seed: 1,
        insert_fraction: 0.75,
    }
}

/// The relaxed sample of the recipe, from the cache or made (once) and stored there.
fn cached_sample(cache_dir: &Path, length: f64, model: &PairModel) -> Result<Sample> {
    let job = SampleJob {
        job: "cgdem bench amorphous sample",
        material: model.material.clone(),
        sample: recipe(length),
        relax: RelaxConfig::default(),
    };
    let cache = JobCache::new(cache_dir);
    let key = JobCache::key(&job)?;
    let where_ = cache.root().join(key.to_string());
    if cache.is_done(&key) {
        println!("sample: cached in {}", where_.display());
    } else {
        println!(
            "sample: relaxing the recipe once (minutes; kept in {}, resumed if interrupted)",
            where_.display()
        );
    }
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let par = super::parallelism(threads);
    let how = RunJobs {
        at_once: 1,
        ..RunJobs::default()
    };
    let mut results = run_jobs::<_, _, anyhow::Error, _>(
        &cache,
        std::slice::from_ref(&job),
        &how,
        |job, dir| {
            let progress = ProgressFile::new(dir.join("relax.progress.json"));
            let s = make_sample_resumable(&job.sample, model, &job.relax, par, Some(&progress))?;
            dem::io::progress::remove(&progress.path)?;
            Ok(s)
        },
    )?;
    match results.pop().flatten() {
        Some(s) => Ok(s),
        None => bail!("the sample job left no result in {}", where_.display()),
    }
}

/// Pairs (and their range) as LAMMPS sees them: radii R = r + delta_f(r, r) / 2.
struct LammpsRange<'a>(&'a PairModel);

impl LammpsRange<'_> {
    fn radius(&self, r: f64) -> f64 {
        r + 0.5 * (self.0.cutoff(r, r) - 2.0 * r)
    }
}

impl PairRange for LammpsRange<'_> {
    fn cutoff(&self, ri: f64, rj: f64) -> f64 {
        self.radius(ri) + self.radius(rj)
    }
    fn max_cutoff(&self, r_max: f64) -> f64 {
        // R grows with r (delta_f does for s <= 1).
        2.0 * self.radius(r_max)
    }
}

pub(super) fn prepare(args: &BenchArgs) -> Result<Prepared> {
    if !(args.length.is_finite() && args.length >= 6.0) {
        bail!(
            "--length {} must be at least 6 d0 (the box must hold the largest particles' range)",
            args.length
        );
    }
    let model = PairModel::cohesive(silica());
    let sample = match &args.sample {
        Some(path) => {
            println!("sample: {}", path.display());
            Sample::load(path)?
        }
        None => {
            let dir = args.cache.clone().unwrap_or_else(default_cache);
            cached_sample(&dir, args.length, &model)?
        }
    };
    let mut p = sample.particles;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2024);
    for v in p.vel.iter_mut() {
        *v = Vec3::new(SLIDING, 0.0, 0.0)
            + Vec3::from_fn(|_, _| RANDOM * (2.0 * rng.gen::<f64>() - 1.0));
    }
    p.omega.iter_mut().for_each(|w| *w = Vec3::zeros());
    let d0 = sample.d0;
    let r0 = 0.5 * d0;
    let m0 = dem::state::sphere_mass(model.material.density, r0);
    let pp = model.params(r0, r0, m0, m0);
    let range = LammpsRange(&model);
    let d_min = 2.0 * p.radius.iter().cloned().fold(f64::INFINITY, f64::min);
    let d_max = 2.0 * p.radius.iter().cloned().fold(0.0, f64::max);
    let counts = pair_counts(&p, &sample.sim_box, &model)?;
    let lammps = System {
        radius: p.radius.iter().map(|&r| range.radius(r)).collect(),
        density: model.material.density,
        k_n: LAMMPS_STIFFNESS * pp.k_n,
        k_t: LAMMPS_STIFFNESS * pp.k_t,
        skin: counts.skin,
    };
    let title = format!(
        "cgdem bench: relaxed amorphous silica (paper 000 Table 5, d0 = {:.2} nm, d = {:.2}-{:.2} d0, s = 1/2), \
         {} particles, cohesive force with tangential history, moving at {SLIDING} m/s\n\
         pairs in range at the start: cgdem {} (r_i + r_j + delta_f), LAMMPS {} (overlaps of R = r + delta_f(r, r) / 2); \
         both neighbour lists with cgdem's skin, {:.4} nm; cgdem's has {} pairs",
        d0,
        d_min / d0,
        d_max / d0,
        p.len(),
        counts.cgdem,
        counts.lammps,
        lammps.skin,
        counts.list,
    );
    Ok(Prepared {
        title,
        noun: "particles",
        particles: p,
        sim_box: sample.sim_box,
        model,
        expect_pairs: None,
        lammps,
    })
}

fn default_cache() -> PathBuf {
    md_bridge::venv::repo_root().join("runs/bench-cache")
}

/// Pairs of the sample in range on each side, cgdem's list size and skin.
struct PairCounts {
    cgdem: usize,
    lammps: usize,
    list: usize,
    skin: f64,
}

fn pair_counts(p: &dem::Particles, bx: &dem::SimBox, model: &PairModel) -> Result<PairCounts> {
    let sim = {
        let mut s = Simulation::new(
            p.clone(),
            *bx,
            model.clone(),
            vec![],
            RunConfig::default(),
            Parallelism::Sequential,
        )?;
        s.step()?;
        s
    };
    // The list was built from these (already wrapped) positions before the first step moved them.
    let list = sim.neighbors();
    let (pos, rad) = (&p.pos, &p.radius);
    let cgdem = (0..list.len())
        .filter(|&k| {
            let (i, j) = (list.i[k] as usize, list.j[k] as usize);
            let d = pos[j] + sim.sim_box.shift(list.image[k]) - pos[i];
            d.norm() < model.cutoff(rad[i], rad[j])
        })
        .count();
    // LAMMPS's pairs: a list of its own ranges without skin, on the same positions.
    let mut exact = NeighborList::new(0.0)?;
    let mut x = p.pos.clone();
    exact.build_with(&mut x, &p.radius, bx, &LammpsRange(model), false)?;
    Ok(PairCounts {
        cgdem,
        lammps: exact.len(),
        list: list.len(),
        skin: list.skin,
    })
}
