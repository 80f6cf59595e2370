//! The detachment-probability scan (`[scan]` of a compare config): near d* a junction's outcome is
//! stochastic (two seeds of one D disagree over a range of sizes), so a bisection with two seeds per
//! D brackets the transition partly by luck. After each side's bisection the scan runs more seeds
//! at the sizes around that side's transition (the bracket's bounds, the sizes whose seeds split,
//! the all-plastic sizes above the bracket, and one step outside on each side), through the same
//! cached jobs (MD worker jobs, DEM junction jobs), and fits P(wear | D) to every run of the side
//! ([`wear::detachment`]): D50, the size where half the junctions detach, with its interval.

use serde::{Deserialize, Serialize};
use wear::detachment::{fit_d50, D50Fit, FitSettings};
use wear::dstar::round_size;
use wear::Outcome;

use super::summary::Span;
use crate::error::{Result, ValidationError};

/// What the scan runs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScanConfig {
    /// Seeds added at every scanned size, on both sides (none of the searches' own); default 3-8:
    /// with the searches' two, eight outcomes per size, enough to tell a P of 1/2 from 0 or 1.
    #[serde(default = "d_seeds")]
    pub seeds: Vec<u64>,
    /// Also scan one size outside the bracket on each side (the nearest the search ran, or one
    /// bracket ratio beyond when it ran none there); default true: the fit sees P reach 0 and 1.
    #[serde(default = "yes")]
    pub outside: bool,
    /// The logistic fit (slope bound, interval level); default `FitSettings::default()`.
    #[serde(default)]
    pub fit: FitSettings,
}

fn d_seeds() -> Vec<u64> {
    (3..=8).collect()
}
fn yes() -> bool {
    true
}

impl ScanConfig {
    /// Checks the seeds against themselves and against the seeds of every search (`searches`: a
    /// name and its seeds), and the fit's settings.
    pub fn validate(&self, searches: &[(String, &[u64])]) -> Result<()> {
        let bad = |reason: String| ValidationError::Config {
            path: "[scan]".into(),
            reason,
        };
        if self.seeds.is_empty() {
            return Err(bad(
                "seeds must hold at least one seed (or leave [scan] out)".into(),
            ));
        }
        for (i, s) in self.seeds.iter().enumerate() {
            if self.seeds[..i].contains(s) {
                return Err(bad(format!("seed {s} is listed twice")));
            }
        }
        for (name, seeds) in searches {
            if let Some(s) = self.seeds.iter().find(|s| seeds.contains(s)) {
                return Err(bad(format!(
                    "seed {s} is one of {name}'s search seeds {seeds:?}: the scan adds other seeds \
                     (the search's runs already count in the fit)"
                )));
            }
        }
        fit_d50(&[], &self.fit)?;
        Ok(())
    }
}

/// The sizes to scan: the bracket's ends, the split sizes inside it and the all-plastic sizes above
/// it (the transition's width), and with `outside` one size beyond on each side: the nearest size
/// the search ran, else the end times (or divided by) the bracket's ratio upper / lower, rounded as
/// the search rounds its sizes, when that stays within `limits`. Sorted, without repeats; empty when the search found no end at all.
pub fn scan_sizes(
    visited: &[f64],
    bracket: &Span,
    split: &[f64],
    non_monotonic: &[f64],
    limits: [f64; 2],
    outside: bool,
) -> Vec<f64> {
    let mut v: Vec<f64> = bracket
        .iter()
        .flatten()
        .chain(split)
        .chain(non_monotonic)
        .copied()
        .collect();
    if outside {
        let ratio = match bracket {
            [Some(l), Some(u)] if u > l => Some(u / l),
            _ => None,
        };
        if let Some(l) = bracket[0] {
            let below = visited.iter().copied().filter(|&d| d < l).reduce(f64::max);
            let step = ratio.map(|r| round_size(l / r)).filter(|&d| d >= limits[0]);
            v.extend(below.or(step));
        }
        if let Some(u) = bracket[1] {
            let above = visited.iter().copied().filter(|&d| d > u).reduce(f64::min);
            let step = ratio.map(|r| round_size(u * r)).filter(|&d| d <= limits[1]);
            v.extend(above.or(step));
        }
    }
    v.sort_by(f64::total_cmp);
    v.dedup();
    v
}

/// One run as the fit sees it (sigma).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Trial {
    pub diameter: f64,
    pub seed: u64,
    pub outcome: Outcome,
    /// Run by the scan (false: by the search).
    pub scan: bool,
    /// Wall time of the run (s).
    pub seconds: f64,
}

/// The wear fraction at one size.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Fraction {
    pub diameter: f64,
    pub runs: usize,
    pub wear: usize,
}

/// One side's detachment probability.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Detachment {
    /// The sizes the scan ran (sigma) and its seeds.
    pub sizes: Vec<f64>,
    pub seeds: Vec<u64>,
    /// Every run of the side (search and scan), by D then seed.
    pub trials: Vec<Trial>,
    /// Wear outcomes per size.
    pub fractions: Vec<Fraction>,
    /// P(wear | D) fitted to every trial: D50 (sigma), its interval, the slope.
    pub fit: D50Fit,
    /// Runs the scan added and their wall time (s).
    pub scan_runs: usize,
    pub scan_seconds: f64,
    /// The bracket every run of the side gives by majority ([`majority_bracket`]).
    #[serde(default)]
    pub majority_bracket: Span,
}

/// The bracket all the runs of a side give by majority, with no fit: the upper bound is the smallest
/// size from which every size run detaches in more than half its runs, the lower bound the largest
/// smaller size that detaches in fewer than half (a size at exactly one half lies inside). The
/// bisection's own bracket rests on two seeds per size; near d* two seeds agree by luck (a size that
/// detaches 2 times in 8 can give two wear particles), and this one reads every seed. `None`: an
/// open end (no size qualifies). `fractions` in increasing size.
pub fn majority_bracket(fractions: &[Fraction]) -> Span {
    let majority = |f: &Fraction| 2 * f.wear > f.runs;
    let first_of_top = fractions
        .iter()
        .rposition(|f| !majority(f))
        .map_or(0, |i| i + 1);
    let upper = fractions.get(first_of_top).map(|f| f.diameter);
    let lower = fractions[..first_of_top]
        .iter()
        .rev()
        .find(|f| 2 * f.wear < f.runs)
        .map(|f| f.diameter);
    [lower, upper]
}

impl Detachment {
    /// Fits the trials (any order).
    pub fn new(
        sizes: Vec<f64>,
        seeds: Vec<u64>,
        mut trials: Vec<Trial>,
        fit: &FitSettings,
    ) -> Result<Self> {
        trials.sort_by(|a, b| a.diameter.total_cmp(&b.diameter).then(a.seed.cmp(&b.seed)));
        let points: Vec<(f64, bool)> = trials
            .iter()
            .map(|t| (t.diameter, t.outcome == Outcome::WearParticle))
            .collect();
        let mut fractions: Vec<Fraction> = Vec::new();
        for &(d, w) in &points {
            match fractions.last_mut() {
                Some(f) if f.diameter == d => {
                    f.runs += 1;
                    f.wear += usize::from(w);
                }
                _ => fractions.push(Fraction {
                    diameter: d,
                    runs: 1,
                    wear: usize::from(w),
                }),
            }
        }
        let scan: Vec<&Trial> = trials.iter().filter(|t| t.scan).collect();
        Ok(Detachment {
            majority_bracket: majority_bracket(&fractions),
            sizes,
            seeds,
            fit: fit_d50(&points, fit)?,
            fractions,
            scan_runs: scan.len(),
            scan_seconds: scan.iter().map(|t| t.seconds).sum(),
            trials,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_hold_the_bracket_its_splits_and_one_step_outside() {
        // MD: (23.3, 26.3], the search ran 29.2 above and nothing below: one bracket ratio down.
        let v = [23.3, 26.3, 29.2, 35.0, 50.0];
        let s = scan_sizes(&v, &[Some(23.3), Some(26.3)], &[], &[], [8.0, 200.0], true);
        assert_eq!(s.len(), 4);
        assert_eq!(s[0], round_size(23.3 * 23.3 / 26.3), "{s:?}");
        assert_eq!(s[0], 20.6);
        assert_eq!(&s[1..], &[23.3, 26.3, 29.2]);
        // Splits inside and all-plastic sizes above are scanned; the nearest sizes run outside
        // are the steps.
        let v = [13.3, 15.0, 16.7, 20.0, 40.0, 60.0];
        let s = scan_sizes(
            &v,
            &[Some(15.0), Some(16.7)],
            &[],
            &[20.0],
            [6.0, 240.0],
            true,
        );
        assert_eq!(s, vec![13.3, 15.0, 16.7, 20.0]);
        let s = scan_sizes(
            &[30.0, 33.8, 45.0, 52.5, 60.0],
            &[Some(30.0), Some(52.5)],
            &[33.8, 45.0],
            &[],
            [25.0, 360.0],
            true,
        );
        // 30 / 1.75 = 17.1 is below the limit 25: no step below.
        assert_eq!(s, vec![30.0, 33.8, 45.0, 52.5, 60.0]);
        // Without `outside`, and without a bracket.
        let s = scan_sizes(&v, &[Some(15.0), Some(16.7)], &[], &[], [6.0, 240.0], false);
        assert_eq!(s, vec![15.0, 16.7]);
        assert!(scan_sizes(&v, &[None, None], &[], &[], [6.0, 240.0], true).is_empty());
    }

    #[test]
    fn bad_seed_lists_are_refused_with_the_reason() {
        let ok = ScanConfig {
            seeds: vec![3, 4],
            outside: true,
            fit: FitSettings::default(),
        };
        let md: &[u64] = &[1, 2];
        let searches = vec![("[md]".to_string(), md)];
        assert!(ok.validate(&searches).is_ok());
        for (seeds, words) in [
            (vec![], "at least one seed"),
            (vec![3, 3], "listed twice"),
            (vec![2, 3], "search seeds"),
        ] {
            let c = ScanConfig {
                seeds,
                ..ok.clone()
            };
            let e = c.validate(&searches).unwrap_err().to_string();
            assert!(e.contains(words), "{e}");
        }
        let c = ScanConfig {
            fit: FitSettings {
                max_slope: -1.0,
                ..FitSettings::default()
            },
            ..ok
        };
        assert!(c.validate(&searches).is_err());
        // The defaults parse and hold no search seed of the shipped configs.
        let d: ScanConfig = toml::from_str("").unwrap();
        assert_eq!(d.seeds, vec![3, 4, 5, 6, 7, 8]);
        assert!(d.validate(&searches).is_ok());
        assert!(toml::from_str::<ScanConfig>("sedes = [3]").is_err());
    }

    #[test]
    fn fractions_count_each_size_and_the_fit_sees_every_trial() {
        let t = |d: f64, seed: u64, wear: bool, scan: bool| Trial {
            diameter: d,
            seed,
            outcome: if wear {
                Outcome::WearParticle
            } else {
                Outcome::PlasticSmoothing
            },
            scan,
            seconds: 2.0,
        };
        let trials = vec![
            t(20.0, 3, true, true),
            t(10.0, 1, false, false),
            t(20.0, 1, false, false),
            t(30.0, 1, true, false),
            t(10.0, 3, false, true),
            t(30.0, 3, true, true),
        ];
        let d = Detachment::new(
            vec![10.0, 20.0, 30.0],
            vec![3],
            trials,
            &FitSettings::default(),
        )
        .unwrap();
        let f: Vec<(f64, usize, usize)> = d
            .fractions
            .iter()
            .map(|f| (f.diameter, f.runs, f.wear))
            .collect();
        assert_eq!(f, vec![(10.0, 2, 0), (20.0, 2, 1), (30.0, 2, 2)]);
        assert_eq!((d.scan_runs, d.scan_seconds), (3, 6.0));
        assert_eq!(d.fit.runs, 6);
        assert_eq!(d.fit.wear, 3);
        let d50 = d.fit.d50.unwrap();
        assert!(10.0 < d50 && d50 < 30.0, "{d50}");
        assert!(d.trials.windows(2).all(|w| w[0].diameter <= w[1].diameter));
        assert_eq!(d.majority_bracket, [Some(10.0), Some(30.0)]);
    }

    fn fractions(v: &[(f64, usize, usize)]) -> Vec<Fraction> {
        v.iter()
            .map(|&(diameter, wear, runs)| Fraction {
                diameter,
                runs,
                wear,
            })
            .collect()
    }

    #[test]
    fn the_majority_bracket_reads_every_seed() {
        // The d0 = 1 sigma runs of the comparison: the bisection's (15, 16.7] came from two seeds
        // that both detached at 16.7, a size that detaches 2 times in 8.
        let d0_1 = fractions(&[
            (13.3, 0, 2),
            (15.0, 0, 8),
            (16.7, 2, 8),
            (20.0, 1, 8),
            (28.3, 4, 6),
            (40.0, 2, 2),
            (60.0, 2, 2),
        ]);
        assert_eq!(majority_bracket(&d0_1), [Some(20.0), Some(28.3)]);
        // A size at one half lies inside; a minority size above a majority one moves the upper
        // bound above it.
        let half = fractions(&[(30.0, 0, 8), (37.5, 4, 8), (45.0, 5, 8)]);
        assert_eq!(majority_bracket(&half), [Some(30.0), Some(45.0)]);
        let dip = fractions(&[(20.0, 0, 4), (24.0, 3, 4), (27.0, 1, 4), (30.0, 4, 4)]);
        assert_eq!(majority_bracket(&dip), [Some(27.0), Some(30.0)]);
        // Open ends.
        let plastic = fractions(&[(20.0, 0, 2), (24.0, 1, 2)]);
        assert_eq!(majority_bracket(&plastic), [Some(20.0), None]);
        let wear = fractions(&[(20.0, 2, 2), (24.0, 2, 2)]);
        assert_eq!(majority_bracket(&wear), [None, Some(20.0)]);
        assert_eq!(majority_bracket(&[]), [None, None]);
    }
}
