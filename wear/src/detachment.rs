//! The detachment probability against junction size, from runs: near d* the outcome of a junction of
//! size D is stochastic (two seeds of one D disagree over a range of sizes), so a bracket from two
//! seeds per D is partly luck. The size where half the junctions detach, D50, is a sharper summary:
//!
//!   P(wear particle | D) = 1 / (1 + exp(-k (ln D - ln D50))),
//!
//! fitted by maximum likelihood to every run's outcome (a Bernoulli trial at its D). Logistic in ln D
//! because the sizes of a search are spaced by factors, and D50 must stay positive. The slope k says
//! how wide the transition is: P goes from 10 % to 90 % over a factor exp(2 ln 9 / k) in D.
//!
//! How (and why):
//! - for a fixed mu = ln D50 the log-likelihood is concave in k (the logit k (ln D - mu) is linear in
//!   k), so its best k in [0, k_max] comes from a bisection on the score; the profile over mu is then
//!   maximised on a grid and refined by golden section. Deterministic, no random start;
//! - k is bounded by `max_slope`: perfectly separated outcomes (every plastic size below every wear
//!   size) have no finite maximum (k -> infinity); at the bound D50 lies between the last plastic and
//!   the first wear size and the result says the slope sits at its bound;
//! - the interval is the profile-likelihood one: every D50 whose profile log-likelihood lies within
//!   chi2_1(level) / 2 of the maximum (Wilks); an end that reaches a factor of 2 beyond the sizes run
//!   is reported open (None), never extrapolated;
//! - all one outcome (or no runs, or outcomes that fall with D) has no D50: the status says which,
//!   and no number is made up (never NaN).

use serde::{Deserialize, Serialize};

use crate::error::{Result, WearError};

/// How the fit is made.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FitSettings {
    /// Largest slope k (per unit of ln D). Default 100: P from 10 % to 90 % within 4.5 % of D,
    /// finer than any search's spacing of sizes (5 % and up), so the bound only binds on separated
    /// outcomes.
    #[serde(default = "d_max_slope")]
    pub max_slope: f64,
    /// Twice the log-likelihood drop that bounds the interval. Default 3.841: chi2 with one degree
    /// of freedom at 95 %.
    #[serde(default = "d_chi2")]
    pub interval_chi2: f64,
}

fn d_max_slope() -> f64 {
    100.0
}
fn d_chi2() -> f64 {
    3.841
}

impl Default for FitSettings {
    fn default() -> Self {
        FitSettings {
            max_slope: d_max_slope(),
            interval_chi2: d_chi2(),
        }
    }
}

/// What the fit found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FitStatus {
    /// A finite maximum: D50, slope and interval.
    Fitted,
    /// Every plastic size below every wear size: D50 between them, the slope at its bound.
    Separated,
    /// No runs.
    NoRuns,
    /// Every run plastic: D50 lies above the sizes run (not bracketed).
    AllPlastic,
    /// Every run detached: D50 lies below the sizes run (not bracketed).
    AllWear,
    /// The wear fraction does not rise with D: no D50.
    NoRise,
}

/// The fit of P(wear | D).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct D50Fit {
    pub status: FitStatus,
    /// The size where half the junctions detach (None unless fitted or separated).
    pub d50: Option<f64>,
    /// Its profile-likelihood interval; an end is None when it reaches a factor of 2 beyond the
    /// sizes run (open).
    pub interval: [Option<f64>; 2],
    /// k per unit of ln D.
    pub slope: Option<f64>,
    /// The slope sits at `max_slope` (separated outcomes: only a lower bound on the true slope).
    pub slope_at_bound: bool,
    pub max_slope: f64,
    /// Confidence level of the interval (from `interval_chi2`).
    pub level: f64,
    /// Runs and wear outcomes among them.
    pub runs: usize,
    pub wear: usize,
    /// Log-likelihood at the maximum.
    pub log_likelihood: Option<f64>,
}

/// ln(1 + exp(t)) without overflow.
fn softplus(t: f64) -> f64 {
    t.max(0.0) + (-t.abs()).exp().ln_1p()
}

fn sigmoid(z: f64) -> f64 {
    if z >= 0.0 {
        1.0 / (1.0 + (-z).exp())
    } else {
        let e = z.exp();
        e / (1.0 + e)
    }
}

/// Runs grouped by size: (ln D, wear outcomes, plastic outcomes).
type Groups = [(f64, f64, f64)];

fn group(runs: &[(f64, bool)]) -> Vec<(f64, f64, f64)> {
    let mut g: Vec<(f64, f64, f64)> = Vec::new();
    for &(d, y) in runs {
        let x = d.ln();
        let i = match g.iter().position(|e| e.0 == x) {
            Some(i) => i,
            None => {
                g.push((x, 0.0, 0.0));
                g.len() - 1
            }
        };
        if y {
            g[i].1 += 1.0;
        } else {
            g[i].2 += 1.0;
        }
    }
    g.sort_by(|a, b| a.0.total_cmp(&b.0));
    g
}

/// The log-likelihood of (mu, k).
fn log_likelihood(g: &Groups, mu: f64, k: f64) -> f64 {
    g.iter()
        .map(|&(x, w, p)| {
            let z = k * (x - mu);
            -w * softplus(-z) - p * softplus(z)
        })
        .sum()
}

/// The best slope in [0, k_max] at fixed mu: the root of the (decreasing) score in k.
fn best_slope(g: &Groups, mu: f64, k_max: f64) -> f64 {
    let score = |k: f64| -> f64 {
        g.iter()
            .map(|&(x, w, p)| (w - (w + p) * sigmoid(k * (x - mu))) * (x - mu))
            .sum()
    };
    if score(0.0) <= 0.0 {
        return 0.0;
    }
    if score(k_max) >= 0.0 {
        return k_max;
    }
    let (mut lo, mut hi) = (0.0, k_max);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if score(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Fits P(wear | D) to `runs` (D, detached?). Errors only on bad input (a D that is not a positive
/// number, or bad settings); every degenerate data set gets a status instead.
pub fn fit_d50(runs: &[(f64, bool)], s: &FitSettings) -> Result<D50Fit> {
    if !(s.max_slope.is_finite() && s.max_slope > 0.0) {
        return Err(WearError::Setting(format!(
            "detachment fit: max_slope {} must be positive",
            s.max_slope
        )));
    }
    if !(s.interval_chi2.is_finite() && s.interval_chi2 > 0.0) {
        return Err(WearError::Setting(format!(
            "detachment fit: interval_chi2 {} must be positive",
            s.interval_chi2
        )));
    }
    if let Some(&(d, _)) = runs.iter().find(|(d, _)| !(d.is_finite() && *d > 0.0)) {
        return Err(WearError::Setting(format!(
            "detachment fit: junction size {d} must be a positive number"
        )));
    }
    let wear = runs.iter().filter(|r| r.1).count();
    let level = chi2_1_cdf(s.interval_chi2);
    let empty = |status| D50Fit {
        status,
        d50: None,
        interval: [None, None],
        slope: None,
        slope_at_bound: false,
        max_slope: s.max_slope,
        level,
        runs: runs.len(),
        wear,
        log_likelihood: None,
    };
    if runs.is_empty() {
        return Ok(empty(FitStatus::NoRuns));
    }
    if wear == 0 {
        return Ok(empty(FitStatus::AllPlastic));
    }
    if wear == runs.len() {
        return Ok(empty(FitStatus::AllWear));
    }
    let pts = group(runs);
    let (x_min, x_max) = (pts[0].0, pts[pts.len() - 1].0);
    // D50 is sought up to a factor of 2 beyond the sizes run; an interval end there is open.
    let pad = 2f64.ln();
    let (a, b) = (x_min - pad, x_max + pad);
    let profile = |mu: f64| log_likelihood(&pts, mu, best_slope(&pts, mu, s.max_slope));
    const GRID: usize = 800;
    let grid: Vec<f64> = (0..=GRID)
        .map(|i| a + (b - a) * i as f64 / GRID as f64)
        .collect();
    let values: Vec<f64> = grid.iter().map(|&m| profile(m)).collect();
    let i_best = (0..=GRID)
        .max_by(|&i, &j| values[i].total_cmp(&values[j]).then(j.cmp(&i)))
        .unwrap_or(0);
    // Golden section between the grid neighbours of the best grid point.
    let (mut lo, mut hi) = (grid[i_best.saturating_sub(1)], grid[(i_best + 1).min(GRID)]);
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..80 {
        let (m1, m2) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if profile(m1) >= profile(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    let mu = 0.5 * (lo + hi);
    let (mu, ll) = if profile(mu) >= values[i_best] {
        (mu, profile(mu))
    } else {
        (grid[i_best], values[i_best])
    };
    let k = best_slope(&pts, mu, s.max_slope);
    if k <= 1e-9 * s.max_slope {
        return Ok(empty(FitStatus::NoRise));
    }
    let at_bound = k >= s.max_slope * (1.0 - 1e-9);
    // The interval: where the profile falls by chi2 / 2, bisected between grid points.
    let cut = ll - 0.5 * s.interval_chi2;
    let crossing = |dir: f64| -> Option<f64> {
        let step = (b - a) / GRID as f64;
        let mut inside = mu;
        loop {
            let next = inside + dir * step;
            if next < a || next > b {
                return None;
            }
            if profile(next) < cut {
                let (mut i, mut o) = (inside, next);
                for _ in 0..60 {
                    let m = 0.5 * (i + o);
                    if profile(m) >= cut {
                        i = m;
                    } else {
                        o = m;
                    }
                }
                return Some((0.5 * (i + o)).exp());
            }
            inside = next;
        }
    };
    let separated = {
        let last_plastic = pts
            .iter()
            .filter(|p| p.2 > 0.0)
            .map(|p| p.0)
            .fold(f64::MIN, f64::max);
        let first_wear = pts
            .iter()
            .filter(|p| p.1 > 0.0)
            .map(|p| p.0)
            .fold(f64::MAX, f64::min);
        last_plastic < first_wear
    };
    Ok(D50Fit {
        status: if separated {
            FitStatus::Separated
        } else {
            FitStatus::Fitted
        },
        d50: Some(mu.exp()),
        interval: [crossing(-1.0), crossing(1.0)],
        slope: Some(k),
        slope_at_bound: at_bound,
        max_slope: s.max_slope,
        level,
        runs: runs.len(),
        wear,
        log_likelihood: Some(ll),
    })
}

/// P(chi2 with one degree of freedom <= x) = erf(sqrt(x / 2)).
fn chi2_1_cdf(x: f64) -> f64 {
    erf((0.5 * x).sqrt())
}

/// erf by Abramowitz and Stegun 7.1.26 (|error| < 1.5e-7): enough to name a confidence level.
fn erf(x: f64) -> f64 {
    let t = 1.0 / (1.0 + 0.327_591_1 * x.abs());
    let poly = t
        * (0.254_829_592
            + t * (-0.284_496_736
                + t * (1.421_413_741 + t * (-1.453_152_027 + t * 1.061_405_429))));
    let y = 1.0 - poly * (-x * x).exp();
    if x >= 0.0 {
        y
    } else {
        -y
    }
}

/// P(wear | D) of a fit (None without a D50).
pub fn probability(fit: &D50Fit, d: f64) -> Option<f64> {
    Some(sigmoid(fit.slope? * (d.ln() - fit.d50?.ln())))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Runs at sizes d_j with exactly round(n P(d_j)) wear outcomes out of n: data whose maximum
    /// likelihood estimate is the generating (D50, k) up to the rounding.
    fn synthetic(d50: f64, k: f64, sizes: &[f64], n: usize) -> Vec<(f64, bool)> {
        let mut v = Vec::new();
        for &d in sizes {
            let p = sigmoid(k * (d.ln() - d50.ln()));
            let w = (p * n as f64).round() as usize;
            v.extend((0..n).map(|i| (d, i < w)));
        }
        v
    }

    fn sizes(from: f64, factor: f64, count: i32) -> Vec<f64> {
        (0..count).map(|j| from * factor.powi(j)).collect()
    }

    #[test]
    fn recovers_a_known_d50_and_slope() {
        for (d50, k) in [(20.0, 6.0), (31.0, 15.0), (8.5, 3.0)] {
            let data = synthetic(d50, k, &sizes(0.5 * d50, 1.08, 19), 400);
            let f = fit_d50(&data, &FitSettings::default()).unwrap();
            assert_eq!(f.status, FitStatus::Fitted);
            let (got, slope) = (f.d50.unwrap(), f.slope.unwrap());
            assert!((got / d50 - 1.0).abs() < 0.01, "D50 {got} against {d50}");
            assert!((slope / k - 1.0).abs() < 0.05, "slope {slope} against {k}");
            assert!(!f.slope_at_bound);
            let [lo, hi] = f.interval;
            let (lo, hi) = (lo.unwrap(), hi.unwrap());
            assert!(
                lo < got && got < hi && lo < d50 && d50 < hi,
                "{lo} {got} {hi}"
            );
            // 7 600 runs: a narrow interval.
            assert!(hi / lo < 1.1, "{lo} {hi}");
            assert!((f.level - 0.95).abs() < 1e-3, "{}", f.level);
        }
    }

    #[test]
    fn the_estimate_is_the_maximum_of_the_likelihood() {
        // 33 runs, overlapping outcomes: the fit beats every point of a brute-force grid.
        let data = [
            (10.0, false),
            (10.0, false),
            (12.0, false),
            (12.0, true),
            (14.0, false),
            (14.0, true),
            (14.0, true),
            (17.0, true),
            (17.0, false),
            (20.0, true),
            (20.0, true),
        ]
        .repeat(3);
        let f = fit_d50(&data, &FitSettings::default()).unwrap();
        assert_eq!(f.status, FitStatus::Fitted);
        let pts = group(&data);
        let ll = f.log_likelihood.unwrap();
        assert!((log_likelihood(&pts, f.d50.unwrap().ln(), f.slope.unwrap()) - ll).abs() < 1e-12);
        for i in 0..=200 {
            let mu = 9f64.ln() + (25f64 / 9.0).ln() * i as f64 / 200.0;
            for j in 0..=200 {
                let k = 100.0 * j as f64 / 200.0;
                assert!(log_likelihood(&pts, mu, k) <= ll + 1e-9, "mu {mu} k {k}");
            }
        }
        // Its interval holds it and the profile at each end has fallen by chi2 / 2.
        let [lo, hi] = f.interval;
        let (lo, hi) = (lo.unwrap(), hi.unwrap());
        assert!(lo < f.d50.unwrap() && f.d50.unwrap() < hi);
        for end in [lo, hi] {
            let mu = end.ln();
            let p = log_likelihood(&pts, mu, best_slope(&pts, mu, 100.0));
            assert!((ll - p - 0.5 * 3.841).abs() < 1e-6, "{end}: {}", ll - p);
        }
    }

    #[test]
    fn separated_outcomes_put_d50_between_them_with_the_slope_at_its_bound() {
        let data = vec![
            (10.0, false),
            (10.0, false),
            (12.0, false),
            (12.0, false),
            (14.0, true),
            (14.0, true),
            (16.0, true),
        ];
        for max_slope in [30.0, 100.0] {
            let s = FitSettings {
                max_slope,
                ..FitSettings::default()
            };
            let f = fit_d50(&data, &s).unwrap();
            assert_eq!(f.status, FitStatus::Separated);
            let d50 = f.d50.unwrap();
            assert!(12.0 < d50 && d50 < 14.0, "{d50}");
            assert!(f.slope_at_bound);
            assert_eq!(f.slope, Some(max_slope));
            let [lo, hi] = f.interval;
            assert!(lo.unwrap() < d50 && d50 < hi.unwrap());
        }
    }

    #[test]
    fn one_outcome_or_none_or_a_falling_fraction_has_no_d50() {
        let s = FitSettings::default();
        let plastic: Vec<(f64, bool)> = [10.0, 20.0, 30.0].iter().map(|&d| (d, false)).collect();
        let wear: Vec<(f64, bool)> = [10.0, 20.0].iter().map(|&d| (d, true)).collect();
        let falling = vec![
            (10.0, true),
            (10.0, true),
            (20.0, true),
            (20.0, false),
            (30.0, false),
        ];
        for (data, status) in [
            (vec![], FitStatus::NoRuns),
            (plastic, FitStatus::AllPlastic),
            (wear, FitStatus::AllWear),
            (falling, FitStatus::NoRise),
        ] {
            let f = fit_d50(&data, &s).unwrap();
            assert_eq!(f.status, status);
            assert_eq!((f.d50, f.slope, f.interval), (None, None, [None, None]));
            assert_eq!(f.runs, data.len());
            // Serialises without a NaN (serde_json refuses none, so check the text).
            let text = serde_json::to_string(&f).unwrap();
            assert!(!text.contains("NaN") && text.contains("null"), "{text}");
            assert_eq!(probability(&f, 15.0), None);
        }
    }

    #[test]
    fn bad_input_is_refused() {
        let s = FitSettings::default();
        assert!(fit_d50(&[(0.0, true), (2.0, false)], &s).is_err());
        assert!(fit_d50(&[(f64::NAN, true)], &s).is_err());
        let bad = FitSettings {
            max_slope: 0.0,
            ..s
        };
        assert!(fit_d50(&[(1.0, true), (2.0, false)], &bad).is_err());
        let bad = FitSettings {
            interval_chi2: -1.0,
            ..s
        };
        assert!(fit_d50(&[(1.0, true), (2.0, false)], &bad).is_err());
    }

    #[test]
    fn an_open_end_is_reported_open() {
        // One wear among many plastics at the largest size only: the upper end of the interval is
        // not bounded within a factor 2 beyond the sizes.
        let data = vec![(10.0, false), (10.0, false), (12.0, false), (12.0, true)];
        let f = fit_d50(&data, &FitSettings::default()).unwrap();
        assert_eq!(f.status, FitStatus::Fitted);
        assert_eq!(f.interval[1], None);
        let p = probability(&f, f.d50.unwrap()).unwrap();
        assert!((p - 0.5).abs() < 1e-12);
    }
}
