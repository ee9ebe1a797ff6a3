//! [`Num`]: a number as the error messages write it.

use core::fmt::{self, Write};

/// A number as the messages write it : up to
/// `digits` significant digits, trailing zeros dropped; plain for
/// `1e-3 <= |x| < 1e6`, in exponent form otherwise; `0` for both zeros;
/// `NaN`, `inf` and `-inf` by name.
#[derive(Debug, Clone, Copy)]
pub struct Num {
    value: f64,
    digits: usize,
}

/// The fewest significant digits a message writes.
const DIGITS: usize = 6;

/// Enough significant digits to tell any two `f64` apart.
const MAX_DIGITS: usize = 17;

impl Num {
    /// `value` with 6 significant digits.
    pub fn new(value: f64) -> Self {
        Self {
            value,
            digits: DIGITS,
        }
    }

    /// `value` with the fewest significant digits, from 6 up, that do not
    /// write it as [`Num::new`] writes `limit` (unless it is `limit`): a
    /// value just beyond a limit must not read as the limit.
    pub fn apart_from(value: f64, limit: f64) -> Self {
        let shown = rounded(limit, DIGITS);
        let mut digits = DIGITS;
        while digits < MAX_DIGITS && value != limit && rounded(value, digits) == shown {
            digits += 1;
        }
        Self { value, digits }
    }

    /// `value` apart from the bound of `[min, max]` it is beyond (the upper
    /// one unless it is below `min`).
    pub fn outside(value: f64, min: f64, max: f64) -> Self {
        Self::apart_from(value, if value < min { min } else { max })
    }
}

impl fmt::Display for Num {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let x = self.value;
        if x.is_nan() {
            return f.write_str("NaN");
        }
        if x.is_infinite() {
            return f.write_str(if x > 0.0 { "inf" } else { "-inf" });
        }
        if x == 0.0 {
            return f.write_str("0");
        }
        let decimals = self.digits.saturating_sub(1);
        let mut sci = Buf::new();
        write!(sci, "{x:.decimals$e}")?;
        let (mantissa, exponent) = sci.as_str().split_once('e').ok_or(fmt::Error)?;
        let exponent: i32 = exponent.parse().map_err(|_| fmt::Error)?;
        // The exponent after rounding: 999999.7 is 1e6, not 1000000.
        if (-3..6).contains(&exponent) {
            let places = usize::try_from(self.digits as i64 - 1 - i64::from(exponent))
                .map_err(|_| fmt::Error)?;
            let mut plain = Buf::new();
            write!(plain, "{x:.places$}")?;
            f.write_str(trim_zeros(plain.as_str()))
        } else {
            f.write_str(trim_zeros(mantissa))?;
            write!(f, "e{exponent}")
        }
    }
}

/// `value` rounded to `digits` significant digits, as written and read back.
fn rounded(value: f64, digits: usize) -> Option<f64> {
    let mut b = Buf::new();
    let decimals = digits.saturating_sub(1);
    write!(b, "{value:.decimals$e}").ok()?;
    b.as_str().parse().ok()
}

/// `1.500` as `1.5`, `2.000` as `2`; a string without a point unchanged.
fn trim_zeros(s: &str) -> &str {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        s
    }
}

/// A number's text, on the stack: at most 40 bytes (the longest a [`Num`]
/// writes is 27).
struct Buf {
    bytes: [u8; 40],
    len: usize,
}

impl Buf {
    fn new() -> Self {
        Self {
            bytes: [0; 40],
            len: 0,
        }
    }

    fn as_str(&self) -> &str {
        self.bytes
            .get(..self.len)
            .and_then(|b| core::str::from_utf8(b).ok())
            .unwrap_or("")
    }
}

impl fmt::Write for Buf {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        let end = self.len + s.len();
        let dst = self.bytes.get_mut(self.len..end).ok_or(fmt::Error)?;
        dst.copy_from_slice(s.as_bytes());
        self.len = end;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::string::ToString;

    #[test]
    fn numbers_are_short() {
        let cases = [
            (1e308, "1e308"),
            (-2.5e-7, "-2.5e-7"),
            (1e-6, "1e-6"),
            (0.001, "0.001"),
            (0.000_99, "9.9e-4"),
            (0.009_945, "0.009945"),
            (-0.0, "0"),
            (0.0, "0"),
            (80.0, "80"),
            (-7.245_830_4, "-7.24583"),
            (123_456.7, "123457"),
            (999_999.7, "1e6"),
            (1e6, "1e6"),
            (1_234_567.0, "1.23457e6"),
            (f64::NAN, "NaN"),
            (f64::INFINITY, "inf"),
            (f64::NEG_INFINITY, "-inf"),
            (f64::MAX, "1.79769e308"),
            (f64::MIN_POSITIVE / 4.0, "5.56268e-309"),
        ];
        for (x, want) in cases {
            assert_eq!(Num::new(x).to_string(), want, "{x:e}");
        }
        assert_eq!(Num::apart_from(1e-6, 1e-6).to_string(), "1e-6");
        assert_eq!(
            Num::apart_from(0.009_999_999, 0.01).to_string(),
            "0.009999999"
        );
        assert_eq!(
            Num::outside(-80.000_000_2, -80.0, 80.0).to_string(),
            "-80.0000002"
        );
        assert_eq!(
            Num::apart_from(f64::MAX, 1.797_69e308).to_string(),
            "1.797693e308"
        );
    }
}
