//! A claim of a paper that the workbench reproduces: reference value, measured value, tolerance and
//! verdict; one row of `summary.csv`.

use super::figure::csv_field;

/// How close the measured value must be to the reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Tolerance {
    /// |measured - reference| <= t |reference|.
    Relative(f64),
    /// |measured - reference| <= t.
    Absolute(f64),
    /// measured < reference (a trend: a ratio below 1, say).
    Below,
    /// measured > reference.
    Above,
    /// Shown beside the paper's value, not a pass/fail target (e.g. paper 000's uncalibrated amorphous
    /// figures, DESIGN.md section 8).
    Info,
}

impl std::fmt::Display for Tolerance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Tolerance::Relative(t) => write!(f, "±{} %", sig(100.0 * t, 2)),
            Tolerance::Absolute(t) => write!(f, "±{}", sig(*t, 2)),
            Tolerance::Below => f.write_str("< reference"),
            Tolerance::Above => f.write_str("> reference"),
            Tolerance::Info => f.write_str("not a target"),
        }
    }
}

/// The verdict of a claim.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    Pass,
    Fail,
    Info,
}

impl Verdict {
    pub fn name(self) -> &'static str {
        match self {
            Verdict::Pass => "pass",
            Verdict::Fail => "fail",
            Verdict::Info => "info",
        }
    }
}

/// Where a claim's measured value is plotted: the figure's CSV has a row with this panel, series and
/// x whose y is the measured value (the tests check it).
#[derive(Debug, Clone, PartialEq)]
pub struct Plotted {
    pub figure: String,
    pub panel: String,
    pub series: String,
    pub x: f64,
}

/// One row of the summary.
#[derive(Debug, Clone, PartialEq)]
pub struct Claim {
    /// Paper id ("000", "001", "004") or "workbench" for the engine's own checks.
    pub paper: String,
    /// Figure, table or equation of the paper ("Fig. 5", "Table 5", "eq 6").
    pub item: String,
    pub quantity: String,
    pub reference: f64,
    pub measured: f64,
    pub tolerance: Tolerance,
    /// One sentence shown in the HTML (a known difference, the case's conditions); not in the CSV.
    pub note: String,
    pub plotted: Option<Plotted>,
}

impl Claim {
    pub fn new(
        paper: &str,
        item: &str,
        quantity: impl Into<String>,
        reference: f64,
        measured: f64,
        tolerance: Tolerance,
    ) -> Self {
        Claim {
            paper: paper.into(),
            item: item.into(),
            quantity: quantity.into(),
            reference,
            measured,
            tolerance,
            note: String::new(),
            plotted: None,
        }
    }

    pub fn note(mut self, note: impl Into<String>) -> Self {
        self.note = note.into();
        self
    }

    pub fn plotted(mut self, figure: &str, panel: &str, series: &str, x: f64) -> Self {
        self.plotted = Some(Plotted {
            figure: figure.into(),
            panel: panel.into(),
            series: series.into(),
            x,
        });
        self
    }

    /// Pass, fail (a non-finite measurement always fails) or info.
    pub fn verdict(&self) -> Verdict {
        let (m, r) = (self.measured, self.reference);
        if self.tolerance == Tolerance::Info {
            return Verdict::Info;
        }
        let ok = m.is_finite()
            && match self.tolerance {
                Tolerance::Relative(t) => (m - r).abs() <= t * r.abs(),
                Tolerance::Absolute(t) => (m - r).abs() <= t,
                Tolerance::Below => m < r,
                Tolerance::Above => m > r,
                Tolerance::Info => true,
            };
        if ok {
            Verdict::Pass
        } else {
            Verdict::Fail
        }
    }

    /// The `summary.csv` row (numbers in shortest round-trip form).
    pub fn csv_row(&self) -> String {
        format!(
            "{},{},{},{:?},{:?},{},{}",
            csv_field(&self.paper),
            csv_field(&self.item),
            csv_field(&self.quantity),
            self.reference,
            self.measured,
            csv_field(&self.tolerance.to_string()),
            self.verdict().name()
        )
    }
}

/// The header of `summary.csv`.
pub const SUMMARY_HEADER: &str = "paper,item,quantity,reference,measured,tolerance,pass";

/// `v` with `digits` significant digits, without trailing zeros (the digits that mean something).
pub fn sig(v: f64, digits: usize) -> String {
    dem::io::Sig(v, digits).to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn verdicts_follow_the_tolerance_and_nan_fails() {
        let c = |m: f64, t| Claim::new("000", "eq 6", "q", 1.0, m, t);
        assert_eq!(c(1.04, Tolerance::Relative(0.05)).verdict(), Verdict::Pass);
        assert_eq!(c(1.06, Tolerance::Relative(0.05)).verdict(), Verdict::Fail);
        assert_eq!(c(0.5, Tolerance::Below).verdict(), Verdict::Pass);
        assert_eq!(c(1.5, Tolerance::Below).verdict(), Verdict::Fail);
        assert_eq!(c(1.5, Tolerance::Above).verdict(), Verdict::Pass);
        assert_eq!(
            c(f64::NAN, Tolerance::Absolute(1e9)).verdict(),
            Verdict::Fail
        );
        assert_eq!(c(f64::NAN, Tolerance::Info).verdict(), Verdict::Info);
    }

    #[test]
    fn csv_rows_have_the_seven_columns() {
        let row = Claim::new(
            "000",
            "Fig. 5",
            "sigma_N, s = 1/2",
            0.1,
            0.1 + 0.2,
            Tolerance::Relative(0.07),
        )
        .csv_row();
        let f = super::super::figure::csv_split(&row);
        assert_eq!(f.len(), SUMMARY_HEADER.split(',').count());
        assert_eq!(f[2], "\"sigma_N, s = 1/2\"".trim_matches('"'));
        assert_eq!(f[4].parse::<f64>().unwrap(), 0.1 + 0.2);
        assert_eq!(f[5], "±7 %");
        assert_eq!(f[6], "fail");
    }

    #[test]
    fn significant_digits_drop_the_noise() {
        assert_eq!(sig(0.10000000000008556, 4), "0.1");
        assert_eq!(sig(1234.5678, 4), "1235");
        assert_eq!(sig(0.0123456, 3), "0.0123");
        assert_eq!(sig(1.5e-5, 3), "1.5e-5");
        assert_eq!(sig(-2.0, 3), "-2");
        assert_eq!(sig(0.0, 3), "0");
    }
}
