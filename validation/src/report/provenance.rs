//! Provenance on the report's first page: git revision, LAMMPS version and potential checksum (from
//! the MD sections), seeds, profile, host, date and the wall time of each section.

use std::process::Command;

use super::{Context, SectionRun};

/// The report's provenance, as (name, value) rows in display order.
#[derive(Debug, Clone, PartialEq)]
pub struct Provenance {
    pub rows: Vec<(String, String)>,
    /// (section id, seconds).
    pub timings: Vec<(String, f64)>,
}

impl Provenance {
    pub fn gather(ctx: &Context, runs: &[SectionRun], total_seconds: f64) -> Self {
        let mut rows = vec![
            ("profile".to_string(), ctx.profile.name().to_string()),
            ("git revision".into(), git_revision()),
            ("cgdem version".into(), env!("CARGO_PKG_VERSION").into()),
            ("host".into(), host()),
            ("date (UTC)".into(), utc_now()),
            (
                "machine".into(),
                format!(
                    "{} cores, load average {} (1, 5, 15 min) at the end; cases side by side: {}",
                    std::thread::available_parallelism().map_or(1, |n| n.get()),
                    load_average(),
                    ctx.at_once
                ),
            ),
            ("case cache".into(), ctx.cache.root().display().to_string()),
        ];
        // Entries the sections gave (LAMMPS version, potential checksum, seeds), merged by name.
        let mut extra: Vec<(String, Vec<String>)> = Vec::new();
        for r in runs {
            if let Ok(o) = &r.output {
                for (k, v) in &o.provenance {
                    match extra.iter_mut().find(|(n, _)| n == k) {
                        Some((_, vs)) if !vs.contains(v) => vs.push(v.clone()),
                        Some(_) => {}
                        None => extra.push((k.clone(), vec![v.clone()])),
                    }
                }
            }
        }
        for key in ["LAMMPS version", "potential checksum (sha256)"] {
            if !extra.iter().any(|(k, _)| k == key) {
                extra.push((key.into(), vec!["not used by the sections run".into()]));
            }
        }
        rows.extend(extra.into_iter().map(|(k, v)| (k, v.join("; "))));
        let mut timings: Vec<(String, f64)> = runs
            .iter()
            .map(|r| (r.section.id.to_string(), r.seconds))
            .collect();
        timings.push(("total".into(), total_seconds));
        Provenance { rows, timings }
    }

    pub fn to_json(&self) -> String {
        let rows: serde_json::Map<String, serde_json::Value> = self
            .rows
            .iter()
            .map(|(k, v)| (k.clone(), serde_json::Value::String(v.clone())))
            .collect();
        let timings: serde_json::Map<String, serde_json::Value> = self
            .timings
            .iter()
            .map(|(k, v)| (k.clone(), serde_json::json!(v)))
            .collect();
        serde_json::to_string_pretty(
            &serde_json::json!({ "provenance": rows, "section_seconds": timings }),
        )
        .unwrap_or_default()
    }
}

/// `git rev-parse HEAD` of the working directory, marked "+ local changes" when the tree is dirty.
fn git_revision() -> String {
    let run = |args: &[&str]| {
        Command::new("git")
            .args(args)
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    match run(&["rev-parse", "HEAD"]) {
        Some(rev) => {
            let dirty = run(&["status", "--porcelain", "--untracked-files=no"])
                .is_some_and(|s| !s.is_empty());
            if dirty {
                format!("{rev} + local changes")
            } else {
                rev
            }
        }
        None => "unknown (not run from a git checkout)".into(),
    }
}

fn host() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .or_else(|_| std::fs::read_to_string("/etc/hostname"))
        .map(|s| s.trim().to_string())
        .unwrap_or_else(|_| "unknown".into())
}

/// The 1, 5 and 15 minute load averages (timings are figures of the load on a shared machine).
pub fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".into())
}

/// Now as `YYYY-MM-DD hh:mm:ss`.
pub fn utc_now() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    utc(secs)
}

/// Unix seconds as a UTC date and time (the civil-from-days algorithm of H. Hinnant).
pub fn utc(secs: u64) -> String {
    let days = (secs / 86_400) as i64;
    let rem = secs % 86_400;
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!(
        "{y:04}-{m:02}-{d:02} {:02}:{:02}:{:02}",
        rem / 3600,
        rem % 3600 / 60,
        rem % 60
    )
}

#[cfg(test)]
mod tests {
    use super::utc;

    #[test]
    fn dates_are_civil_utc() {
        assert_eq!(utc(0), "1970-01-01 00:00:00");
        assert_eq!(utc(951_782_400), "2000-02-29 00:00:00");
        assert_eq!(utc(1_700_000_000), "2023-11-14 22:13:20");
    }
}
