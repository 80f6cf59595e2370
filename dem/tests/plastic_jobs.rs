//! Sweeps of the plastic-wear model run as cached jobs (dem::jobs): the same results for any number
//! of jobs side by side (each job's loop is sequential and deterministic), a rerun finds them all
//! cached and runs nothing, and a Slurm-array share runs only its jobs.

use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

use dem::jobs::{JobCache, RunJobs, Shard};
use dem::scenario::plastic::{run_impacts, ImpactFile};

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("cgdem-plastic-jobs-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn impact_sweeps_are_cached_deterministic_jobs() {
    let file: ImpactFile = toml::from_str(
        "[model]\nhardness = 6.6e9\n[projectile]\nradius = 0.003\ndensity = 2500.0\n\
         [impact]\nspeed = 35.0\nangle_deg = 45.0\n[sweep]\nangle_deg = [20.0, 45.0, 70.0]\naims = 2\n",
    )
    .unwrap();
    let jobs = file.jobs().unwrap();
    assert_eq!(jobs.len(), 6);
    let ran = AtomicUsize::new(0);
    let count = |_: &_, _: &_| {
        ran.fetch_add(1, Ordering::Relaxed);
    };
    let how = |n: usize, shard: Shard| RunJobs {
        at_once: n,
        shard,
        ..RunJobs::default()
    };
    let two = JobCache::new(scratch("two"));
    let a = run_impacts(&jobs, &two, &how(2, Shard::whole()), &count).unwrap();
    assert_eq!(ran.swap(0, Ordering::Relaxed), 6);
    let one = JobCache::new(scratch("one"));
    let b = run_impacts(&jobs, &one, &how(1, Shard::whole()), &count).unwrap();
    assert_eq!(
        serde_json::to_string(&a).unwrap(),
        serde_json::to_string(&b).unwrap(),
        "two at once and one at a time differ"
    );
    ran.store(0, Ordering::Relaxed);
    let again = run_impacts(&jobs, &two, &how(2, Shard::whole()), &count).unwrap();
    assert_eq!(ran.load(Ordering::Relaxed), 0, "a rerun runs nothing");
    assert_eq!(again, a);
    // A Slurm array task takes every second job and leaves the rest.
    let shared = JobCache::new(scratch("shard"));
    let part = run_impacts(
        &jobs,
        &shared,
        &how(1, Shard::parse("1/2").unwrap()),
        &count,
    )
    .unwrap();
    assert_eq!(ran.load(Ordering::Relaxed), 3);
    assert!(part
        .iter()
        .enumerate()
        .all(|(k, r)| r.is_some() == (k % 2 == 1)));
    let points = file.points(&a.into_iter().map(Option::unwrap).collect::<Vec<_>>());
    assert_eq!(points.len(), 3);
    assert_eq!(points[1].aims, 2);
    for c in [&two, &one, &shared] {
        std::fs::remove_dir_all(c.root()).ok();
    }
}
