//! The critical junction size d* from runs: bisection on the junction size D between a plastic and a
//! debris outcome, several seeds per D, until the bracket is narrower than a requested relative width.
//! Pure logic over the verdicts the caller's runs gave, so that the DEM and the MD sides search alike
//! (the caller runs each round's jobs, locally or on a cluster, and feeds the outcomes back).
//!
//! Rules, and why:
//! - a size is *plastic* (P) or *debris* (W) only when every seed agrees; a split vote (M) is the
//!   transition's own width showing, not a bound;
//! - the bracket is (lower, upper] with lower the largest P below upper, the smallest W: paper 000
//!   reports 10 nm < d* < 20 nm in this sense;
//! - a round probes the middle of the bracket; where split sizes lie inside it, it probes the middle of
//!   the gaps on both sides of them, so that both bounds can still move;
//! - if the starting range does not hold a P below a W, it widens by `widen` (a factor) towards the
//!   missing side, within the sizes the geometry allows;
//! - a P above the smallest W (the outcomes are noisy near d*) is reported as non-monotonic and does not
//!   move the bounds.

use serde::{Deserialize, Serialize};

use crate::error::{Result, WearError};
use crate::outcome::Outcome;

/// What the search is asked to do, in the caller's length unit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SearchSettings {
    /// Starting range [D_low, D_high]: a size expected plastic and one expected to detach.
    pub range: [f64; 2],
    /// Smallest and largest size the geometry and the discretisation allow.
    pub limits: [f64; 2],
    /// Stop when (upper - lower) / ((upper + lower) / 2) is at most this.
    #[serde(default = "d_width")]
    pub relative_width: f64,
    /// Factor by which the range widens when an end does not give the expected outcome.
    #[serde(default = "d_widen")]
    pub widen: f64,
    /// Most rounds of probes before giving up (the result then says it did not converge).
    #[serde(default = "d_rounds")]
    pub max_rounds: usize,
}

fn d_width() -> f64 {
    // Paper 000's bracket is 10-20 nm, 67 % wide; a quarter of that resolves d* against eq (22)'s 18.5.
    0.15
}
fn d_widen() -> f64 {
    // Sizes grow as D^3 in particles: 1.5 keeps a widened run affordable while moving far enough.
    1.5
}
fn d_rounds() -> usize {
    // Ten halvings narrow a factor-2 range to 0.1 %: more means the outcomes do not settle.
    10
}

impl SearchSettings {
    /// Checks the settings.
    pub fn validate(&self) -> Result<()> {
        let [lo, hi] = self.range;
        let [min, max] = self.limits;
        let ok = [lo, hi, min, max, self.relative_width, self.widen]
            .iter()
            .all(|v| v.is_finite() && *v > 0.0)
            && lo < hi
            && min <= lo
            && hi <= max
            && self.widen > 1.0
            && self.max_rounds > 0;
        if ok {
            Ok(())
        } else {
            Err(WearError::Setting(format!(
                "d* search: need 0 < limits[0] <= range[0] < range[1] <= limits[1], relative_width > 0, \
                 widen > 1, max_rounds > 0; got range {:?}, limits {:?}, relative_width {}, widen {}, \
                 max_rounds {}",
                self.range, self.limits, self.relative_width, self.widen, self.max_rounds
            )))
        }
    }
}

/// The seeds' verdicts at one size.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Class {
    /// Every seed smoothed plastically.
    Plastic,
    /// Every seed detached a wear particle.
    Debris,
    /// The seeds disagree.
    Split,
}

/// The outcomes of every seed at one size.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Probe {
    pub size: f64,
    pub outcomes: Vec<Outcome>,
}

impl Probe {
    /// P, W or M.
    pub fn class(&self) -> Class {
        let wear = self
            .outcomes
            .iter()
            .filter(|&&o| o == Outcome::WearParticle)
            .count();
        match wear {
            0 => Class::Plastic,
            n if n == self.outcomes.len() => Class::Debris,
            _ => Class::Split,
        }
    }
}

/// Where the search stands.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Bracket {
    /// Largest all-plastic size below `upper` (None: none yet).
    pub lower: Option<f64>,
    /// Smallest all-debris size (None: none yet).
    pub upper: Option<f64>,
    /// Sizes whose seeds disagree, inside the bracket.
    pub split: Vec<f64>,
    /// All-plastic sizes above `upper`: outcomes that contradict a single threshold.
    pub non_monotonic: Vec<f64>,
}

impl Bracket {
    /// The bracket of a set of probes.
    pub fn of(probes: &[Probe]) -> Self {
        let mut sorted: Vec<&Probe> = probes.iter().collect();
        sorted.sort_by(|a, b| a.size.total_cmp(&b.size));
        let upper = sorted
            .iter()
            .find(|p| p.class() == Class::Debris)
            .map(|p| p.size);
        let below = |s: f64| upper.is_none_or(|u| s < u);
        let lower = sorted
            .iter()
            .rev()
            .find(|p| p.class() == Class::Plastic && below(p.size))
            .map(|p| p.size);
        let inside = |s: f64| lower.is_none_or(|l| s > l) && below(s);
        Bracket {
            lower,
            upper,
            split: sorted
                .iter()
                .filter(|p| p.class() == Class::Split && inside(p.size))
                .map(|p| p.size)
                .collect(),
            non_monotonic: sorted
                .iter()
                .filter(|p| p.class() == Class::Plastic && !below(p.size))
                .map(|p| p.size)
                .collect(),
        }
    }

    /// (upper - lower) / ((upper + lower) / 2), when both bounds exist.
    pub fn relative_width(&self) -> Option<f64> {
        match (self.lower, self.upper) {
            (Some(l), Some(u)) => Some((u - l) / (0.5 * (u + l))),
            _ => None,
        }
    }
}

/// What to do next.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Step {
    /// Run every seed at these sizes, then ask again.
    Probe(Vec<f64>),
    /// The search ended: `converged` when the bracket is narrow enough, otherwise `reason` says why not.
    Done { converged: bool, reason: String },
}

/// Sizes are rounded to three significant digits, so that probes have readable names and reruns and
/// wider searches hit the same cached runs.
pub fn round_size(d: f64) -> f64 {
    if d <= 0.0 || !d.is_finite() {
        return d;
    }
    let scale = 10f64.powi(2 - d.log10().floor() as i32);
    (d * scale).round() / scale
}

/// The next step of the search given the probes so far (any order; the first call gets an empty list).
pub fn next_step(s: &SearchSettings, probes: &[Probe], rounds_done: usize) -> Result<Step> {
    s.validate()?;
    if let Some(p) = probes.iter().find(|p| p.outcomes.is_empty()) {
        return Err(WearError::Setting(format!(
            "size {} has no outcome: every probe needs at least one seed",
            p.size
        )));
    }
    let [lo, hi] = s.range;
    let [min, max] = s.limits;
    let known = |d: f64| probes.iter().any(|p| p.size == d);
    let start: Vec<f64> = [lo, hi]
        .into_iter()
        .map(round_size)
        .filter(|&d| !known(d))
        .collect();
    if !start.is_empty() {
        return Ok(Step::Probe(start));
    }
    let b = Bracket::of(probes);
    if rounds_done >= s.max_rounds {
        return Ok(Step::Done {
            converged: false,
            reason: format!("stopped after {} rounds (max_rounds)", s.max_rounds),
        });
    }
    let smallest = probes.iter().map(|p| p.size).fold(f64::INFINITY, f64::min);
    let largest = probes.iter().map(|p| p.size).fold(0.0, f64::max);
    let (lower, upper) = match (b.lower, b.upper) {
        (Some(l), Some(u)) => (l, u),
        (None, _) => {
            // Nothing plastic below the debris yet: look further down.
            let d = round_size((smallest / s.widen).max(min));
            if smallest <= min || known(d) {
                return Ok(Step::Done {
                    converged: false,
                    reason: format!(
                        "no size down to the smallest allowed ({min}) smoothed plastically on every seed"
                    ),
                });
            }
            return Ok(Step::Probe(vec![d]));
        }
        (Some(_), None) => {
            let d = round_size((largest * s.widen).min(max));
            if largest >= max || known(d) {
                return Ok(Step::Done {
                    converged: false,
                    reason: format!(
                        "no size up to the largest allowed ({max}) detached a wear particle on every seed"
                    ),
                });
            }
            return Ok(Step::Probe(vec![d]));
        }
    };
    let narrow = |a: f64, c: f64| (c - a) / (0.5 * (c + a)) <= s.relative_width;
    if narrow(lower, upper) {
        return Ok(Step::Done {
            converged: true,
            reason: format!(
                "bracket ({lower}, {upper}] is within the relative width {}",
                s.relative_width
            ),
        });
    }
    // Gaps to probe: the whole bracket, or the two gaps around the split sizes inside it.
    let gaps: Vec<(f64, f64)> = match (b.split.first(), b.split.last()) {
        (Some(&first), Some(&last)) => vec![(lower, first), (last, upper)],
        _ => vec![(lower, upper)],
    };
    let probes_next: Vec<f64> = gaps
        .into_iter()
        .filter(|&(a, c)| !narrow(a, c))
        .map(|(a, c)| round_size(0.5 * (a + c)))
        .filter(|&d| d > lower && d < upper && !known(d))
        .collect();
    if probes_next.is_empty() {
        return Ok(Step::Done {
            converged: false,
            reason: format!(
                "the seeds disagree at {:?} inside ({lower}, {upper}]: the transition is wider than \
                 the requested {}",
                b.split, s.relative_width
            ),
        });
    }
    Ok(Step::Probe(probes_next))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn settings() -> SearchSettings {
        SearchSettings {
            range: [10.0, 20.0],
            limits: [4.0, 40.0],
            relative_width: 0.1,
            widen: 1.5,
            max_rounds: 12,
        }
    }

    /// Runs the search against an oracle giving the outcome of each (size, seed).
    fn search(
        s: &SearchSettings,
        oracle: impl Fn(f64, usize) -> Outcome,
        seeds: usize,
    ) -> (Vec<Probe>, Step) {
        let mut probes: Vec<Probe> = Vec::new();
        let mut rounds = 0;
        loop {
            match next_step(s, &probes, rounds).unwrap() {
                Step::Probe(ds) => {
                    for d in ds {
                        probes.push(Probe {
                            size: d,
                            outcomes: (0..seeds).map(|k| oracle(d, k)).collect(),
                        });
                    }
                    rounds += 1;
                }
                done => return (probes, done),
            }
        }
    }

    fn threshold(t: f64) -> impl Fn(f64, usize) -> Outcome {
        move |d, _| {
            if d >= t {
                Outcome::WearParticle
            } else {
                Outcome::PlasticSmoothing
            }
        }
    }

    #[test]
    fn a_sharp_threshold_is_bracketed_to_the_requested_width() {
        let (probes, done) = search(&settings(), threshold(18.5), 2);
        let b = Bracket::of(&probes);
        let (l, u) = (b.lower.unwrap(), b.upper.unwrap());
        assert!(l < 18.5 && 18.5 <= u, "{b:?}");
        assert!(b.relative_width().unwrap() <= 0.1, "{b:?}");
        assert!(
            matches!(
                done,
                Step::Done {
                    converged: true,
                    ..
                }
            ),
            "{done:?}"
        );
        // Bisection: about log2(range / width) rounds, not a sweep.
        assert!(probes.len() <= 6, "{} probes", probes.len());
    }

    #[test]
    fn the_range_widens_towards_the_missing_outcome_within_the_limits() {
        let (probes, done) = search(&settings(), threshold(31.0), 2);
        let b = Bracket::of(&probes);
        assert!(b.lower.unwrap() < 31.0 && 31.0 <= b.upper.unwrap(), "{b:?}");
        assert!(matches!(
            done,
            Step::Done {
                converged: true,
                ..
            }
        ));
        let (probes, _) = search(&settings(), threshold(6.0), 2);
        let b = Bracket::of(&probes);
        assert!(b.lower.unwrap() < 6.0 && 6.0 <= b.upper.unwrap(), "{b:?}");
        // Beyond the limits the search says so instead of inventing a bound.
        let (_, done) = search(&settings(), threshold(100.0), 2);
        match done {
            Step::Done { converged, reason } => {
                assert!(!converged && reason.contains("largest allowed"), "{reason}")
            }
            s => panic!("{s:?}"),
        }
    }

    #[test]
    fn split_seeds_are_a_transition_zone_not_a_bound() {
        // Seed 0 detaches from 15, seed 1 from 17: sizes in [15, 17) are split.
        let oracle = |d: f64, k: usize| {
            if d >= [15.0, 17.0][k] {
                Outcome::WearParticle
            } else {
                Outcome::PlasticSmoothing
            }
        };
        let (probes, done) = search(&settings(), oracle, 2);
        let b = Bracket::of(&probes);
        assert!(b.lower.unwrap() < 15.0 && b.upper.unwrap() >= 17.0, "{b:?}");
        assert!(!b.split.is_empty());
        assert!(b.split.iter().all(|&d| (15.0..17.0).contains(&d)), "{b:?}");
        assert!(matches!(done, Step::Done { .. }));
    }

    #[test]
    fn contradicting_outcomes_are_flagged_and_do_not_move_the_bounds() {
        let p = |size, o| Probe {
            size,
            outcomes: vec![o, o],
        };
        let probes = vec![
            p(10.0, Outcome::PlasticSmoothing),
            p(15.0, Outcome::WearParticle),
            p(17.5, Outcome::PlasticSmoothing),
            p(20.0, Outcome::WearParticle),
        ];
        let b = Bracket::of(&probes);
        assert_eq!((b.lower, b.upper), (Some(10.0), Some(15.0)));
        assert_eq!(b.non_monotonic, vec![17.5]);
    }

    #[test]
    fn bad_settings_and_empty_probes_are_refused() {
        let mut s = settings();
        s.range = [20.0, 10.0];
        assert!(next_step(&s, &[], 0).is_err());
        let mut s = settings();
        s.widen = 1.0;
        assert!(next_step(&s, &[], 0).is_err());
        let empty = [Probe {
            size: 10.0,
            outcomes: vec![],
        }];
        assert!(next_step(&settings(), &empty, 0).is_err());
    }

    #[test]
    fn sizes_round_to_three_significant_digits() {
        assert_eq!(round_size(14.999_99), 15.0);
        assert_eq!(round_size(0.123_456), 0.123);
        assert_eq!(round_size(123_456.0), 123_000.0);
    }
}
