//! What the plastic-wear model (paper 001) claims and how it measures up, for the validation report:
//! [`claims`] turns results (of any size) into rows of (paper, figure, quantity, reference, measured,
//! tolerance, pass), and [`quick_profile`] runs a small set of jobs (seconds on two cores, cached)
//! that yields every claim.
//!
//! The references are the paper's statements: eq 16 within the issue's 15 %, the wear peak "between
//! 0 and 90 deg" (~45 deg in the text), the COR minimum "at ~25 deg" with the deviation's maximum "at
//! about the same angle", COR ~ 1 near 90 deg, the wear threshold "~1000 N", H_l ~ mu_a H
//! (section 3.1), Archard's law at small loads, and energy balance (Figs. 12-13).

use dem::jobs::{JobCache, RunJobs};
use dem::scenario::plastic::{
    run_impacts, run_scratches, ImpactFile, ImpactPoint, ImpactResult, ScratchFile, ScratchResult,
};

use crate::error::{Result, ValidationError};

/// How a claim's measured value is judged against its reference.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Rule {
    /// |measured / reference - 1| <= tolerance.
    Relative,
    /// |measured - reference| <= tolerance.
    Absolute,
    /// measured >= reference (tolerance unused).
    AtLeast,
    /// measured <= reference (tolerance unused).
    AtMost,
}

/// One row of the report.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Claim {
    pub paper: String,
    pub figure: String,
    pub quantity: String,
    pub reference: f64,
    pub measured: f64,
    pub tolerance: f64,
    pub rule: Rule,
    pub pass: bool,
}

impl Claim {
    fn new(
        figure: &str,
        quantity: &str,
        reference: f64,
        measured: f64,
        tolerance: f64,
        rule: Rule,
    ) -> Claim {
        let pass = measured.is_finite()
            && match rule {
                Rule::Relative => (measured / reference - 1.0).abs() <= tolerance,
                Rule::Absolute => (measured - reference).abs() <= tolerance,
                Rule::AtLeast => measured >= reference,
                Rule::AtMost => measured <= reference,
            };
        Claim {
            paper: "001".into(),
            figure: figure.into(),
            quantity: quantity.into(),
            reference,
            measured,
            tolerance,
            rule,
            pass,
        }
    }

    /// The tolerance as text ("+-15 %", ">= 1", ...).
    pub fn tolerance_text(&self) -> String {
        match self.rule {
            Rule::Relative => format!("+-{:.0} %", 100.0 * self.tolerance),
            Rule::Absolute => format!("+-{}", self.tolerance),
            Rule::AtLeast => format!(">= {}", self.reference),
            Rule::AtMost => format!("<= {}", self.reference),
        }
    }
}

/// The results the claims are drawn from.
#[derive(Debug, Clone, PartialEq)]
pub struct PlasticResults {
    /// Normal impacts of the 1 cm, 8 g/cm^3 sphere (Fig. 4): any H at 45 m/s and any V_z at 1.7 GPa.
    pub normal: Vec<ImpactResult>,
    /// Oblique sweep points (Figs. 5-7) of the 3 mm sphere at 30/35/40 m/s (mu_a = 0.25) and at
    /// 35 m/s with a smaller mu_a.
    pub oblique: Vec<ImpactPoint>,
    /// Oblique single impacts whose energy ledger is judged (Fig. 12).
    pub oblique_runs: Vec<ImpactResult>,
    /// A scratch test at mu_a = 0.25, H = 1.7 GPa over loads from below the threshold (Figs. 3, 10).
    pub scratch: ScratchResult,
}

fn curve(p: &[ImpactPoint], speed: f64, mu_a: f64) -> Vec<&ImpactPoint> {
    p.iter()
        .filter(|x| x.speed == speed && x.mu_a == mu_a)
        .collect()
}

fn arg(c: &[&ImpactPoint], f: impl Fn(&ImpactPoint) -> f64) -> (f64, f64) {
    c.iter()
        .map(|p| (p.angle_deg, f(p)))
        .fold(
            (f64::NAN, f64::NEG_INFINITY),
            |m, x| if x.1 > m.1 { x } else { m },
        )
}

/// Every claim the results can judge.
pub fn claims(r: &PlasticResults) -> Vec<Claim> {
    let mut out = Vec::new();
    // Fig. 4: eq 16.
    let ratio = |x: &ImpactResult| x.wear_volume / x.reference_wear_volume;
    let worst = |sel: &dyn Fn(&ImpactResult) -> bool| {
        r.normal
            .iter()
            .filter(|x| sel(x))
            .map(ratio)
            .fold(1.0f64, |w, q| {
                if (q - 1.0).abs() > (w - 1.0).abs() {
                    q
                } else {
                    w
                }
            })
    };
    if let Some(x) = r
        .normal
        .iter()
        .find(|x| x.hardness == 1.7e9 && x.speed == 45.0)
    {
        out.push(Claim::new(
            "4",
            "W_V / eq 16 at H = 1.7 GPa, V_z = 45 m/s",
            1.0,
            ratio(x),
            0.15,
            Rule::Relative,
        ));
    }
    out.push(Claim::new(
        "4a",
        "worst W_V / eq 16 over H at V_z = 45 m/s",
        1.0,
        worst(&|x| x.speed == 45.0),
        0.15,
        Rule::Relative,
    ));
    out.push(Claim::new(
        "4b",
        "worst W_V / eq 16 over V_z at H = 1.7 GPa",
        1.0,
        worst(&|x| x.hardness == 1.7e9),
        0.15,
        Rule::Relative,
    ));
    // Figs. 5-7.
    let base = curve(&r.oblique, 35.0, 0.25);
    if !base.is_empty() {
        let (at, _) = arg(&base, |p| p.wear_volume);
        out.push(Claim::new(
            "5a",
            "angle of the largest wear volume at 35 m/s (deg)",
            45.0,
            at,
            25.0,
            Rule::Absolute,
        ));
        let peaks: Vec<f64> = [30.0, 35.0, 40.0]
            .iter()
            .map(|&v| arg(&curve(&r.oblique, v, 0.25), |p| p.wear_volume).1)
            .collect();
        out.push(Claim::new(
            "5a",
            "growth of the peak wear from 30 to 35 to 40 m/s (smaller ratio)",
            1.0,
            (peaks[1] / peaks[0]).min(peaks[2] / peaks[1]),
            0.0,
            Rule::AtLeast,
        ));
        let (cor_at, _) = arg(&base, |p| -p.cor);
        let (dev_at, _) = arg(&base, |p| p.deviation_deg);
        out.push(Claim::new(
            "7a",
            "angle of the smallest COR at mu_a = 0.25 (deg)",
            25.0,
            cor_at,
            10.0,
            Rule::Absolute,
        ));
        out.push(Claim::new(
            "7b",
            "angle of the largest deviation at mu_a = 0.25 (deg)",
            25.0,
            dev_at,
            15.0,
            Rule::Absolute,
        ));
        if let Some(p90) = base.iter().find(|p| p.angle_deg == 90.0) {
            out.push(Claim::new(
                "7a",
                "COR at 90 deg",
                1.0,
                p90.cor,
                0.05,
                Rule::Relative,
            ));
        }
        let soft_mu = r
            .oblique
            .iter()
            .filter(|p| p.speed == 35.0 && p.mu_a < 0.25)
            .map(|p| p.mu_a)
            .fold(f64::NAN, f64::max);
        let soft = curve(&r.oblique, 35.0, soft_mu);
        let at60 = |c: &[&ImpactPoint]| {
            c.iter()
                .find(|p| p.angle_deg == 60.0)
                .map(|p| p.wear_volume)
        };
        if let (Some(s), Some(h)) = (at60(&soft), at60(&base)) {
            out.push(Claim::new(
                "6",
                &format!("W_V(mu_a = {soft_mu}) / W_V(mu_a = 0.25) at 60 deg"),
                1.0,
                s / h,
                0.0,
                Rule::AtLeast,
            ));
        }
    }
    // Figs. 3 and 10.
    if let Some(f) = &r.scratch.archard {
        out.push(Claim::new(
            "3a",
            "load at which wear starts (N, Archard line's onset)",
            1000.0,
            f.onset_load,
            0.5,
            Rule::Relative,
        ));
        out.push(Claim::new(
            "10",
            "R^2 of Archard's line at small loads",
            0.97,
            f.r2,
            0.0,
            Rule::AtLeast,
        ));
        out.push(Claim::new(
            "10",
            "wear rate at the largest load over Archard's line",
            1.5,
            f.excess_at_largest,
            0.0,
            Rule::AtLeast,
        ));
    }
    if let Some(h) = &r.scratch.shear_hardness {
        out.push(Claim::new(
            "3b",
            "H_l = dF_x/dA_z over mu_a H",
            1.0,
            h.slope / h.reference,
            0.2,
            Rule::Relative,
        ));
    }
    // Figs. 12-13.
    let impact_err = r
        .normal
        .iter()
        .chain(&r.oblique_runs)
        .map(|x| x.energy.max_balance_error)
        .fold(0.0, f64::max);
    out.push(Claim::new(
        "12",
        "largest energy-balance error of the impacts (of E0)",
        0.01,
        impact_err,
        0.0,
        Rule::AtMost,
    ));
    let scratch_err = r
        .scratch
        .runs
        .iter()
        .map(|x| x.energy.max_balance_error)
        .fold(0.0, f64::max);
    out.push(Claim::new(
        "13",
        "largest energy-balance error of the scratches (of the external work)",
        0.01,
        scratch_err,
        0.0,
        Rule::AtMost,
    ));
    out
}

const NORMAL: &str =
    "[projectile]\nradius = 0.01\ndensity = 8000.0\n[impact]\nspeed = 45.0\nangle_deg = 90.0\n";
const OBLIQUE: &str = "[model]\nhardness = 6.6e9\n[projectile]\nradius = 0.003\ndensity = 2500.0\n[impact]\nspeed = 35.0\nangle_deg = 45.0\n";
const ANGLES: &str =
    "angle_deg = [10.0, 20.0, 25.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0, 90.0]\naims = 4\n";

fn parse<T: serde::de::DeserializeOwned>(text: &str) -> T {
    toml::from_str(text).expect("the quick profile's configs parse")
}

/// Runs the quick profile through `cache` (seconds on two cores; a rerun is read from the cache):
/// normal impacts at H = 1, 1.7, 4, 7 GPa and V_z = 20, 60 m/s; the oblique sweep at 10 angles,
/// 4 landing points, 30/35/40 m/s and mu_a = 0.15 at 35 m/s; single impacts at 29, 45 and 90 deg; a
/// scratch test over 9 loads from 0.5 to 10 kN on a 3.2 cm slide.
pub fn quick_profile(cache: &JobCache, how: &RunJobs) -> Result<PlasticResults> {
    let quiet = |_: &_, _: &_| {};
    let files: Vec<ImpactFile> = vec![
        parse(&format!(
            "{NORMAL}[sweep]\nhardness = [1.0e9, 1.7e9, 4.0e9, 7.0e9]\n"
        )),
        parse(&format!("{NORMAL}[sweep]\nspeed = [20.0, 60.0]\n")),
        parse(&format!(
            "{OBLIQUE}[sweep]\n{ANGLES}speed = [30.0, 35.0, 40.0]\n"
        )),
        parse(&format!("{OBLIQUE}[sweep]\n{ANGLES}mu_a = [0.15]\n")),
        parse(&format!(
            "{OBLIQUE}[sweep]\nangle_deg = [29.0, 45.0, 90.0]\n"
        )),
    ];
    let mut sets = Vec::new();
    for f in &files {
        let jobs = f.jobs()?;
        let runs: Option<Vec<ImpactResult>> = run_impacts(&jobs, cache, how, &quiet)?
            .into_iter()
            .collect();
        sets.push(runs.ok_or_else(pending)?);
    }
    let mut normal = sets[0].clone();
    normal.extend(sets[1].iter().cloned());
    let mut oblique = files[2].points(&sets[2]);
    oblique.extend(files[3].points(&sets[3]));
    let scratch: ScratchFile = parse(
        "[indent]\nspeed = 0.02\nloads = [500.0, 1000.0, 1500.0, 2000.0, 3000.0, 4000.0, 6000.0, 8000.0, 10000.0]\n\
         [slide]\nduration = 0.16\n",
    );
    let tests = scratch.tests()?;
    let scratch = run_scratches(&tests, cache, how, &|_, _| {})?
        .ok_or_else(pending)?
        .remove(0);
    Ok(PlasticResults {
        normal,
        oblique,
        oblique_runs: sets[4].clone(),
        scratch,
    })
}

fn pending() -> ValidationError {
    ValidationError::Report(
        "jobs of other shards are pending: run again once every shard has finished".into(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rules_judge_as_they_say() {
        assert!(Claim::new("4", "q", 1.0, 0.86, 0.15, Rule::Relative).pass);
        assert!(!Claim::new("4", "q", 1.0, 0.84, 0.15, Rule::Relative).pass);
        assert!(Claim::new("7a", "q", 25.0, 35.0, 10.0, Rule::Absolute).pass);
        assert!(!Claim::new("7a", "q", 25.0, 35.5, 10.0, Rule::Absolute).pass);
        assert!(Claim::new("10", "q", 0.97, 0.99, 0.0, Rule::AtLeast).pass);
        assert!(!Claim::new("12", "q", 0.01, 0.02, 0.0, Rule::AtMost).pass);
        assert!(!Claim::new("12", "q", 0.01, f64::NAN, 0.0, Rule::AtMost).pass);
        assert_eq!(
            Claim::new("4", "q", 1.0, 1.0, 0.15, Rule::Relative).tolerance_text(),
            "+-15 %"
        );
    }
}
