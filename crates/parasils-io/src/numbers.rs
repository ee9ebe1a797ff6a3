//! Numbers in messages and summaries, readable whatever their size: plain
//! decimals for ordinary values, exponent form for huge or tiny ones
//! (`1e308`, not three hundred digits).
//!
//! [`Shortest`] writes every digit a value needs to read back the same
//! (`0.30000000000000004`): a user's own input quoted in an error. It is not
//! `parasils_num::Num`, which rounds to six significant digits for the
//! kinematics' and the profiles' messages. [`Fixed`] writes a set count of
//! decimals (tables, summaries); [`AtTime`] the prefix of an error at a
//! sample's time.

use core::fmt;

/// The smallest magnitude written without an exponent (but 0).
const PLAIN_MIN: f64 = 1e-4;
/// The magnitude from which an exponent is used.
const PLAIN_MAX: f64 = 1e15;

/// Whether `v` reads well as a plain decimal: zero, or a finite magnitude in
/// `[1e-4, 1e15)`.
fn plain(v: f64) -> bool {
    v == 0.0 || (PLAIN_MIN..PLAIN_MAX).contains(&v.abs())
}

/// A number in its shortest text that reads back to the same `f64`: `0.3`,
/// `-15`, `2.5e-7`, `1e308`, `NaN`, `inf`.
///
/// ```
/// use parasils_io::Shortest;
///
/// assert_eq!(Shortest(-15.0).to_string(), "-15");
/// assert_eq!(Shortest(0.1 + 0.2).to_string(), "0.30000000000000004");
/// assert_eq!(Shortest(1e308).to_string(), "1e308");
/// assert_eq!(Shortest(-2.5e-7).to_string(), "-2.5e-7");
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shortest(pub f64);

impl fmt::Display for Shortest {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let v = self.0;
        let text = if !v.is_finite() || plain(v) {
            format!("{v}")
        } else {
            format!("{v:e}")
        };
        f.pad(&text)
    }
}

/// A number with a fixed count of decimals (`{:.N}`), in exponent form with
/// as many decimals from `1e9` on (`1.000e300`, not three hundred digits);
/// a value that rounds to zero is written without a sign. The width and
/// alignment of the format apply (`{:>9}`).
///
/// ```
/// use parasils_io::Fixed;
///
/// assert_eq!(format!("{:>9}", Fixed(-15.0, 4)), " -15.0000");
/// assert_eq!(Fixed(4.5, 3).to_string(), "4.500");
/// assert_eq!(Fixed(1e300, 3).to_string(), "1.000e300");
/// assert_eq!(Fixed(-3e-9, 3).to_string(), "0.000");
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fixed(pub f64, pub usize);

impl fmt::Display for Fixed {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Fixed(v, decimals) = *self;
        let text = if v.is_finite() && v.abs() >= PLAIN_FIXED_MAX {
            format!("{v:.decimals$e}")
        } else {
            let text = format!("{v:.decimals$}");
            match text.strip_prefix('-') {
                Some(unsigned) if unsigned.bytes().all(|b| b == b'0' || b == b'.') => {
                    unsigned.to_owned()
                }
                _ => text,
            }
        };
        f.pad(&text)
    }
}

/// The magnitude from which [`Fixed`] uses an exponent.
const PLAIN_FIXED_MAX: f64 = 1e9;

/// `at t = 1.234 s: `, the prefix of an error at a sample's time: 3
/// decimals, or an exponent for a time that would read as `0.000` without
/// being 0, or that is huge (`at t = 1.000e-300 s`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AtTime(pub f64);

impl fmt::Display for AtTime {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let t = self.0;
        if t != 0.0 && t.abs() < 5e-4 {
            write!(f, "at t = {t:.3e} s: ")
        } else {
            write!(f, "at t = {} s: ", Fixed(t, 3))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ordinary_values_are_plain_and_extremes_have_an_exponent() {
        for (v, want) in [
            (0.0, "0"),
            (4.5, "4.5"),
            (1000.0, "1000"),
            (1e-4, "0.0001"),
            (9.9e-5, "9.9e-5"),
            (1e15, "1e15"),
            (f64::NAN, "NaN"),
            (f64::NEG_INFINITY, "-inf"),
        ] {
            assert_eq!(Shortest(v).to_string(), want);
        }
        assert_eq!(format!("{:>6}", Shortest(4.5)), "   4.5");
    }

    #[test]
    fn times_in_messages() {
        assert_eq!(AtTime(4.444).to_string(), "at t = 4.444 s: ");
        assert_eq!(AtTime(0.0).to_string(), "at t = 0.000 s: ");
        assert_eq!(AtTime(1e300).to_string(), "at t = 1.000e300 s: ");
        assert_eq!(AtTime(1e-300).to_string(), "at t = 1.000e-300 s: ");
        assert_eq!(Fixed(0.0004, 3).to_string(), "0.000");
        assert_eq!(Fixed(-0.0004, 3).to_string(), "0.000");
        assert_eq!(Fixed(-0.0, 4).to_string(), "0.0000");
        assert_eq!(Fixed(-0.1, 1).to_string(), "-0.1");
        assert_eq!(Fixed(1e9, 1).to_string(), "1.0e9");
        assert_eq!(Fixed(f64::NAN, 4).to_string(), "NaN");
    }
}
