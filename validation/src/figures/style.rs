//! What every figure shares: the embedded font and the error conversion.

use std::sync::OnceLock;

use plotters::style::{register_font, FontStyle};

use crate::error::ValidationError;

/// DejaVu Sans (licence in `assets/LICENSE-DejaVu.txt`): bitmap text needs a font file, and a
/// shipped one makes the figures independent of the machine's fonts.
static FONT: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");

/// The family name figures ask for.
pub const FAMILY: &str = "sans-serif";

/// Registers the embedded font (once per process).
pub fn ensure_font() -> Result<(), ValidationError> {
    static DONE: OnceLock<bool> = OnceLock::new();
    let ok = *DONE.get_or_init(|| register_font(FAMILY, FontStyle::Normal, FONT).is_ok());
    if ok {
        Ok(())
    } else {
        Err(ValidationError::Draw {
            path: "<font>".into(),
            reason: "the embedded DejaVu Sans could not be loaded".into(),
        })
    }
}

/// Wraps a plotters error with the figure's path.
pub fn draw_err(path: &std::path::Path, e: impl std::fmt::Display) -> ValidationError {
    ValidationError::Draw {
        path: path.display().to_string(),
        reason: e.to_string(),
    }
}

/// Ten colours that stay distinguishable (matplotlib's "tab10"); series beyond ten repeat them.
const PALETTE: [(u8, u8, u8); 10] = [
    (31, 119, 180),
    (255, 127, 14),
    (44, 160, 44),
    (214, 39, 40),
    (148, 103, 189),
    (140, 86, 75),
    (227, 119, 194),
    (127, 127, 127),
    (188, 189, 34),
    (23, 190, 207),
];

/// The colour of series `k`.
pub fn colour(k: usize) -> plotters::style::RGBColor {
    let (r, g, b) = PALETTE[k % PALETTE.len()];
    plotters::style::RGBColor(r, g, b)
}

/// Tick labels: six significant decimals at most, no "-0" for a tick at zero, and from 1e5 on in
/// exponent form ("-1.6e6", not "-1600000", which overran the label area of a force in pN).
pub fn tick(v: &f64) -> String {
    let r = (v * 1e6).round() / 1e6;
    if r == 0.0 {
        "0".into()
    } else if r.abs() >= 1e5 {
        format!("{r:e}")
    } else {
        format!("{r}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_short_and_never_negative_zero() {
        assert_eq!(tick(&0.15000000000000002), "0.15");
        assert_eq!(tick(&-1e-19), "0");
        assert_eq!(tick(&-0.25), "-0.25");
        assert_eq!(tick(&16020.0), "16020");
        assert_eq!(tick(&-1600000.0), "-1.6e6");
        assert_eq!(tick(&200000.0), "2e5");
    }

    #[test]
    fn colours_cycle_through_ten() {
        assert_eq!(colour(0), colour(10));
        assert_ne!(colour(0), colour(1));
    }

    #[test]
    fn the_font_loads() {
        ensure_font().unwrap();
        ensure_font().unwrap();
    }
}
