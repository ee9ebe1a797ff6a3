//! Structured values read from a fuzzer's bytes.
//!
//! A fuzz input is a plain byte string; the targets read it as a sequence of
//! choices and numbers. Reading past the end gives zeros, so every input,
//! however short, is a complete case, and the fuzzer's mutations of one
//! byte change one choice or one number.
//!
//! A float is read as a tag byte and then its value: the tag picks a raw
//! bit pattern of the float type (every NaN, infinity, subnormal and
//! extreme exponent is reachable), a small fixed-point number (the sizes a
//! robot works at, which raw patterns almost never hit), or one of the
//! special values that break naive code (signed zeros, the extremes, the
//! smallest normal and subnormal numbers, one ulp around 1).

use parasils::Real;

/// A float type whose bit patterns the fuzzer may choose.
pub trait FuzzFloat: Real {
    /// `"f32"` or `"f64"`, for messages.
    const NAME: &'static str;
    /// The float with the given bits (the low bytes of `bits` for `f32`).
    fn from_raw(bits: u64) -> Self;
    /// The number of bytes of a raw bit pattern.
    const BYTES: usize;
    /// The values that break naive code (see the module docs).
    fn specials() -> [Self; 16];
    /// The float nearest `x`.
    fn of(x: f64) -> Self;
    /// Its machine epsilon, as an `f64`.
    const EPS: f64;
    /// Its value as an `f64` (exact).
    fn wide(self) -> f64;
}

impl FuzzFloat for f64 {
    const NAME: &'static str = "f64";
    const BYTES: usize = 8;
    const EPS: f64 = f64::EPSILON;
    fn of(x: f64) -> Self {
        x
    }
    fn wide(self) -> f64 {
        self
    }
    fn from_raw(bits: u64) -> Self {
        f64::from_bits(bits)
    }
    fn specials() -> [Self; 16] {
        [
            0.0,
            -0.0,
            1.0,
            -1.0,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::MAX,
            f64::MIN,
            f64::MIN_POSITIVE,
            f64::from_bits(1),
            f64::EPSILON,
            1.0 + f64::EPSILON,
            1.0 - f64::EPSILON / 2.0,
            1e154,
            1e-154,
        ]
    }
}

impl FuzzFloat for f32 {
    const NAME: &'static str = "f32";
    const BYTES: usize = 4;
    const EPS: f64 = f32::EPSILON as f64;
    fn of(x: f64) -> Self {
        // Rounding to the nearest f32 is what is asked for.
        #[allow(clippy::cast_possible_truncation)]
        let y = x as f32;
        y
    }
    fn wide(self) -> f64 {
        f64::from(self)
    }
    fn from_raw(bits: u64) -> Self {
        // The low 32 bits, on purpose.
        #[allow(clippy::cast_possible_truncation)]
        f32::from_bits(bits as u32)
    }
    fn specials() -> [Self; 16] {
        [
            0.0,
            -0.0,
            1.0,
            -1.0,
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::MAX,
            f32::MIN,
            f32::MIN_POSITIVE,
            f32::from_bits(1),
            f32::EPSILON,
            1.0 + f32::EPSILON,
            1.0 - f32::EPSILON / 2.0,
            1e19,
            1e-19,
        ]
    }
}

/// A cursor over a fuzz input (see the module docs).
#[derive(Debug, Clone)]
pub struct Input<'a> {
    data: &'a [u8],
}

impl<'a> Input<'a> {
    /// A cursor at the start of `data`.
    pub fn new(data: &'a [u8]) -> Self {
        Self { data }
    }

    /// The next byte, 0 past the end.
    pub fn byte(&mut self) -> u8 {
        match self.data.split_first() {
            Some((&b, rest)) => {
                self.data = rest;
                b
            }
            None => 0,
        }
    }

    /// The next `n <= 8` bytes as a little-endian integer, zero-padded.
    pub fn uint(&mut self, n: usize) -> u64 {
        (0..n.min(8)).fold(0u64, |acc, i| acc | u64::from(self.byte()) << (8 * i))
    }

    /// A choice in `0..n` (`n >= 1`), from one byte.
    pub fn choose(&mut self, n: u8) -> u8 {
        self.byte() % n.max(1)
    }

    /// A flag, from one byte.
    pub fn flag(&mut self) -> bool {
        self.byte() & 1 == 1
    }

    /// A float of type `T` (see the module docs).
    pub fn real<T: FuzzFloat>(&mut self) -> T {
        let tag = self.byte();
        match tag % 4 {
            0 => T::from_raw(self.uint(T::BYTES)),
            // A fixed-point number: a signed 16-bit integer over 2^(tag / 4 % 16),
            // so from whole millimetres down to fractions of a micrometre.
            1 | 2 => {
                let n = self.uint(2) as u16 as i16;
                let shift = i32::from(tag / 4 % 16);
                T::of(f64::from(n) / f64::from(1u32 << shift))
            }
            _ => {
                let specials = T::specials();
                let i = usize::from(tag / 4 % 16);
                specials.get(i).copied().unwrap_or(T::of(0.0))
            }
        }
    }

    /// `N` floats of type `T`.
    pub fn reals<T: FuzzFloat, const N: usize>(&mut self) -> [T; N] {
        core::array::from_fn(|_| self.real())
    }

    /// Everything not read yet.
    pub fn rest(&self) -> &'a [u8] {
        self.data
    }
}
