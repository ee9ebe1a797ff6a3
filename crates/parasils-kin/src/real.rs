//! The float types the crate is generic over.

use nalgebra::RealField;

/// A float type the kinematics run in: `f32` (firmware) or `f64` (host).
///
/// Everything in the crate is generic over `T: Real`. The trait adds to
/// nalgebra's [`RealField`] the two conversions the solvers need (constants
/// written in `f64` into `T`, and values of `T` out to `f64` for error
/// reports) and the crate's own sine and cosine, [`Real::sincos`].
pub trait Real: RealField + Copy {
    /// `x` rounded to `Self`.
    fn lit(x: f64) -> Self;
    /// `self` as an `f64` (exact for both `f32` and `f64`).
    fn to_f64(self) -> f64;
    /// Whether the value is neither NaN nor infinite.
    fn finite(self) -> bool;
    /// The machine epsilon of `Self`.
    const EPSILON: Self;
    /// The smallest positive normal number (`f64::MIN_POSITIVE`, `f32::MIN_POSITIVE`).
    const MIN_POSITIVE: Self;

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
    /// give NaN.
    ///
    /// ```
    /// use parasils_kin::Real;
    ///
    /// let (s, c) = 1.0_f32.sincos();
    /// assert_eq!((s, c), (0.841_470_96, 0.540_302_3)); // correctly rounded
    /// let (s, c) = 0.5_f64.sincos();
    /// assert!((s - 0.5_f64.sin()).abs() <= f64::EPSILON * s);
    /// assert!((c - 0.5_f64.cos()).abs() <= f64::EPSILON * c);
    /// ```
    ///
    /// Types other than `f32` and `f64` get nalgebra's `sin_cos`.
    #[inline]
    fn sincos(self) -> (Self, Self) {
        self.sin_cos()
    }
}

impl Real for f64 {
    #[inline(always)]
    fn lit(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self
    }
    #[inline(always)]
    fn finite(self) -> bool {
        self.is_finite()
    }
    const EPSILON: Self = f64::EPSILON;
    const MIN_POSITIVE: Self = f64::MIN_POSITIVE;
    #[inline]
    fn sincos(self) -> (Self, Self) {
        crate::trig::sincos_f64(self)
    }
}

impl Real for f32 {
    #[inline(always)]
    fn lit(x: f64) -> Self {
        x as f32
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        f64::from(self)
    }
    #[inline(always)]
    fn finite(self) -> bool {
        self.is_finite()
    }
    const EPSILON: Self = f32::EPSILON;
    const MIN_POSITIVE: Self = f32::MIN_POSITIVE;
    #[inline]
    fn sincos(self) -> (Self, Self) {
        crate::trig::sincos_f32(self)
    }
}

/// `x` degrees in radians, as `T`.
#[inline]
pub fn deg<T: Real>(x: f64) -> T {
    T::lit(x.to_radians())
}
