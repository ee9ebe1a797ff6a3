//! [`Real`]: the float types the kinematics and the profiles are generic over.

use nalgebra::RealField;

use crate::trig::{sincos_f32, sincos_f64};

mod sealed {
    /// Seals [`super::Real`]: only `f32` and `f64` implement it.
    pub trait Sealed {}
    impl Sealed for f32 {}
    impl Sealed for f64 {}
}

/// A float type the kinematics and the profiles run in: `f32` (firmware) or
/// `f64` (host). The trait is sealed.
///
/// Everything in `parasils-kin` and `parasils-traj` is generic over
/// `T: Real`, and both re-export this trait, so that code using both needs
/// one bound. It is nalgebra's [`RealField`] (whose methods the arithmetic
/// calls: `sqrt`, `abs`, `max`, `is_finite`, ...) with what the two crates
/// add to it, each under one name: constants written in `f64` into `T`
/// ([`Real::lit`]) and values of `T` out to `f64` for error reports
/// ([`Real::to_f64`]), a sample index as a time ([`Real::from_index`]), the
/// constants and tests of IEEE floats that `RealField` lacks, and the
/// crate's own sine and cosine ([`Real::sincos`]). None of these names is
/// also a method of `RealField`, so no call on a `T: Real` is ambiguous.
///
/// The conversions never panic and never fail: they are the `as` casts of
/// the language, written once here so that no caller needs an `unwrap`.
pub trait Real: RealField + Copy + Default + sealed::Sealed {
    /// The machine epsilon of `Self`.
    const EPSILON: Self;
    /// The smallest positive normal number (`f64::MIN_POSITIVE`, `f32::MIN_POSITIVE`).
    const MIN_POSITIVE: Self;
    /// The largest finite number (`f64::MAX`, `f32::MAX`).
    const MAX: Self;
    /// Positive infinity.
    const INFINITY: Self;

    /// `x` rounded to `Self` (to nearest for `f32`).
    fn lit(x: f64) -> Self;
    /// A sample index as `Self`: exact up to 2^24 for `f32`, 2^53 for `f64`.
    fn from_index(k: usize) -> Self;
    /// `self` as an `f64` (exact for both `f32` and `f64`), for error reports.
    fn to_f64(self) -> f64;
    /// Whether the value is neither NaN nor infinite.
    fn finite(self) -> bool;
    /// Whether the value is a normal number: neither zero, subnormal,
    /// infinite nor NaN.
    fn is_normal(self) -> bool;
    /// Whether the value is NaN.
    fn is_nan(self) -> bool;

    /// `(sin self, cos self)` for an angle `self` in rad: the crate's own
    /// sine and cosine, both from one range reduction, in `Self`'s own
    /// arithmetic.
    ///
    /// Named apart from nalgebra's (libm's)
    /// [`ComplexField::sin_cos`](nalgebra::ComplexField::sin_cos): `x.sincos()`
    /// is this one, `x.sin_cos()` libm's. On a Cortex-M4F, whose FPU has no
    /// `f64`, libm's `f32` sine and cosine compute in emulated `f64`; this
    /// one stays in `f32` (the instruction counts of both are in
    /// `BENCHMARKS.md`). The method (a Cody-Waite reduction by `pi/2`,
    /// minimax polynomials on `[-pi/4, pi/4]`) is described in `src/trig.rs`.
    ///
    /// | | `f32` | `f64` |
    /// |---|---|---|
    /// | own range, rad (beyond it: libm's `sin_cos`) | `abs(x) < 2^8` | `abs(x) < 2^19` |
    /// | largest error, sine / cosine | 0.567 / 0.563 ulp | 0.579 / 0.576 ulp |
    /// | results not correctly rounded | 0.03 % | 0.3 % |
    ///
    /// Errors are in units in the last place of the exact result: for `f32`
    /// over every `f32` of the range, against libm's `f64`; for `f64` on 20
    /// million random angles against the x87's 64-bit-mantissa `sinl` and
    /// `cosl`, and at the `f64` closest to a multiple of `pi/2` in every
    /// binade against 300-bit arithmetic (the largest error found is quoted).
    /// The results keep that relative accuracy near the zeros of both (`x`
    /// near `k pi/2`); `sin(-x) = -sin x` and `cos(-x) = cos x` exactly,
    /// `sin(-0) = -0`; `sin^2 + cos^2` is 1 within 2 eps; NaN and infinities
    /// give NaN. (The tests are `parasils-kin`'s `tests/trig.rs`: the
    /// kinematics are what call it.)
    ///
    /// ```
    /// use parasils_num::Real;
    ///
    /// let (s, c) = 1.0_f32.sincos();
    /// assert_eq!((s, c), (0.841_470_96, 0.540_302_3)); // correctly rounded
    /// let (s, c) = 0.5_f64.sincos();
    /// assert!((s - 0.5_f64.sin()).abs() <= f64::EPSILON * s);
    /// assert!((c - 0.5_f64.cos()).abs() <= f64::EPSILON * c);
    /// ```
    fn sincos(self) -> (Self, Self);
}

impl Real for f64 {
    const EPSILON: Self = f64::EPSILON;
    const MIN_POSITIVE: Self = f64::MIN_POSITIVE;
    const MAX: Self = f64::MAX;
    const INFINITY: Self = f64::INFINITY;
    #[inline(always)]
    fn lit(x: f64) -> Self {
        x
    }
    #[inline]
    #[allow(clippy::cast_precision_loss)]
    fn from_index(k: usize) -> Self {
        k as f64
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self
    }
    #[inline(always)]
    fn finite(self) -> bool {
        self.is_finite()
    }
    #[inline(always)]
    fn is_normal(self) -> bool {
        f64::is_normal(self)
    }
    #[inline(always)]
    fn is_nan(self) -> bool {
        f64::is_nan(self)
    }
    #[inline]
    fn sincos(self) -> (Self, Self) {
        sincos_f64(self)
    }
}

impl Real for f32 {
    const EPSILON: Self = f32::EPSILON;
    const MIN_POSITIVE: Self = f32::MIN_POSITIVE;
    const MAX: Self = f32::MAX;
    const INFINITY: Self = f32::INFINITY;
    #[inline(always)]
    #[allow(clippy::cast_possible_truncation)]
    fn lit(x: f64) -> Self {
        x as f32
    }
    #[inline]
    #[allow(clippy::cast_precision_loss)]
    fn from_index(k: usize) -> Self {
        k as f32
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        f64::from(self)
    }
    #[inline(always)]
    fn finite(self) -> bool {
        self.is_finite()
    }
    #[inline(always)]
    fn is_normal(self) -> bool {
        f32::is_normal(self)
    }
    #[inline(always)]
    fn is_nan(self) -> bool {
        f32::is_nan(self)
    }
    #[inline]
    fn sincos(self) -> (Self, Self) {
        sincos_f32(self)
    }
}

#[cfg(test)]
#[allow(clippy::float_cmp, reason = "the conversions are exact")]
mod tests {
    use super::Real;

    /// Generic code sees the same numbers as the concrete types.
    fn facts<T: Real>() -> [f64; 4] {
        [
            T::EPSILON.to_f64(),
            T::MIN_POSITIVE.to_f64(),
            T::MAX.to_f64(),
            T::from_index(16_777_217).to_f64(),
        ]
    }

    #[test]
    fn constants_and_conversions_are_the_types_own() {
        assert_eq!(
            facts::<f64>(),
            [f64::EPSILON, f64::MIN_POSITIVE, f64::MAX, 16_777_217.0]
        );
        // 2^24 + 1 is the first integer f32 cannot hold: it rounds to even.
        assert_eq!(
            facts::<f32>(),
            [
                f64::from(f32::EPSILON),
                f64::from(f32::MIN_POSITIVE),
                f64::from(f32::MAX),
                16_777_216.0
            ]
        );
        assert_eq!(f32::lit(0.1), 0.1_f32);
        assert_eq!(f32::lit(1e39), f32::INFINITY);
        assert!(<f32 as Real>::INFINITY.to_f64().is_infinite());
    }

    #[test]
    fn the_tests_of_floats() {
        fn tests<T: Real>(x: T) -> [bool; 3] {
            [x.finite(), x.is_normal(), x.is_nan()]
        }
        assert_eq!(tests(1.0_f64), [true, true, false]);
        assert_eq!(tests(f64::MIN_POSITIVE / 2.0), [true, false, false]);
        assert_eq!(tests(0.0_f32), [true, false, false]);
        assert_eq!(tests(f32::NEG_INFINITY), [false, false, false]);
        assert_eq!(tests(f32::NAN), [false, false, true]);
    }
}
