//! The float types the crate is generic over.

use nalgebra::RealField;

/// A float type the kinematics run in: `f32` (firmware) or `f64` (host).
///
/// Everything in the crate is generic over `T: Real`. The trait adds to
/// nalgebra's [`RealField`] the two conversions the solvers need: constants
/// written in `f64` into `T`, and values of `T` out to `f64` for error reports.
pub trait Real: RealField + Copy {
    /// `x` rounded to `Self`.
    fn lit(x: f64) -> Self;
    /// `self` as an `f64` (exact for both `f32` and `f64`).
    fn to_f64(self) -> f64;
    /// Whether the value is neither NaN nor infinite.
    fn finite(self) -> bool;
    /// The machine epsilon of `Self`.
    const EPSILON: Self;
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
}

/// `x` degrees in radians, as `T`.
#[inline]
pub fn deg<T: Real>(x: f64) -> T {
    T::lit(x.to_radians())
}
