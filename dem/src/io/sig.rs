//! Numbers printed with the digits that mean something: `Sig(0.10000000000008556, 4)` shows `0.1`.
//! Log lines and tables use it (`tracing::info!(strain = %Sig(e, 4))`); files keep full precision.

/// `value` with `digits` significant digits, trailing zeros dropped; exponent form outside
/// 1e-4 .. 1e6.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sig(pub f64, pub usize);

impl std::fmt::Display for Sig {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let Sig(v, digits) = *self;
        if !v.is_finite() {
            return write!(f, "{v}");
        }
        if v == 0.0 {
            return f.write_str("0");
        }
        let digits = digits.max(1);
        let mag = v.abs().log10().floor() as i32;
        let trim = |s: &str| -> String {
            if s.contains('.') {
                s.trim_end_matches('0').trim_end_matches('.').to_string()
            } else {
                s.to_string()
            }
        };
        if !(-4..6).contains(&mag) {
            let s = format!("{:.*e}", digits - 1, v);
            return match s.split_once('e') {
                Some((m, e)) => write!(f, "{}e{e}", trim(m)),
                None => f.write_str(&s),
            };
        }
        let decimals = (digits as i32 - 1 - mag).max(0) as usize;
        f.write_str(&trim(&format!("{v:.decimals$}")))
    }
}

#[cfg(test)]
mod tests {
    use super::Sig;

    #[test]
    fn significant_digits_drop_the_noise() {
        assert_eq!(Sig(0.10000000000008556, 4).to_string(), "0.1");
        assert_eq!(Sig(1234.5678, 4).to_string(), "1235");
        assert_eq!(Sig(0.0123456, 3).to_string(), "0.0123");
        assert_eq!(Sig(1.5e-5, 3).to_string(), "1.5e-5");
        assert_eq!(Sig(-2.0, 3).to_string(), "-2");
        assert_eq!(Sig(0.0, 3).to_string(), "0");
        assert_eq!(Sig(f64::NAN, 3).to_string(), "NaN");
    }
}
