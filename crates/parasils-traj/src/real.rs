//! The float types the crate is generic over.
//!
//! Every profile is generic over `T: Real`, implemented for [`f32`] and [`f64`]
//! only (the trait is sealed). `f64` is the reference; `f32` is for
//! micro-controllers, with the error budget stated in the crate docs.

use num_traits::Float;

mod sealed {
    /// Seals [`super::Real`]: only `f32` and `f64` implement it.
    pub trait Sealed {}
    impl Sealed for f32 {}
    impl Sealed for f64 {}
}

/// A float type a profile can be computed in: [`f32`] or [`f64`].
///
/// The conversions below never panic and never fail: they are the `as` casts of
/// the language, written once here so that the profiles need no `unwrap`.
pub trait Real:
    Float + core::fmt::Debug + core::fmt::Display + Default + Send + Sync + 'static + sealed::Sealed
{
    /// Converts an `f64` constant to `Self` (rounded to nearest for `f32`).
    fn lit(x: f64) -> Self;
    /// Converts a sample index to `Self`; exact up to 2^24 for `f32`, 2^53 for `f64`.
    fn from_index(k: usize) -> Self;
    /// Widens to `f64` (exact), for error reports.
    fn widen(self) -> f64;
}

impl Real for f32 {
    #[inline]
    #[allow(clippy::cast_possible_truncation)]
    fn lit(x: f64) -> Self {
        x as f32
    }
    #[inline]
    #[allow(clippy::cast_precision_loss)]
    fn from_index(k: usize) -> Self {
        k as f32
    }
    #[inline]
    fn widen(self) -> f64 {
        f64::from(self)
    }
}

impl Real for f64 {
    #[inline]
    fn lit(x: f64) -> Self {
        x
    }
    #[inline]
    #[allow(clippy::cast_precision_loss)]
    fn from_index(k: usize) -> Self {
        k as f64
    }
    #[inline]
    fn widen(self) -> f64 {
        self
    }
}
